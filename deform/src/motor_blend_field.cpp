#include "spinmotor/deform/motor_blend_field.hpp"

#include <cmath>
#include <sstream>

#include "dlb_point.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/parallel.hpp"
#include "spinmotor/deform/deformer.hpp"

namespace spinmotor {

ga::Mot checked_unit_motor(const ga::Mot& m, const std::string& what) {
  for (double c : m.c)
    if (!std::isfinite(c)) throw Error(what + " is not finite");
  const auto n = m * ga::reverse(m);
  const double alpha = n.get<ga::blade::s>(), beta = n.get<ga::blade::e123ni>();
  if (std::abs(alpha - 1.0) > 1e-6 || std::abs(beta) > 1e-6) {
    std::ostringstream s;
    s << what << " is not a unit motor (<M ~M>_0 = " << alpha << ", <M ~M>_4 = " << beta << ")";
    throw Error(s.str());
  }
  return ga::normalize(m);
}

namespace {

/// Σ_j s_pj w_j R_j, the unnormalized linear blend.
[[gnu::always_inline]] inline ga::Mot linear_sum(const double* w, Eigen::Index k, int pivot,
                                                 const ga::Mot* motors, const double* signs) {
  const double* sp = signs + pivot * k;
  ga::Mot acc;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double s = sp[j] * w[j];
    for (int c = 0; c < 8; ++c) acc.c[c] += s * motors[j].c[c];
  }
  return acc;
}

/// Per-vertex motor of the field for the prepared controls. Inlined into the vertex loops.
template <ga::Blend Mode>
[[gnu::always_inline]] inline ga::Mot field_motor(const double* w, Eigen::Index k, int pivot,
                                                  const ga::Dll* logs, const ga::Mot* motors,
                                                  const double* signs) {
  if constexpr (Mode == ga::Blend::Log) {
    ga::Dll acc;
    for (Eigen::Index j = 0; j < k; ++j)
      for (int c = 0; c < 6; ++c) acc.c[c] += w[j] * logs[j].c[c];
    return ga::exp(acc);  // eq. (1): exp(Σ_j w_j log R_j)
  } else if constexpr (Mode == ga::Blend::PivotLog) {
    const ga::Dll* lp = logs + pivot * k;  // lp[pivot] is exactly zero
    ga::Dll acc;
    for (Eigen::Index j = 0; j < k; ++j)
      for (int c = 0; c < 6; ++c) acc.c[c] += w[j] * lp[j].c[c];
    return ga::exp(acc) * motors[pivot];
  } else {
    const ga::Mot acc = linear_sum(w, k, pivot, motors, signs);
    // ga::normalize without the throw (a cancelled blend is reported after the loop).
    const auto nn = acc * ga::reverse(acc);
    const double alpha = nn.get<ga::blade::s>(), beta = nn.get<ga::blade::e123ni>();
    if (!(alpha > 0.0)) {
      ga::Mot bad;
      bad.c.fill(std::nan(""));
      return bad;
    }
    const double a = 1.0 / std::sqrt(alpha);
    return acc * ga::MV<ga::blade::s, ga::blade::e123ni>{a, -0.5 * beta / alpha * a};
  }
}

/// Four vertices of the linear (DLB) blend at once, i0..i0+3: Σ_j s_pj w_ij R_j in lanes, then
/// dlb_point's formula lane by lane (component layout of ga/interop.hpp: rotor part
/// (m0, −m3, −m2, −m1), dual part (−m7, −m4, −m5, −m6)). Writes V_out rows i0..i0+3.
[[gnu::always_inline]] inline void dlb_block(const double* w, Eigen::Index k, const int* pivot,
                                             const ga::Mot* motors, const double* signs,
                                             const Eigen::MatrixXd& P, Eigen::Index i0,
                                             Eigen::MatrixXd& V_out) {
  using A = Eigen::Array<double, 4, 1>;
  A acc[8];
  for (auto& a : acc) a.setZero();
  const int* pv = pivot + i0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double* wj = w + i0 * k + j;
    const A s(signs[pv[0] * k + j] * wj[0], signs[pv[1] * k + j] * wj[k], signs[pv[2] * k + j] * wj[2 * k],
              signs[pv[3] * k + j] * wj[3 * k]);
    for (int c = 0; c < 8; ++c) acc[c] += s * motors[j].c[c];
  }
  const A& rw = acc[0];
  const A vx = -acc[3], vy = -acc[2], vz = -acc[1];
  const A d0 = -acc[7], dx = -acc[4], dy = -acc[5], dz = -acc[6];
  const A px = P.col(0).segment<4>(i0).array(), py = P.col(1).segment<4>(i0).array(),
          pz = P.col(2).segment<4>(i0).array();
  const A s2 =
      2.0 / (rw * rw + vx * vx + vy * vy + vz * vz);  // a cancelled blend gives inf/NaN: reported later
  const A ax = vy * pz - vz * py, ay = vz * px - vx * pz, az = vx * py - vy * px;  // v × p
  const A bx = vy * az - vz * ay, by = vz * ax - vx * az, bz = vx * ay - vy * ax;  // v × (v × p)
  const A cx = vy * dz - vz * dy, cy = vz * dx - vx * dz, cz = vx * dy - vy * dx;  // v × dv
  V_out.col(0).segment<4>(i0).array() = px + s2 * (rw * ax + bx + rw * dx - d0 * vx + cx);
  V_out.col(1).segment<4>(i0).array() = py + s2 * (rw * ay + by + rw * dy - d0 * vy + cy);
  V_out.col(2).segment<4>(i0).array() = pz + s2 * (rw * az + bz + rw * dz - d0 * vz + cz);
}

