#pragma once
// ArapDeformer: as-rigid-as-possible surface modeling (Sorkine & Alexa 2007; CGA paper §VII, eqs 9–13)
// with handle regions moved by motors. Follows the bind/pose contract of deformer.hpp.
//
// Energy (eqs. 9–10 with unit cell weights): E(X', R) = Σ_i Σ_{(u,v) ∈ C_i} w_uv |e'_uv − R_i e_uv|²,
// e = rest and e' = deformed edge vectors, R_i the rotor of cell C_i (eq. 11), with
//   Spokes          (the paper's eq. 9) C_i = the edges (i, j) of the one-ring, w_ij the cotangent
//                   weight ½(cot α_ij + cot β_ij) (= −L_ij of cotangent_laplacian.hpp);
//   SpokesAndRims   (Chao et al. 2010; libigl's default for triangle meshes) C_i = the three edges of
//                   every face around i, each with its face's ½ cot of the opposite angle.
// Both energies have the same global (Poisson) matrix: ∂E/∂X' = 0 is L X' = B(R) with L the
// cotangent Laplacian (eq. 12), B_i = ½ Σ_j w_ij (R_i + R_j) e_ij (spokes) or
// B_i = ⅓ Σ_{faces t ∋ i} (R_t0 + R_t1 + R_t2) Σ_{edges (i,j) of t} c_t,ij e_ij (spokes and rims).
//
// Cotangent weights can be negative (obtuse angles). Default: kept (as libigl does). L stays positive
// semi-definite whatever their signs (it is the stiffness matrix of linear finite elements), so the
// global step is still an exact minimisation and the energy never increases; but a cell energy with a
// negative weight is not a sum of squares any more, and E can in principle become negative on very
// obtuse meshes. `clamp_negative_weights` replaces every negative weight by 0 (per edge for spokes, per
// face corner for spokes-and-rims; the global matrix is assembled from the same clamped weights, so
// monotonicity holds exactly as well); a vertex whose weights all clamp to 0 then floats and the
// factorization reports it.
//
// Iteration: rigid cells and handles on the local/global layer (fit/cells.hpp RigidCells,
// fit/local_global.hpp LocalGlobal, §VII):
//   local   per vertex (parallel, allocation-free) the covariance S_i = Σ w e e'ᵀ and its best rotor
//           by Horn's method (ga/rotor_fit.hpp), warm-started from the rotor of the previous iteration
//           (or of the previous pose); the energy of the current positions, E(X'_k) = min_R E(X'_k, R),
//           comes out of the same pass (cell by cell: Σ w|e'|² + Σ w|e|² − 2 tr(R_i S_i), evaluated
//           term by term instead when that difference cancels, so that a rigid motion gives ~1e-30,
//           not roundoff of the terms).
//   global  L_FF X'_F = B_F − L_FC X'_C: the handle vertices C are eliminated (hard constraints,
//           eq. 13 with the constrained rows and columns removed); L_FF is factorized once per handle
//           set at bind (CholeskySolver: CHOLMOD) and the three coordinates are solved together; the
//           handles' share L_FC X'_C is computed once per pose.
// Stopping: the layer's rule (relative energy change ≤ tolerance, or E_k zero to roundoff: ≤ 1e-24 of
// the rest-edge scale Σ w |e|²), or after `iterations` global steps. The report lists E_0 (initial
// guess) … E_k: non-increasing (each step minimises exactly; ties to roundoff).
//
// Handles: pose() takes one unit motor per handle; the handle's vertices are placed at M p ~M (the
// whole region moves rigidly). Vertices that no face references are kept at their rest position
// (or moved by their handle). Every connected component of the mesh needs a handle vertex, otherwise
// its position is undetermined: bind throws Error naming the component (index, size, a vertex), e.g.
// for ogre.obj's 44 components. Degenerate faces are rejected by require() (naming the face).
//
// Initial guess of each pose (default Harmonic):
//   Rest      rest positions with the handles placed;
//   Harmonic  surface harmonic coordinates (CGA paper §IV) blending the handle motors, exp(Σ λ_j log M_j),
//             with the same cotangent Laplacian (λ solved with the ARAP factorization: k extra right-hand
//             sides at bind, no second factorization): fewer iterations for large rotations (measured:
//             90° bends, 176 instead of 324 iterations to 1e-7 on a bar, 392 instead of 1146 to 1e-5 on
//             a 10k tube), not always at moderate ones (a 60° turn of a tube: 60 instead of 50);
//   Previous  the previous pose's result with the handles re-placed (Rest on the first pose): for
//             interactive or animated posing.
#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/deform/deformer.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"
#include "spinmotor/fit/cells.hpp"
#include "spinmotor/fit/local_global.hpp"
#include "spinmotor/linalg/dirichlet_solver.hpp"
#include "spinmotor/linalg/ordering.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

