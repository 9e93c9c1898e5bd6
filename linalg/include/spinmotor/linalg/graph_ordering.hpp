#pragma once
// graph_ordering: a fill-reducing permutation of a symmetric sparse pattern given as a graph, for a
// caller that assembles its own (block) matrix in the permuted order instead of handing CHOLMOD a
// matrix (spin/dirac_assembly: the 4×4 quaternion blocks of the vertex graph).
#include <Eigen/Core>
#include <array>
#include <span>
#include <string_view>

#include "spinmotor/linalg/ordering.hpp"

namespace spinmotor {

/// The orderings graph_ordering implements.
inline constexpr std::array<Ordering, 3> kGraphOrderings{Ordering::Natural, Ordering::AMD, Ordering::METIS};

/// Inputs: the full compressed-column pattern of a symmetric n×n graph (colptr: n + 1 offsets, rowind:
/// row indices sorted within each column, both triangles and the diagonal present); an ordering among
/// natural, amd (CHOLMOD's AMD) and metis (METIS_NodeND through CHOLMOD); the caller's name for messages.
/// CHOLMOD reads the arrays without changing them (its interface takes them non-const).
/// Output: perm with perm[k] = the old index of the k-th vertex in the new order.
/// Errors: BadInput for another ordering or an inconsistent pattern; Numerical if CHOLMOD fails.
[[nodiscard]] Eigen::VectorXi graph_ordering(Eigen::Index n, std::span<int> colptr, std::span<int> rowind,
                                             Ordering ordering, std::string_view who);

}  // namespace spinmotor
