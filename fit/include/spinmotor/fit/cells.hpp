#pragma once
// The cells of the local step (local_global.hpp): each fits a transform to the current positions and
// gives its share of the global step's right-hand side. Three kinds, on a triangle mesh (rest V0, F):
//
//   RigidCells          a rotation per vertex (ARAP, Sorkine & Alexa 2007, eqs. 9–12; CGA paper §VII):
//                       Spokes (the edges (i, j) of the one-ring, w_ij = ½(cot α + cot β) = −L_ij) or
//                       SpokesAndRims (Chao et al. 2010: the three edges of every face around i, each
//                       with its face's ½ cot of the opposite angle). E_i = Σ w |e' − R_i e|²; the best R_i
//                       by ga::best_rotation warm-started from the previous fit; the right-hand side
//                       B_i = ½ Σ_j w_ij (R_i + R_j) e_ij (spokes) or ⅓ Σ_{t ∋ i} (R_t0 + R_t1 + R_t2) G_t,i
//                       (spokes and rims); the global matrix is the Laplacian of the cells' weights.
//   SimilarityFaces     a similarity of each face's plane (as-similar-as-possible, Liu et al. 2008): the
//                       map J_f = Σ_{i∈f} v_i ∇φ_iᵀ (3×2 in an orthonormal frame of the rest face) and its
//                       conformal part T_f = [α −β; β α] in the frames of the rest and the current plane;
//                       E_f = A_f |J_f − T_f|²_F; the right-hand side at corner i: A_f T_f ∇φ_i. A face
//                       collapsed in the current positions keeps its previous T_f.
//   SimilarityOneRings  a similarity s_i R_i per vertex for its cotangent-weighted spokes (3D Procrustes
//                       with scale: ga::best_similarity); E_i = Σ_j w_ij |e'_ij − s_i R_i e_ij|²; the
//                       right-hand side ½ Σ_j w_ij (T_i + T_j)(v⁰_i − v⁰_j). A cell whose covariance
//                       vanishes keeps its previous transform; each fit is warm-started from the cell's
//                       previous rotor.
// Each kind is bound once (rest data, CSR layouts) and fits in parallel without allocating. Faces with
// every corner fixed (SimilarityFaces) and cells of vertices no free vertex touches (SimilarityOneRings)
// are left out: the cost scales with the free region.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "spinmotor/fit/local_global.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/ga/rotor_fit.hpp"

namespace spinmotor::fit {

class RigidCells {
 public:
  enum class Kind { Spokes, SpokesAndRims };

  /// Inputs: rest positions P (n×3), faces F, the cotangent Laplacian L of (P, F), the corner cotangents
  /// C (m×3, ½ cot per corner; read for SpokesAndRims), clamp: negative weights to 0.
  static RigidCells bind(const RowMatrix3& P, const Eigen::MatrixXi& F, const Eigen::SparseMatrix<double>& L,
                         const Eigen::MatrixXd& C, Kind kind, bool clamp);

  /// The global matrix: L with the cells' (possibly clamped) weights, symmetric to the last bit.
  const Eigen::SparseMatrix<double>& global_matrix() const { return L_; }
  /// Fits every cell's rotor to X (warm-started from the previous fit); returns Σ_i E_i (cell energies
  /// as Σ w|e'|² + Σ w|e|² − 2 tr(R S), term by term where that cancels). Adds the fallback fits.
  double fit(const RowMatrix3& X, Eigen::Index& fallbacks);
  /// B rows for the vertices `rows` (the free vertices in the solver's order).
  void rhs(const Eigen::VectorXi& rows, RowMatrix3& B) const;
  /// min_R E(X, R) with cold-started rotors, term by term.
  double energy(const RowMatrix3& X) const;
  /// Σ_i Σ w |e|² over the cells (the energy's scale).
  double energy_scale() const { return energy_scale_; }
  const std::vector<ga::Rot>& rotors() const { return rot_; }
  void reset_rotors();
  /// The one-ring CSR (neighbours of vertex i: nbr()[off()[i] .. off()[i+1])).
  const std::vector<int>& off() const { return off_; }
  const std::vector<int>& nbr() const { return nbr_; }

 private:
  void build_one_ring();
  int slot(int i, int j) const;
  void bind_spokes(bool clamp);
  void bind_rims(const Eigen::MatrixXd& C);
  void assemble_global_matrix();
  double cell_energy_direct(Eigen::Index i, const Eigen::Matrix3d& R, const RowMatrix3& X) const;

