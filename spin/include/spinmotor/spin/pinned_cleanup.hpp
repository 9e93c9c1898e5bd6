#pragma once
// Pose-keeping conformal cleanup: make an edit as conformal as possible while some vertices stay
// exactly where the edit put them.
//
// What. Given a rest mesh (V0, F), an edit V1 with the same connectivity (a skinned pose, the output of
// any deformer, a foreign tool that kept the vertex order) and a set P of pinned vertices, return V with
//   1. V_P = V1_P exactly (the pins are Dirichlet values: copied, never solved for),
//   2. the free vertices placed to minimise the discrete as-similar-as-possible (ASAP) energy w.r.t. V0
//      (low quasi-conformal error Q, mesh/metrics/quasi_conformal.hpp),
//   3. the enclosed volume (closed meshes) or the total area (open meshes) equal to the rest mesh's.
// The §7.2 conformal snap (conformal_snap.hpp) finds the nearest spin transformation of the whole edit
// and gives much of a large bend away; here the pins hold the pose (e.g. the rigid parts of a skinned
// limb) and only the free region (the blend band around a joint) is made conformal.
//
// Energy (as-similar-as-possible, ASAP), two kinds of cells mixed with a weight β ∈ [0, 1]:
//   E(V, T) = (1 − β) E_faces + β/2 E_vertices,
//   E_faces    = Σ_f A_f |J_f − T_f|²_F: J_f = Σ_{i∈f} v_i ∇φ_iᵀ the map of face f from its rest plane
//                (3×2 in an orthonormal frame of that plane; A_f the rest area, ∇φ_i the rest hat-function
//                gradients), T_f a similarity of that plane into R³ (Liu et al. 2008, "A local/global
//                approach to mesh parameterization", ASAP; for linear elements E_faces = Σ_f Σ_{ij∈f}
//                ½ cot θ_k |e'_ij − T_f e_ij|²);
//   E_vertices = Σ_i Σ_{j~i} w_ij |e'_ij − s_i R_i e_ij|²: one similarity T_i = s_i R_i (R_i ∈ SO(3)) per
//                vertex for its one-ring spokes, e = rest, e' = current edge vectors, w_ij = −L_ij the
//                cotangent weights of the rest mesh (ARAP surface modelling, Sorkine & Alexa 2007, eq. 3,
//                with a scale per cell).
// (the factor ½ makes both terms 2·area for a unit mismatch). Conformal maps are the zero-energy
// states of both. Why mixed (measured, tests/test_pinned_cleanup.cpp "polish experiment"): a single
// triangle cannot tell a fold (its own normal flipped) from a rotation, so face cells alone fold freely
// (the 90° LBS elbow: Q_mean 1.007 but 28 folded edges, i.e. adjacent normals > 90° apart; the bent
// sausage: 4; a 180° LBS twist: 620), while vertex cells alone also penalise bending (a one-ring's
// spokes leave its plane), which is not conformal distortion: bent sausage Q_mean 1.037 (vertex cells)
// vs 1.029 (β = 0.25) vs 1.018 (faces, folded). β = 0.25 (default) keeps the folds away on the elbow and
// the sausage. Spin view (Crane, Pinkall & Schröder 2011): every T e = conj(λ) e λ for a quaternion λ,
// |λ|² = s (§2), the local step is the best-fit similarity of §7.2 (for a face or a one-ring), and the
// global step is the Poisson problem of §5.6 (Δ f̃ = ∇·ẽ for target edges ẽ = λ̄ e λ, as eq. 8) with
// the pins as boundary values.
//
// Iteration (local/global with a volume or area multiplier), per frame from V = V1:
//   local   faces with a free corner: in frames of the rest plane and of the current triangle's own
//           plane J_f is the 2×2 [a b; c d], T_f = [α −β'; β' α], α = (a + d)/2, β' = (c − b)/2 (its
//           conformal part, the closed form of quasi_conformal.hpp). Vertices with a free vertex in their
//           closed one-ring: S_i = Σ_j w_ij e_ij e'_ijᵀ = U Σ Wᵀ, R_i = W diag(1, 1, det(W Uᵀ)) Uᵀ (via the
//           closed-form eigenvectors of S Sᵀ, Jacobi SVD when rank < 2), s_i = tr(R_i S_i) / Σ_j w_ij
//           |e_ij|². A collapsed face or cell keeps its previous similarity.
//   global  L V = b(T), b_i = (1 − β) Σ_{f∋i} A_f T_f ∇φ_i + β ½ Σ_j w_ij (T_i + T_j)(v⁰_i − v⁰_j) (the
//           divergence of the rotated-scaled rest edges, the ARAP/ASAP right-hand side; L the cotangent
//           Laplacian of the rest mesh for both terms), with V_P = V1_P and ONE linear constraint g·V = c
//           restoring the kept measure to first order around the current V_k:
//             volume  vol(V) = 1/6 Σ_f v0·(v1 × v2), g_i = ∂vol/∂v_i = 1/6 Σ_{f∋i} v_j × v_k
//                     ((i, j, k) the face's corners in counter-clockwise order),
//             area    A(V) = Σ_f ½|e1 × e2|, g_i = ∂A/∂v_i = Σ_{f∋i} ½ n_f × (v_k − v_j) (n_f the unit
//                     normal; over the mesh this is ½ L(V) V, the mean-curvature normal),
//           c = target − measure(V_k) + g·V_k. The KKT system [L_FF g_F; g_Fᵀ 0][V_F; μ] = [b̂_F; c]
//           (b̂ = b − L_FP V1_P) is solved with the factor of L_FF bound once: X_a = L_FF⁻¹ b̂_F,
//           X_g = L_FF⁻¹ g_F (one back-substitution of 6 columns), V_F = X_a − μ X_g with μ such that
//           g·V = c. No refactorisation per iteration or per frame. keep = None drops the constraint.
//   start   (harmonic_start, default) the first global step does not use the similarities fitted to V1
//           in the free region (an LBS elbow folds its inner side, and the fold then takes the
//           iteration 100+ steps to undo): the pinned cells' similarities (quaternion of R, sign-aligned,
//           and log s) are interpolated harmonically over the free vertices (L_FF x_F = −L_FP x_P, the
//           same factor, 5 columns) and that step uses the vertex cells only. 90° elbow, 6k vertices:
//           36 steps to the tolerance; at tolerance 1e-6, 65 steps instead of 155 from V1,
//           the same final Q.
//   accel.  Anderson acceleration of the fixed point x -> G(x) on the free coordinates (Peng et al.
//           2018, "Anderson acceleration for geometry optimization and physics simulation"): x_{k+1} =
//           G_k − ΔG γ, γ = argmin |f_k − ΔF γ|, f = G(x) − x, the last `anderson` differences; a step
//           whose energy rises is replaced by the plain iterate and the history restarts. Affine
//           combinations keep the pins (not part of x) exact; the returned V is a plain iterate.
//   stop    after each local step the energy E_k (normalised by its rest scale, 2 × area) is recorded;
//           stop when |E_k − E_{k−1}| ≤ tolerance · E_k (k ≥ 1), or E_k ≤ 1e-28 (the edit is already
//           conformal there: a similarity of the rest mesh comes back unchanged, no step taken), or after
//           max_iterations global steps. Defaults (1e-4, 100) from the 90° elbow: Q_mean/Q_max 1.025/1.25
//           after 5 steps, 1.015/1.19 after 20, 1.0147/1.163 at the stop (36), unchanged at 150.
//           For a per-frame time budget cap max_iterations: the 90° elbow + 90° twist (6k) reaches
//           Q_max 1.51 at its stop (97 steps) but 2.58 at 40; at 100k vertices (bench_pinned_cleanup,
//           bend 90°) one step costs ~60 ms of CPU, and 10 steps already give Q_mean 1.020, Q_max 1.23.
// Pose attraction (soft pins). Pins hold what they pin, not what lies between: on a rig with soft weights
// (CesiumMan: 62 pins at the default threshold for 2,338 vertices) the free region is most of the body,
// and the conformal optimum drifts from the pose (4% of the diagonal, a stride that closes). An optional
// term holds every free vertex near the edit with a strength of its own:
//   E_a = Σ_{i free} c_i |v_i − v1_i|²,  c_i = γ a_i m_i / A,
// γ = options.pose_weight (dimensionless), a_i ∈ [0, 1] per vertex (bind's `attraction`, e.g. a rig's
// dominant skin weight mapped to 1 on rigid parts and 0 at the joint's centre: rig_pins.hpp
// pin_attraction_from_weights), m_i the barycentric vertex area and A the area of the rest mesh, so that
// E_a is independent of the sampling and of the mesh's scale in the same units as the ASAP energy (for a
// uniform offset of the whole mesh by d: E_a = γ d²). It is a continuous penalty toward the edit, so the
// pins stay exact and everything else trades conformality against pose by γ. The global step becomes
// (L + C) V = b + C V1 (C = diag(c), factorised once at bind instead of L: no cost per frame), the
// energy and stopping rule include E_a, and the harmonic start interpolates the pinned cells'
// similarities by (L + C)_FF x_F = C x̂_F − L_FP x_P, i.e. toward the similarities fitted to the edit
// where it is attracted (x̂) and harmonically where c = 0.
// Warm start (options.warm_start, for animations): consecutive frames of an animation differ little, and
// so do their cleanups' corrections V_out − V_edit. Frame k then starts from V_edit,k + (V_out,k−1 −
// V_edit,k−1) on the free vertices (the pins stay exact) and skips the harmonic start; the stopping rule
// is unchanged. The correction is carried in world coordinates, so a frame that turns the free region far
// from its predecessor (a cut, a jump in time) starts no better than from the edit: reset() between
// shots. Measured (bench_pinned_cleanup "anim" rows, tests/spin/test_pinned_cleanup.cpp "warm start").
// Faces whose three corners are pinned never change and are skipped, so the per-frame cost scales with
// the free region (plus O(n) passes in the Dirichlet solve).
//
// Limits (measured, tests/test_pinned_cleanup.cpp): a twist of the free band by 90° stays near Q_mean
// 1.26 (LBS 1.28): a band twisted between two rigid ends is sheared, not conformal, and the iteration
// finds no better state; a 180° LBS twist (the band collapsed onto the axis) cleans up to Q_mean 1.03
// but keeps a few folded edges (Q_max 2.4).
//
// Inputs: bind(rest, pins): rest mesh (triangles, no degenerate face; closed for keep = Volume), pins
// (vertex indices; order and repeats do not matter). cleanup(V_edit, V_out): V_edit n×3 finite.
// Outputs: V_out (n×3, resized only when its size is wrong) and a PinnedCleanupResult.
// Errors (spinmotor::Error, BadInput): empty pins, a pin out of range (naming its position and value),
// a connected component of the mesh without a pin (naming it and one of its vertices: its free
// vertices would have no anchor), keep = Volume on a mesh with boundary, a degenerate rest face (naming
// it), V_edit of the wrong size or with a non-finite coordinate (naming the vertex). Numerical: the
// factorisation failed.
#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/fit/local_global.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// Which global measure the cleanup keeps at its rest value.
enum class CleanupKeep {
  Auto,    ///< Volume for a closed mesh, Area for a mesh with boundary (default)
  Volume,  ///< enclosed volume (closed meshes only)
  Area,    ///< total surface area
  None,    ///< no constraint (plain ASAP with pins)
};
inline constexpr OptionNames<CleanupKeep, 4> kCleanupKeepNames{"keep",
                                                               {{{CleanupKeep::Auto, "auto"},
                                                                 {CleanupKeep::Volume, "volume"},
                                                                 {CleanupKeep::Area, "area"},
                                                                 {CleanupKeep::None, "none"}}}};
