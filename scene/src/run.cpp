#include "spinmotor/scene/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <stdexcept>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"
#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/curvature_spin_flow.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::scene {

using nlohmann::json;

struct SceneRunner::Impl {
  const Scene& scene;
  std::unique_ptr<SceneDeformer> d;
  double bind_ms = 0;
  json bind_extra;  // the deformer's bind figures, merged into every frame's metrics
  // Conformal snap (Crane et al. 2011 §7.2): bound once on the rest mesh (Laplacian factor, symbolic
  // analysis), then one snap per frame.
  // Shape mode (Le Folgoc 2019 extrusion toward the edit's curvature) binds nothing: each frame runs
  // its own extrusion from the rest mesh.
  // Pinned mode (the pose-keeping cleanup): bound once for the rest mesh and the pinned handles' vertices.
  std::optional<ConformalSnap> snapper;
  std::optional<PinnedCleanup> cleaner;   // the handles pinned
  std::optional<RigCleanup> rig_cleaner;  // "pins": "weights": the rig cleanup
  json clean(std::size_t f, FrameResult& fr);
  std::size_t next = 0;  // the frame next() computes

  explicit Impl(const Scene& s);
  FrameResult frame(std::size_t f);
};

SceneRunner::Impl::Impl(const Scene& s) : scene(s) {
  using clock = std::chrono::steady_clock;
  if (scene.ik && scene.deformer_type != "spline")
    throw scene.error("/ik", "the `ik` block drives the spline deformer; this scene's deformer is '" +
                                 scene.deformer_type + "'");
  const auto t0 = clock::now();
  d = bind_deformer(scene);
  bind_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
  // Every pose entry must name a control of this deformer.
  const std::vector<std::string> controls = d->control_names();
  const std::set<std::string> known(controls.begin(), controls.end());
  for (const Pose& p : scene.frames)
    for (const auto& [name, _] : p.motors)
      if (!known.count(name)) {
        std::string list;
        for (const auto& c : controls) list += (list.empty() ? "'" : ", '") + c + "'";
        throw scene.error(p.entry_path(name),
                          "no handle or control named '" + name + "' (" +
                              (list.empty() ? std::string("this deformer takes no pose entries")
                                            : "this deformer's controls: " + list) +
                              ")");
      }

  bind_extra = d->bind_report();
  if (scene.snap.enabled && scene.snap.mode == SnapMode::Pinned) {
    std::vector<int> pins;
    for (int h : scene.snap.pin_handles)
      for (Eigen::Index k = 0; k < scene.handles[h].vertices.size(); ++k)
        pins.push_back(scene.handles[h].vertices[k]);
    try {
      PinnedCleanupOptions o;
      o.keep = scene.snap.keep;
      o.max_iterations = scene.snap.iterations;
      if (scene.snap.pin_weights) {
        // The skin's rigid parts pinned and the rest attracted by its weights: the rig defaults
        // (rig_cleanup.hpp; scene.cpp checked the deformer is a skin).
        if (!d->skin()) throw Error("\"pins\": \"weights\" needs a skin deformer");
        RigCleanupOptions ro;
        ro.pin_threshold = scene.snap.pin_threshold;
        ro.pin_margin = scene.snap.pin_margin;
        o.pose_weight = scene.snap.pose_weight.value_or(ro.cleanup.pose_weight);
        ro.cleanup = o;
        rig_cleaner.emplace(RigCleanup::bind(scene.mesh, d->skin()->weights, d->skin()->skeleton, ro));
      } else {
        o.pose_weight = scene.snap.pose_weight.value_or(PinnedCleanupOptions{}.pose_weight);
        cleaner.emplace(PinnedCleanup::bind(scene.mesh, pins, o));
      }
    } catch (const Error& e) {
      throw Error(scene.name() + ": /snap: " + e.what(), e.kind());
    }
  }
  if (scene.snap.enabled && scene.snap.mode == SnapMode::Free) {
    try {
      snapper.emplace(scene.mesh, ConformalSnapOptions{.tradeoff = scene.snap.tradeoff,
                                                       .rho_smoothing = scene.snap.smooth_rho});
    } catch (const Error& e) {
      throw Error(scene.name() + ": /snap: " + e.what(), e.kind());
    }
  }
}

