#pragma once
// Orbit camera shared by `spinmotor render` and the viewer (window-free, unit-tested).
//
// The eye sits on a sphere of radius `distance` around `target`; azimuth turns about the `up` axis,
// elevation lifts towards it (degrees). With up = +y, azimuth 0 and elevation 0 the eye is on +z
// looking down −z. Perspective projection with vertical field of view `fovy_deg`; OpenGL clip
// conventions (right-handed eye space, looking down −z, depth in [−1, 1]).
// Pixel coordinates: x to the right, y down, pixel centres at half-integers, origin top-left.
#include <Eigen/Core>

namespace spinmotor::render {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  ///< unit length
};

struct OrbitCamera {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  ///< world up axis (unit)
  double azimuth_deg = 30;
  double elevation_deg = 20;  ///< clamped to (−89.9, 89.9) by eye()
  double distance = 3;        ///< eye–target distance (scene units), > 0
  double fovy_deg = 35;       ///< vertical field of view
  double scene_radius = 1;    ///< radius of the framed bounding sphere (sets the clip planes)

  Eigen::Vector3d eye() const;
  /// World → eye (4×4, rigid).
  Eigen::Matrix4d view() const;
  /// Eye → clip for a width/height `aspect`.
  Eigen::Matrix4d projection(double aspect) const;
  /// Pixel position (x right, y down, in [0, w]×[0, h]) and eye-space depth of world point p.
  Eigen::Vector3d project(const Eigen::Vector3d& p, int width, int height) const;
  /// The ray from the eye through pixel (x, y) (same pixel convention as project()).
  Ray pixel_ray(double x, double y, int width, int height) const;

  /// Orbit: add degrees of azimuth and elevation.
  void orbit(double d_azimuth, double d_elevation);
  /// Pan: move the target by (dx, dy) pixels of a width×height view (the point under the cursor follows it).
  void pan(double dx, double dy, int width, int height);
  /// Zoom: distance *= factor (> 0).
  void zoom(double factor);
};

/// A camera that frames the bounding box of V (n×3): target at the box centre, distance such that the
/// bounding sphere (half the diagonal, times `margin`) fits the smaller field of view of a view with
/// width/height `aspect`. Throws Error if V is empty or not finite.
OrbitCamera frame_bounding_box(const Eigen::MatrixXd& V, double aspect, double azimuth_deg = 30,
                               double elevation_deg = 20,
                               const Eigen::Vector3d& up = Eigen::Vector3d::UnitY(), double margin = 1.05);

}  // namespace spinmotor::render
