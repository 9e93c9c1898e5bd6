#pragma once
// geometric_nested_dissection: a fill-reducing order of the free unknowns of a mesh-shaped sparse
// system from the unknowns' positions, for the Laplacian-type systems of ARAP and the harmonic bind.
// Recursive median splits along the longest bounding-box axis; the unknowns of the half with the
// shorter boundary that touch the other half form the separator, numbered after both halves. O(n log n)
// and no graph partitioner: on tubes and other long, thin meshes it predicts fewer factorization flops
// than AMD (ARAP: docs/performance.md, "ARAP"); CholeskySolver's try_natural picks the cheaper of the
// two by symbolic analysis.
#include <Eigen/Core>
#include <span>
#include <vector>

namespace spinmotor {

/// Inputs: P (n×3 positions, one row per unknown); the symmetric adjacency as offsets and neighbour
/// lists (CSR, or a symmetric matrix's compressed columns: the neighbours of i are nbr[off[i] ..
/// off[i+1]); a diagonal entry is ignored); excluded (n flags; non-zero: a constrained unknown, left
/// out of the order and of the graph).
/// Output: the free unknowns (those not excluded), each once, in nested-dissection order.
[[nodiscard]] std::vector<int> geometric_nested_dissection(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                                           std::span<const int> off, std::span<const int> nbr,
                                                           std::span<const char> excluded);

}  // namespace spinmotor