enum class ArapEnergy { Spokes, SpokesAndRims };
enum class ArapInitial { Rest, Harmonic, Previous };
inline constexpr OptionNames<ArapEnergy, 2> kArapEnergyNames{
    "energy", {{{ArapEnergy::Spokes, "spokes"}, {ArapEnergy::SpokesAndRims, "spokes-and-rims"}}}};
constexpr const auto& option_names(ArapEnergy) { return kArapEnergyNames; }
inline constexpr OptionNames<ArapInitial, 3> kArapInitialNames{"initial",
                                                               {{{ArapInitial::Rest, "rest"},
                                                                 {ArapInitial::Harmonic, "harmonic"},
                                                                 {ArapInitial::Previous, "previous"}}}};
constexpr const auto& option_names(ArapInitial) { return kArapInitialNames; }

/// What the last pose() did: the local/global solve's report (fit/local_global.hpp: energies E(X'_0)
/// (initial guess), E(X'_1), …, iterations, converged, local and global step times, fallback fits: the
/// rotor fits that took the Jacobi path) and the time of the initial guess.
struct ArapReport : fit::SolveReport {
  double initial_ms = 0.0;  ///< placing the handles and the initial guess
};

/// Where bind() spent its time (ms).
struct ArapBindReport {
  double weights_ms = 0.0;   ///< cotangent Laplacian (and face cotangents)
  double cells_ms = 0.0;     ///< per-cell coefficients (one-ring CSR, rims)
  double factor_ms = 0.0;    ///< component check, extraction of L_FF and its factorization
  double harmonic_ms = 0.0;  ///< harmonic coordinates of the handles (initial = Harmonic)
  std::string ordering;      ///< "amd" or "nested-dissection" (the one factorized)
  bool supernodal = false;   ///< supernodal or simplicial factorization
  double factor_nonzeros = 0.0, factor_flops = 0.0;  ///< of the Cholesky factor of L_FF
};

class ArapDeformer {
 public:
  using RowMatrix3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  struct Options {
    ArapEnergy energy = ArapEnergy::SpokesAndRims;
    bool clamp_negative_weights = false;
    int iterations = 100;     ///< at most this many global steps per pose (≥ 0)
    double tolerance = 1e-6;  ///< relative energy change that stops the iteration (≥ 0)
    /// Harmonic by default: handles moved by one rigid motion then give that rigid motion at once
    /// (from Rest, 30 iterations leave a tube visibly non-rigid); Rest skips the k extra solves at bind.
    ArapInitial initial = ArapInitial::Harmonic;
    /// Factorization of L_FF (CHOLMOD). Auto: simplicial LDLᵀ up to kSupernodalFrom free vertices
    /// (its three-column solves are faster, which pays off after a few iterations), supernodal LLᵀ
    /// above (its factorization is much faster at 1M). Figures: docs/performance.md, "ARAP".
    enum class Factorization { Auto, Simplicial, Supernodal };
    Factorization factorization = Factorization::Auto;
    static constexpr Eigen::Index kSupernodalFrom = 300'000;
    /// Fill-reducing ordering of L_FF (ordering.hpp): auto, amd or nested-dissection (others: Error).
    /// Auto: both AMD and a geometric nested dissection (recursive median splits of the free vertices
    /// along their longest axis, the shorter boundary as separator) are analysed and the one with
    /// fewer factorization flops is used (AMD wins on scanned meshes, nested dissection on long tubes:
    /// docs/performance.md, "ARAP").
    using Ordering = spinmotor::Ordering;
    static constexpr Ordering kOrderings[] = {Ordering::Auto, Ordering::AMD, Ordering::NestedDissection};
    Ordering ordering = Ordering::Auto;
  };

