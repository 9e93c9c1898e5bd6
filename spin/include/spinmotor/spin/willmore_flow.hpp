#pragma once
// Conformal Willmore flow (Crane, Pinkall & Schröder 2011, §7.3): spin transformations whose curvature
// change removes a fraction τ of the mean curvature half-density, ρ = −τ H.
//
// Since H̃|df̃| = (H + ρ)|df| (§4.1), one step with ρ = −τ H scales the half-density by (1 − τ), so the
// Willmore energy W = ∫ H² |df|² (scale-invariant) ideally drops by the factor (1 − τ)². On a disk
// (possibly punctured) this needs no eigenvalue shift; τ = 1 is the minimal surface of §7.3
// (minimal_surface_step.hpp). On a closed surface the shift γ absorbs the constant part of ρ (a round
// sphere, H constant, is a fixed point); other closed shapes still lose energy, but the paper leaves
// the closed flow to future work and so does this code: it is the same step, without a guarantee.
//
// Discretisation of H ("H via the magnitude of the mean curvature normal HN = Δf", §7.3): signed,
//   H_i = (L V)_i · N_i / (2 A_i)       at interior vertices,
// with the positive semi-definite cotangent Laplacian L (cotangent_laplacian.hpp), the mixed Voronoi
// areas A_i and the area-weighted vertex normal N_i (outward for counter-clockwise faces), so H = 1/r
// on a sphere of radius r with outward normals. This is the sign and scale of SpinTransform's ρ:
// a constant ρ = 0.2 on a flat disk gives H = 0.19993 in this convention, and ρ = −H flattens a
// spherical cap to mean |H| 1.6e-4 of before (tests/test_willmore_flow.cpp). The magnitude alone
// would lose the sign of saddles and dents. (L V)_i at a boundary vertex also carries the boundary
// curve's curvature, so there H_i is the mean of H over its interior neighbours (0 if it has none).
// Per face H_f is the mean of its three corners, as face_rho_from_vertices (curvature_change.hpp).
//
// Cost: each step changes the mesh, so each step binds a new SpinTransform (validation, ordering,
// symbolic and numeric factorization, Poisson factor) — one full spin_transform per step. The
// pattern of the eigen matrix does not change between steps, so the symbolic analysis could be
// reused, but SpinTransform does not expose that. Measured (Release, shared 2-core machine): 18 ms
// per step on a 3.2k-face disk, 1.1 s on an 80k-face disk.
//
// Measured on closed meshes (no guarantee, see above): spot.obj, τ = 0.3, W 131.8 → 89.9 → 60.6 →
// 42.1 (per-step ratios 0.67–0.70 against the disk's 0.49); ρ = −H in one step 131.8 → 87.5.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace spinmotor {

/// Inputs: V (n×3), F (m×3, counter-clockwise). Output: n signed mean curvatures H_i (1/length, the
/// convention above; boundary vertices get their interior neighbours' mean). Throws Error naming a
/// degenerate face, an index out of range or a non-finite coordinate.
Eigen::VectorXd vertex_mean_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: m values H_f, the mean of vertex_mean_curvature at the corners:
/// the ρ of SpinTransform that doubles the mean curvature half-density (ρ = −H removes it).
Eigen::VectorXd face_mean_curvature(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// One step: spin transformation of `mesh` with ρ_f = −τ H_f. Inputs: mesh (as SpinTransform), τ
/// (finite; τ ∈ (0, 1] is the useful range, 1 = minimal surface), spin options (the scale option
/// decides the normalisation; boundary tangents are honoured). Output: the SpinTransform result.
/// Throws Error on bad input, numerical_error if the result is not finite.
SpinTransformResult willmore_flow_step(const Mesh& mesh, double tau,
                                       const SpinTransformOptions& options = {});

/// Progress of a flow, reported after every step.
struct WillmoreFlowProgress {
  int step = 0;  ///< 1..steps
  int steps = 0;
  double willmore = 0;    ///< W after this step
  double step_ms = 0;     ///< wall time of this step (H, bind, solve, W)
  double elapsed_ms = 0;  ///< since the flow started
};

struct WillmoreFlowOptions {
  double tau = 0.1;            ///< step τ: ρ = −τ H of the current surface at every step
  int steps = 10;              ///< number of steps N ≥ 1
  bool keep_positions = true;  ///< keep every step's positions in the result
  /// Per-step spin options (default KeepArea normalisation). Boundary targets apply at every step: after
  /// the first they hold the boundary's tangents (e.g. planar ones flatten the surface step by step,
  /// towards a conformal parameterisation: Fig. 17).
  SpinTransformOptions spin;
  std::function<void(const WillmoreFlowProgress&)> progress;  ///< optional, called after each step
};

struct WillmoreFlowResult {
  Eigen::MatrixXd V;                       ///< n×3 positions after the last step
  Eigen::VectorXd willmore;                ///< N+1 values: W before the flow, then after each step
  std::vector<Eigen::MatrixXd> positions;  ///< N+1 position sets (input first) if keep_positions
  Eigen::VectorXd step_ms;                 ///< N wall times (ms)
};

/// N steps of ρ = −τ H, rebinding on the current surface each step. Inputs: mesh, options. Output: the
/// final positions, W (willmore_energy, mesh/metrics/willmore.hpp) per step, optionally all positions.
/// Throws Error on bad input (τ not finite, steps < 1, bad mesh), numerical_error naming the step if
/// a step fails or produces non-finite positions or energy.
WillmoreFlowResult willmore_flow(const Mesh& mesh, const WillmoreFlowOptions& options);

}  // namespace spinmotor
