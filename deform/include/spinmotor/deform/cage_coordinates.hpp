#pragma once
// Cage coordinates (CGA paper §VI): weights λ_j(x) of the k vertices of a closed triangle cage at
// points x inside it, a partition of unity with x = Σ_j λ_j(x) C_j (exactly for mean-value
// coordinates, to the grid's interpolation error for harmonic coordinates).
//
//   check_cage                the cage must be a closed, consistently and outward oriented triangle mesh
//   mean_value_coordinates    Ju, Schaefer & Warren 2005, closed form per triangle (their Fig. 4
//                             pseudo-code); exact linear precision, may be negative for a non-convex cage
//   harmonic_cage_coordinates Joshi et al. 2007 on a regular grid: ≥ 0, interpolating, smooth inside
//
// Harmonic coordinates on the grid: cubic cells of size h = (largest extent of the cage) / grid, the
// cage's box padded by 2 cells. Every triangle is rasterized into the nodes within √3 h of it, each node
// keeping its closest triangle, closest point and barycentric coordinates there. Nodes are classified
//   boundary  within h/2 of the cage: Dirichlet values = the barycentric coordinates of the closest
//             point (linear on each cage triangle, as Joshi et al.);
//   exterior  reachable from the grid's border through non-boundary nodes (flood fill);
//   interior  the rest (inside the cage): unknowns of the 7-point Laplace equation Δλ_j = 0.
// (A node-based form of Joshi's cell classification: every edge between an inside and an outside node
// crosses the cage within h/2 of one of its ends, so boundary nodes separate interior from exterior.)
// One CHOLMOD factorization of the interior Laplacian (SPD), its unknowns numbered by the grid's nested
// dissection (linalg/geometric_ordering.hpp), one right-hand side per cage vertex.
// At a point, λ is the trilinear interpolation of the 8 nodes of its cell; exterior nodes of a cell
// that contains an inside point lie within √3 h of the cage and take the barycentric values of their
// closest point. Interpolation error: a linear function f is reproduced up to max |∇f| · √3 h (the
// node values differ from f by at most |∇f| × the node's distance to its closest point, the discrete
// maximum principle carries that bound inside, trilinear interpolation is exact for f); for positions,
// |Σ λ_j C_j − x| ≤ √3 h (harmonic_interpolation_bound()).
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: cage vertices C (k×3), faces CF (m×3). Throws Error naming the element when a face has an
/// index out of range, repeated corners or zero area, an edge is not shared by exactly two faces (not
/// closed: names the edge and its face count), an oriented edge appears twice (not consistently
/// oriented: names the edge and the two faces), or the signed volume is ≤ 0 (inside out).
void check_cage(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF);

/// The generalized winding number of the closed cage at x (1 inside, 0 outside; Σ solid angles / 4π).
double cage_winding_number(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF, const Eigen::Vector3d& x);

/// Inputs: cage (check_cage), points X (n×3), each inside the cage or on it. Output: n×k mean value
/// coordinates (rows sum to 1, Σ_j λ_ij C_j = x_i to rounding; a point on the cage gets its linear
/// barycentric coordinates there). Throws Error "point i is outside the cage" (winding number < ½).
Eigen::MatrixXd mean_value_coordinates(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF,
                                       const Eigen::MatrixXd& X);

/// Inputs: cage (check_cage), points X (n×3) inside the cage or on it, grid cells along the cage's
/// largest extent (4 ≤ grid ≤ 512). Output: n×k harmonic coordinates (≥ 0, rows sum to 1). Throws
/// Error like mean_value_coordinates, and numerical_error if the factorization fails.
Eigen::MatrixXd harmonic_cage_coordinates(const Eigen::MatrixXd& C, const Eigen::MatrixXi& CF,
                                          const Eigen::MatrixXd& X, int grid = 64);

/// √3 h, h = (largest extent of the cage) / grid: the bound on |Σ λ_j C_j − x| stated above.
double harmonic_interpolation_bound(const Eigen::MatrixXd& C, int grid);

}  // namespace spinmotor