constexpr const auto& option_names(CleanupKeep) { return kCleanupKeepNames; }

struct PinnedCleanupOptions {
  CleanupKeep keep = CleanupKeep::Auto;
  /// β ∈ [0, 1]: the energy is (1 − β) E_faces + β/2 E_vertices (header comment); 0 = face cells only.
  double vertex_cell_weight = 0.25;
  int max_iterations = 100;  ///< global steps per frame (≥ 1)
  double tolerance = 1e-4;   ///< relative energy change that stops the iteration (> 0)
  /// Anderson acceleration depth (differences kept; 0 = plain local/global). See the header comment.
  int anderson = 5;
  /// First global step from the pinned cells' similarities interpolated harmonically over the free
  /// vertices instead of those fitted to the edit (header comment).
  bool harmonic_start = true;
  /// γ ≥ 0: strength of the pose attraction E_a = γ/A Σ_i a_i m_i |v_i − v1_i|² that holds the free
  /// vertices near the edit (header comment, "Pose attraction"); 0 (default) = pins only.
  double pose_weight = 0;
  /// Animations: start each frame from the previous frame's result carried along with the edit,
  /// V = V_edit + (V_out_prev − V_edit_prev) on the free vertices, instead of the harmonic start (header
  /// comment, "Warm start"). The first frame, and the first after reset(), starts as usual.
  bool warm_start = false;
  /// Record the area-weighted Q_mean of the whole mesh after every global step (result.q_mean);
  /// costs one pass over all faces per iteration, for convergence reports.
  bool record_quasi_conformal = false;
};