/// The DLB pose: blocks of four vertices, the last n mod 4 one by one.
void run_linear_pose(const MotorBlendField::Weights& W, const Eigen::MatrixXd& P,
                     const Eigen::VectorXi& pivot, const std::vector<ga::Mot>& motors,
                     const std::vector<double>& signs, Eigen::MatrixXd& V_out) {
  const Eigen::Index n = P.rows(), k = W.cols(), blocks = n / 4;
  const double* w = W.data();
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index b = 0; b < blocks; ++b)
    dlb_block(w, k, pivot.data(), motors.data(), signs.data(), P, 4 * b, V_out);
  for (Eigen::Index i = 4 * blocks; i < n; ++i)
    V_out.row(i) = detail::dlb_point(linear_sum(w + i * k, k, pivot[i], motors.data(), signs.data()).data(),
                                     Eigen::Vector3d(P(i, 0), P(i, 1), P(i, 2)))
                       .transpose();
}

template <ga::Blend Mode, class Out>
void run_field(const MotorBlendField::Weights& W, const Eigen::MatrixXd& P, const Eigen::VectorXi& pivot,
               const std::vector<ga::Dll>& logs, const std::vector<ga::Mot>& motors,
               const std::vector<double>& signs, bool inverse, Out&& out) {
  const Eigen::Index n = P.rows(), k = W.cols();
  const double* w = W.data();
  const int* pv = pivot.size() ? pivot.data() : nullptr;
  const ga::Dll* lg = logs.data();
  const ga::Mot* mo = motors.data();
  const double* sg = signs.data();
#pragma omp parallel for schedule(static) if (parallel::worth(n, parallel::kMotorBlend))
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p(P(i, 0), P(i, 1), P(i, 2));
    ga::Mot m = field_motor<Mode>(w + i * k, k, pv ? pv[i] : 0, lg, mo, sg);
    if (inverse) m = ga::reverse(m);
    out(i, ga::transform(m, p));
  }
}

template <class Out>
void dispatch(ga::Blend mode, const MotorBlendField::Weights& W, const Eigen::MatrixXd& P,
              const Eigen::VectorXi& pivot, const std::vector<ga::Dll>& logs,
              const std::vector<ga::Mot>& motors, const std::vector<double>& signs, bool inverse, Out&& out) {
  switch (mode) {
    case ga::Blend::Log:
      return run_field<ga::Blend::Log>(W, P, pivot, logs, motors, signs, inverse, out);
    case ga::Blend::PivotLog:
      return run_field<ga::Blend::PivotLog>(W, P, pivot, logs, motors, signs, inverse, out);
    case ga::Blend::DLB:
    default:
      return run_field<ga::Blend::DLB>(W, P, pivot, logs, motors, signs, inverse, out);
  }
}

/// After a DLB blend: the first vertex whose blended motor cancelled (only with negative weights).
void check_finite_output(const Eigen::MatrixXd& V) {
  if (V.allFinite()) return;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
      throw numerical_error("MotorBlendField: the linear blend of the motors cancels at vertex " +
                            std::to_string(i) + " (its weights are not a positive partition of unity)");
}

}  // namespace

