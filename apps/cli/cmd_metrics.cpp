// `spinmotor metrics REST DEFORMED`: quality of a deformation with fixed connectivity.
#include <cstdio>
#include <iostream>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"

namespace {

using spinmotor::Error;

// Same vertex count and the very same face list: the metrics compare vertex i with vertex i.
void require_same_connectivity(const spinmotor::Mesh& rest, const spinmotor::Mesh& def,
                               const std::string& rest_path, const std::string& def_path) {
  if (rest.V.rows() != def.V.rows())
    throw Error("metrics: " + rest_path + " has " + std::to_string(rest.V.rows()) + " vertices but " +
                def_path + " has " + std::to_string(def.V.rows()) +
                " (the meshes must share their connectivity)");
  if (rest.F.rows() != def.F.rows())
    throw Error("metrics: " + rest_path + " has " + std::to_string(rest.F.rows()) + " faces but " + def_path +
                " has " + std::to_string(def.F.rows()) + " (the meshes must share their connectivity)");
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f)
    if (rest.F.row(f) != def.F.row(f)) {
      auto face = [&](const Eigen::MatrixXi& F) {
        return "(" + std::to_string(F(f, 0)) + ", " + std::to_string(F(f, 1)) + ", " +
               std::to_string(F(f, 2)) + ")";
      };
      throw Error("metrics: face " + std::to_string(f) + " differs: " + face(rest.F) + " in " + rest_path +
                  ", " + face(def.F) + " in " + def_path + " (the meshes must share their connectivity)");
    }
}

void print_table(const spinmotor::DeformationMetrics& m) {
  auto row = [](const char* name, double value, const char* note) {
    if (*note)
      std::printf("  %-22s %-14.8g %s\n", name, value, note);
    else
      std::printf("  %-22s %.8g\n", name, value);
  };
  std::printf("vertices %lld, faces %lld\n", static_cast<long long>(m.vertices),
              static_cast<long long>(m.faces));
  row("q_mean", m.q_mean, "rest-area-weighted mean of sigma_max/sigma_min (1 = conformal)");
  row("q_max", m.q_max, "");
  if (m.collapsed_faces > 0)
    std::printf("  %-22s %-14lld %s\n", "collapsed_faces", static_cast<long long>(m.collapsed_faces),
                "deformed faces of zero area (Q = inf, excluded from the means)");
  row("area_distortion", m.area_distortion, "mean |log(A'/A)|, global scale removed");
  row("area_distortion_max", m.area_distortion_max, "");
  row("area_scale", m.area_scale, "total deformed area / total rest area");
  row("edge_distortion", m.edge_distortion, "mean |log(l'/l)|, global scale removed");
  row("edge_distortion_max", m.edge_distortion_max, "");
  const std::string aligned =
      std::string("after ") + std::string(spinmotor::option_name(m.alignment)) + " alignment";
  row("rms", m.rms, ("RMS vertex distance / bounding-box diagonal, " + aligned).c_str());
  row("max", m.max, ("max vertex distance / bounding-box diagonal, " + aligned).c_str());
  row("diagonal", m.diagonal, "rest bounding-box diagonal");
  if (m.volume_ratio) row("volume_ratio", *m.volume_ratio, "enclosed volume / rest volume (closed meshes)");
  if (m.alignment == spinmotor::Alignment::Similarity) row("alignment_scale", m.transform.scale, "");
  if (m.willmore_rest) row("willmore_rest", *m.willmore_rest, "integral of H^2 dA (sphere: 4 pi)");
  if (m.willmore_deformed) row("willmore_deformed", *m.willmore_deformed, "");
}

const spinmotor::cli::RegisterCommand register_metrics{
    "metrics", "Quality metrics of a deformation: quasi-conformal error, area/edge distortion, distances",
    [](CLI::App& sub) {
      struct Args {
        std::string rest, deformed, align = "none";
        bool json = false, no_willmore = false, quiet = false;
      };
      auto args = std::make_shared<Args>();
      sub.add_option("REST", args->rest, "Rest mesh (OBJ, OFF, PLY, STL)")->required();
      sub.add_option("DEFORMED", args->deformed, "Deformed mesh with the same connectivity")->required();
      sub.add_flag("--json", args->json, "Print a JSON object instead of a table");
      sub.add_option("--align", args->align, "Transformation removed before the vertex distances")
          ->check(CLI::IsMember({"none", "translation", "rigid", "similarity"}))
          ->capture_default_str();
      sub.add_flag("--no-willmore", args->no_willmore, "Skip the Willmore energies");
      sub.add_flag("-q,--quiet", args->quiet, "Print nothing unless --json (checks the inputs only)");
      sub.footer(
          "Examples:\n"
          "  spinmotor metrics rest.obj posed.obj\n"
          "  spinmotor metrics rest.obj snapped.obj --align similarity --json");
      sub.callback([args] {
        const spinmotor::Mesh rest = spinmotor::read_mesh(args->rest);
        const spinmotor::Mesh def = spinmotor::read_mesh(args->deformed);
        require_same_connectivity(rest, def, args->rest, args->deformed);
        spinmotor::MetricsOptions options;
        options.alignment = spinmotor::parse_option<spinmotor::Alignment>(args->align);
        options.willmore = !args->no_willmore;
        const spinmotor::DeformationMetrics m = spinmotor::compute_metrics(rest, def.V, options);
        if (args->json)
          std::cout << spinmotor::to_json(m).dump(2) << '\n';
        else if (!args->quiet)
          print_table(m);
      });
    }};

}  // namespace
