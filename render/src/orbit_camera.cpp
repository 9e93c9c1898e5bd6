#include "spinmotor/render/orbit_camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "spinmotor/core/error.hpp"

namespace spinmotor::render {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// Orthonormal basis of the ground plane (orthogonal to up): b is the eye direction at azimuth 0, a the
// one at azimuth 90 (a = up × b). up = +y: b = +z, a = +x. up = +z: b = −y (front view), a = +x.
void ground_basis(const Eigen::Vector3d& up, Eigen::Vector3d& a, Eigen::Vector3d& b) {
  const Eigen::Vector3d u = up.normalized();
  Eigen::Vector3d ref = std::abs(u.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(0, -1, 0);
  b = (ref - ref.dot(u) * u).normalized();
  a = u.cross(b);
}
}  // namespace

Eigen::Vector3d OrbitCamera::eye() const {
  Eigen::Vector3d a, b;
  ground_basis(up, a, b);
  const double el = std::clamp(elevation_deg, -89.9, 89.9) * kDeg, az = azimuth_deg * kDeg;
  const Eigen::Vector3d dir =
      std::cos(el) * (std::cos(az) * b + std::sin(az) * a) + std::sin(el) * up.normalized();
  return target + distance * dir;
}

Eigen::Matrix4d OrbitCamera::view() const {
  const Eigen::Vector3d e = eye();
  const Eigen::Vector3d f = (target - e).normalized();
  const Eigen::Vector3d s = f.cross(up.normalized()).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.block<1, 3>(0, 0) = s.transpose();
  M.block<1, 3>(1, 0) = u.transpose();
  M.block<1, 3>(2, 0) = -f.transpose();
  M(0, 3) = -s.dot(e);
  M(1, 3) = -u.dot(e);
  M(2, 3) = f.dot(e);
  return M;
}

Eigen::Matrix4d OrbitCamera::projection(double aspect) const {
  const double n = std::max(1e-4 * distance, distance - 4 * scene_radius);
  const double far = distance + 4 * scene_radius;
  const double t = 1.0 / std::tan(0.5 * fovy_deg * kDeg);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = t / aspect;
  P(1, 1) = t;
  P(2, 2) = -(far + n) / (far - n);
  P(2, 3) = -2 * far * n / (far - n);
  P(3, 2) = -1;
  return P;
}

Eigen::Vector3d OrbitCamera::project(const Eigen::Vector3d& p, int width, int height) const {
  const Eigen::Vector4d pe = view() * p.homogeneous();
  const Eigen::Vector4d c = projection(double(width) / height) * pe;
  return {(c.x() / c.w() * 0.5 + 0.5) * width, (0.5 - c.y() / c.w() * 0.5) * height, -pe.z()};
}

Ray OrbitCamera::pixel_ray(double x, double y, int width, int height) const {
  const double t = std::tan(0.5 * fovy_deg * kDeg), aspect = double(width) / height;
  const double nx = 2 * x / width - 1, ny = 1 - 2 * y / height;
  const Eigen::Matrix4d V = view();
  const Eigen::Matrix3d R = V.topLeftCorner<3, 3>().transpose();  // eye → world
  const Eigen::Vector3d d_eye(nx * t * aspect, ny * t, -1);
  return {eye(), (R * d_eye).normalized()};
}

void OrbitCamera::orbit(double d_azimuth, double d_elevation) {
  azimuth_deg = std::fmod(azimuth_deg + d_azimuth, 360.0);
  elevation_deg = std::clamp(elevation_deg + d_elevation, -89.0, 89.0);
}

void OrbitCamera::pan(double dx, double dy, int width, int height) {
  const Eigen::Matrix3d R = view().topLeftCorner<3, 3>();
  const double units_per_pixel = 2 * distance * std::tan(0.5 * fovy_deg * kDeg) / height;
  target += units_per_pixel * (-dx * R.row(0).transpose() + dy * R.row(1).transpose());
}

void OrbitCamera::zoom(double factor) {
  if (factor > 0 && std::isfinite(factor)) distance *= factor;
}

OrbitCamera frame_bounding_box(const Eigen::MatrixXd& V, double aspect, double azimuth_deg,
                               double elevation_deg, const Eigen::Vector3d& up, double margin) {
  if (V.rows() == 0 || V.cols() != 3) throw Error("frame_bounding_box: expected n×3 vertices with n > 0");
  if (!V.allFinite()) throw Error("frame_bounding_box: non-finite vertex coordinates");
  if (!(aspect > 0)) throw Error("frame_bounding_box: aspect must be positive");
  OrbitCamera cam;
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  cam.target = (0.5 * (lo + hi)).transpose();
  cam.scene_radius = std::max(0.5 * (hi - lo).norm(), 1e-12);
  cam.up = up.normalized();
  cam.azimuth_deg = azimuth_deg;
  cam.elevation_deg = elevation_deg;
  const double half_fovy = 0.5 * cam.fovy_deg * kDeg;
  const double half_fovx = std::atan(std::tan(half_fovy) * aspect);
  cam.distance = margin * cam.scene_radius / std::sin(std::min(half_fovy, half_fovx));
  return cam;
}

}  // namespace spinmotor::render