MotorBlendField MotorBlendField::bind(const Eigen::MatrixXd& V_rest, Weights W, ga::Blend mode,
                                      std::span<const ga::Mot> rest_motors) {
  const Eigen::Index n = V_rest.rows(), k = W.cols();
  if (V_rest.cols() != 3) throw Error("MotorBlendField: V must have 3 columns");
  if (W.rows() != n) {
    std::ostringstream s;
    s << "MotorBlendField: " << W.rows() << " weight rows for " << n << " vertices";
    throw Error(s.str());
  }
  if (k == 0) throw Error("MotorBlendField: needs at least one control motor");
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!V_rest.row(i).allFinite())
      throw Error("MotorBlendField: vertex " + std::to_string(i) + " is not finite");
    if (!W.row(i).allFinite())
      throw Error("MotorBlendField: the weights of vertex " + std::to_string(i) + " are not finite");
  }
  if (!rest_motors.empty() && static_cast<Eigen::Index>(rest_motors.size()) != k) {
    std::ostringstream s;
    s << "MotorBlendField: " << rest_motors.size() << " rest motors for " << k << " controls";
    throw Error(s.str());
  }
  MotorBlendField f;
  f.mode_ = mode;
  f.W_ = std::move(W);
  f.P_ = V_rest;
  if (mode != ga::Blend::Log) {
    f.pivot_.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index p = 0;
      for (Eigen::Index j = 1; j < k; ++j)
        if (f.W_(i, j) > f.W_(i, p)) p = j;  // first maximum, as ga::blend
      f.pivot_[i] = static_cast<int>(p);
    }
  }
  f.logs_.resize(mode == ga::Blend::PivotLog ? k * k : k);
  f.motors_.resize(k);
  f.signs_.resize(mode == ga::Blend::DLB ? k * k : 0);
  if (!rest_motors.empty()) {  // §III.A: bind the rest pose, p'_i = ~M_i^0 p_i M_i^0
    f.prepare(rest_motors);
    const Eigen::MatrixXd P0 = f.P_;
    auto& P = f.P_;
    dispatch(mode, f.W_, P0, f.pivot_, f.logs_, f.motors_, f.signs_, true,
             [&P](Eigen::Index i, const Eigen::Vector3d& p) { P.row(i) = p; });
    if (!P.allFinite()) throw Error("MotorBlendField: the linear blend of the rest motors cancels");
  }
  return f;
}

void MotorBlendField::prepare(std::span<const ga::Mot> motors) {
  const Eigen::Index k = controls();
  if (static_cast<Eigen::Index>(motors.size()) != k) {
    std::ostringstream s;
    s << "MotorBlendField: " << motors.size() << " motors given for " << k << " controls";
    throw Error(s.str());
  }
  for (Eigen::Index j = 0; j < k; ++j)
    motors_[j] = checked_unit_motor(motors[j], "motor " + std::to_string(j));
  switch (mode_) {
    case ga::Blend::Log:
      for (Eigen::Index j = 0; j < k; ++j) logs_[j] = ga::log(motors_[j]);
      break;
    case ga::Blend::PivotLog:
      for (Eigen::Index p = 0; p < k; ++p) {
        const ga::Mot inv = ga::reverse(motors_[p]);
        for (Eigen::Index j = 0; j < k; ++j)
          logs_[p * k + j] = j == p ? ga::Dll{} : ga::log(motors_[j] * inv);
      }
      break;
    case ga::Blend::DLB:
      for (Eigen::Index p = 0; p < k; ++p) {
        const ga::Mot rp = ga::reverse(motors_[p]);
        for (Eigen::Index j = 0; j < k; ++j)
          signs_[p * k + j] = std::signbit(ga::scalar(motors_[j], rp)) ? -1.0 : 1.0;
      }
      break;
  }
}

void MotorBlendField::pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) {
  prepare(motors);
  const Eigen::Index n = vertices();
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  if (mode_ == ga::Blend::DLB) {
    run_linear_pose(W_, P_, pivot_, motors_, signs_, V_out);
    check_finite_output(V_out);
    return;
  }
  dispatch(mode_, W_, P_, pivot_, logs_, motors_, signs_, false,
           [&V_out](Eigen::Index i, const Eigen::Vector3d& p) {
             V_out(i, 0) = p.x();
             V_out(i, 1) = p.y();
             V_out(i, 2) = p.z();
           });
}

void MotorBlendField::pose_generators(std::span<const ga::Dll> generators, Eigen::MatrixXd& V_out) {
  const Eigen::Index k = controls();
  if (mode_ != ga::Blend::Log) throw Error("MotorBlendField::pose_generators needs the Log blend");
  if (static_cast<Eigen::Index>(generators.size()) != k) {
    std::ostringstream s;
    s << "MotorBlendField: " << generators.size() << " generators given for " << k << " controls";
    throw Error(s.str());
  }
  for (Eigen::Index j = 0; j < k; ++j) {
    for (double c : generators[j].c)
      if (!std::isfinite(c))
        throw Error("MotorBlendField: generator " + std::to_string(j) + " is not finite");
    logs_[j] = generators[j];
  }
  const Eigen::Index n = vertices();
  if (V_out.rows() != n || V_out.cols() != 3) V_out.resize(n, 3);
  run_field<ga::Blend::Log>(W_, P_, pivot_, logs_, motors_, signs_, false,
                            [&V_out](Eigen::Index i, const Eigen::Vector3d& p) {
                              V_out(i, 0) = p.x();
                              V_out(i, 1) = p.y();
                              V_out(i, 2) = p.z();
                            });
}

ga::Mot MotorBlendField::vertex_motor(Eigen::Index i, std::span<const ga::Mot> motors) const {
  if (i < 0 || i >= vertices())
    throw Error("MotorBlendField::vertex_motor: vertex " + std::to_string(i) + " out of range");
  if (static_cast<Eigen::Index>(motors.size()) != controls())
    throw Error("MotorBlendField::vertex_motor: wrong motor count");
  return ga::blend(motors, std::span<const double>(W_.row(i).data(), static_cast<std::size_t>(controls())),
                   mode_);
}

}  // namespace spinmotor
