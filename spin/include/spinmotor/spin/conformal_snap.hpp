#pragma once
// Conformal snap: the nearest spin transformation of an arbitrary deformation (Crane, Pinkall &
// Schröder 2011, §7.2, Figs 4, 14, 18, 19, 21).
//
// Given a rest mesh (V, F) and edited positions V' with the same connectivity (any deformer of the
// project, or a foreign tool that kept the vertex order):
//   1. best-fit similarity per face (§7.2): rotate both triangles into a common plane (A₁, A₂), take
//      the map B between the planar triangles, B = RY its polar decomposition, and
//      S = sqrt(det Y) A₂⁻¹ R A₁; as a quaternion μ_f with S v = conj(μ_f) v μ_f (|μ_f|² = sqrt(det Y));
//   2. average to the vertices with consistent signs (q and −q are the same similarity: signs are
//      propagated face to face across edges first, then aligned at each vertex) → μ (n×4);
//   3. the optimal ρ_f = Re(conj((Bμ)_f)(Dμ)_f)/|(Bμ)_f|² (§7.2), the ρ minimising |(D − ρB)μ|²;
//   4. λ of the spin transformation for that ρ (spin_transform.hpp), eq. 7 by default (see below);
//   5. tradeoff t (Fig. 21): λ_t = (1 − t) μ + t λ̂, λ̂ = λ q with the quaternion q minimising
//      Σ_i M_i |λ_i q − μ_i|² (λq solves whatever λ solves: it is λ followed by a similarity, so this
//      aligns the sign, scale and rotation of λ with μ before interpolating); t = 1 is the spin
//      transformation, t = 0 the edit's own similarity field;
//   6. reconstruction: eq. 8 edges + Poisson (§5.6) with the factor bound once per rest mesh;
//   7. alignment to the edit: the best similarity (Umeyama), the best translation, or none.
// Surfaces with boundary use §5.7 with the target tangents taken from the edit (the unit outgoing
// boundary edge of V' at every boundary vertex), as in §7.4's Fig. 15. Those tangents change with
// every edit and enter the eigen matrix's unknowns, so with boundary_tangents each snap of an open
// mesh binds a new SpinTransform (the closed case binds once).
//
// Why the Standard problem (eq. 7) is the default although the paper found eq. 6 "more robust" here:
// with the optimal ρ of step 3 the residual (D − ρB)μ is orthogonal to Bμ on every face, so
// μ*(B*A)μ = Σ_f A_f Re(conj(Bμ)_f (Dμ − ρBμ)_f) = 0 exactly. The generalized problem A*Aλ = γB*Aλ
// therefore has no reason to return an eigenvector near μ: B*A is indefinite and μ sits on its null
// cone. Measured on an exact spin transformation (tests/test_snap.cpp, smooth ρ of amplitude 0.1 on a
// unit icosphere of level 3): eq. 7 returns it to 1.2e-4 of the bounding-box diagonal (RMS; max
// 2.7e-4, Q_mean 1.0061 as the original), eq. 6 misses it by 0.26 (RMS; max 0.42, Q_mean 2.15).
// Eq. 7 minimises |Aλ|² over mass-normalised λ, which for an exact spin transformation is μ itself
// up to discretisation (|Aμ| ≈ 0), so it cannot miss it.
//
// Limits (bench_snap's pose-retention study). The snap is the nearest spin transformation in the
// least-squares sense of ρ and gives up much of a large bend: a sausage bent to 60° between its end
// axes keeps 28° at t = 1 (Q_mean 1.149 → 1.008), 43° at t = 0.5. An edit with a crease (a 90° two-
// bone linear-blend-skinned elbow, Q_max 30) gives ρ spikes (|ρ| up to 68 where the mean is 0.23),
// and the spin transformation of a spiky ρ is not conformal on the mesh (Q_mean 1.41 at t = 1), and
// the global alignment of λ with μ is then too coarse for a linear blend (t = 0.5 overshoots the
// bend). rho_smoothing helps Q (40 passes: 1.06, below the edit's 1.127) but not the pose.
#include <Eigen/Core>
#include <memory>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace spinmotor {