// The pose-keeping cleanup of frame f (pinned handles, or the rig cleanup): fr.V becomes the cleaned
// pose, the edit moves to fr.V_unsnapped; returns the frame's "snap" figures.
json SceneRunner::Impl::clean(std::size_t f, FrameResult& fr) {
  using clock = std::chrono::steady_clock;
  const auto t2 = clock::now();
  Eigen::MatrixXd V_clean;
  DeformationMetrics ms;
  json out = {{"mode", "pinned"}};
  const bool first = f == 0;  // the bind is paid by the first frame
  double bind = 0;
  try {
    if (rig_cleaner) {
      const RigCleanupResult r = (*rig_cleaner)(fr.V, V_clean);
      bind = rig_cleaner->bind_ms();
      out.update({{"pins", rig_cleaner->pins().size()},
                  {"keep", "per piece"},
                  {"pose_weight", rig_cleaner->options().cleanup.pose_weight},
                  {"measure_ratio", r.volume_ratio},
                  {"edit_measure_ratio", r.edit_volume_ratio},
                  {"pin_error", r.pin_error},
                  {"iterations", r.iterations},
                  {"converged", r.converged}});
    } else {
      const PinnedCleanupResult pr = cleaner->cleanup(fr.V, V_clean);
      bind = cleaner->bind_ms();
      out.update({{"pins", cleaner->pins().size()},
                  {"keep", option_name(pr.kept)},
                  {"pose_weight", cleaner->options().pose_weight},
                  {"measure_ratio", pr.measure_ratio()},  // kept volume or area / rest
                  {"edit_measure_ratio", pr.rest_measure != 0 ? pr.edit_measure / pr.rest_measure : 1.0},
                  {"pin_error", pr.pin_error},
                  {"iterations", pr.iterations},
                  {"converged", pr.converged}});
    }
    ms = compute_metrics(scene.mesh, V_clean);
  } catch (const Error& e) {
    throw Error(scene.name() + ": snap (pinned mode): " + e.what(), e.kind());
  }
  const VertexDistances dist = vertex_distances(fr.V, V_clean, Alignment::None);
  out.update({{"q_mean", detail::finite_or_null(ms.q_mean)},
              {"q_max", detail::finite_or_null(ms.q_max)},
              {"area_distortion", detail::finite_or_null(ms.area_distortion)},
              {"rms_edit_to_snap", dist.rms},  // relative to the edit's bounding-box diagonal
              {"max_edit_to_snap", dist.max},
              {"bind_ms", first ? bind : 0.0},
              {"total_ms",
               (first ? bind : 0.0) + std::chrono::duration<double, std::milli>(clock::now() - t2).count()},
              {"metrics", to_json(ms)}});
  fr.V_unsnapped = std::move(fr.V);
  fr.V = std::move(V_clean);
  return out;
}

