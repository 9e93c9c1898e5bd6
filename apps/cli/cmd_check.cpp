// `spinmotor check MESH [--json]`: validate a mesh file and print its report.
//
// Exit code 0 when the mesh has none of the defects (non-manifold edges or vertices, degenerate
// faces, duplicate / unreferenced / non-finite vertices, inconsistent orientation; boundaries,
// several components and genus are properties), 2 when it has any or cannot be read. The report goes
// to stdout (a table, or one JSON object with --json); the error naming the first defect of each kind
// goes to stderr. Vertex and face indices in messages are 0-based (OBJ files count from 1).
// `check` writes no file.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/mesh/validate_json.hpp"

namespace {

using spinmotor::MeshReport;

nlohmann::ordered_json to_json(const std::string& file, const MeshReport& r) {
  nlohmann::ordered_json j;  // "file" first, then the report's keys (validate_json.hpp)
  j["file"] = file;
  const nlohmann::ordered_json report = spinmotor::report_json(r);  // named: items() must not outlive it
  for (const auto& [key, value] : report.items()) j[key] = value;
  return j;
}

void print_table(const std::string& file, const MeshReport& r) {
  auto row = [](const char* name, long long value, const char* note = "") {
    if (*note)
      std::printf("  %-26s %-10lld %s\n", name, value, note);
    else
      std::printf("  %-26s %lld\n", name, value);
  };
  auto defect = [&](const char* name, long long value) { row(name, value, value ? "<- defect" : ""); };
  std::printf("%s\n", file.c_str());
  row("vertices", r.vertices);
  row("faces", r.faces);
  row("edges", r.edges);
  row("components", r.components);
  row("boundary_loops", r.boundary_loops);
  row("boundary_edges", r.boundary_edges);
  row("euler_characteristic", r.euler_characteristic);
  if (r.genus >= 0)
    row("genus", r.genus);
  else
    std::printf("  %-26s %-10s (%s)\n", "genus", "undefined", r.genus_note.c_str());
  defect("non_manifold_edges", r.non_manifold_edges);
  defect("non_manifold_vertices", r.non_manifold_vertices);
  defect("degenerate_faces", r.degenerate_faces);
  defect("duplicate_vertices", r.duplicate_vertices);
  defect("unreferenced_vertices", r.unreferenced_vertices);
  defect("nonfinite_vertices", r.nonfinite_vertices);
  defect("inconsistent_orientation", r.inconsistent_orientation);
  if (r.has_defects())
    std::printf("defects (0-based indices): %s\n", r.defects_summary().c_str());
  else
    std::printf("ok: no defects (%s, %s)\n", r.is_closed() ? "closed" : "with boundary",
                r.components == 1 ? "one component" : (std::to_string(r.components) + " components").c_str());
}

const spinmotor::cli::RegisterCommand register_check{
    "check", "Validate a mesh: counts, topology and defects (exit 0 if it has no defect, 2 otherwise)",
    [](CLI::App& sub) {
      struct Args {
        std::string mesh;
        bool json = false, quiet = false;
      };
      auto args = std::make_shared<Args>();
      sub.add_option("MESH", args->mesh, "Mesh file (OBJ, OFF, PLY, STL)")->required();
      sub.add_flag("--json", args->json, "Print one JSON object instead of a table");
      sub.add_flag("-q,--quiet", args->quiet,
                   "Print nothing but errors: the exit code says whether the mesh has defects");
      sub.footer(
          "Examples:\n"
          "  spinmotor check spot.obj\n"
          "  spinmotor check scan.ply --json > report.json\n"
          "  for f in *.obj; do spinmotor check -q \"$f\" || echo \"$f\"; done   # list the meshes with "
          "defects");
      sub.callback([args] {
        const spinmotor::Mesh mesh = spinmotor::read_mesh(args->mesh);  // throws Error (exit 2) if unreadable
        const MeshReport r = spinmotor::validate(mesh);
        if (args->json)
          std::cout << to_json(args->mesh, r).dump(2) << std::endl;
        else if (!args->quiet) {
          print_table(args->mesh, r);
          std::fflush(stdout);
        }
        if (r.has_defects()) throw spinmotor::Error(args->mesh + " has defects: " + r.defects_summary());
      });
    }};

}  // namespace
