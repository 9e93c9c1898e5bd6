// Offscreen renderer (render/): camera maths, a normal-coloured sphere whose silhouette is the
// disk the camera predicts, Q colouring of a twisted capsule vs its conformal snap, the checkerboard,
// and `spinmotor render` (PNG written atomically, exit 2 without output on bad input).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/spin/conformal_snap.hpp"

namespace test_render {

using namespace spinmotor;
using namespace spinmotor::render;
using Eigen::MatrixXd;
using Eigen::Vector3d;

namespace {

bool is_background(const Image& im, int x, int y) {
  const auto p = im.pixel(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

struct Disk {
  double area = 0, cx = 0, cy = 0;
};
Disk coverage(const Image& im) {
  Disk d;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      if (!is_background(im, x, y)) d.area += 1, d.cx += x + 0.5, d.cy += y + 0.5;
  if (d.area > 0) d.cx /= d.area, d.cy /= d.area;
  return d;
}

MatrixXd twist_z(const MatrixXd& V, double degrees, double z0, double z1) {
  MatrixXd out = V;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double a = degrees * std::numbers::pi / 180.0 * (V(i, 2) - z0) / (z1 - z0);
    out(i, 0) = std::cos(a) * V(i, 0) - std::sin(a) * V(i, 1);
    out(i, 1) = std::sin(a) * V(i, 0) + std::cos(a) * V(i, 1);
  }
  return out;
}

// Pixels of the mesh whose colour lies on the warm half of the Q map (red above blue).
double warm_fraction(const Image& im) {
  double mesh = 0, warm = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width * 3 / 4; ++x) {  // left of the colour bar
      if (is_background(im, x, y)) continue;
      const auto p = im.pixel(x, y);
      mesh += 1;
      warm += p[0] > p[2] ? 1 : 0;
    }
  return mesh > 0 ? warm / mesh : 0;
}

}  // namespace

TEST_CASE("orbit camera: the target projects to the centre, pixel rays go through projected points",
          "[render]") {
  OrbitCamera cam;
  cam.target = Vector3d(1, 2, 3);
  cam.distance = 5, cam.azimuth_deg = 40, cam.elevation_deg = 25;
  CHECK((cam.eye() - cam.target).norm() == Approx(5));
  const Vector3d c = cam.project(cam.target, 640, 480);
  CHECK(c.x() == Approx(320));
  CHECK(c.y() == Approx(240));
  CHECK(c.z() == Approx(5));
  const Vector3d p(1.3, 2.4, 2.9);
  const Vector3d px = cam.project(p, 640, 480);
  const Ray r = cam.pixel_ray(px.x(), px.y(), 640, 480);
  const Vector3d to_p = p - r.origin;
  CHECK((to_p - to_p.dot(r.direction) * r.direction).norm() < 1e-9);
  // Azimuth 0, elevation 0, up +y: the eye is on +z; +x is to the right, +y up (smaller pixel y).
  OrbitCamera front;
  front.distance = 4, front.azimuth_deg = 0, front.elevation_deg = 0;
  CHECK((front.eye() - Vector3d(0, 0, 4)).norm() < 1e-12);
  CHECK(front.project(Vector3d(0.5, 0, 0), 100, 100).x() > 50);
  CHECK(front.project(Vector3d(0, 0.5, 0), 100, 100).y() < 50);
  // up +z, azimuth 0: the eye is on −y (front view).
  front.up = Vector3d::UnitZ();
  CHECK((front.eye() - Vector3d(0, -4, 0)).norm() < 1e-12);
  // Framing: a bounding sphere of radius r at distance d subtends asin(r/d) < half the field of view.
  const OrbitCamera fr = frame_bounding_box(icosphere(2).V, 2.0);
  CHECK(std::asin(fr.scene_radius / fr.distance) < 0.5 * fr.fovy_deg * std::numbers::pi / 180);
  CHECK_THROWS_AS(frame_bounding_box(MatrixXd(0, 3), 1.0), Error);
}

TEST_CASE("a unit sphere in normal colours is the disk the camera predicts", "[render]") {
  const Mesh sphere = icosphere(5);  // 10,242 vertices: its silhouette is within 0.05% of the sphere's
  RenderOptions o;
  o.width = 300, o.height = 240;
  o.azimuth_deg = 0, o.elevation_deg = 0, o.distance = 4.0;
  o.style.color = ColorMode::Normals;
  RenderTimings t;
  const Image im = render_mesh(sphere, nullptr, o, &t);
  INFO("backend " << t.backend);
  REQUIRE(im.width == 300);
  REQUIRE(im.height == 240);
  const Disk d = coverage(im);
  REQUIRE(d.area > 0);
  // Perspective silhouette of a unit sphere at distance 4: a cone of half-angle asin(1/4); its image
  // radius in pixels is (h/2) tan(asin(1/4)) / tan(fovy/2).
  const OrbitCamera cam = render_camera(sphere.V, o);
  const double r =
      0.5 * o.height * std::tan(std::asin(1.0 / 4.0)) / std::tan(0.5 * cam.fovy_deg * std::numbers::pi / 180);
  const double r_measured = std::sqrt(d.area / std::numbers::pi);
  std::printf("sphere silhouette: radius %.2f px (predicted %.2f), centre (%.2f, %.2f); %s\n", r_measured, r,
              d.cx, d.cy, t.backend.c_str());
  CHECK(std::abs(r_measured - r) < 1.5);
  CHECK(std::abs(d.cx - 150) < 0.5);
  CHECK(std::abs(d.cy - 120) < 0.5);
  // Every pixel well inside the disk is covered, every one well outside is background.
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const double rho = std::hypot(x + 0.5 - 150, y + 0.5 - 120);
      if (rho < r - 2) REQUIRE_FALSE(is_background(im, x, y));
      if (rho > r + 2) REQUIRE(is_background(im, x, y));
    }
  // Colours are ½(n + 1): the centre faces the eye (+z), the right rim +x, the top rim +y.
  const auto centre = im.pixel(150, 120), right = im.pixel(150 + int(0.85 * r), 120),
             top = im.pixel(150, 120 - int(0.85 * r)), left = im.pixel(150 - int(0.85 * r), 120);
  CHECK(std::abs(centre[0] - 128) <= 4);
  CHECK(std::abs(centre[1] - 128) <= 4);
  CHECK(centre[2] >= 250);
  CHECK(right[0] > 200);
  CHECK(left[0] < 55);
  CHECK(top[1] > 200);
}