FrameResult SceneRunner::Impl::frame(std::size_t f) {
  using clock = std::chrono::steady_clock;
  FrameResult fr;
  const auto t1 = clock::now();
  d->pose(scene.frames[f], fr.V);
  fr.pose_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
  DeformationMetrics m;
  try {
    m = compute_metrics(scene.mesh, fr.V);
  } catch (const Error& e) {
    throw Error(scene.name() + ": metrics: " + e.what(), e.kind());
  }
  json j = {{"scene", scene.file.string()},
            {"mesh", scene.mesh_source},
            {"deformer", scene.deformer_type},
            {"vertices", scene.mesh.V.rows()},
            {"faces", scene.mesh.F.rows()},
            {"bind_ms", bind_ms},
            {"pose_ms", fr.pose_ms},
            {"q_mean", detail::finite_or_null(m.q_mean)},
            {"q_max", detail::finite_or_null(m.q_max)},
            {"area_distortion", detail::finite_or_null(m.area_distortion)}};
  if (scene.animated) j["frame"] = scene.first_frame + static_cast<int>(f);
  if (scene.frames[f].time) j["time"] = *scene.frames[f].time;
  const json extra = d->report(scene.frames[f], fr.V);  // named: items() of a temporary would dangle
  for (const auto& [k, v] : extra.items()) j[k] = v;
  for (const auto& [k, v] : bind_extra.items()) j[k] = v;
  j["metrics"] = to_json(m);
  if (cleaner || rig_cleaner) j["snap"] = clean(f, fr);
  if (scene.snap.enabled && scene.snap.mode == SnapMode::Shape) {
    const auto t2 = clock::now();
    CurvatureFlow flow;
    DeformationMetrics ms;
    Eigen::MatrixXd V_snap;
    try {
      CurvatureSpinOptions co;
      co.alpha = 0.05;  // the extrusion default (curvature_spin_flow.hpp)
      co.area_epsilon = scene.snap.area_constraint;
      flow = curvature_extrusion(scene.mesh.V, scene.mesh.F, fr.V, scene.snap.steps, co);
      V_snap = umeyama_fit(flow.V, fr.V).apply(flow.V);
      ms = compute_metrics(scene.mesh, V_snap);
    } catch (const Error& e) {
      throw Error(scene.name() + ": snap (shape mode): " + e.what(), e.kind());
    }
    const VertexDistances dist = vertex_distances(fr.V, V_snap, Alignment::None);
    j["snap"] = {{"mode", "shape"},
                 {"steps", scene.snap.steps},
                 {"area_constraint", scene.snap.area_constraint},
                 {"q_mean", detail::finite_or_null(ms.q_mean)},
                 {"q_max", detail::finite_or_null(ms.q_max)},
                 {"area_distortion", detail::finite_or_null(ms.area_distortion)},
                 {"rms_edit_to_snap", dist.rms},
                 {"max_edit_to_snap", dist.max},
                 {"closure", flow.closure},
                 {"total_ms", std::chrono::duration<double, std::milli>(clock::now() - t2).count()},
                 {"metrics", to_json(ms)}};
    fr.V_unsnapped = std::move(fr.V);
    fr.V = std::move(V_snap);
  }
  if (snapper) {
    ConformalSnapResult sr;
    DeformationMetrics ms;
    try {
      sr = snapper->snap(fr.V);
      ms = compute_metrics(scene.mesh, sr.V);
    } catch (const Error& e) {
      throw Error(scene.name() + ": snap: " + e.what(), e.kind());
    }
    const VertexDistances dist = vertex_distances(fr.V, sr.V, Alignment::None);
    const bool first = f == 0;  // the bind is paid by the first frame
    j["snap"] = {{"mode", option_name(SnapMode::Free)},
                 {"tradeoff", scene.snap.tradeoff},
                 {"smooth_rho", scene.snap.smooth_rho},
                 {"q_mean", detail::finite_or_null(ms.q_mean)},
                 {"q_max", detail::finite_or_null(ms.q_max)},
                 {"area_distortion", detail::finite_or_null(ms.area_distortion)},
                 {"rms_edit_to_snap", dist.rms},  // relative to the edit's bounding-box diagonal
                 {"max_edit_to_snap", dist.max},
                 {"eigenvalue", sr.eigenvalue},
                 {"bind_ms", (first ? snapper->bind_ms() : 0.0) + sr.timings.bind},
                 {"similarity_fit_ms", sr.timings.similarity_fit},
                 {"eigen_ms", sr.timings.eigen},
                 {"poisson_ms", sr.timings.poisson},
                 {"total_ms", (first ? snapper->bind_ms() : 0.0) + sr.timings.total()},
                 {"metrics", to_json(ms)}};
    fr.V_unsnapped = std::move(fr.V);
    fr.V = std::move(sr.V);
  }
  fr.metrics = std::move(j);
  return fr;
}

