// Scene deformer "spline": SplineDeformer (CGA paper §III), driven either by named key motors
// (`keys`, posed in `pose`), by the motors of its two end handles (no `keys`: keys {from, to}, linear
// basis unless `basis` says otherwise), or by a joint chain (§III.C): the `ik` block solved by FABRIK
// (SplineIkDeformer, one control "ik.target"), or a posed chain given in `fit`, turned into joint
// motors and fitted by a B-spline with pinned ends.
//   {"type": "spline", "from": handle, "to": handle, "basis": "linear" | "quadratic" | "bezier" |
//    "bspline", "degree": d, "keys": [names], "weights": "mean-value" | "cotan",
//    "fit": {"controls": m, "chain": [[x,y,z]...], "posed": [[x,y,z]...]}}
// Defaults: SplineDeformer::Options (bspline, degree 3, mean-value), SplineIkDeformer::Options.
#include <algorithm>
#include <chrono>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/chain_fit.hpp"
#include "spinmotor/deform/spline_deformer.hpp"
#include "spinmotor/deform/spline_ik.hpp"
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

/// A spline posed once by a given posed joint chain (`fit.posed`): the fit is bind-time work and the
/// deformer has no controls.
class PosedChainSpline {
 public:
  struct Options {
    SplineDeformer::Options spline{};
    Eigen::MatrixXd rest_chain{}, posed_chain{};
  };
  static PosedChainSpline bind(const Mesh& rest, const Rig& rig, const Options& o) {
    PosedChainSpline d;
    d.spline_ = SplineDeformer::bind(rest, rig.handles, o.spline);
    const auto t0 = std::chrono::steady_clock::now();
    d.fit_ = fit_chain(rest.V, d.spline_.parameter(), o.rest_chain, o.posed_chain,
                       {.controls = o.spline.keys, .degree = o.spline.degree});
    d.fit_ms_ = ms_since(t0);
    return d;
  }
  const std::vector<Control>& controls() const { return controls_; }
  Eigen::Index vertices() const { return spline_.vertices(); }
  void pose(std::span<const ga::Mot>, Eigen::MatrixXd& V_out) {
    spline_.pose_generators(fit_.fit.generators, V_out);
  }
  const ChainFit& chain_fit() const { return fit_; }
  double fit_ms() const { return fit_ms_; }

 private:
  SplineDeformer spline_;
  ChainFit fit_;
  std::vector<Control> controls_;
  double fit_ms_ = 0;
};

json fit_report(const ChainFit& c, double fit_ms) {
  return {{"controls", c.fit.controls.size()},
          {"used_svd", c.fit.used_svd},
          {"rcond", c.fit.rcond},
          {"residual", c.fit.residual},
          {"joint_parameters", std::vector<double>(c.joint_parameters.data(),
                                                   c.joint_parameters.data() + c.joint_parameters.size())},
          {"fit_ms", fit_ms}};
}

/// Errors of the chain solve and fit (fabrik.hpp, chain_fit.hpp, bspline_fit.hpp, spline_ik.hpp), as
/// opposed to those of the mesh and its handles (SplineDeformer::bind).
bool is_chain_error(const std::string& msg) {
  for (const char* p : {"fabrik", "chain_", "fit_bspline", "SplineIkDeformer"})
    if (msg.rfind(p, 0) == 0) return true;
  return false;
}

/// The `from` handle follows the first key (control) motor exactly and the `to` handle the last one.
json end_handle_error(const Scene& s, int from, int to, const ga::Mot& first, const ga::Mot& last,
                      const Eigen::MatrixXd& V) {
  const Handle hs[2] = {s.handles[from], s.handles[to]};
  const ga::Mot ms[2] = {first, last};
  return max_handle_error(s.mesh.V, V, hs, ms);
}

/// The spline's end handles: the `from` and `to` names, their indices in s.handles, the rig of the two.
struct SplineEnds {
  std::string from, to;
  int ifrom = -1, ito = -1;
  Rig rig;
};

/// Reads `from` and `to` of the deformer block; throws on an unknown handle or the same handle twice.
SplineEnds spline_ends(const Scene& s) {
  const json& b = s.deformer;
  const std::string from = b["from"].get<std::string>(), to = b["to"].get<std::string>();
  s.handle(from, "/deformer/from");
  s.handle(to, "/deformer/to");
  if (from == to) throw s.error("/deformer/to", "`from` and `to` must be different handles");
  const int ifrom = s.handle_index(from), ito = s.handle_index(to);
  return {from, to, ifrom, ito, Rig{.handles = {s.handles[ifrom], s.handles[ito]}}};
}

