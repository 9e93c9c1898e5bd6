#pragma once
// geometric_nested_dissection: a fill-reducing order of the free unknowns of a mesh-shaped sparse
// system from the unknowns' positions, for the Laplacian-type systems of ARAP and the harmonic bind.
// Recursive median splits along the longest bounding-box axis; the unknowns of the half with the
// shorter boundary that touch the other half form the separator, numbered after both halves. O(n log n)
// and no graph partitioner: on tubes and other long, thin meshes it predicts fewer factorization flops
// than AMD (ARAP: docs/performance.md, "ARAP"); CholeskySolver's try_natural picks the cheaper of the
// two by symbolic analysis.
//
// grid_nested_dissection: the same for the unknowns of a 7-point stencil on a regular 3D grid (the
// harmonic cage coordinates), from their integer coordinates alone. A 7-point edge changes exactly one
// coordinate by ±1, so it changes s = a·x for a = (±1, ±1, ±1) by ±1 and for a = a unit axis by 0 or
// ±1: the nodes with s = c separate those with s < c from those with s > c (George 1973, nested
// dissection: separators numbered after both halves, recursively). A diagonal plane holds 1/√3 of the
// nodes an axis plane holds over the same area (its layers are 1/√3 apart), and the top fronts'
// dense factorization grows as the cube of their size: on the ball inside the 98-vertex bench cage
// (grid 64, 121k unknowns) axis planes predicted 3.6× METIS's flops, diagonal planes 0.85×, ordered
// in ~20 ms where METIS takes ~0.75 s (docs/performance.md, "Cage bind").
#include <Eigen/Core>
#include <array>
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

/// Input: the integer grid coordinates of the m unknowns (distinct; any subset of the grid); two
/// unknowns are coupled when they differ by one in one coordinate (the 7-point stencil).
/// Output: the unknowns' indices 0 … m−1, each once, in nested-dissection order. At each level, of the
/// four diagonal directions and the three axes, the one whose plane through the median holds the
/// fewest unknowns separates (among the planes that leave at most 3/4 of the region on either side;
/// the recursion is O(log m) deep); regions of ≤ 32 unknowns keep their input order.
[[nodiscard]] std::vector<int> grid_nested_dissection(std::span<const std::array<int, 3>> nodes);

}  // namespace spinmotor