/// One frame: the local/global solve's report (fit/local_global.hpp: iterations, converged, the
/// normalised energy E_k after each local step, phase times, fallback fits: collapsed faces and cells,
/// rejected accelerations) and the cleanup's own figures.
struct PinnedCleanupResult : fit::SolveReport {
  bool all_pinned = false;               ///< every vertex is pinned: V_out = V_edit, nothing solved
  CleanupKeep kept = CleanupKeep::None;  ///< the measure actually constrained (Auto resolved)
  std::vector<double> q_mean;            ///< Q_mean after each global step (record_quasi_conformal only)
  double rest_measure = 0;               ///< rest volume (Volume) or area (Area, None: area)
  double edit_measure = 0;               ///< the same measure of V_edit
  double measure = 0;                    ///< the same measure of V_out
  double measure_ratio() const { return rest_measure != 0 ? measure / rest_measure : 1.0; }
  double pin_error = 0;  ///< max |V_out(p) − V_edit(p)| over pins / bounding-box diagonal of V_edit (0)
  double total_ms = 0;   ///< whole cleanup() call
};

class PinnedCleanup {
 public:
  PinnedCleanup();
  ~PinnedCleanup();
  PinnedCleanup(PinnedCleanup&&) noexcept;
  PinnedCleanup& operator=(PinnedCleanup&&) noexcept;

