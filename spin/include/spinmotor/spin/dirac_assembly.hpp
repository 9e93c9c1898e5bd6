#pragma once
// Direct assembly of the Hermitian matrices of the spin-transformation eigenproblems (Crane et al.
// 2011, §5.5, §5.7) in the compressed storage a sparse Cholesky factorization reads.
//
// Unknowns. Each vertex i carries either a full quaternion (4 real unknowns) or, where the boundary
// tangent is prescribed (§5.7), the pair (a, b) with λ_i = W_i (a + b T̃_i) (2 unknowns). With a real
// vertex scaling s (the V of eq. 7, or 1) the quaternion field is λ_i = s_i U_i x_i, U_i the identity
// or the 4×2 block W_i C_i. In matrix form λ = S Û x.
//
// Matrices (lower triangle only, CSC, one fixed pattern per bind; K̂ etc. in the notation of
// dirac_operator.hpp, A = D − PB):
//   normal_matrix  K = Ûᵀ S Âᵀ M̂_F Â S Û          (A*A of eqs. 6–7, written (AVU)*(AVU) in §5.7)
//   mixed_matrix   G = Ûᵀ S B̂ᵀ M̂_F Â S Û          (B*A of eq. 6; Hermitian only on closed meshes)
// Per face f with area A, counter-clockwise opposite edges e_a and curvature change ρ, the quaternion
// entries are (derived from eq. 5 and §5.3; the reference code of the paper builds the same A*A):
//   (A*A)_ab += −e_a e_b / (4A) + ρ (e_b − e_a) / 6 + A ρ² / 9,   (B*A)_ab += −e_b / 6 − A ρ / 9.
// Each face's three vertex pairs are summed per edge and per vertex in parallel (OpenMP) and written
// straight into the value array: no triplets, no sparse products.
//
// Complex form. Seen as a right C-vector space (p = w1 + j w2, w1, w2 ∈ span{1, i}), H^n is C^2n and
// left multiplication by q = z1 + j z2 is the complex 2×2 block [z1 −z̄2; z2 z̄1]; for
// q = a + bi + cj + dk, z1 = a + bi and z2 = c − di. This is a representation (products map to
// products, q̄ to the conjugate transpose), so A*A is also a Hermitian 2n×2n complex matrix with 2×2
// blocks: half the storage of the real 4×4 form, and a supernodal complex Cholesky of it costs about
// a third of the real one (bench_spin). It needs every vertex to keep a full quaternion (the
// boundary reduction λ = W(a + bT̃) is not a complex subspace), so it exists only without reductions.
//
// Ordering. The vertices are renumbered once per bind by a fill-reducing ordering of the VERTEX graph
// (n nodes), and every vertex keeps its 2 or 4 unknowns together; the factorization can then use its
// natural order. Ordering the n-node graph is ~16× cheaper than ordering the 4n×4n matrix, whose
// 4×4 blocks a general ordering has to rediscover (bench_spin measures both).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <complex>
#include <string>
#include <vector>

#include "spinmotor/linalg/graph_ordering.hpp"
#include "spinmotor/linalg/ordering.hpp"

namespace spinmotor {

/// The fill-reducing orderings of the vertex graph (ordering.hpp) that DiracAssembly and SpinTransform
/// accept: none, CHOLMOD's AMD or METIS nested dissection (graph_ordering's). Others throw Error (BadInput).
inline constexpr const auto& kVertexOrderings = kGraphOrderings;
/// Their names (natural, amd, metis): the CLI's and Python's choices for `ordering`.
inline std::vector<std::string> vertex_ordering_values() { return ordering_values(kVertexOrderings); }

class DiracAssembly {
 public:
  /// Inputs: V (n×3), F (m×3, counter-clockwise, every face with positive area, every vertex in a
  /// face), ordering (one of kVertexOrderings), and the reduced (boundary) vertices with their 4×2 blocks U_i
  /// = W_i C_i (§5.7). Throws Error on an unsupported ordering, a degenerate face, an index out of range, an
  /// unreferenced vertex, a reduced vertex listed twice or out of range.
  DiracAssembly(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Ordering ordering = Ordering::AMD,
                const Eigen::VectorXi& reduced_vertices = {},
                const std::vector<Eigen::Matrix<double, 4, 2>>& reductions = {});

  Eigen::Index num_vertices() const { return n_; }
  Eigen::Index num_faces() const { return m_; }
  /// Number of real unknowns: 4 per free vertex, 2 per reduced vertex.
  Eigen::Index num_unknowns() const { return dof_offset_[n_]; }
  bool has_reductions() const { return reduced_; }

  /// Face areas A_f (m) and barycentric vertex areas (n), the diagonals of M_F and M_V (§5.4).
  const Eigen::VectorXd& face_areas() const { return area_; }
  const Eigen::VectorXd& vertex_areas() const { return vertex_area_; }
  /// order()[k] is the original index of the k-th vertex in the unknowns' order.
  const Eigen::VectorXi& order() const { return order_; }

  /// The symmetric pattern (lower triangle including the diagonal, compressed, values zero). Built on
  /// first use (the complex form never needs it: at 1M faces it holds 29M entries).
  const Eigen::SparseMatrix<double>& pattern() const;

