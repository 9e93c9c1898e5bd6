#pragma once
// Picking for the viewer (window-free): which face and point of the surface a pixel ray hits, and
// brush selection of vertices around a point.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "spinmotor/render/orbit_camera.hpp"

namespace spinmotor::viewer {

struct TriangleHit {
  double t = 0;         ///< ray parameter (distance along the unit direction), > 0
  double u = 0, v = 0;  ///< barycentrics of b and c: p = (1 − u − v) a + u b + v c
};

/// Möller–Trumbore ray–triangle intersection, both sides of the triangle. Nothing for a miss, a hit
/// behind the origin (t ≤ 0), or a ray parallel to the triangle's plane.
std::optional<TriangleHit> intersect_ray_triangle(const render::Ray& ray, const Eigen::Vector3d& a,
                                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c);

struct MeshHit {
  Eigen::Index face = -1;
  Eigen::Index vertex = -1;  ///< the face's corner nearest to the hit point
  double t = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

/// The nearest hit of `ray` on the mesh (V n×3, F m×3), brute force over faces (about 1 ms per 100k
/// faces on one core; a pick happens per click, not per frame).
std::optional<MeshHit> pick(const render::Ray& ray, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

/// Brush selection: indices of the vertices within `radius` of `centre`, ascending.
std::vector<int> vertices_in_sphere(const Eigen::MatrixXd& V, const Eigen::Vector3d& centre, double radius);

}  // namespace spinmotor::viewer
