#pragma once
// SplineDeformer: spline-aligned deformation with key motors (CGA paper §III). Follows the bind/pose
// contract of deformer.hpp.
//
// bind: two handles {from, to}; λ = harmonic_field(rest, from → 0, to → 1, weights) (§III, §VIII);
//   each vertex gets the basis weights W_j(λ_i) of the n keys (spline_basis.hpp); with rest key
//   motors R_j^0 the points are bound as p'_i = ~S^0(λ_i) p_i S^0(λ_i) (§III.A), else p'_i = p_i.
// pose: n key motors R_j; every vertex moves by S(λ_i) = exp(Σ_j W_j(λ_i) log R_j) (eq. 1),
//   p_i' = S(λ_i) p'_i ~S(λ_i) (eq. 2). The `from` handle follows R_1 and the `to` handle R_n exactly
//   (every basis interpolates its end keys).
// pose_generators: the same from the generators B_j = log R_j directly (what the B-spline fit of
//   bspline_fit.hpp produces).
#include <span>
#include <vector>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/deform/spline_basis.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

class SplineDeformer {
 public:
  struct Options {
    SplineBasis basis = SplineBasis::BSpline;
    int degree = 3;  ///< BSpline only
    int keys = 4;    ///< number of key motors n (Quadratic: 3)
    HarmonicWeights weights = HarmonicWeights::MeanValue;
    /// Optional rest-pose key motors (§III.A binding); empty = identities.
    std::vector<ga::Mot> rest_keys{};
    /// Names of the key controls (size `keys`); empty: "key0", "key1", ...
    std::vector<std::string> key_names{};
  };

  /// handles: exactly two, {from (λ = 0), to (λ = 1)}. Throws Error for a bad basis/key count
  /// (check_spline), bad handles, a degenerate face, or a component without a handle vertex.
  static SplineDeformer bind(const Mesh& rest, std::span<const Handle> handles, const Options& options);
  /// The deformer shape (deformer.hpp): rig.handles = {from, to}.
  static SplineDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.handles, options);
  }

  /// n unit key motors (see deformer.hpp).
  void pose(std::span<const ga::Mot> keys, Eigen::MatrixXd& V_out) { field_.pose(keys, V_out); }
  /// n generators B_j = log R_j.
  void pose_generators(std::span<const ga::Dll> keys, Eigen::MatrixXd& V_out) {
    field_.pose_generators(keys, V_out);
  }

  /// The harmonic parameter λ (n values in [0, 1]).
  const Eigen::VectorXd& parameter() const { return lambda_; }
  const MotorBlendField& field() const { return field_; }
  const Options& options() const { return options_; }
  /// One control per key; key j is anchored at (1 − t) c_from + t c_to, t = j/(keys − 1), c the rest
  /// centroids of the end handles (where it acts along the harmonic parameter).
  const std::vector<Control>& controls() const { return controls_; }
  Eigen::Index vertices() const { return lambda_.size(); }

 private:
  Eigen::VectorXd lambda_;
  MotorBlendField field_;
  Options options_;
  std::vector<Control> controls_;
};

}  // namespace spinmotor
