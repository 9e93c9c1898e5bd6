#include "spinmotor/viewer/selection.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "spinmotor/core/error.hpp"

namespace spinmotor::viewer {
namespace {

/// OrbitCamera::project with the matrices computed once: (pixel x, pixel y, eye depth); depth ≤ 0 is
/// behind the eye.
struct Projector {
  Eigen::Matrix4d view, clip;
  double w, h;
  Projector(const render::OrbitCamera& cam, int width, int height)
      : view(cam.view()), clip(cam.projection(double(width) / height) * view), w(width), h(height) {}
  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const {
    const Eigen::Vector4d c = clip * p.homogeneous();
    const double depth = -(view.row(2).head<3>().dot(p) + view(2, 3));
    if (!(depth > 0)) return {0, 0, depth};
    return {(c.x() / c.w() * 0.5 + 0.5) * w, (0.5 - c.y() / c.w() * 0.5) * h, depth};
  }
};

template <class Inside>
std::vector<int> select(const Eigen::MatrixXd& V, const render::OrbitCamera& cam, int w, int h,
                        const DepthMap* depth, Inside inside) {
  if (w <= 0 || h <= 0) throw Error("selection: the view size must be positive");
  const Projector project(cam, w, h);
  const double tolerance = 2e-3 * cam.distance;
  std::vector<int> out;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d s = project(V.row(i).transpose());
    if (!(s.z() > 0) || !inside(Eigen::Vector2d(s.x(), s.y()))) continue;
    if (depth && !depth->visible(s.x(), s.y(), s.z(), tolerance)) continue;
    out.push_back(int(i));
  }
  return out;
}

}  // namespace

DepthMap DepthMap::render(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const render::OrbitCamera& cam,
                          int width, int height) {
  if (width <= 0 || height <= 0) throw Error("DepthMap: the view size must be positive");
  DepthMap d;
  d.width_ = width, d.height_ = height;
  d.depth_.assign(std::size_t(width) * height, std::numeric_limits<float>::infinity());
  const Projector project(cam, width, height);
  std::vector<Eigen::Vector3d> S(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) S[i] = project(V.row(i).transpose());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d& a = S[F(f, 0)];
    const Eigen::Vector3d& b = S[F(f, 1)];
    const Eigen::Vector3d& c = S[F(f, 2)];
    if (!(a.z() > 0 && b.z() > 0 && c.z() > 0)) continue;  // crosses the eye plane: not drawn
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (!(std::abs(area) > 1e-12)) continue;
    const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(width - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(height - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;  // pixel centre
        // Barycentrics in screen space; 1/depth is affine there (perspective-correct depth).
        const double wa = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const double wb = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double z = 1.0 / (wa / a.z() + wb / b.z() + wc / c.z());
        float& slot = d.depth_[std::size_t(y) * width + x];
        slot = std::min(slot, float(z));
      }
  }
  return d;
}

double DepthMap::depth(int x, int y) const {
  x = std::clamp(x, 0, width_ - 1), y = std::clamp(y, 0, height_ - 1);
  return depth_[std::size_t(y) * width_ + x];
}

bool DepthMap::visible(double px, double py, double d, double tolerance) const {
  // The farthest depth in the 3×3 pixels around the point: a vertex lies on its own triangles, whose
  // depth at the neighbouring pixel centres varies by the surface slope, and a silhouette vertex may
  // have background next to it. A vertex behind the surface has only nearer depths around it.
  const int cx = int(std::floor(px)), cy = int(std::floor(py));
  double farthest = -std::numeric_limits<double>::infinity();
  for (int y = cy - 1; y <= cy + 1; ++y)
    for (int x = cx - 1; x <= cx + 1; ++x)
      if (x >= 0 && y >= 0 && x < width_ && y < height_) farthest = std::max(farthest, depth(x, y));
  return !(d > farthest + tolerance);
}

bool point_in_polygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

std::vector<int> vertices_in_box(const Eigen::MatrixXd& V, const render::OrbitCamera& cam, int w, int h,
                                 const Eigen::Vector2d& a, const Eigen::Vector2d& b, const DepthMap* depth) {
  const Eigen::Vector2d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  return select(V, cam, w, h, depth, [&](const Eigen::Vector2d& p) {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  });
}

std::vector<int> vertices_in_lasso(const Eigen::MatrixXd& V, const render::OrbitCamera& cam, int w, int h,
                                   const std::vector<Eigen::Vector2d>& lasso, const DepthMap* depth) {
  if (lasso.size() < 3) return {};
  Eigen::Vector2d lo = lasso[0], hi = lasso[0];
  for (const auto& p : lasso) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return select(V, cam, w, h, depth, [&](const Eigen::Vector2d& p) {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all() && point_in_polygon(p, lasso);
  });
}

std::vector<int> selection_union(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> out;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

std::vector<int> selection_difference(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> out;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

}  // namespace spinmotor::viewer
