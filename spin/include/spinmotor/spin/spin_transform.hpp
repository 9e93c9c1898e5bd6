#pragma once
// Spin transformations of triangle meshes (Crane, Pinkall & Schröder 2011, §5): given a change ρ of
// mean curvature half-density per face, find the similarity field λ (n×4 quaternions, real part
// first) of the eigenproblem nearest (D − ρ)λ = 0, integrate the transformed edges (eq. 8) by a
// Poisson solve (§5.6), and normalise.
//
// Two steps, so that an interactive tool can call solve() for many ρ on one mesh:
//   bind   (constructor)  validate the mesh; per-face geometry, topology, vertex ordering and the
//                         symbolic Cholesky analysis of the 4×4-block eigen matrix (its pattern does not
//                         depend on ρ); the cotangent Laplacian with one vertex pinned, factored once.
//   solve(ρ)              assemble A*A for this ρ into the analysed pattern, factor it numerically
//                         (CHOLMOD), inverse iteration to the smallest eigenpair, transformed edges,
//                         Poisson solve with the stored factor, normalisation.
//
// Eigenproblems (SpinEigenProblem):
//   Standard     (AV)*(AV) λ̂ = γ λ̂, λ = V λ̂, V = M_V^{-1/2} rescaled to mean 1          (eq. 7; default)
//   Generalized  A*A λ = γ B*A λ, the eigenvalue of smallest |γ|                            (eq. 6; closed
//   meshes) Unweighted   A*A λ = γ λ: what the SpinXForm reference code iterates on (no M_V; this
//                matched bumpy_reference.obj, see tests/test_spin.cpp)
// The smallest eigenpair is found by inverse iteration on ONE factorization of the left-hand side
// (plus a relative shift of 1e-8 of its mean diagonal, so that the ρ = 0 case, whose kernel is the
// constants, factors), iterated until the eigen-residual ‖Kx − θx‖/‖Kx‖ (x normalised, K the shifted
// matrix; for (6) ‖Kx − θGx‖/‖Kx‖) is below `tolerance` — or has stalled below 1e-6 at its roundoff
// floor ε‖K‖/θ, as when the eigenvalue is at the shift (ρ = 0) — or for exactly `iterations` steps
// when `fixed_iterations` (SpinXForm runs 3 from the all-ones real quaternions, without a test).
// By default the iterates are combined by Rayleigh–Ritz (`krylov`), which needs about half the
// solves of plain inverse iteration; of a multiple eigenvalue it returns the start vector's
// projection, as plain inverse iteration would.
//
// Boundary conditions (§5.7): at listed boundary vertices the target tangent T̃ replaces the 4
// unknowns by 2, λ_i = W_i (a + b T̃_i), with W_i the rotation taking the source tangent T_i (the unit
// outgoing boundary edge, surface on the left) to T̃_i under v ↦ W̄ v W. Other boundary vertices are free.
//
// Reconstruction (§5.6): ẽ_ij of eq. 8 on every edge, then L f̃ = ∇·ẽ with the cotangent Laplacian
// L (mesh/cotangent_laplacian.hpp) and one vertex pinned, then normalisation (SpinScale). The
// reference code pins the last vertex; any pinned vertex gives the same solution up to a translation,
// which the normalisation removes, so the last vertex of the fill-reducing order is pinned. L and its
// CHOLMOD factor do not depend on ρ: they are prepared on a second thread during bind, overlapping
// the eigen matrix's analysis and (in a one-shot run) its factorization.
#include <Eigen/Core>
#include <memory>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/dirac_assembly.hpp"

namespace spinmotor {

/// The eigenproblem (CLI `--problem`, Python `problem=`): Standard is eq. 7, Generalized eq. 6, Unweighted
/// A*A λ = γ λ (the reference code's).
enum class SpinEigenProblem { Standard, Generalized, Unweighted };
inline constexpr OptionNames<SpinEigenProblem, 3> kSpinEigenProblemNames{
    "problem",
    {{{SpinEigenProblem::Standard, "standard"},
      {SpinEigenProblem::Generalized, "generalized"},
      {SpinEigenProblem::Unweighted, "unweighted"}}}};
constexpr const auto& option_names(SpinEigenProblem) { return kSpinEigenProblemNames; }

enum class SpinScale {
  KeepArea,     ///< scale to the input's total area, translate to the input's vertex mean (default)
  UnitMaxNorm,  ///< SpinXForm: centre the vertex mean at the origin, then max |v| = 1
  None,         ///< the Poisson solution translated to the input's vertex mean
};
inline constexpr OptionNames<SpinScale, 3> kSpinScaleNames{
    "scale", {{{SpinScale::KeepArea, "area"}, {SpinScale::UnitMaxNorm, "unit"}, {SpinScale::None, "none"}}}};
constexpr const auto& option_names(SpinScale) { return kSpinScaleNames; }

/// Prescribed target tangents at boundary vertices (§5.7).
struct SpinBoundaryTangents {
  Eigen::VectorXi vertices;  ///< k boundary vertices
  Eigen::MatrixXd targets;   ///< k×3 target tangent directions T̃ (normalised on input; nonzero)
};

struct SpinTransformOptions {
  SpinEigenProblem problem = SpinEigenProblem::Standard;
  double tolerance = 1e-10;       ///< eigen-residual at which inverse iteration stops (see above)
  int iterations = 50;            ///< maximum inverse iterations (exact count when fixed_iterations)
  bool fixed_iterations = false;  ///< run exactly `iterations` steps with no test (SpinXForm: 3)
  /// Rayleigh–Ritz on all iterates (the Krylov space of the inverse; same solves, Lanczos-rate
  /// convergence) instead of plain inverse iteration. Not used with fixed_iterations.
  bool krylov = true;
  SpinScale scale = SpinScale::KeepArea;
  /// Fill-reducing ordering of the vertex graph. METIS costs more than AMD to compute but its factor
  /// needs 10–40% fewer flops; in bench_spin it lowered the total on all meshes (8k–400k faces).
  Ordering ordering = Ordering::METIS;
  /// Baseline only: leave the vertices in input order and let CHOLMOD order the 4n×4n matrix itself
  /// with `ordering` (what a generic sparse Cholesky does); slower, kept for the benchmarks.
  bool order_full_matrix = false;
  bool supernodal = true;  ///< CHOLMOD supernodal LLᵀ (else simplicial)
  /// Factor the complex Hermitian 2n×2n form of the eigen matrix (dirac_assembly.hpp) instead of the
  /// real 4n×4n one: same eigenpairs, ~3× faster factorization. Ignored (real form) with boundary
  /// tangents, whose reduced unknowns are not a complex subspace.
  bool complex_form = true;
  SpinBoundaryTangents boundary;  ///< empty: natural boundary conditions

