#include "spinmotor/viewer/gizmo.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace spinmotor::viewer {

std::optional<double> axis_parameter(const render::Ray& ray, const Eigen::Vector3d& centre,
                                     const Eigen::Vector3d& axis) {
  // Closest points of the lines centre + s a and o + t d: solve the 2×2 normal equations.
  const Eigen::Vector3d a = axis.normalized(), d = ray.direction.normalized(), w = centre - ray.origin;
  const double b = a.dot(d), den = 1 - b * b;
  if (den < 1e-9) return std::nullopt;
  return (b * d.dot(w) - a.dot(w)) / den;
}

std::optional<double> ring_angle(const render::Ray& ray, const Eigen::Vector3d& centre,
                                 const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = axis.normalized();
  const double dn = ray.direction.dot(a);
  if (std::abs(dn) < 1e-9) return std::nullopt;
  const double t = (centre - ray.origin).dot(a) / dn;
  const Eigen::Vector3d r = ray.origin + t * ray.direction - centre;
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);  // right-handed about a
  return std::atan2(r.dot(e2), r.dot(e1));
}

GizmoDrag begin_drag(GizmoMode mode, int axis_index, const Eigen::Vector3d& centre, const ga::Mot& start,
                     const render::Ray& ray) {
  GizmoDrag d;
  d.mode = mode;
  d.centre = centre;
  d.axis = Eigen::Vector3d::Unit(std::clamp(axis_index, 0, 2));
  d.start = start;
  const auto v =
      mode == GizmoMode::Translate ? axis_parameter(ray, centre, d.axis) : ring_angle(ray, centre, d.axis);
  d.valid = v.has_value();
  d.start_value = v.value_or(0);
  return d;
}

ga::Mot drag_motor(const GizmoDrag& drag, const render::Ray& ray) {
  if (!drag.valid) return drag.start;
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  if (drag.mode == GizmoMode::Translate) {
    const auto s = axis_parameter(ray, drag.centre, drag.axis);
    if (!s) return drag.start;
    D.translation() = (*s - drag.start_value) * drag.axis;
  } else {
    const auto phi = ring_angle(ray, drag.centre, drag.axis);
    if (!phi) return drag.start;
    // Rotation by the angle change about the axis line through the centre: x ↦ R (x − c) + c.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(*phi - drag.start_value, drag.axis).toRotationMatrix();
    D.linear() = R;
    D.translation() = drag.centre - R * drag.centre;
  }
  return ga::from_isometry(D * ga::to_isometry(drag.start));
}

std::optional<ga::Mot> simulated_drag(const render::OrbitCamera& cam, int w, int h, GizmoMode mode,
                                      int axis_index, const Eigen::Vector3d& c, double radius,
                                      const ga::Mot& start, double amount) {
  const Eigen::Vector3d a = Eigen::Vector3d::Unit(std::clamp(axis_index, 0, 2));
  auto ray_through = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d px = cam.project(p, w, h);
    return cam.pixel_ray(px.x(), px.y(), w, h);
  };
  Eigen::Vector3d press, release;
  if (mode == GizmoMode::Translate) {
    press = c + radius * a;
    release = press + amount * a;
  } else {
    const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
    const double phi = amount * std::numbers::pi / 180;
    press = c + radius * e1;
    release = c + radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
  }
  const GizmoDrag d = begin_drag(mode, axis_index, c, start, ray_through(press));
  if (!d.valid) return std::nullopt;
  return drag_motor(d, ray_through(release));
}

Eigen::Vector3d posed_centroid(const Eigen::MatrixXd& V_rest, const std::vector<int>& vertices,
                               const ga::Mot& m) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  if (vertices.empty()) return c;
  for (int i : vertices) c += V_rest.row(i).transpose();
  c /= double(vertices.size());
  return ga::to_isometry(m) * c;  // the centroid of rigidly moved points is the moved centroid
}

}  // namespace spinmotor::viewer
