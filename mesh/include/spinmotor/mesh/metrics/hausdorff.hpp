#pragma once
// Point-to-surface distances and the (vertex-sampled) Hausdorff distance between two triangle
// meshes of any connectivity.
//
// Distances are exact Euclidean distances to the closest point of the closest triangle (Ericson,
// Real-Time Collision Detection, §5.1.5), found with a bounding-volume hierarchy (axis-aligned boxes,
// median splits) and best-first traversal; queries run in parallel. The one-sided distance from A to B
// is sampled at A's vertices: max_i dist(a_i, B), a lower bound of the continuous one-sided Hausdorff
// distance that is exact when the farthest point of A is a vertex (e.g. for a translated copy).
#include <Eigen/Core>

namespace spinmotor {

/// Inputs: P (k×3) query points, V (n×3), F (m×3, m ≥ 1) the surface. Output: k distances (units of V);
/// if closest_face is given, it receives the index of a closest triangle per point.
/// Throws Error on non-finite coordinates, no faces or an index out of range.
Eigen::VectorXd point_mesh_distances(const Eigen::MatrixXd& P, const Eigen::MatrixXd& V,
                                     const Eigen::MatrixXi& F, Eigen::VectorXi* closest_face = nullptr);

struct HausdorffDistance {
  double a_to_b = 0.0;       ///< max over A's vertices of the distance to surface B
  double b_to_a = 0.0;       ///< max over B's vertices of the distance to surface A
  double hausdorff = 0.0;    ///< max(a_to_b, b_to_a)
  double mean_a_to_b = 0.0;  ///< mean over A's vertices (referenced by A's faces) of the distance to B
  double mean_b_to_a = 0.0;
};

/// Inputs: mesh A (VA, FA) and mesh B (VB, FB), connectivity independent. Output: as above, sampled
/// at the vertices referenced by the faces. Throws Error as point_mesh_distances.
HausdorffDistance hausdorff_distance(const Eigen::MatrixXd& VA, const Eigen::MatrixXi& FA,
                                     const Eigen::MatrixXd& VB, const Eigen::MatrixXi& FB);

}  // namespace spinmotor
