// Scene deformer "spline": SplineDeformer (CGA paper §III), driven either by named key motors
// (`keys`, posed in `pose`) or by a joint chain (§III.C): the `ik` block solved by FABRIK, or a posed
// chain given in `fit`, turned into joint motors and fitted by a B-spline with pinned ends.
//   {"type": "spline", "from": handle, "to": handle, "basis": "linear" | "quadratic" | "bezier" |
//    "bspline", "degree": d, "keys": [names], "weights": "mean-value" | "cotan",
//    "fit": {"controls": m, "chain": [[x,y,z]...], "posed": [[x,y,z]...]}}
// With an `ik` block the one control is "ik.target": its motor moves the scene's target point (an
// animation or an interactive drag moves the target; FABRIK and the fit run again in pose(), which
// stays per-frame work: no harmonic field is recomputed).
#include <algorithm>
#include <chrono>
#include <limits>

#include "spinmotor/deform/chain_fit.hpp"
#include "spinmotor/deform/fabrik.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

using nlohmann::json;

json to_json(const Eigen::MatrixXd& P) {
  json a = json::array();
  for (Eigen::Index i = 0; i < P.rows(); ++i) a.push_back({P(i, 0), P(i, 1), P(i, 2)});
  return a;
}

Eigen::MatrixXd points(const json& a) {
  Eigen::MatrixXd P(static_cast<Eigen::Index>(a.size()), 3);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) P(static_cast<Eigen::Index>(i), c) = a[i][c].get<double>();
  return P;
}

class SplineScene final : public SceneDeformer {
public:
  SplineScene(const Scene& s, SplineDeformer d, int from, int to) : scene_(s), d_(std::move(d)), from_(from), to_(to) {}

  // Keys mode.
  std::vector<std::string> keys;
  // Chain mode.
  bool chain_mode = false;
  ChainFit chain;
  std::optional<FabrikResult> ik;
  Eigen::MatrixXd rest_chain;
  double ik_ms = 0, fit_ms = 0;

  static constexpr const char* kIkTarget = "ik.target";

  const Eigen::VectorXd& parameter() const { return d_.parameter(); }
  std::vector<std::string> controls() const override {
    return ik ? std::vector<std::string>{kIkTarget} : keys;
  }

  std::optional<Eigen::Vector3d> control_anchor(const std::string& name) const override {
    if (ik) return name == kIkTarget ? std::optional<Eigen::Vector3d>(scene_.ik->target) : std::nullopt;
    // Key j acts around parameter j/(k−1) of the harmonic field that runs from `from` to `to`.
    const auto it = std::find(keys.begin(), keys.end(), name);
    if (it == keys.end()) return std::nullopt;
    const double t = keys.size() > 1 ? double(it - keys.begin()) / double(keys.size() - 1) : 0.0;
    return (1 - t) * from_centroid_ + t * to_centroid_;
  }

  /// The target of this pose: the scene's target moved by the "ik.target" motor.
  Eigen::Vector3d ik_target(const Pose& pose) const { return ga::to_isometry(pose.motor(kIkTarget)) * scene_.ik->target; }

  /// FABRIK from the rest chain to `target`, then the B-spline fit of the joint motors (§III.C).
  void solve_ik(const Eigen::Vector3d& target) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    ik = fabrik(rest_chain, target,
                {.tolerance = scene_.ik->tolerance, .max_iterations = scene_.ik->iterations,
                 .end_rotation = scene_.ik->orientation});
    const auto t1 = clock::now();
    chain = fit_chain(scene_.mesh.V, parameter(), rest_chain, ik->joints, {.controls = controls_, .degree = degree_},
                      scene_.ik->orientation);
    ik_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    fit_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
    solved_target_ = target;
  }

  void pose(const Pose& pose, Eigen::MatrixXd& V_out) override {
    if (ik) {
      const Eigen::Vector3d target = ik_target(pose);
      if (target != solved_target_) try {
          solve_ik(target);
        } catch (const Error& e) {
          throw scene_.error(pose.entry_path(kIkTarget), e.what());
        }
    }
    if (chain_mode) return d_.pose_generators(chain.fit.generators, V_out);
    motors_.resize(keys.size());
    for (std::size_t j = 0; j < keys.size(); ++j) motors_[j] = pose.motor(keys[j]);
    d_.pose(motors_, V_out);
  }

  json report(const Pose& pose, const Eigen::MatrixXd& V_out) const override {
    // The `from` handle follows the first key (control) and the `to` handle the last one exactly.
    const ga::Mot first = chain_mode ? chain.fit.controls.front() : pose.motor(keys.front());
    const ga::Mot last = chain_mode ? chain.fit.controls.back() : pose.motor(keys.back());
    const Handle hs[2] = {scene_.handles[from_], scene_.handles[to_]};
    const ga::Mot ms[2] = {first, last};
    json r = {{"max_handle_error", max_handle_error(scene_.mesh.V, V_out, hs, ms)}};
    if (ik) {
      const Handle& to = scene_.handles[to_];
      const Eigen::Vector3d tip = handle_centroid(V_out, to);
      const Eigen::Vector3d t = ik_target(pose);
      r["ik"] = {{"target", {t.x(), t.y(), t.z()}},
                 {"reachable", ik->reachable},
                 {"converged", ik->converged},
                 {"iterations", ik->iterations},
                 {"fabrik_error", ik->error},
                 {"tip", {tip.x(), tip.y(), tip.z()}},
                 {"tip_error", (tip - t).norm()}};
    }
    return r;
  }

  json bind_report() const override {
    if (!chain_mode) return json::object();
    json f = {{"controls", chain.fit.controls.size()},
              {"used_svd", chain.fit.used_svd},
              {"rcond", chain.fit.rcond},
              {"residual", chain.fit.residual},
              {"joint_parameters", std::vector<double>(chain.joint_parameters.data(),
                                                       chain.joint_parameters.data() + chain.joint_parameters.size())},
              {"fit_ms", fit_ms}};
    json r = {{"fit", f}, {"posed_chain", to_json(ik ? ik->joints : points(scene_.deformer["fit"]["posed"]))}};
    if (ik) r["ik_ms"] = ik_ms;
    return r;
  }

  int controls_ = 0, degree_ = 3;  ///< of the chain fit

