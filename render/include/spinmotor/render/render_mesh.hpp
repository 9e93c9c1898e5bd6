#pragma once
// One picture of a mesh without a window: `spinmotor render`, the README gallery and the tests.
//
//   RenderOptions o;  o.color = ColorMode::Q;  o.width = 1024;  o.height = 768;
//   Image im = render_mesh(deformed, &rest, o);     // Q of deformed vs rest, with a colour bar
//   write_png("out.png", im);
//
// Creates an OffscreenContext for the call (EGL surfaceless, EGL pbuffer or OSMesa; see
// offscreen_context.hpp), so it needs no X server.
#include <optional>
#include <string>

#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/render/image.hpp"
#include "spinmotor/render/mesh_renderer.hpp"
#include "spinmotor/render/orbit_camera.hpp"

namespace spinmotor::render {

struct RenderOptions {
  int width = 800, height = 600;
  RenderStyle style;
  double azimuth_deg = 30, elevation_deg = 20;
  std::optional<double> distance;  ///< eye–target distance; default frames the bounding box
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  bool color_bar = true;  ///< with ColorMode::Q
  int samples = 4;        ///< MSAA samples
};

struct RenderTimings {
  double context_ms = 0;  ///< context creation + program compilation
  double upload_ms = 0;   ///< set_mesh (GPU vertices, buffers) + Q
  double draw_ms = 0;     ///< draw + read back (includes the rasterisation)
  std::string backend;    ///< OffscreenContext::description()
};

/// Parses "WxH" (1 ≤ W, H ≤ 16384) into options.width/height; Error naming `option` otherwise.
void parse_size(const std::string& text, RenderOptions& options, const char* option = "--size");
/// Parses "AZ,EL[,DIST]" (degrees, degrees, distance > 0) into the options; Error naming `option` otherwise.
void parse_camera(const std::string& text, RenderOptions& options, const char* option = "--camera");
/// Parses "LO,HI" (1 ≤ LO < HI) into options.style.q_min/q_max; Error naming `option` otherwise.
void parse_q_range(const std::string& text, RenderOptions& options, const char* option = "--q-range");

/// The camera render_mesh uses for `V` (target the box centre, framing distance unless given).
OrbitCamera render_camera(const Eigen::MatrixXd& V, const RenderOptions& options);

/// Renders `mesh`; with ColorMode::Q the per-face quasi-conformal error of mesh.V against rest->V
/// (same connectivity) is shown, so `rest` is required then. Throws Error on bad input (mismatched
/// sizes, Q mode without rest, non-finite coordinates, size out of range) or when no context can be made.
Image render_mesh(const Mesh& mesh, const Mesh* rest, const RenderOptions& options,
                  RenderTimings* timings = nullptr);

}  // namespace spinmotor::render