/// What "snap" does to an edit (CLI `snap --mode`, the scene's snap block, the viewer):
///   Free    the nearest spin transformation of the whole edit (§7.2, ConformalSnap below);
///   Shape   Le Folgoc et al. 2019: extrusion from the rest mesh toward the edit's curvature
///           (curvature_spin_flow.hpp);
///   Pinned  the pose-keeping cleanup: pinned vertices stay where the edit put them, the rest is made
///           as conformal as possible at the rest volume (pinned_cleanup.hpp).
/// "spin" is the former name of Free, still accepted.
enum class SnapMode { Free, Shape, Pinned };
inline constexpr OptionNames<SnapMode, 4> kSnapModeNames{"snap mode",
                                                         {{{SnapMode::Free, "free"},
                                                           {SnapMode::Free, "spin"},
                                                           {SnapMode::Shape, "shape"},
                                                           {SnapMode::Pinned, "pinned"}}}};
constexpr const auto& option_names(SnapMode) { return kSnapModeNames; }

/// How the snapped mesh is placed onto the edit (CLI `snap --align`, Python `alignment=`).
enum class SnapAlignment {
  Similarity,   ///< best rotation + uniform scale + translation (Umeyama) onto V' (default)
  Translation,  ///< vertex means matched; rotation and scale are those of λ aligned with μ
  None,         ///< the reconstruction with λ aligned with μ, vertex mean at the rest mesh's
};
inline constexpr OptionNames<SnapAlignment, 3> kSnapAlignmentNames{
    "snap alignment",
    {{{SnapAlignment::Similarity, "similarity"},
      {SnapAlignment::Translation, "translation"},
      {SnapAlignment::None, "none"}}}};
constexpr const auto& option_names(SnapAlignment) { return kSnapAlignmentNames; }

struct ConformalSnapOptions {
  /// Standard (eq. 7, default) or Generalized (eq. 6, closed meshes only); see the header comment.
  SpinEigenProblem problem = SpinEigenProblem::Standard;
  double tradeoff = 1.0;  ///< t ∈ [0, 1]: 0 follows the edit (μ), 1 is conformal (λ); Fig. 21
  SnapAlignment alignment = SnapAlignment::Similarity;
  /// Open meshes: prescribe the edit's boundary tangents (§5.7); else natural boundary conditions.
  bool boundary_tangents = true;
  /// Passes of area-weighted averaging of ρ over each face and its edge neighbours before the eigen
  /// solve (0: the exact §7.2 ρ). For edits with creases, whose ρ has spikes (§7.1: "ρ should not
  /// contain any large spikes"); it moves the snap away from an exact spin transformation.
  int rho_smoothing = 0;
  double tolerance = 1e-10;  ///< eigen-residual of the inverse iteration (spin_transform.hpp)
  int iterations = 50;       ///< maximum inverse iterations
  Ordering ordering = Ordering::METIS;
};

/// Wall-clock times in milliseconds of one snap.
struct SnapTimings {
  double similarity_fit = 0;  ///< per-face similarities, vertex averages, optimal ρ
  double bind = 0;     ///< SpinTransform bind inside this snap (open meshes with boundary tangents only)
  double eigen = 0;    ///< assembly + numeric factorization + inverse iteration
  double poisson = 0;  ///< tradeoff blend, eq. 8 edges, Poisson solve, alignment to the edit
  double total() const { return similarity_fit + bind + eigen + poisson; }
};

