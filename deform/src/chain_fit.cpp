#include "spinmotor/deform/chain_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/deformer.hpp"

namespace spinmotor {

namespace {

/// The minimal rotation taking unit vector a onto unit vector b (half-way quaternion (1 + a·b, a × b)).
ga::Rot minimal_rotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double w = 1.0 + a.dot(b);
  if (w < 1e-12) {  // antiparallel: a half turn about any axis perpendicular to a
    Eigen::Vector3d axis = a.cross(Eigen::Vector3d::UnitX());
    if (axis.squaredNorm() < 1e-6) axis = a.cross(Eigen::Vector3d::UnitY());
    axis.normalize();
    return ga::Rot(0.0, axis.x(), axis.y(), axis.z());
  }
  const Eigen::Vector3d v = a.cross(b);
  const double s = 1.0 / std::sqrt(w * w + v.squaredNorm());
  return ga::Rot(w * s, v.x() * s, v.y() * s, v.z() * s);
}

void check_chain(const Eigen::MatrixXd& c, const char* what) {
  if (c.rows() < 2 || c.cols() != 3)
    throw Error(std::string("chain_motors: the ") + what + " chain needs at least 2 joints (k×3)");
  if (!c.allFinite())
    throw Error(std::string("chain_motors: a joint of the ") + what + " chain is not finite");
  for (Eigen::Index i = 0; i + 1 < c.rows(); ++i)
    if (!((c.row(i + 1) - c.row(i)).norm() > 0.0)) {
      std::ostringstream s;
      s << "chain_motors: bone " << i << " of the " << what << " chain has zero length";
      throw Error(s.str());
    }
}

}  // namespace

std::vector<ga::Mot> chain_motors(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& posed,
                                  const std::optional<ga::Rot>& end_rotation) {
  check_chain(rest, "rest");
  check_chain(posed, "posed");
  if (rest.rows() != posed.rows())
    throw Error("chain_motors: the rest and posed chains have different joint counts");
  const Eigen::Index k = rest.rows();
  // Rotation-minimising bone frames F_b (parallel transport).
  std::vector<ga::Rot> frame(k - 1);
  for (Eigen::Index b = 0; b + 1 < k; ++b) {
    const Eigen::Vector3d r = (rest.row(b + 1) - rest.row(b)).normalized().transpose();
    const Eigen::Vector3d q = (posed.row(b + 1) - posed.row(b)).normalized().transpose();
    if (b == 0) {
      frame[b] = minimal_rotation(r, q);
    } else {
      const Eigen::Vector3d carried = ga::rotate(frame[b - 1], r);
      frame[b] = minimal_rotation(carried, q) * frame[b - 1];
    }
  }
  std::vector<ga::Mot> Q(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    ga::Rot R;
    if (i == 0) {
      R = frame[0];
    } else if (i == k - 1) {
      R = end_rotation ? *end_rotation : frame[k - 2];
    } else {  // half-way between the two bones' frames
      R = frame[i - 1] * ga::exp(0.5 * ga::log(ga::reverse(frame[i - 1]) * frame[i]));
    }
    const double nr = R.coeffs().norm();
    if (!std::isfinite(nr) || std::abs(nr - 1.0) > 1e-6)
      throw Error("chain_motors: the end rotation is not a unit rotor");
    R = ga::Rot(R.w() / nr, R.x() / nr, R.y() / nr, R.z() / nr);
    const Eigen::Vector3d p = rest.row(i).transpose(), pp = posed.row(i).transpose();
    Q[i] = ga::motor(R, ga::translator(pp - ga::rotate(R, p)));  // T(p') R T(−p)
  }
  return Q;
}

Eigen::VectorXd chain_parameters(const Eigen::MatrixXd& V, const Eigen::VectorXd& lambda,
                                 const Eigen::MatrixXd& chain) {
  check_chain(chain, "rest");
  const Eigen::Index n = V.rows(), k = chain.rows();
  if (lambda.size() != n) throw Error("chain_parameters: one λ per vertex needed");
  // Normalized arc length s_i of the joints.
  Eigen::VectorXd s(k);
  s[0] = 0.0;
  for (Eigen::Index i = 1; i < k; ++i) s[i] = s[i - 1] + (chain.row(i) - chain.row(i - 1)).norm();
  const double total = s[k - 1];
  s /= total;
  // s_v: arc length of the closest point of the polyline to each vertex.
  Eigen::VectorXd sv(n);
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d x = V.row(v).transpose();
    double best = std::numeric_limits<double>::infinity(), bs = 0.0;
    for (Eigen::Index b = 0; b + 1 < k; ++b) {
      const Eigen::Vector3d a = chain.row(b).transpose(), e = (chain.row(b + 1) - chain.row(b)).transpose();
      const double t = std::clamp((x - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      const double d2 = (a + t * e - x).squaredNorm();
      if (d2 < best) best = d2, bs = s[b] + t * (s[b + 1] - s[b]);
    }
    sv[v] = bs;
  }
  Eigen::VectorXd out(k);
  out[0] = 0.0;
  out[k - 1] = 1.0;
  for (Eigen::Index i = 1; i + 1 < k; ++i) {
    const double h = 0.5 * std::min(s[i] - s[i - 1], s[i + 1] - s[i]);
    double sw = 0.0, swl = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sw, swl) if (parallel::worth(n, parallel::kMotorBlend))
    for (Eigen::Index v = 0; v < n; ++v) {
      const double w = 1.0 - std::abs(sv[v] - s[i]) / h;
      if (w > 0.0) sw += w, swl += w * lambda[v];
    }
    out[i] = sw > 0.0 ? swl / sw : s[i];
  }
  for (Eigen::Index i = 1; i < k; ++i) out[i] = std::clamp(out[i], out[i - 1], 1.0);
  return out;
}

ChainFit fit_chain(const Eigen::MatrixXd& V, const Eigen::VectorXd& lambda, const Eigen::MatrixXd& rest_chain,
                   const Eigen::MatrixXd& posed_chain, const BSplineFitOptions& options,
                   const std::optional<ga::Rot>& end_rotation) {
  ChainFit r;
  r.joint_motors = chain_motors(rest_chain, posed_chain, end_rotation);
  r.joint_parameters = chain_parameters(V, lambda, rest_chain);
  BSplineFitOptions o = options;
  o.interpolate_ends = true;
  r.fit = fit_bspline_motors(
      r.joint_motors, std::span<const double>(r.joint_parameters.data(), r.joint_parameters.size()), o);
  return r;
}

}  // namespace spinmotor
