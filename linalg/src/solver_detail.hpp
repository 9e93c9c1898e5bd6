#pragma once
// Internal to spinmotor_linalg: input checks and matrix-graph components shared by the solvers.
#include <Eigen/SparseCore>
#include <complex>
#include <string>
#include <vector>

namespace spinmotor::detail {

/// Throws Error(BadInput) prefixed with `who` unless A is square, compressed and finite.
/// Scalar: double or std::complex<double> (as for matrix_components and pattern_hash).
template <class Scalar>
void check_square_finite(const Eigen::SparseMatrix<Scalar>& A, const char* who);

/// Connected components of the graph with an edge i–j for every stored entry A(i,j), i ≠ j (the
/// pattern is symmetrised). Labels 0..count−1 in order of the smallest index in each component.
struct GraphComponents {
  std::vector<int> label;
  std::vector<int> size;   ///< per component
  std::vector<int> first;  ///< smallest index per component
  int count() const { return static_cast<int>(size.size()); }
};
template <class Scalar>
GraphComponents matrix_components(const Eigen::SparseMatrix<Scalar>& A);

/// "connected component c (s <plural>, e.g. <noun> i)" (plural used when s ≠ 1).
std::string describe_component(const GraphComponents& g, int c, const char* noun, const char* plural);

/// A column that no maximum matching of A's bipartite row–column graph covers, or −1 when A is
/// structurally nonsingular (a perfect matching exists). Greedy matching (diagonal first) plus
/// augmenting paths: O(nnz) when the diagonal is stored, as for every mesh operator.
int structurally_singular_column(const Eigen::SparseMatrix<double>& A);

/// Cheap pattern fingerprint (size, nnz, and a hash of the index arrays) to detect a factorize()
/// call with a pattern different from the analyzed one.
template <class Scalar>
std::size_t pattern_hash(const Eigen::SparseMatrix<Scalar>& A);

}  // namespace spinmotor::detail