struct ConformalSnapResult {
  Eigen::MatrixXd V;       ///< n×3 snapped positions (aligned to the edit as asked)
  Eigen::VectorXd rho;     ///< m optimal ρ of §7.2 (after rho_smoothing; units 1/length of the rest mesh)
  Eigen::MatrixXd mu;      ///< n×4 vertex similarities of the edit (real part first)
  Eigen::MatrixXd lambda;  ///< n×4 spin transformation's similarity field, aligned with mu (λ̂ above)
  double eigenvalue = 0;   ///< smallest eigenvalue of the problem solved (SpinTransformResult)
  int iterations = 0;      ///< inverse iterations
  double residual = 0;     ///< eigen-residual
  Eigen::Index collapsed_faces = 0;  ///< edited faces of zero area (no similarity; weight 0 in step 2)
  Similarity alignment;              ///< transform applied to the reconstruction in step 7
  SnapTimings timings;
};

/// Step 1. Inputs: V_rest (n×3), F (m×3, counter-clockwise), V_edit (n×3). Output: m×4 quaternions μ_f
/// (real part first) with S_f v = conj(μ_f) v μ_f the best-fit similarity of face f (§7.2). A face
/// collapsed in the edit (|e1×e2| ≤ 16 ε ℓ²max) gets the zero quaternion; `collapsed` (optional)
/// receives their number. Throws Error on mismatched sizes, non-finite coordinates (naming vertex
/// and component) or a degenerate rest face (naming it).
Eigen::MatrixXd best_fit_similarities(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                      const Eigen::MatrixXd& V_edit, Eigen::Index* collapsed = nullptr);

/// Step 2. Inputs: F (m×3), n, face quaternions Sf (m×4, any signs; zero rows are skipped), face
/// weights (m, ≥ 0, e.g. rest areas). Output: n×4 weighted vertex averages after sign alignment
/// (face signs propagated across edges from face 0 of each component, then each incident face
/// aligned with the vertex's first one, then the field's global sign fixed so that its first nonzero
/// summed component is positive): flipping the sign of any rows of Sf gives the same output.
/// Throws Error naming a vertex with no face of nonzero weight.
Eigen::MatrixXd vertex_similarities(const Eigen::MatrixXi& F, Eigen::Index n, const Eigen::MatrixXd& Sf,
                                    const Eigen::VectorXd& face_weights);

/// Step 3. Inputs: V (n×3 rest), F (m×3), mu (n×4). Output: m values
/// ρ_f = Re(conj((Bμ)_f)(Dμ)_f)/|(Bμ)_f|² (§7.2; D of eq. 5, B of §5.3). Throws numerical_error naming a
/// face where Bμ vanishes.
Eigen::VectorXd nearest_rho(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& mu);

class ConformalSnap {
 public:
  /// Bind. Inputs: rest mesh (connected oriented manifold, no degenerate faces or unreferenced
  /// vertices; closed for the Generalized problem), options (tradeoff in [0, 1], finite). Closed
  /// meshes, or open ones without boundary_tangents: the SpinTransform (vertex ordering, symbolic
  /// analysis of the eigen matrix, cotangent Laplacian factor) is bound here, once.
  explicit ConformalSnap(const Mesh& rest, const ConformalSnapOptions& options = {});
  ~ConformalSnap();
  ConformalSnap(ConformalSnap&&) noexcept;
  ConformalSnap& operator=(ConformalSnap&&) noexcept;

  /// Inputs: V_edit (n×3, finite, same vertex order as the rest mesh). Output: the snap. Throws
  /// Error on a wrong size or a non-finite coordinate (naming vertex and component).
  ConformalSnapResult snap(const Eigen::MatrixXd& V_edit);
  /// Same with the per-face similarities given (m×4, e.g. best_fit_similarities with any sign flips).
  ConformalSnapResult snap_face_similarities(const Eigen::MatrixXd& Sf, const Eigen::MatrixXd& V_edit);

  const ConformalSnapOptions& options() const;
  void set_tradeoff(double t);  ///< Error unless t ∈ [0, 1]
  double bind_ms() const;       ///< time of the constructor
  const Mesh& rest() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot: ConformalSnap(rest, options).snap(V_edit).
ConformalSnapResult conformal_snap(const Mesh& rest, const Eigen::MatrixXd& V_edit,
                                   const ConformalSnapOptions& options = {});

}  // namespace spinmotor