private:
  const Scene& scene_;
  SplineDeformer d_;
  int from_, to_;
  Eigen::Vector3d from_centroid_ = handle_centroid(scene_.mesh.V, scene_.handles[from_]);
  Eigen::Vector3d to_centroid_ = handle_centroid(scene_.mesh.V, scene_.handles[to_]);
  Eigen::Vector3d solved_target_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<ga::Mot> motors_;
};

SplineBasis parse_basis(const std::string& b) {
  if (b == "linear") return SplineBasis::Linear;
  if (b == "quadratic") return SplineBasis::Quadratic;
  if (b == "bezier") return SplineBasis::Bezier;
  return SplineBasis::BSpline;
}

}  // namespace

std::unique_ptr<SceneDeformer> bind_spline(const Scene& s) {
  using clock = std::chrono::steady_clock;
  const json& b = s.deformer;
  const std::string from = b["from"].get<std::string>(), to = b["to"].get<std::string>();
  s.handle(from, "/deformer/from");
  s.handle(to, "/deformer/to");
  if (from == to) throw s.error("/deformer/to", "`from` and `to` must be different handles");
  const int ifrom = s.handle_index(from), ito = s.handle_index(to);
  const Handle ends[2] = {s.handles[ifrom], s.handles[ito]};

  SplineDeformer::Options o;
  o.basis = parse_basis(b.value("basis", "bspline"));
  o.degree = b.value("degree", 3);
  o.weights = b.value("weights", "mean-value") == "cotan" ? HarmonicWeights::Cotangent : HarmonicWeights::MeanValue;
  const json fit = b.value("fit", json::object());
  const bool chain_mode = s.ik.has_value() || fit.contains("posed");

  auto bind = [&](const SplineDeformer::Options& opt) {
    try {
      return SplineDeformer::bind(s.mesh, ends, opt);
    } catch (const Error& e) {
      throw Error(s.name() + ": " + e.what(), e.kind());
    }
  };

  if (!chain_mode) {
    if (fit.size() > 0) throw s.error("/deformer/fit", "a fit needs a posed chain: an `ik` block or `fit.posed`");
    if (!b.contains("keys"))
      throw s.error("/deformer", "the spline deformer needs `keys` (names of its key motors) or an `ik` block");
    std::vector<std::string> keys = b["keys"].get<std::vector<std::string>>();
    for (std::size_t i = 0; i < keys.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (keys[i] == keys[j]) throw s.error("/deformer/keys/" + std::to_string(i), "duplicate key name '" + keys[i] + "'");
    o.keys = static_cast<int>(keys.size());
    try {
      check_spline(o.basis, o.keys, o.degree);
    } catch (const Error& e) {
      throw s.error("/deformer/keys", e.what());
    }
    auto d = std::make_unique<SplineScene>(s, bind(o), ifrom, ito);
    d->keys = std::move(keys);
    return d;
  }

  // Chain mode (§III.C): joint motors → B-spline fit → control generators.
  if (o.basis != SplineBasis::BSpline)
    throw s.error("/deformer/basis", "fitting a joint chain (§III.C) needs the bspline basis");
  if (b.contains("keys")) throw s.error("/deformer/keys", "the key motors come from the chain fit: remove `keys`");
  Eigen::MatrixXd rest, posed;
  std::optional<ga::Rot> end_rotation;
  if (s.ik) {
    if (fit.contains("chain") || fit.contains("posed"))
      throw s.error("/deformer/fit", "the chain comes from the `ik` block: remove `chain`/`posed` here");
    rest = s.ik->chain;
    end_rotation = s.ik->orientation;
  } else {
    if (!fit.contains("chain")) throw s.error("/deformer/fit", "`posed` needs the rest `chain`");
    rest = points(fit["chain"]);
    posed = points(fit["posed"]);
    if (posed.rows() != rest.rows())
      throw s.error("/deformer/fit/posed", "has " + std::to_string(posed.rows()) + " joints, `chain` has " +
                                               std::to_string(rest.rows()));
  }
  const int k = static_cast<int>(rest.rows());
  o.keys = fit.value("controls", std::max(o.degree + 1, k));
  if (o.keys < o.degree + 1)
    throw s.error("/deformer/fit/controls", "degree " + std::to_string(o.degree) + " needs at least " +
                                                std::to_string(o.degree + 1) + " controls");
  auto d = std::make_unique<SplineScene>(s, bind(o), ifrom, ito);
  d->chain_mode = true;
  d->rest_chain = rest;
  d->controls_ = o.keys;
  d->degree_ = o.degree;
  try {
    if (s.ik) {
      d->solve_ik(s.ik->target);
      return d;
    }
    const auto t1 = clock::now();
    d->chain = fit_chain(s.mesh.V, d->parameter(), rest, posed, {.controls = o.keys, .degree = o.degree},
                         end_rotation);
    d->fit_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
  } catch (const Error& e) {
    throw s.error(s.ik ? "/ik" : "/deformer/fit", e.what());
  }
  return d;
}

}  // namespace spinmotor::scene
