#include "spinmotor/deform/fabrik.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

/// Places `b` on the ray from `a` through `b` at distance d from a (p = (1 − λ) a + λ b, λ = d/r in the
/// paper's notation, written as a + d (b − a)/r). When b coincides with a, keeps `fallback`'s direction.
inline Eigen::Vector3d place(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double d,
                             const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d u = b - a;
  const double r = u.norm();
  return a + (r > 0.0 ? (d / r) * u : d * fallback);
}

/// FABRIK on joints P (in place) with bone lengths len, root fixed at P.row(0).
FabrikResult solve(Eigen::MatrixXd P, const std::vector<double>& len,
                   const std::vector<Eigen::Vector3d>& rest_dir, const Eigen::Vector3d& t,
                   const FabrikOptions& o) {
  const int k = static_cast<int>(P.rows());
  FabrikResult res;
  const Eigen::Vector3d root = P.row(0).transpose();
  double total = 0.0;
  for (double l : len) total += l;
  auto joint = [&P](int i) { return Eigen::Vector3d(P.row(i).transpose()); };
  res.reachable = (t - root).norm() <= total;
  if (!res.reachable) {  // stretch the chain straight towards the target
    for (int i = 0; i + 1 < k; ++i) P.row(i + 1) = place(joint(i), t, len[i], rest_dir[i]).transpose();
    res.error = (joint(k - 1) - t).norm();
    res.converged = res.error <= o.tolerance;
    res.joints = std::move(P);
    return res;
  }
  res.error = (joint(k - 1) - t).norm();
  int kicks = 0;
  while (res.error > o.tolerance && res.iterations < o.max_iterations) {
    const double previous = res.error;
    // Forward reaching: the end effector to the target, then towards the root.
    P.row(k - 1) = t.transpose();
    for (int i = k - 2; i >= 0; --i)
      P.row(i) = place(joint(i + 1), joint(i), len[i], -rest_dir[i]).transpose();
    // Backward reaching: the root back in place, then outwards.
    P.row(0) = root.transpose();
    for (int i = 0; i + 1 < k; ++i)
      P.row(i + 1) = place(joint(i), joint(i + 1), len[i], rest_dir[i]).transpose();
    ++res.iterations;
    res.error = (joint(k - 1) - t).norm();
    // A straight chain aimed along its own line (target on that line) has no preferred bending plane:
    // FABRIK then stalls. Bend the middle joint out of line by 1% of a bone and go on (a few times).
    if (k > 2 && res.error > o.tolerance && previous - res.error <= 1e-12 * total && kicks < 3) {
      ++kicks;
      const int mid = k / 2;
      const Eigen::Vector3d axis = (joint(k - 1) - root).normalized();
      Eigen::Vector3d perp = axis.cross(Eigen::Vector3d::UnitX());
      if (perp.squaredNorm() < 1e-6) perp = axis.cross(Eigen::Vector3d::UnitY());
      P.row(mid) += 0.01 * std::min(len[mid - 1], len[mid]) * perp.normalized().transpose();
    }
  }
  res.converged = res.error <= o.tolerance;
  res.joints = std::move(P);
  return res;
}

}  // namespace

FabrikResult fabrik(const Eigen::MatrixXd& chain, const Eigen::Vector3d& target,
                    const FabrikOptions& options) {
  const int k = static_cast<int>(chain.rows());
  if (k < 2 || chain.cols() != 3) throw Error("fabrik: the chain needs at least 2 joints (k×3)");
  if (!chain.allFinite()) throw Error("fabrik: a chain joint is not finite");
  if (!target.allFinite()) throw Error("fabrik: the target is not finite");
  if (!(options.tolerance > 0.0)) throw Error("fabrik: the tolerance must be > 0");
  if (options.max_iterations < 1) throw Error("fabrik: max_iterations must be ≥ 1");
  std::vector<double> len(k - 1);
  std::vector<Eigen::Vector3d> dir(k - 1);
  for (int i = 0; i + 1 < k; ++i) {
    const Eigen::Vector3d u = (chain.row(i + 1) - chain.row(i)).transpose();
    len[i] = u.norm();
    if (!(len[i] > 0.0)) {
      std::ostringstream s;
      s << "fabrik: bone " << i << " (joints " << i << " and " << i + 1 << ") has zero length";
      throw Error(s.str());
    }
    dir[i] = u / len[i];
  }
  if (!options.end_rotation) return solve(chain, len, dir, target, options);

  const ga::Rot& r = *options.end_rotation;
  const double nr = r.coeffs().norm();
  if (!std::isfinite(nr) || std::abs(nr - 1.0) > 1e-6)
    throw Error("fabrik: the end rotation is not a unit rotor");
  const Eigen::Vector3d end_dir = ga::rotate(r, dir[k - 2]) / nr / nr;
  FabrikResult res;
  if (k == 2) {  // only the root: the end joint is fixed by the orientation
    res.joints = chain;
  } else {
    std::vector<double> sub_len(len.begin(), len.end() - 1);
    std::vector<Eigen::Vector3d> sub_dir(dir.begin(), dir.end() - 1);
    res = solve(chain.topRows(k - 1), sub_len, sub_dir, target - len[k - 2] * end_dir, options);
  }
  Eigen::MatrixXd P(k, 3);
  P.topRows(k - 1) = res.joints.topRows(k - 1);
  P.row(k - 1) = P.row(k - 2) + len[k - 2] * end_dir.transpose();
  res.joints = std::move(P);
  res.error = (res.joints.row(k - 1).transpose() - target).norm();
  res.converged = res.error <= options.tolerance;
  if (k == 2) res.reachable = res.converged;
  return res;
}

}  // namespace spinmotor
