#pragma once
// SurfaceHarmonicDeformer: multi-handle harmonic coordinates on the surface with one motor per handle
// (CGA paper §IV). Follows the bind/pose contract of deformer.hpp.
//
// bind: k ≥ 1 disjoint handles; λ_j = harmonic_coordinates(rest, handles, weights) (one factorization,
//   k right-hand sides; a partition of unity, λ_j = 1 on handle j and 0 on the others), stored per
//   vertex for the blend.
// pose: k motors, motor j for handles[j]; each vertex moves by M_i = blend(R; λ_i1..λ_ik, mode),
//   p_i' = M_i p_i ~M_i: Log (the paper's exp(Σ λ_j log R_j)), PivotLog or Linear (DLB). A handle's
//   own vertices have λ = e_j exactly, so they follow their motor exactly (rigidly) in every mode.
#include <span>
#include <vector>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

class SurfaceHarmonicDeformer {
 public:
  struct Options {
    HarmonicWeights weights = HarmonicWeights::MeanValue;
    ga::Blend blend = ga::Blend::Log;
    /// Optional rest-pose motors of the handles (§III.A binding); empty = identities.
    std::vector<ga::Mot> rest_motors{};
  };

  /// Throws Error for bad handles (check_handles), a degenerate face, a connected component without
  /// any handle vertex (naming it), or rest motors that are not unit.
  static SurfaceHarmonicDeformer bind(const Mesh& rest, std::span<const Handle> handles,
                                      const Options& options);
  static SurfaceHarmonicDeformer bind(const Mesh& rest, std::span<const Handle> handles);
  /// The deformer shape (deformer.hpp): rig.handles, one control per handle.
  static SurfaceHarmonicDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.handles, options);
  }

  /// One unit motor per handle, in handle order (see deformer.hpp).
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out) { field_.pose(motors, V_out); }

  /// n×k harmonic coordinates λ (row i: the weights of vertex i).
  const MotorBlendField::Weights& coordinates() const { return field_.weights(); }
  const MotorBlendField& field() const { return field_; }
  /// One control per handle (its name, anchored at its rest centroid).
  const std::vector<Control>& controls() const { return controls_; }
  Eigen::Index vertices() const { return field_.vertices(); }
  const Options& options() const { return options_; }

 private:
  MotorBlendField field_;
  Options options_;
  std::vector<Control> controls_;
};

}  // namespace spinmotor
