// `spinmotor snap REST EDITED --pin FILE --out OUT [--keep auto|volume|area|none] [--json]`: see
// snap_pinned.hpp.
#include "snap_pinned.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::cli {

void snap_pinned(const Mesh& rest, const Mesh& edited, const SnapPinnedArgs& a) {
  if (a.pin_file.empty()) throw Error("snap: --mode pinned needs --pin FILE (the vertices to keep in place)");
  const Eigen::VectorXi pins = read_pin_file(a.pin_file, rest.V.rows());
  PinnedCleanupOptions o;
  o.keep = parse_option<CleanupKeep>(a.keep, "snap: --keep: ");
  o.pose_weight = a.pose_weight;
  PinnedCleanup pc = PinnedCleanup::bind(rest, pins, o);
  Eigen::MatrixXd V;
  const PinnedCleanupResult r = pc.cleanup(edited.V, V);
  Mesh out = edited.has_uv() ? edited : rest;
  out.V = V;
  write_mesh(a.out, out);
  const QuasiConformalSummary q0 = quasi_conformal_summary(rest.V, rest.F, edited.V);
  const QuasiConformalSummary q1 = quasi_conformal_summary(rest.V, rest.F, V);
  const std::string kept(option_name(r.kept));
  const double before = r.rest_measure != 0 ? r.edit_measure / r.rest_measure : 1.0;
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  if (a.json) {
    std::cout << nlohmann::json{{"mode", "pinned"},
                                {"vertices", rest.V.rows()},
                                {"faces", rest.F.rows()},
                                {"pins", pc.pins().size()},
                                {"keep", kept},
                                {"pose_weight", a.pose_weight},
                                {"q_mean_before", finite(q0.q_mean)},
                                {"q_max_before", finite(q0.q_max)},
                                {"q_mean_after", finite(q1.q_mean)},
                                {"q_max_after", finite(q1.q_max)},
                                {"measure_ratio_before", before},
                                {"measure_ratio_after", r.measure_ratio()},
                                {"pin_error", r.pin_error},
                                {"iterations", r.iterations},
                                {"converged", r.converged},
                                {"bind_ms", pc.bind_ms()},
                                {"cleanup_ms", r.total_ms}}
                     .dump(2)
              << '\n';
  } else if (!a.quiet) {
    std::printf("snap (pinned): %lld vertices, %lld faces, %lld pins, keeping the %s\n",
                static_cast<long long>(rest.V.rows()), static_cast<long long>(rest.F.rows()),
                static_cast<long long>(pc.pins().size()), kept.c_str());
    std::printf("  Q_mean before %.6f, after %.6f (Q_max %.4g -> %.4g)\n", q0.q_mean, q1.q_mean, q0.q_max,
                q1.q_max);
    std::printf("  %s ratio to rest: before %.4f, after %.6f; pin error %.3g of the diagonal\n", kept.c_str(),
                before, r.measure_ratio(), r.pin_error);
    std::printf("  %d iterations%s; bind %.1f ms, cleanup %.1f ms\n", r.iterations,
                r.converged ? "" : " (not converged)", pc.bind_ms(), r.total_ms);
    std::printf("  wrote %s\n", a.out.c_str());
  }
}

}  // namespace spinmotor::cli
