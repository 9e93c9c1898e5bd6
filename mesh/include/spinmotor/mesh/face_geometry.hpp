#pragma once
// Per-face geometry of a triangle mesh: areas, unit normals, edge lengths, corner angles and the
// cotangents of the corner angles — the ingredients of every discrete operator in this module.
//
// Corner convention (shared with topology.hpp): corner c of face f is vertex F(f,c); the edge
// opposite corner c joins F(f,c+1) and F(f,c+2) (indices mod 3), i.e. it is edge FE(f,c).
//
// Degenerate faces. A face is degenerate when twice its area is at roundoff level relative to its
// longest edge: |(x1−x0)×(x2−x0)| ≤ 16·ε·ℓ²max (ε = machine epsilon): collinear or coincident
// corners. Quantities that divide by the area (normals, cotangents, gradients, mean-value weights,
// Voronoi areas) throw spinmotor::Error naming the face instead of returning Inf/NaN; face_areas and
// corner_angles are well defined there and do not throw. All functions also throw on F indices out of
// range, on non-finite coordinates and on V/F without 3 columns.
#include <Eigen/Core>
#include <limits>

namespace spinmotor {

/// The 16·ε above: a face with |(x1−x0)×(x2−x0)| ≤ kDegenerateFace·ℓ²max is degenerate.
inline constexpr double kDegenerateFace = 16.0 * std::numeric_limits<double>::epsilon();

/// Inputs: V (n×3), F (m×3). Output: m areas (units of V squared). Zero for a degenerate face.
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3, counter-clockwise). Output: m×3 unit normals, (x1−x0)×(x2−x0) normalised,
/// so they point outward on a closed surface whose faces are counter-clockwise seen from outside.
/// Throws Error naming the first degenerate face.
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: m×3, entry (f,c) = length of the edge opposite corner c.
Eigen::MatrixXd face_edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: m×3 interior angles in radians, entry (f,c) = angle at corner c
/// (computed as atan2(|a×b|, a·b), accurate for all angles). The three angles of a face sum to π.
Eigen::MatrixXd corner_angles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Inputs: V (n×3), F (m×3). Output: m×3, entry (f,c) = cot of the angle at corner c, i.e. the cotangent
/// weight of the edge opposite corner c: (a·b)/|a×b| with a, b the edges leaving the corner.
/// Throws Error naming the first degenerate face.
Eigen::MatrixXd cotangents(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace spinmotor
