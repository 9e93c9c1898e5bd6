#include "spinmotor/render/render_mesh.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/offscreen_context.hpp"

namespace spinmotor::render {
namespace {

// "a,b[,c]" → numbers; Error naming the option on anything else.
std::vector<double> parse_list(const std::string& s, const char* option, std::size_t lo, std::size_t hi) {
  std::vector<double> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw Error(std::string(option) + ": '" + item + "' is not a finite number (in '" + s + "')");
    out.push_back(v);
  }
  if (out.size() < lo || out.size() > hi)
    throw Error(std::string(option) + ": expected " + std::to_string(lo) +
                (lo == hi ? "" : "-" + std::to_string(hi)) + " comma-separated numbers, got '" + s + "'");
  return out;
}
}  // namespace

void parse_size(const std::string& text, RenderOptions& o, const char* option) {
  int w = 0, h = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
    throw Error(std::string(option) + ": expected WxH with 1 <= W, H <= 16384, got '" + text + "'");
  o.width = w, o.height = h;
}

void parse_camera(const std::string& text, RenderOptions& o, const char* option) {
  const auto c = parse_list(text, option, 2, 3);
  o.azimuth_deg = c[0], o.elevation_deg = c[1];
  if (c.size() == 3) {
    if (!(c[2] > 0))
      throw Error(std::string(option) + ": distance must be positive, got " + std::to_string(c[2]));
    o.distance = c[2];
  }
}

void parse_q_range(const std::string& text, RenderOptions& o, const char* option) {
  const auto q = parse_list(text, option, 2, 2);
  if (!(q[0] >= 1 && q[1] > q[0]))
    throw Error(std::string(option) + ": expected 1 <= LO < HI, got '" + text + "'");
  o.style.q_min = q[0], o.style.q_max = q[1];
}

OrbitCamera render_camera(const Eigen::MatrixXd& V, const RenderOptions& o) {
  OrbitCamera cam = frame_bounding_box(V, double(o.width) / o.height, o.azimuth_deg, o.elevation_deg, o.up);
  if (o.distance) {
    if (!(*o.distance > 0))
      throw Error("camera distance must be positive, got " + std::to_string(*o.distance));
    cam.distance = *o.distance;
  }
  return cam;
}

Image render_mesh(const Mesh& mesh, const Mesh* rest, const RenderOptions& o, RenderTimings* timings) {
  if (o.width < 1 || o.height < 1 || o.width > 16384 || o.height > 16384)
    throw Error("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                " outside [1, 16384]");
  Eigen::VectorXd Q;
  if (o.style.color == ColorMode::Q) {
    if (!rest) throw Error("colour mode q needs the rest mesh (--rest)");
    if (rest->V.rows() != mesh.V.rows() || rest->F.rows() != mesh.F.rows() || rest->F != mesh.F)
      throw Error("rest mesh has " + std::to_string(rest->V.rows()) + " vertices / " +
                  std::to_string(rest->F.rows()) + " faces, the mesh " + std::to_string(mesh.V.rows()) +
                  " / " + std::to_string(mesh.F.rows()) +
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
