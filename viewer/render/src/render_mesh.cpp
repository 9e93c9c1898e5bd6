#include "spinmotor/render/render_mesh.hpp"

#include <chrono>

#include "spinmotor/error.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/offscreen_context.hpp"

namespace spinmotor::render {
namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

OrbitCamera render_camera(const Eigen::MatrixXd& V, const RenderOptions& o) {
  OrbitCamera cam = frame_bounding_box(V, double(o.width) / o.height, o.azimuth_deg, o.elevation_deg, o.up);
  if (o.distance) {
    if (!(*o.distance > 0)) throw Error("camera distance must be positive, got " + std::to_string(*o.distance));
    cam.distance = *o.distance;
  }
  return cam;
}

Image render_mesh(const Mesh& mesh, const Mesh* rest, const RenderOptions& o, RenderTimings* timings) {
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw Error("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) + " outside [1, 16384]");
  Eigen::VectorXd Q;
  if (o.style.color == ColorMode::Q) {
    if (!rest) throw Error("colour mode q needs the rest mesh (--rest)");
    if (rest->V.rows() != mesh.V.rows() || rest->F.rows() != mesh.F.rows() || rest->F != mesh.F)
      throw Error("rest mesh has " + std::to_string(rest->V.rows()) + " vertices / " + std::to_string(rest->F.rows()) +
                  " faces, the mesh " + std::to_string(mesh.V.rows()) + " / " + std::to_string(mesh.F.rows()) +
                  " (or different faces): Q needs the same connectivity");
    Q = quasi_conformal_error(rest->V, rest->F, mesh.V);  // validates coordinates, names bad vertices/faces
  }
  const OrbitCamera cam = render_camera(mesh.V, o);  // validates V finite
  auto t0 = std::chrono::steady_clock::now();
  OffscreenContext context;
  MeshRenderer renderer;
  Framebuffer fb(o.width, o.height, o.samples);
  if (timings) timings->context_ms = ms_since(t0), timings->backend = context.description();
  t0 = std::chrono::steady_clock::now();
  renderer.set_mesh(mesh);
  if (Q.size()) renderer.set_face_values(Q);
  if (timings) timings->upload_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  fb.bind();
  renderer.draw(cam, o.width, o.height, o.style);
  Image im = fb.read();
  if (timings) timings->draw_ms = ms_since(t0);
  if (o.style.color == ColorMode::Q && o.color_bar) draw_color_bar(im, o.style.q_min, o.style.q_max);
  return im;
}

}  // namespace spinmotor::render
