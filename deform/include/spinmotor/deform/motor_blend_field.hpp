#pragma once
// MotorBlendField: the per-vertex motor field M_i = blend(R_1..R_k; w_i1..w_ik) applied to a point
// set, p_i' = M_i p_i ~M_i (CGA paper eq. 2). The engine shared by every weight-based deformer:
// surface harmonic coordinates (§IV, weights = harmonic coordinates), spline-aligned deformation
// (§III, weights = spline basis functions of the harmonic parameter), skinning (bone weights).
// It follows the bind/pose contract of deformer.hpp.
//
// bind: V_rest (n×3), W (n×k, row i = the weights of vertex i, normally a partition of unity), the
//   blend mode (ga/blend.hpp: Log = exp(Σ w log R), PivotLog, Linear = DLB), and optionally the k
//   rest-pose motors R_j^0 (§III.A): then each point is stored as p'_i = ~M_i^0 p_i M_i^0 with
//   M_i^0 = blend(R^0; w_i), so that pose(R^0) gives back V_rest. Empty = identities (p'_i = p_i).
// pose: k unit motors -> V_out (n×3). Per frame the k motor logarithms (Log), the k² relative logs
//   log(R_j ~R_p) (PivotLog) or the k² signs <R_j ~R_p>_0 (Linear) are computed once; the
//   per-vertex work is then Σ_j w_ij B_j (6k multiply-adds), one motor exponential (or one
//   normalization) and one point transform, in parallel over vertices, with no allocation. The
//   Linear blend runs four vertices per SIMD lane group (it is otherwise latency-bound).
//   The result equals ga::blend(R, W.row(i), mode) applied to p'_i, vertex by vertex, to rounding
//   (vertex_motor() is that reference path; the tests compare the two).
#include <Eigen/Core>
#include <span>
#include <vector>

#include "spinmotor/ga.hpp"

namespace spinmotor {

class MotorBlendField {
 public:
  /// Row-major so that the k weights of a vertex are contiguous.
  using Weights = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  MotorBlendField() = default;

  /// Inputs as above. Throws Error on mismatched sizes, non-finite positions or weights, k = 0, or a
  /// rest motor that is not a finite unit motor (naming its index).
  static MotorBlendField bind(const Eigen::MatrixXd& V_rest, Weights W, ga::Blend mode,
                              std::span<const ga::Mot> rest_motors = {});

  /// Inputs: k unit motors (|<M ~M> − 1| ≤ 1e-6; they are renormalized). Output: V_out (n×3, resized
  /// only if needed). Throws Error naming a motor that is not finite or not unit, or a wrong count.
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out);

  /// Log mode only: pose from the generators B_j directly (M_i = exp(Σ_j w_ij B_j)). Unlike
  /// pose(exp(B)), a generator whose rotation exceeds π keeps its meaning (no log of an exp); the
  /// B-spline fit (bspline_fit.hpp) produces generators.
  void pose_generators(std::span<const ga::Dll> generators, Eigen::MatrixXd& V_out);

  /// The motor of vertex i for the given controls, ga::blend(motors, W.row(i), mode) (reference path,
  /// not for per-vertex loops).
  ga::Mot vertex_motor(Eigen::Index i, std::span<const ga::Mot> motors) const;

  Eigen::Index vertices() const { return P_.rows(); }
  Eigen::Index controls() const { return W_.cols(); }
  ga::Blend mode() const { return mode_; }
  const Weights& weights() const { return W_; }
  /// The bound points p'_i (n×3): V_rest when the rest motors are identities.
  const Eigen::MatrixXd& bound_positions() const { return P_; }

 private:
  void prepare(std::span<const ga::Mot> motors);

  Eigen::MatrixXd P_;  // column-major: contiguous lanes for the vectorized loops
  Weights W_;
  Eigen::VectorXi pivot_;  // argmax_j w_ij (first maximum, as ga::blend), PivotLog and Linear
  ga::Blend mode_ = ga::Blend::Log;
  std::vector<ga::Dll> logs_;    // Log: k; PivotLog: k², logs_[p k + j] = log(R_j ~R_p)
  std::vector<ga::Mot> motors_;  // k, normalized
  std::vector<double> signs_;    // Linear: k², ±1 = sign <R_j ~R_p>_0 (as ga::blend)
};

/// Throws Error unless m is finite and unit to 1e-6 (<M ~M>_0 = 1, <M ~M>_4 = 0); returns
/// ga::normalize(m). `what` names the motor in the message ("motor 3", "key 'tip'").
ga::Mot checked_unit_motor(const ga::Mot& m, const std::string& what);

}  // namespace spinmotor