  RowMatrix3 P_;
  Eigen::MatrixXi F_;
  Eigen::SparseMatrix<double> L_;
  // One-ring CSR (the off-diagonal pattern of L, rows sorted): for the slot k of vertex i (neighbour
  // j = nbr_[k]) the spoke weight w_[k], the covariance coefficient kappa_.row(k) (S_i = Σ_k κ_k
  // (x'_j − x'_i)ᵀ) and the right-hand-side coefficient h_.row(k) (B_i = R_i h_self_i + Σ_k R_j h_k).
  std::vector<int> off_, nbr_;
  Eigen::VectorXd w_;
  RowMatrix3 kappa_, h_, h_self_;
  // Rims of the spokes-and-rims cells: edge (rim_l_, rim_m_) with weight rim_c_, CSR by rim_off_.
  std::vector<int> rim_off_, rim_l_, rim_m_;
  Eigen::VectorXd rim_c_;
  Eigen::VectorXd a_rest_;  // Σ_{(u,v) ∈ C_i} w_uv |e_uv|² per cell
  double energy_scale_ = 0.0;
  std::vector<ga::Rot> rot_;
  std::vector<Eigen::Matrix3d> Rm_;
};

/// A face with a free corner: its rest data.
struct ActiveFace {
  std::array<int, 3> v;        // corner vertices
  double area;                 // rest area A_f
  std::array<double, 6> grad;  // rest gradients ∇φ_i in the rest frame (b1, b2): (x0, y0, x1, y1, x2, y2)
  Eigen::Vector3d b1, b2;      // orthonormal frame of the rest plane (the collapsed-face start)
};

class SimilarityFaces {
 public:
  /// Inputs: rest positions V0 (n×3), faces F, fixed (n flags: constrained vertices), free (the free
  /// vertices in increasing order). Faces with a free corner take part. Throws Error naming a degenerate
  /// rest face.
  static SimilarityFaces bind(const Eigen::MatrixXd& V0, const Eigen::MatrixXi& F,
                              const std::vector<char>& fixed, const Eigen::VectorXi& free);
  /// The transforms back to the rest frames (the start of a solve).
  void reset();
  /// Fits every face (parallel); returns Σ_f A_f |J_f − T_f|²; adds the collapsed faces.
  double fit(const RowMatrix3& X, Eigen::Index& fallbacks);
  /// Adds weight · Σ_{f ∋ i} A_f T_f ∇φ_i to b, for the free vertex of rank k (its index in `free`).
  void add_rhs(Eigen::Index k, double weight, Eigen::Vector3d& b) const;
  double area() const { return area_; }  ///< Σ A_f over the faces taking part
  const std::vector<ActiveFace>& faces() const { return faces_; }
  const std::vector<int>& fixed_faces() const { return fixed_faces_; }

 private:
  std::vector<ActiveFace> faces_;
  std::vector<int> fixed_faces_;
  double area_ = 0;
  std::vector<int> inc_offset_;           // free rank k -> incidences
  std::vector<std::pair<int, int>> inc_;  // (face, corner)
  std::vector<std::array<Eigen::Vector3d, 2>> T_;
};

class SimilarityOneRings {
 public:
  /// Inputs: rest positions V0, the cotangent Laplacian L, the free vertices. Cells: every free vertex
  /// and its neighbours. ok() is false when a cell's rest weights Σ_j w_ij |e_ij|² are ≤ 0 (a one-ring
  /// of obtuse triangles): no similarity can be fitted there, and the caller goes without these cells.
  static SimilarityOneRings bind(const Eigen::MatrixXd& V0, const Eigen::SparseMatrix<double>& L,
                                 const Eigen::VectorXi& free);
  bool ok() const { return ok_; }
  void reset();
  /// Fits every cell (parallel); returns Σ_i (Σ_j w_ij |e'_ij|² − s_i tr(R_i S_i)); adds collapsed cells.
  double fit(const RowMatrix3& X, Eigen::Index& fallbacks);
  /// Adds weight · ½ Σ_j w_ij (T_i + T_j)(v⁰_i − v⁰_j) to b for vertex i (which has a cell).
  void add_rhs(int i, double weight, Eigen::Vector3d& b) const;
  double rest_scale() const { return dsum_; }  ///< Σ_i Σ_j w_ij |e_ij|²
  int cell_of(int i) const { return cell_of_[i]; }
  const Eigen::Matrix3d& transform(int cell) const { return T_[cell]; }  ///< s R as a matrix
  const ga::Similarity& similarity(int cell) const { return sim_[cell]; }
  void set_similarity(int cell, const ga::Similarity& s);

 private:
  Eigen::MatrixXd V0_;
  std::vector<int> vertex_, offset_, nbr_, cell_of_;
  std::vector<double> w_, d_;
  double dsum_ = 0;
  bool ok_ = true;
  std::vector<Eigen::Matrix3d> T_;
  std::vector<ga::Similarity> sim_;
};

}  // namespace spinmotor::fit