SceneRunner::SceneRunner(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
SceneRunner::~SceneRunner() = default;
SceneRunner::SceneRunner(SceneRunner&&) noexcept = default;
SceneRunner& SceneRunner::operator=(SceneRunner&&) noexcept = default;
double SceneRunner::bind_ms() const { return impl_->bind_ms; }
std::size_t SceneRunner::frames() const { return impl_->scene.frames.size(); }
std::size_t SceneRunner::frame() const { return impl_->next; }

FrameResult SceneRunner::next() {
  if (done()) throw std::logic_error("SceneRunner::next: every frame has been computed");
  FrameResult fr = impl_->frame(impl_->next);
  ++impl_->next;  // only once the frame succeeded
  return fr;
}

RunResult run_scene(const Scene& scene, const RunProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  SceneRunner run(scene);
  RunResult r;
  r.bind_ms = run.bind_ms();
  if (progress) progress(0, run.frames(), seconds());
  while (!run.done()) {
    r.frames.push_back(run.next());
    if (progress) progress(r.frames.size(), run.frames(), seconds());
  }
  return r;
}

std::filesystem::path output_path(const Scene& scene, const std::filesystem::path& spec, int frame,
                                  const std::optional<std::filesystem::path>& out_dir) {
  std::filesystem::path p = spec;
  if (scene.animated) {
    char num[16];
    std::snprintf(num, sizeof num, ".%04d", scene.first_frame + frame);
    p.replace_filename(spec.stem().string() + num + spec.extension().string());
  }
  if (p.is_relative()) p = (out_dir ? *out_dir : scene.dir) / p;
  return p;
}

namespace {

/// Blue (Q = 1) → yellow → red (Q ≥ 2), interpolated on log2 Q.
std::array<std::uint8_t, 3> q_colour(double q) {
  const double t = std::isfinite(q) ? std::clamp(std::log2(std::max(q, 1.0)), 0.0, 1.0) : 1.0;
  const double c[3][3] = {{49, 54, 149}, {255, 255, 191}, {165, 0, 38}};
  const int k = t < 0.5 ? 0 : 1;
  const double s = t < 0.5 ? 2 * t : 2 * t - 1;
  std::array<std::uint8_t, 3> rgb;
  for (int i = 0; i < 3; ++i)
    rgb[i] = static_cast<std::uint8_t>(std::lround(c[k][i] + s * (c[k + 1][i] - c[k][i])));
  return rgb;
}

template <class T>
void put(std::ostream& o, T v) {
  o.write(reinterpret_cast<const char*>(&v), sizeof v);  // little-endian hosts (x86-64, aarch64)
}

}  // namespace

void write_q_colors_ply(const std::filesystem::path& path, const Mesh& rest, const Eigen::MatrixXd& V) {
  const Eigen::VectorXd Q = quasi_conformal_error(rest.V, rest.F, V);
  AtomicFile out(path);
  std::ostream& o = out.stream();
  o << "ply\nformat binary_little_endian 1.0\ncomment spinmotor: per-face quasi-conformal error Q (blue 1, "
       "red >= 2)\n"
    << "element vertex " << V.rows() << "\nproperty double x\nproperty double y\nproperty double z\n"
    << "element face " << rest.F.rows() << "\nproperty list uchar int vertex_indices\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty double quality\nend_header\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int c = 0; c < 3; ++c) put(o, V(i, c));
  for (Eigen::Index f = 0; f < rest.F.rows(); ++f) {
    put<std::uint8_t>(o, 3);
    for (int c = 0; c < 3; ++c) put<std::int32_t>(o, rest.F(f, c));
    for (std::uint8_t v : q_colour(Q[f])) put(o, v);
    put(o, std::isfinite(Q[f]) ? Q[f] : -1.0);
  }
  out.commit();
}

FrameWriter::FrameWriter(const Scene& scene, std::optional<std::filesystem::path> out_dir)
    : scene_(scene), out_dir_(std::move(out_dir)) {}

FrameWriter::~FrameWriter() {
  if (keep_) return;
  std::error_code ec;  // never throws from a destructor; a file may already be gone
  for (std::size_t f = 0; f < written_; ++f)
    for (const auto& p : paths(f)) std::filesystem::remove(p, ec);
}

std::vector<std::filesystem::path> FrameWriter::paths(std::size_t frame) const {
  const int f = static_cast<int>(frame);
  std::vector<std::filesystem::path> p;
  for (const auto& spec : {scene_.output.mesh, scene_.output.metrics, scene_.output.colors})
    if (spec) p.push_back(output_path(scene_, *spec, f, out_dir_));
  return p;
}

void FrameWriter::write(std::size_t frame, const FrameResult& fr) {
  if (frame != written_) throw std::logic_error("FrameWriter::write: frames are written in order");
  const std::vector<std::filesystem::path> p = paths(frame);
  std::size_t done = 0;  // files of this frame on disk (same order as paths())
  try {
    if (scene_.output.mesh) {
      Mesh m = scene_.mesh;  // keeps F, UV, FUV: only the positions change
      m.V = fr.V;
      write_mesh(p[done], m);
      ++done;
    }
    if (scene_.output.metrics) {
      write_text_atomic(p[done], fr.metrics.dump(2) + "\n");
      ++done;
    }
    if (scene_.output.colors) {
      write_q_colors_ply(p[done], scene_.mesh, fr.V);
      ++done;
    }
  } catch (...) {
    std::error_code ec;
    for (std::size_t k = 0; k < done; ++k) std::filesystem::remove(p[k], ec);
    throw;
  }
  ++written_;
}

std::vector<std::filesystem::path> write_outputs(const Scene& scene, const RunResult& result,
                                                 const std::optional<std::filesystem::path>& out_dir) {
  FrameWriter out(scene, out_dir);
  std::vector<std::filesystem::path> written;
  for (std::size_t f = 0; f < result.frames.size(); ++f) {
    out.write(f, result.frames[f]);
    for (auto& p : out.paths(f)) written.push_back(std::move(p));
  }
  out.keep();
  return written;
}

}  // namespace spinmotor::scene