/// Key mode: a SplineDeformer driven by the named key motors `keys` (none: the end handles' motors as
/// two keys, linear unless `basis` is given) with options `o`. Throws on a `fit` block, a duplicate key
/// or a basis the keys do not suit; bind errors are prefixed with the scene's name.
std::unique_ptr<SceneDeformer> bind_keyed_spline(const Scene& s, const SplineEnds& ends,
                                                 SplineDeformer::Options o, const json& fit) {
  const json& b = s.deformer;
  if (fit.size() > 0)
    throw s.error("/deformer/fit", "a fit needs a posed chain: an `ik` block or `fit.posed`");
  std::vector<std::string> keys = {ends.from,
                                   ends.to};  // no `keys`: the end handles' motors are the two keys
  if (b.contains("keys")) {
    keys = b["keys"].get<std::vector<std::string>>();
  } else if (!b.contains("basis")) {
    o.basis = SplineBasis::Linear;
  }
  for (std::size_t i = 0; i < keys.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (keys[i] == keys[j])
        throw s.error("/deformer/keys/" + std::to_string(i), "duplicate key name '" + keys[i] + "'");
  o.keys = static_cast<int>(keys.size());
  o.key_names = keys;
  try {
    check_spline(o.basis, o.keys, o.degree);
  } catch (const Error& e) {
    throw s.error(b.contains("keys") ? "/deformer/keys" : "/deformer/basis", e.what());
  }
  const int ifrom = ends.ifrom, ito = ends.ito;
  auto report = [&s, ifrom, ito](const AnyDeformer&, std::span<const ga::Mot> m, const Eigen::MatrixXd& V) {
    return json{{"max_handle_error", end_handle_error(s, ifrom, ito, m.front(), m.back(), V)}};
  };
  SplineDeformer d = [&] {
    try {
      return SplineDeformer::bind(s.mesh, ends.rig, o);
    } catch (const Error& e) {
      throw Error(s.name() + ": " + e.what(), e.kind());
    }
  }();
  return std::make_unique<SceneDeformer>(s, std::move(d), report);
}

/// Chain mode (§III.C) checks: the bspline basis, no `keys`, the rest chain from the `ik` block or
/// `fit.chain` (not both), enough controls. Sets o.keys to the control count (`fit.controls`, default
/// max(degree + 1, joints)) and returns the rest chain.
Eigen::MatrixXd chain_rest(const Scene& s, const json& fit, SplineDeformer::Options& o) {
  if (o.basis != SplineBasis::BSpline)
    throw s.error("/deformer/basis", "fitting a joint chain (§III.C) needs the bspline basis");
  if (s.deformer.contains("keys"))
    throw s.error("/deformer/keys", "the key motors come from the chain fit: remove `keys`");
  Eigen::MatrixXd rest = s.ik ? s.ik->chain : Eigen::MatrixXd();
  if (s.ik) {
    if (fit.contains("chain") || fit.contains("posed"))
      throw s.error("/deformer/fit", "the chain comes from the `ik` block: remove `chain`/`posed` here");
  } else if (!fit.contains("chain")) {
    throw s.error("/deformer/fit", "`posed` needs the rest `chain`");
  } else {
    rest = points(fit["chain"]);
  }
  const int k = static_cast<int>(rest.rows());
  o.keys = fit.value("controls", std::max(o.degree + 1, k));
  if (o.keys < o.degree + 1)
    throw s.error("/deformer/fit/controls", "degree " + std::to_string(o.degree) + " needs at least " +
                                                std::to_string(o.degree + 1) + " controls");
  return rest;
}

/// Chain mode with an `ik` block: a SplineIkDeformer (FABRIK, then the B-spline fit) with o's controls,
/// degree and weights; reports the fit, the posed chain and the IK solve. A failed first solve is an
/// error of /ik, any other bind error is prefixed with the scene's name.
std::unique_ptr<SceneDeformer> bind_ik_spline(const Scene& s, const SplineEnds& ends,
                                              const SplineDeformer::Options& o) {
  SplineIkDeformer::Options io;
  io.controls = o.keys;
  io.degree = o.degree;
  io.weights = o.weights;
  Rig ik_rig = ends.rig;
  ik_rig.ik = IkChain{.chain = s.ik->chain,
                      .target = s.ik->target,
                      .tolerance = s.ik->tolerance,
                      .iterations = s.ik->iterations,
                      .orientation = s.ik->orientation};
  SplineIkDeformer d = [&] {
    try {
      return SplineIkDeformer::bind(s.mesh, ik_rig, io);
    } catch (const Error& e) {
      const std::string msg = e.what();
      // A failed first solve (FABRIK or the fit) is a problem of the ik block; the rest of the mesh's.
      if (is_chain_error(msg)) throw s.error("/ik", msg);
      throw Error(s.name() + ": " + msg, e.kind());
    }
  }();
  json bind_report = {{"fit", fit_report(d.chain_fit(), d.fit_ms())},
                      {"posed_chain", to_json(d.fabrik_result().joints)},
                      {"ik_ms", d.fabrik_ms()}};
  const int ifrom = ends.ifrom, ito = ends.ito;
  auto report = [&s, ifrom, ito](const AnyDeformer& any, std::span<const ga::Mot>, const Eigen::MatrixXd& V) {
    const SplineIkDeformer& ik = *any.get<SplineIkDeformer>();
    const auto& c = ik.chain_fit().fit.controls;
    const Eigen::Vector3d tip = handle_centroid(V, s.handles[ito]), t = ik.target();
    const FabrikResult& f = ik.fabrik_result();
    return json{{"max_handle_error", end_handle_error(s, ifrom, ito, c.front(), c.back(), V)},
                {"ik",
                 {{"target", {t.x(), t.y(), t.z()}},
                  {"reachable", f.reachable},
                  {"converged", f.converged},
                  {"iterations", f.iterations},
                  {"fabrik_error", f.error},
                  {"tip", {tip.x(), tip.y(), tip.z()}},
                  {"tip_error", (tip - t).norm()}}}};
  };
  return std::make_unique<SceneDeformer>(s, std::move(d), report, bind_report);
}

/// Chain mode with `fit.posed`: a PosedChainSpline fitted once to the posed chain against the rest
/// chain `rest`; reports the fit and the posed chain. Throws when the two chains differ in length; a
/// failed fit is an error of /deformer/fit, any other bind error is prefixed with the scene's name.
std::unique_ptr<SceneDeformer> bind_posed_chain_spline(const Scene& s, const SplineEnds& ends,
                                                       const SplineDeformer::Options& o,
                                                       const Eigen::MatrixXd& rest, const json& fit) {
  const Eigen::MatrixXd posed = points(fit["posed"]);
  if (posed.rows() != rest.rows())
    throw s.error("/deformer/fit/posed", "has " + std::to_string(posed.rows()) + " joints, `chain` has " +
                                             std::to_string(rest.rows()));
  PosedChainSpline d = [&] {
    try {
      return PosedChainSpline::bind(s.mesh, ends.rig,
                                    {.spline = o, .rest_chain = rest, .posed_chain = posed});
    } catch (const Error& e) {
      const std::string msg = e.what();
      if (is_chain_error(msg)) throw s.error("/deformer/fit", msg);
      throw Error(s.name() + ": " + msg, e.kind());
    }
  }();
  json bind_report = {{"fit", fit_report(d.chain_fit(), d.fit_ms())}, {"posed_chain", to_json(posed)}};
  const int ifrom = ends.ifrom, ito = ends.ito;
  auto report = [&s, ifrom, ito](const AnyDeformer& any, std::span<const ga::Mot>, const Eigen::MatrixXd& V) {
    const auto& c = any.get<PosedChainSpline>()->chain_fit().fit.controls;
    return json{{"max_handle_error", end_handle_error(s, ifrom, ito, c.front(), c.back(), V)}};
  };
  return std::make_unique<SceneDeformer>(s, std::move(d), report, bind_report);
}

}  // namespace

std::unique_ptr<SceneDeformer> bind_spline(const Scene& s) {
  const json& b = s.deformer;
  const SplineEnds ends = spline_ends(s);
  SplineDeformer::Options o;
  o.basis = deformer_option(s, "basis", o.basis);
  o.degree = b.value("degree", o.degree);
  o.weights = deformer_option(s, "weights", o.weights);
  const json fit = b.value("fit", json::object());
  const bool chain_mode = s.ik.has_value() || fit.contains("posed");
  if (!chain_mode) return bind_keyed_spline(s, ends, o, fit);
  // Chain mode (§III.C): joint motors → B-spline fit → control generators.
  const Eigen::MatrixXd rest = chain_rest(s, fit, o);
  if (s.ik) return bind_ik_spline(s, ends, o);
  return bind_posed_chain_spline(s, ends, o, rest, fit);
}

}  // namespace spinmotor::scene
