#include "solver_detail.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <sstream>

#include "spinmotor/core/error.hpp"

namespace spinmotor::detail {

template <class Scalar>
void check_square_finite(const Eigen::SparseMatrix<Scalar>& A, const char* who) {
  if (A.rows() != A.cols()) {
    std::ostringstream s;
    s << who << ": matrix must be square, got " << A.rows() << "x" << A.cols();
    throw Error(s.str());
  }
  if (!A.isCompressed())
    throw Error(std::string(who) + ": matrix must be compressed (call makeCompressed())");
  const Scalar* v = A.valuePtr();
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    if (!std::isfinite(std::abs(v[k]))) {
      const auto* outer = A.outerIndexPtr();
      const Eigen::Index col =
          std::upper_bound(outer, outer + A.outerSize() + 1, static_cast<int>(k)) - outer - 1;
      std::ostringstream s;
      s << who << ": matrix entry (" << A.innerIndexPtr()[k] << ", " << col << ") is not finite (" << v[k]
        << ")";
      throw Error(s.str());
    }
}

namespace {
int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}
}  // namespace

template <class Scalar>
GraphComponents matrix_components(const Eigen::SparseMatrix<Scalar>& A) {
  const int n = static_cast<int>(A.rows());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int j = 0; j < A.outerSize(); ++j)
    for (typename Eigen::SparseMatrix<Scalar>::InnerIterator it(A, j); it; ++it) {
      int a = find_root(parent, static_cast<int>(it.row())), b = find_root(parent, j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // root = smallest index
    }
  GraphComponents g;
  g.label.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    const int r = find_root(parent, i);
    if (g.label[r] < 0) {  // r ≤ i, so components are met in order of their smallest index
      g.label[r] = g.count();
      g.size.push_back(0);
      g.first.push_back(r);
    }
    g.label[i] = g.label[r];
    ++g.size[g.label[i]];
  }
  return g;
}

std::string describe_component(const GraphComponents& g, int c, const char* noun, const char* plural) {
  std::ostringstream s;
  s << "connected component " << c << " (" << g.size[c] << " " << (g.size[c] == 1 ? noun : plural)
    << ", e.g. " << noun << " " << g.first[c] << ")";
  return s.str();
}

int structurally_singular_column(const Eigen::SparseMatrix<double>& A) {
  const int n = static_cast<int>(A.cols());
  const int* p = A.outerIndexPtr();
  const int* ri = A.innerIndexPtr();
  std::vector<int> row_match(A.rows(), -1), col_match(n, -1);
  for (int j = 0; j < n; ++j) {  // greedy: the diagonal if stored, else the first free row
    int pick = -1;
    for (int k = p[j]; k < p[j + 1]; ++k)
      if (row_match[ri[k]] < 0 && (pick < 0 || ri[k] == j)) pick = ri[k];
    if (pick >= 0) row_match[pick] = j, col_match[j] = pick;
  }
  // Augmenting paths (iterative DFS) for the columns left unmatched.
  std::vector<int> stamp(A.rows(), -1), col_stack, pos_stack, via_row;
  for (int j0 = 0; j0 < n; ++j0) {
    if (col_match[j0] >= 0) continue;
    col_stack.assign(1, j0);
    pos_stack.assign(1, p[j0]);
    via_row.clear();
    bool found = false;
    while (!col_stack.empty() && !found) {
      const int j = col_stack.back();
      int& k = pos_stack.back();
      if (k == p[j + 1]) {
        col_stack.pop_back();
        pos_stack.pop_back();
        if (!via_row.empty()) via_row.pop_back();
        continue;
      }
      const int i = ri[k++];
      if (stamp[i] == j0) continue;
      stamp[i] = j0;
      via_row.push_back(i);
      if (row_match[i] < 0) {
        found = true;
        break;
      }
      col_stack.push_back(row_match[i]);
      pos_stack.push_back(p[row_match[i]]);
    }
    if (!found) return j0;
    // Flip the path: col_stack[t] takes via_row[t].
    for (size_t t = 0; t < col_stack.size(); ++t) {
      row_match[via_row[t]] = col_stack[t];
      col_match[col_stack[t]] = via_row[t];
    }
  }
  return -1;
}

template <class Scalar>
std::size_t pattern_hash(const Eigen::SparseMatrix<Scalar>& A) {
  std::size_t h = std::hash<Eigen::Index>()(A.rows()) ^ (std::hash<Eigen::Index>()(A.nonZeros()) << 1);
  const auto mix = [&h](std::size_t v) { h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
  for (Eigen::Index j = 0; j <= A.outerSize(); ++j) mix(static_cast<std::size_t>(A.outerIndexPtr()[j]));
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) mix(static_cast<std::size_t>(A.innerIndexPtr()[k]));
  return h;
}

template void check_square_finite(const Eigen::SparseMatrix<double>&, const char*);
template void check_square_finite(const Eigen::SparseMatrix<std::complex<double>>&, const char*);
template GraphComponents matrix_components(const Eigen::SparseMatrix<double>&);
template GraphComponents matrix_components(const Eigen::SparseMatrix<std::complex<double>>&);
template std::size_t pattern_hash(const Eigen::SparseMatrix<double>&);
template std::size_t pattern_hash(const Eigen::SparseMatrix<std::complex<double>>&);

}  // namespace spinmotor::detail