  ArapDeformer() = default;
  ArapDeformer(ArapDeformer&&) noexcept = default;
  ArapDeformer& operator=(ArapDeformer&&) noexcept = default;

  /// Inputs: rest mesh (V n×3, F m×3), k ≥ 1 disjoint handles (check_handles), options.
  /// Precomputes the weights, the per-cell coefficients, the factorization of L_FF (and, for the
  /// harmonic initial guess, the harmonic coordinates). Throws Error (BadInput) for a degenerate face,
  /// bad handles, a component without a handle or bad options; Numerical if the factorization fails.
  static ArapDeformer bind(const Mesh& rest, std::span<const Handle> handles, const Options& options);
  static ArapDeformer bind(const Mesh& rest, std::span<const Handle> handles);
  /// The deformer shape (deformer.hpp): rig.handles, one control per handle.
  static ArapDeformer bind(const Mesh& rest, const Rig& rig, const Options& options) {
    return bind(rest, rig.handles, options);
  }

  /// Changes the handles. The factorization is kept when the union of the handle vertices is
  /// unchanged (only the assignment of vertices to motors changed); otherwise L_FF is re-factorized.
  /// Returns true if it re-factorized. Same errors as bind.
  bool set_handles(std::span<const Handle> handles);

  /// Inputs: one unit motor per handle (deformer.hpp). Output: V_out (n×3) the ARAP solution with the
  /// handles placed by their motors. Throws Error on a wrong motor count or a bad motor, and
  /// numerical_error if the iteration produces non-finite values.
  void pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out);

  /// The ARAP energy min_R E(V, R) of any positions V (n×3), evaluated term by term with the best
  /// rotations (Horn, cold start). Used to check the energies of pose() and by benchmarks.
  double energy(const Eigen::MatrixXd& V) const;

  /// The best rotor of every cell for the last pose's output (n, ga::Rot).
  const std::vector<ga::Rot>& rotors() const { return cells_.rotors(); }
  const ArapReport& report() const { return report_; }
  const ArapBindReport& bind_report() const { return bind_report_; }
  const Options& options() const { return options_; }
  Eigen::Index vertices() const { return P_.rows(); }
  /// One control per handle (its name, anchored at its rest centroid).
  const std::vector<Control>& controls() const { return controls_; }
  /// The global matrix (the cotangent Laplacian with the energy's weights), n×n.
  const Eigen::SparseMatrix<double>& laplacian() const { return cells_.global_matrix(); }
  /// The free vertex of each row of the factorized block L_FF (for messages of the factorization).
  const Eigen::VectorXi& free_order() const { return solver_.free(); }

 private:
  struct Cells;  // the solve's Problem: the rigid cells (arap.cpp)
  void bind_handles(std::span<const Handle> handles);
  void factorize(const std::vector<int>& constrained);
  void bind_harmonic();
  void find_unreferenced();

  Options options_;
  Eigen::MatrixXi F_;
  RowMatrix3 P_;  // rest positions
  fit::RigidCells cells_;
  Eigen::VectorXi unreferenced_;

  // Handles.
  std::vector<Eigen::VectorXi> handle_sets_;
  std::vector<std::string> handle_names_;
  std::vector<Control> controls_;
  Eigen::VectorXi constrained_, constrained_handle_;  // handle of each constrained vertex (−1: unreferenced)
  // L_FF (rows in a geometric nested-dissection order of the free vertices, free_order()) and its
  // factorization, in the local/global solver.
  fit::LocalGlobal solver_;
  MotorBlendField harmonic_;
  bool has_harmonic_ = false;

  // Per-pose state and scratch, reused across poses.
  RowMatrix3 X_, values_;
  std::vector<ga::Mot> motors_;
  Eigen::MatrixXd Xcol_;
  bool has_previous_ = false;
  ArapReport report_;
  ArapBindReport bind_report_;
};

}  // namespace spinmotor