  /// Inputs: rho (m), scale (n, s_i > 0; empty means all ones). Output: K's values written into
  /// `K`, which must have pattern() (copy it once, then refill for each ρ).
  void normal_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                     Eigen::SparseMatrix<double>& K) const;
  /// Same for G = B*A (eq. 6). The imaginary part of its diagonal (zero on a closed mesh up to
  /// rounding) is dropped so that the lower triangle describes a symmetric matrix.
  void mixed_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                    Eigen::SparseMatrix<double>& G) const;

  /// Complex form (only without reductions): pattern with 2 complex unknowns per vertex, (w1, w2) =
  /// (a + bi, c − di) for λ_i = a + bi + cj + dk, lower triangle, values zero. Built on first use.
  const Eigen::SparseMatrix<std::complex<double>>& complex_pattern() const;
  /// K and G in complex form, written into a copy of complex_pattern().
  void normal_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                     Eigen::SparseMatrix<std::complex<double>>& K) const;
  void mixed_matrix(const Eigen::VectorXd& rho, const Eigen::VectorXd& scale,
                    Eigen::SparseMatrix<std::complex<double>>& G) const;
  /// Inputs: w (2n complex unknowns), scale (n or empty). Output: λ (n×4, original order).
  Eigen::MatrixXd expand(const Eigen::VectorXcd& w, const Eigen::VectorXd& scale) const;

  /// Inputs: x (num_unknowns), scale (n or empty). Output: λ (n×4, ORIGINAL vertex order), λ_i = s_i U_i x_i.
  Eigen::MatrixXd expand(const Eigen::VectorXd& x, const Eigen::VectorXd& scale) const;
  /// The unknowns x whose expansion (scale 1) is the quaternion field (n×4) closest in the least-squares
  /// sense per vertex (x_i = U_i⁺ λ_i); used for start vectors.
  Eigen::VectorXd restrict_field(const Eigen::MatrixXd& lambda) const;

 private:
  using RowQuats = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;
  /// Sets area_, normal_, edge_vec_ and vertex_area_ from V and F; throws on a bad index, a non-finite
  /// position, a degenerate face or a vertex in no face.
  void init_face_geometry(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  /// Sets the edges E_ of F and their incident faces, corners and signs (EF_offset_, EF_face_,
  /// EF_corner_, EF_sign_).
  void init_edges(const Eigen::MatrixXi& F);
  /// Sets the vertex → corner lists VF_offset_, VF_corner_ of F.
  void init_vertex_corners(const Eigen::MatrixXi& F);
  /// Sets order_ and rank_: `ordering` applied to the vertex graph of E_.
  void init_ordering(Ordering ordering);
  /// Sets U_, dof_offset_ and reduced_: 2 unknowns (reductions[r]) for reduced_vertices[r], 4 for every
  /// other vertex, in the new order; throws on an index out of range or listed twice.
  void init_unknowns(const Eigen::VectorXi& reduced_vertices,
                     const std::vector<Eigen::Matrix<double, 4, 2>>& reductions);
  /// Sets the neighbour lists nb_offset_, nb_vertex_, nb_edge_, nb_e0_is_row_ from E_ and rank_.
  void init_neighbours();
  void normal_entries(const Eigen::VectorXd& rho, Eigen::VectorXd& diag, RowQuats& edge_q) const;
  void mixed_entries(const Eigen::VectorXd& rho, Eigen::VectorXd& diag, RowQuats& edge_q) const;
  void fill_complex(const Eigen::VectorXd& scale, const Eigen::VectorXd& diag, const RowQuats& edge_q,
                    Eigen::SparseMatrix<std::complex<double>>& K) const;
  void fill(const Eigen::VectorXd& scale, const Eigen::VectorXd& diag,
            const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& edge_q,
            Eigen::SparseMatrix<double>& K) const;

  Eigen::Index n_ = 0, m_ = 0;
  bool reduced_ = false;
  Eigen::MatrixXi F_;  // faces (original vertex indices)
  Eigen::VectorXd area_, vertex_area_;
  Eigen::MatrixXd edge_vec_;                    // m×9: e_0, e_1, e_2 (opposite corners 0, 1, 2)
  Eigen::MatrixXd normal_;                      // m×3 unit normals
  Eigen::MatrixXi E_;                           // unique edges (original indices, E0 < E1)
  Eigen::VectorXi EF_offset_, EF_face_;         // edge → faces (CSR)
  Eigen::VectorXi EF_sign_;                     // +1 if face's corner pair (c, c+1) runs E0 → E1, else −1
  Eigen::VectorXi EF_corner_;                   // the corner c of that pair
  Eigen::VectorXi VF_offset_, VF_corner_;       // vertex → (3f + c) corners (CSR)
  Eigen::VectorXi order_, rank_;                // new → old, old → new
  std::vector<Eigen::Index> dof_offset_;        // per NEW vertex index, n+1 entries
  std::vector<Eigen::Matrix<double, 4, 2>> U_;  // per NEW vertex index (used when dof = 2)
  // Per new vertex j: its neighbours k > j in new order, with the edge and whether the edge's
  // stored orientation (E0 → E1) is (row k, column j).
  Eigen::VectorXi nb_offset_, nb_vertex_, nb_edge_, nb_e0_is_row_;
  mutable Eigen::SparseMatrix<double> pattern_;
  mutable Eigen::SparseMatrix<std::complex<double>> complex_pattern_;
};

}  // namespace spinmotor