TEST_CASE("Q colouring of a twisted capsule turns blue after its conformal snap", "[render]") {
  const Mesh rest = capsule(0.5, 3.0, 48, 24);
  Mesh twisted = rest;
  twisted.V = twist_z(rest.V, 90, -0.5, 3.5);
  Mesh snapped = rest;
  snapped.V = ConformalSnap(rest).snap(twisted.V).V;
  const double q_twist = quasi_conformal_summary(rest.V, rest.F, twisted.V).q_mean;
  const double q_snap = quasi_conformal_summary(rest.V, rest.F, snapped.V).q_mean;
  RenderOptions o;
  o.width = 320, o.height = 240;
  o.up = Vector3d::UnitZ();
  o.azimuth_deg = 0, o.elevation_deg = 10;
  o.style.color = ColorMode::Q;
  o.style.q_min = 1.0, o.style.q_max = 1.3;
  const Image a = render_mesh(twisted, &rest, o), b = render_mesh(snapped, &rest, o);
  const double wa = warm_fraction(a), wb = warm_fraction(b);
  std::printf("twisted capsule: Q_mean %.4f, warm pixels %.3f; snapped: Q_mean %.4f, warm pixels %.3f\n",
              q_twist, wa, q_snap, wb);
  REQUIRE(q_twist > 1.05);
  REQUIRE(q_snap < 1.02);
  CHECK(wa > 0.5);
  CHECK(wb < 0.05);
  // The colour bar: red at its top, blue at its bottom.
  const int bar_x = o.width - std::max(10, o.width / 50) / 2 - 52, top = (o.height - o.height / 2) / 2 + 2;
  const auto hi = a.pixel(bar_x, top), lo = a.pixel(bar_x, top + o.height / 2 - 4);
  CHECK(hi[0] > 150);
  CHECK(hi[2] < 80);
  CHECK(lo[2] > 130);
  CHECK(lo[0] < 80);
  // Without a rest mesh Q cannot be shown.
  CHECK_THROWS_AS(render_mesh(twisted, nullptr, o), Error);
  Mesh other = icosphere(1);
  CHECK_THROWS_AS(render_mesh(twisted, &other, o), Error);
}

