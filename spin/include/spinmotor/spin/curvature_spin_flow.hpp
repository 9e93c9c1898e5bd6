#pragma once
// Spin transformations as a regularised quadratic problem in curvature space (Le Folgoc & Blanc 2019,
// §5–§6, Appendix D), on Ye et al.'s face edge-constraint nets.
//
// One step on the current surface (V, F) with face areas A (diagonal, ⊗ I₄):
//   D_X = D_f + diag(H), (D_X φ)_i = ½ Σ_j E_ij φ_j (face_dirac_operator.hpp, extrinsic operator plus the
//   integrated mean curvature; D_X 1 = H, so φ ≡ 1 is the identity), D_ρ = D_X − ρA, and φ (m×4) minimises
//     φᵀ(D_ρ A⁻¹ D_ρ)φ + α (φ−1)ᵀ R (φ−1),   R = (A + β Ā L_f) / ΣA        (eq. 8)
//   with L_f the integrated face Laplacian (dual edges, weights |e_ij| / |c_i − c_j|), Ā the mean face
//   area (R is dimensionless: α and β are scale-free);
//   ρ_i = h̄_i / sqrt(A_i) for a target half-density h̄ (Ye eq. 10; Le Folgoc §6, ρ = h̄ sqrt(Ā/A) with h̄
//   a density), so that ρ ≡ H/A (h̄ = h) gives φ ≡ 1 exactly;
//   optionally the area-distortion soft constraint (Appendix D) (1/ε²) Σ_i a_i s̃_i², a_i = A_i/ΣA,
//   s̃_i = s_i + 4 Re δφ_i − 4 Σ_j a_j Re δφ_j the log area distortion against target areas A*
//   (s_i = log(A_i/A*_i) − log(ΣA/ΣA*)) linearised at φ = 1 (|φ|⁴ is the area factor, eq. 19); its
//   dense part is the rank-one −(16/ε²) u uᵀ (u = the weights a_i on the real parts) and is solved with
//   the Sherman–Morrison(–Woodbury) identity on one sparse Cholesky factor (no dense matrix);
//   on genus g > 0 optionally the exactness constraints (Appendix C, eq. 12): for each of the 2g harmonic
//   1-forms ω^k (kernel of the graph Helmholtzian d₀d₀ᵀ + d₁ᵀd₁, found by removing the exact and co-exact
//   parts of random edge values) Im Σ_i φ̄_i (Σ_j E_ij ω^k_ij) φ_j = 0, linearised at φ = 1:
//   Σ_i ⟨δφ_i, V^k_i ν⟩ = 0 with V^k_i = Σ_j E_ij ω^k_ij and ν = i, j, k (3·2g hard linear constraints,
//   eliminated with the same Cholesky factor; eq. 12 is used instead of the ρ projection (14) because
//   it constrains the solved φ directly);
// then the new vertices come from Ẽ_ij = φ̄_i E_ij φ_j (eq. 4) by least squares (Ye §4.3). Without the
// exactness constraint a torus step leaves a period (non-zero sum of Ẽ around a handle) that the least
// squares cannot fit: it shows in CurvatureSpinStep::closure.
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace spinmotor {

struct CurvatureSpinOptions {
  double alpha = 5.0;  ///< weight of the regulariser (φ−1)ᵀR(φ−1) of eq. 8 (> 0; ellipsoid study: 0.5
                       ///< diverges after 4 steps of τ = ½ without the Laplacian, 5–50 stable)
  double beta = 1.0;   ///< weight of the face Laplacian in R (≥ 0)
  double area_epsilon = 0.0;  ///< tolerance ε of the area soft constraint (Appendix D); 0 = off
  bool exactness = true;      ///< genus > 0: the exactness constraints of Appendix C (ignored on spheres)
};

struct CurvatureSpinStep {
  Eigen::MatrixXd V;     ///< n×3 new positions (centroid kept; scale from φ)
  Eigen::MatrixXd phi;   ///< m×4 face spinors
  double closure = 0.0;  ///< RMS misfit of the least-squares edge recovery / RMS edge (integrability)
  int exactness_constraints = 0;  ///< number of real exactness constraints imposed (3 · 2 genus, or 0)
  double period = 0.0;  ///< genus > 0: max over harmonic forms ω of |Σ_e ẽ_e ω_e| / Σ_e |ẽ_e||ω_e| (0: exact)
};

/// Inputs: V (n×3), F (m×3, counter-clockwise, closed connected manifold), target half-density h_target
/// (m), target areas (m, > 0; used only when options.area_epsilon > 0, may be empty otherwise), options.
/// Output: one spin transformation toward the target. Error naming the bad face / option on bad input.
CurvatureSpinStep curvature_spin_step(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                      const Eigen::VectorXd& h_target, const Eigen::VectorXd& target_area,
                                      const CurvatureSpinOptions& options = {});

struct CurvatureFlow {
  Eigen::MatrixXd V;             ///< n×3 final positions, rescaled to the input's total area
  std::vector<double> willmore;  ///< face Willmore energy (Ye eq. 11) before each step and at the end
  std::vector<double> closure;   ///< per step closure residual
};

/// Optional progress report of the flows below, called after each step with (step 1..steps, steps), on
/// the calling thread. An exception it throws ends the flow and propagates (the Python module's
/// callbacks use this).
using CurvatureProgress = std::function<void(int step, int steps)>;

/// The defaults of curvature_extrusion (a weaker regulariser than fairing's; see below).
inline constexpr CurvatureSpinOptions kExtrusionOptions{.alpha = 0.05};

/// Fairing toward a round sphere (Le Folgoc §6): `steps` steps of δh = −τh (h̄ = (1 − τ) h on the current
/// surface), 0 < τ ≤ 1; with the area constraint, target areas are the input's (A* = A⁰).
CurvatureFlow curvature_fairing(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int steps, double tau,
                                const CurvatureSpinOptions& options = {},
                                const CurvatureProgress& progress = {});

/// Extrusion (Le Folgoc §6, Ye §5.2): from V_sphere (same F) toward the half-density h* and areas A* of
/// V_target, `steps` steps with h̄ = h + (h* − h)/(steps − k) at step k (the last step prescribes h*);
/// the result is rescaled to the target's total area. The ramp keeps each step small, so a weak
/// regulariser reaches the target: spot from its own 6-step faired sphere, 8 steps, mean / max vertex
/// distance after similarity alignment 0.21% / 0.84% of the diagonal with α = 0.05, but 1.1% / 2.0%
/// with α = 0.5 and 3.3% / 6.1% with α = 5 and 12 steps (hence the default below).
CurvatureFlow curvature_extrusion(const Eigen::MatrixXd& V_sphere, const Eigen::MatrixXi& F,
                                  const Eigen::MatrixXd& V_target, int steps,
                                  const CurvatureSpinOptions& options = kExtrusionOptions,
                                  const CurvatureProgress& progress = {});

}  // namespace spinmotor
