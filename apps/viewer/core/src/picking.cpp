#include "spinmotor/viewer/picking.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace spinmotor::viewer {

std::optional<TriangleHit> intersect_ray_triangle(const render::Ray& ray, const Eigen::Vector3d& a,
                                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = ray.direction.cross(e2);
  const double det = e1.dot(p);
  const double scale = e1.norm() * e2.norm();
  if (!(std::abs(det) > 1e-14 * scale)) return std::nullopt;  // parallel (or degenerate triangle)
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = ray.origin - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = ray.direction.dot(q) * inv;
  if (v < 0 || u + v > 1) return std::nullopt;
  const double t = e2.dot(q) * inv;
  if (!(t > 0)) return std::nullopt;
  return TriangleHit{t, u, v};
}

std::optional<MeshHit> pick(const render::Ray& ray, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  MeshHit best;
  best.t = std::numeric_limits<double>::infinity();
  double bu = 0, bv = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const auto h = intersect_ray_triangle(ray, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
    if (h && h->t < best.t) best.t = h->t, best.face = f, bu = h->u, bv = h->v;
  }
  if (best.face < 0) return std::nullopt;
  best.point = ray.origin + best.t * ray.direction;
  const double w[3] = {1 - bu - bv, bu, bv};
  const int k = w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2);
  best.vertex = F(best.face, k);
  return best;
}

std::vector<int> vertices_in_sphere(const Eigen::MatrixXd& V, const Eigen::Vector3d& centre, double radius) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if ((V.row(i).transpose() - centre).squaredNorm() <= radius * radius) out.push_back(int(i));
  return out;
}

}  // namespace spinmotor::viewer