  /// Bind once per rest mesh and pin set: validation, rest gradients and areas, the cotangent
  /// Laplacian of the rest mesh and the Cholesky factor of its free block (DirichletSolver). Errors as
  /// in the header comment.
  /// attraction: the per-vertex a_i ∈ [0, 1] of the pose attraction (n values; empty = all 1; read
  /// only when options.pose_weight > 0).
  static PinnedCleanup bind(const Mesh& rest, std::span<const int> pins,
                            const PinnedCleanupOptions& options = {},
                            std::span<const double> attraction = {});
  static PinnedCleanup bind(const Mesh& rest, const Eigen::VectorXi& pins,
                            const PinnedCleanupOptions& options = {},
                            const Eigen::VectorXd& attraction = Eigen::VectorXd());

  /// One frame. Inputs: V_edit (n×3). Output: V_out (n×3; pins copied bit for bit from V_edit). Keeps
  /// its scratch in the object (one cleanup at a time per object); no factorisation.
  PinnedCleanupResult cleanup(const Eigen::MatrixXd& V_edit, Eigen::MatrixXd& V_out);

  /// Forget the previous frame (warm_start): the next cleanup() starts as a first frame.
  void reset() noexcept;

  Eigen::Index vertices() const;
  const Eigen::VectorXi& pins() const;           ///< sorted, without repeats
  const Eigen::VectorXi& free_vertices() const;  ///< the others, increasing
  bool closed() const;                           ///< the rest mesh has no boundary edge
  CleanupKeep keep() const;                      ///< Auto resolved
  double bind_ms() const;
  const PinnedCleanupOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Pin file (UTF-8 text): 0-based vertex indices separated by white space, usually one per line; '#'
/// starts a comment, blank lines are skipped. Output: the indices in file order. Throws Error "path:line:
/// ..." for a token that is not a non-negative integer or an index ≥ n, "path: ..." for a file that cannot be
/// read or lists no index.
Eigen::VectorXi read_pin_file(const std::filesystem::path& path, Eigen::Index n);

}  // namespace spinmotor