TEST_CASE("the checkerboard follows the texture coordinates", "[render]") {
  const Mesh g = grid(Eigen::Vector2d(2, 2), Eigen::Vector2i(20, 20));
  RenderOptions o;
  o.width = 200, o.height = 200;
  o.up = Vector3d::UnitY();
  o.azimuth_deg = 0, o.elevation_deg = 0;
  o.style.color = ColorMode::Checker;
  o.style.checker_cells = 4.5;
  const Image im = render_mesh(g, nullptr, o);
  // Along the horizontal centre line u runs over [0, 1], i.e. 4.5 cells: the colour switches between
  // orange and white at u·4.5 = 1, 2, 3, 4 (the half cell keeps u = 1 off a cell boundary).
  int switches = 0, prev = -1;
  for (int x = 0; x < im.width; ++x) {
    if (is_background(im, x, 100)) continue;
    const auto p = im.pixel(x, 100);
    const int orange = p[0] - p[2] > 80 ? 1 : 0;
    if (prev >= 0 && orange != prev) ++switches;
    prev = orange;
  }
  CHECK(switches == 4);
}

TEST_CASE("spinmotor render writes a PNG, bad input exits 2 without output", "[render][cli]") {
  const auto dir = std::filesystem::temp_directory_path() / "spinmotor_test_render";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_mesh(dir / "sphere.obj", icosphere(3));
  Mesh t = capsule(0.5, 2.0, 16, 12);
  write_mesh(dir / "rest.obj", t);
  t.V = twist_z(t.V, 60, -0.5, 2.5);
  write_mesh(dir / "twist.obj", t);
  auto run = [&](const std::string& args) {
    const std::string cmd =
        std::string(SPINMOTOR_CLI) + " render " + args + " > " + (dir / "log.txt").string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  const auto png = dir / "out.png";
  REQUIRE(run((dir / "sphere.obj").string() + " --color normals --size 64x48 --out " + png.string()) == 0);
  REQUIRE(std::filesystem::exists(png));
  std::ifstream in(png, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  CHECK(std::string(sig + 1, 3) == "PNG");
  REQUIRE(run((dir / "twist.obj").string() + " --rest " + (dir / "rest.obj").string() +
              " --color q --camera 10,20 --up z --out " + (dir / "q.png").string()) == 0);
  CHECK(std::filesystem::exists(dir / "q.png"));
  const auto bad = dir / "bad.png";
  CHECK(run((dir / "missing.obj").string() + " --out " + bad.string()) == 2);
  CHECK(run((dir / "twist.obj").string() + " --color q --out " + bad.string()) == 2);  // no --rest
  CHECK(run((dir / "twist.obj").string() + " --rest " + (dir / "sphere.obj").string() + " --color q --out " +
            bad.string()) == 2);
  CHECK(run((dir / "sphere.obj").string() + " --size 0x10 --out " + bad.string()) == 2);
  CHECK(run((dir / "sphere.obj").string() + " --camera 10,abc --out " + bad.string()) == 2);
  CHECK_FALSE(std::filesystem::exists(bad));
  int leftovers = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    leftovers += e.path().filename().string().find("bad") != std::string::npos ? 1 : 0;
  CHECK(leftovers == 0);
  std::filesystem::remove_all(dir);
}

}  // namespace test_render
