#pragma once
// The viewer's gizmo maths (window-free, unit-tested): dragging an axis arrow translates a handle's
// motor along that world axis; dragging a ring rotates it about that axis through the gizmo centre.
// The window code only turns mouse positions into rays (OrbitCamera::pixel_ray) and calls drag_motor.
//
//   GizmoDrag d = begin_drag(GizmoMode::Rotate, 2, centre, motor_at_press, ray_at_press);
//   ... every mouse move: pose.motors[name] = drag_motor(d, ray_now);
//
// The new motor is the drag's rigid motion applied after the motor at the press: M = D · M₀, i.e. the
// handle keeps what it had and then moves with the mouse (X' = D M₀ X ~M₀ ~D).
#include <Eigen/Core>
#include <optional>

#include "spinmotor/ga.hpp"
#include "spinmotor/render/orbit_camera.hpp"

namespace spinmotor::viewer {

enum class GizmoMode { Translate, Rotate };

struct GizmoDrag {
  GizmoMode mode = GizmoMode::Translate;
  Eigen::Vector3d centre =
      Eigen::Vector3d::Zero();  ///< where the gizmo is drawn (the handle's posed centroid)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< unit world axis
  ga::Mot start;                                    ///< the motor when the drag began
  double start_value = 0;  ///< axis parameter (translate) or ring angle (rotate) at the press
  bool valid = false;      ///< false when the press ray was degenerate for this axis
};

/// Parameter s of the point centre + s·axis closest to the ray (nothing if the ray is parallel to the axis).
std::optional<double> axis_parameter(const render::Ray& ray, const Eigen::Vector3d& centre,
                                     const Eigen::Vector3d& axis);

/// Angle (radians, right-handed about axis) of the ray's intersection with the plane through centre
/// orthogonal to axis, measured in a fixed basis of that plane (nothing if the ray is parallel to it).
std::optional<double> ring_angle(const render::Ray& ray, const Eigen::Vector3d& centre,
                                 const Eigen::Vector3d& axis);

/// Starts a drag on world axis `axis_index` (0 x, 1 y, 2 z).
GizmoDrag begin_drag(GizmoMode mode, int axis_index, const Eigen::Vector3d& centre, const ga::Mot& start,
                     const render::Ray& ray);

/// The motor for the current mouse ray: D · start, with D the translation along the axis by the change
/// of axis_parameter, or the rotation about the axis line through centre by the change of ring_angle.
/// Returns `start` when the ray is degenerate (parallel) for this drag.
ga::Mot drag_motor(const GizmoDrag& drag, const render::Ray& ray);

/// A drag as the mouse makes it: press on the gizmo drawn at `centre` with size `radius` (the tip of
/// the axis arrow, or the ring at angle 0), release `amount` further (scene units along the axis, or
/// degrees around the ring). Both mouse positions are projected to pixels of `camera` (width×height)
/// and turned back into pixel rays, then begin_drag/drag_motor give the motor, exactly as in the
/// window. Nothing if the camera looks along the axis (degenerate drag).
std::optional<ga::Mot> simulated_drag(const render::OrbitCamera& camera, int width, int height,
                                      GizmoMode mode, int axis_index, const Eigen::Vector3d& centre,
                                      double radius, const ga::Mot& start, double amount);

/// Centroid of the motor-transformed rest positions of `vertices` (where the gizmo of a handle sits).
Eigen::Vector3d posed_centroid(const Eigen::MatrixXd& V_rest, const std::vector<int>& vertices,
                               const ga::Mot& m);

}  // namespace spinmotor::viewer