  /// The reference code's settings: Unweighted problem, exactly 3 inverse iterations from the
  /// all-ones real quaternions, output centred with max |v| = 1 (the last vertex is always pinned).
  static SpinTransformOptions spinxform() {
    SpinTransformOptions o;
    o.problem = SpinEigenProblem::Unweighted;
    o.iterations = 3;
    o.fixed_iterations = true;
    o.scale = SpinScale::UnitMaxNorm;
    return o;
  }
};

/// Timings in milliseconds (wall clock).
struct SpinTimings {
  double bind = 0;           ///< constructor: validation, geometry, ordering, symbolic analysis
  double poisson_setup = 0;  ///< cotangent Laplacian + its factor, on the bind's second thread (overlapped)
  double assembly = 0;       ///< A*A (and B*A) for this ρ
  double factor = 0;         ///< numeric Cholesky factorization
  double eigen = 0;          ///< inverse iterations
  double poisson = 0;        ///< waiting for poisson_setup (first solve only), transformed edges, divergence,
                             ///< solve, normalisation
  double solve_total() const { return assembly + factor + eigen + poisson; }
};

struct SpinTransformResult {
  Eigen::MatrixXd V;       ///< n×3 new positions
  Eigen::MatrixXd lambda;  ///< n×4 similarity field (real part first), normalised to unit 2-norm
  /// Smallest eigenvalue of the problem solved: γ of eq. 6 (Generalized); γ of A*Aλ = γ M_V λ, i.e.
  /// eq. 7 with the mean-1 rescaling undone (Standard; it approximates the square of the shift γ of
  /// eq. 4, units 1/length²); γ of A*A λ = γ λ (Unweighted).
  double eigenvalue = 0;
  int iterations = 0;   ///< inverse iterations performed
  double residual = 0;  ///< eigen-residual after the last iteration
  SpinTimings timings;
};

class SpinTransform {
 public:
  /// Bind. Inputs: mesh (V n×3, F m×3 counter-clockwise; UV unused), options. The mesh must be a
  /// connected, oriented manifold with no degenerate faces, no unreferenced and no non-finite
  /// vertices (Error naming the first offender); the Generalized problem needs a closed mesh; boundary
  /// tangents must name distinct boundary vertices with nonzero targets.
  SpinTransform(const Mesh& mesh, const SpinTransformOptions& options = {});
  ~SpinTransform();
  SpinTransform(SpinTransform&&) noexcept;
  SpinTransform& operator=(SpinTransform&&) noexcept;

  /// Inputs: rho (m, finite). Output: the transformed mesh positions and diagnostics. Throws Error on
  /// a bad ρ, numerical_error if a factorization fails or the result is not finite.
  SpinTransformResult solve(const Eigen::VectorXd& rho);

  /// solve(ρ) without the reconstruction: λ, eigenvalue, iterations, residual and the assembly /
  /// factor / eigen timings; V is left empty and timings.poisson is 0. For callers that change λ
  /// before integrating it (the conformal snap's tradeoff, conformal_snap.hpp).
  SpinTransformResult solve_similarity(const Eigen::VectorXd& rho);

  /// The reconstruction of solve() alone (§5.6) for ANY similarity field: eq. 8 edges of `lambda`
  /// (n×4, real part first, finite), the Poisson solve with the bound Laplacian factor (no
  /// refactorization), then the normalisation options().scale (with SpinScale::None the scale and
  /// orientation carried by λ are kept). Output: n×3 positions; `ms` (optional) receives the wall
  /// time. Throws Error on a wrong size or a non-finite row (naming the vertex).
  Eigen::MatrixXd reconstruct(const Eigen::MatrixXd& lambda, double* ms = nullptr);

  const SpinTransformOptions& options() const;
  double bind_ms() const;
  Eigen::Index num_unknowns() const;
  /// Nonzeros of the Cholesky factor of the eigen matrix (predicted by the symbolic analysis).
  double factor_nonzeros() const;

 private:
  SpinTransformResult solve_impl(const Eigen::VectorXd& rho, bool reconstruct_positions);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot: SpinTransform(mesh, options).solve(rho).
SpinTransformResult spin_transform(const Mesh& mesh, const Eigen::VectorXd& rho,
                                   const SpinTransformOptions& options = {});

/// Similarity field → transformed edge vectors, eq. 8. Inputs: V (n×3), E (k×2 edges), lambda (n×4).
/// Output: k×3, row e = ẽ for the edge from E(e,0) to E(e,1).
Eigen::MatrixXd transformed_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E,
                                  const Eigen::MatrixXd& lambda);

}  // namespace spinmotor
