#pragma once
// Face edge-constraint nets of a triangle mesh (Ye, Diamanti, Chern, Schröder & Schröder 2018, §4.1):
// the classical net, each face carrying its plane's unit normal, so n_i + n_j ⟂ e_ij holds at every edge.
//
// Per interior edge e_ij between faces i and j (ij written per face corner, m×3: slot (f, c) is the
// edge opposite corner c of face f, from F(f, c+1) to F(f, c+2), i.e. traversed counter-clockwise by f):
//   θ_ij   bending angle, the signed angle from n_i to n_j about e_ij, in (−π, π); a convex edge
//          (outward normals diverging, as on a sphere with counter-clockwise faces) is positive;
//   H_ij = ½ |e_ij| tan(θ_ij / 2)   integrated edge mean curvature (Ye §4.1, with the paper's ½: then
//          H_i ≈ H·Area_i with H the mean of the principal curvatures, H = 1 on the unit sphere);
//   E_ij = 2 H_ij + e_ij           hyperedge (eq. 12), e_ij the edge vector as traversed by face i;
//          E_ji = conj(E_ij) and |E_ij| cos(θ_ij/2) = |e_ij|.
// Per face: H_i = Σ_j H_ij (eq. 9), h_i = H_i / sqrt(Area_i) (eq. 10, the mean-curvature half-density)
// and the discrete Willmore energy W = Σ_i H_i² / Area_i (eq. 11; 4π on the round sphere, 2π² on
// Willmore's torus R/r = √2, dimensionless). Boundary edges carry no bending (θ = 0, H_ij = 0) and have
// no neighbour (adjacent = −1).
#include <Eigen/Core>

namespace spinmotor {

struct EdgeConstraintNet {
  Eigen::MatrixXi adjacent;     ///< m×3 face across the edge opposite corner c, −1 on the boundary
  Eigen::MatrixXd edge_length;  ///< m×3 |e_ij|
  Eigen::MatrixXd theta;        ///< m×3 bending angle θ_ij (radians, convex positive, 0 on the boundary)
  Eigen::MatrixXd edge_H;       ///< m×3 H_ij = ½|e_ij| tan(θ_ij/2) (length)
  Eigen::MatrixXd normal;       ///< m×3 unit face normals n_i (counter-clockwise faces: right-handed)
  Eigen::VectorXd area;         ///< m face areas
  Eigen::VectorXd H;            ///< m integrated face mean curvature H_i (eq. 9, length)
  Eigen::VectorXd h;            ///< m half-density h_i = H_i / sqrt(Area_i) (eq. 10, dimensionless)
  double willmore = 0.0;        ///< W = Σ h_i² (eq. 11)

  /// Hyperedge E_ij (eq. 12) of slot (f, c) as a quaternion (w, x, y, z) = (2 H_ij, e_ij).
  Eigen::Vector4d hyperedge(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index f, int c) const;
};

/// Inputs: V (n×3), F (m×3, counter-clockwise). Output: the net above. Requires a manifold, oriented
/// mesh without degenerate faces (boundaries allowed); otherwise Error naming the defect. Error naming
/// the edge when two adjacent faces fold onto each other (|θ| = π: tan(θ/2) undefined).
EdgeConstraintNet edge_constraint_net(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: the face-based discrete Willmore energy Σ H_i²/Area_i (Ye eq. 11).
double face_willmore_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
