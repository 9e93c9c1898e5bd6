// The viewer's window-free logic (apps/viewer/core): ray–triangle and mesh picking, gizmo maths (a
// simulated mouse drag gives exactly the translation / rotation it should), undo/redo, the snap
// worker's stale-result rule, the scene session (pose, undo, save), and — when the viewer is built
// and xvfb-run exists — the viewer's headless screenshot under Xvfb checked pixel by pixel.
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "spinmotor/viewer/session.hpp"
#include "spinmotor/viewer/snap_worker.hpp"
#include "spinmotor/viewer/undo_stack.hpp"

// stb_image (PNG only), private to this test.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace test_viewer_logic {

using namespace spinmotor;
using namespace spinmotor::viewer;
using Eigen::Vector3d;

namespace {
const ga::Mot kIdentity = ga::from_isometry(Eigen::Isometry3d::Identity());

Vector3d apply(const ga::Mot& m, const Vector3d& p) { return ga::to_isometry(m) * p; }

render::OrbitCamera test_camera() {
  render::OrbitCamera cam;
  cam.target = Vector3d(0.1, -0.2, 0.3);
  cam.distance = 6, cam.azimuth_deg = 35, cam.elevation_deg = 25, cam.scene_radius = 2;
  return cam;
}
}  // namespace

TEST_CASE("ray-triangle intersection: hit point, barycentrics, misses", "[viewer]") {
  const Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  const render::Ray down{Vector3d(0.5, 0.25, 3), Vector3d(0, 0, -1)};
  const auto h = intersect_ray_triangle(down, a, b, c);
  REQUIRE(h);
  CHECK(h->t == Approx(3));
  CHECK(h->u == Approx(0.25));  // p = (1-u-v) a + u b + v c = (2u, 2v, 0)
  CHECK(h->v == Approx(0.125));
  CHECK(intersect_ray_triangle({Vector3d(0.5, 0.25, 3), Vector3d(0, 0, 1)}, a, b, c) ==
        std::nullopt);  // behind
  CHECK(intersect_ray_triangle({Vector3d(1.5, 1.5, 3), Vector3d(0, 0, -1)}, a, b, c) ==
        std::nullopt);  // outside
  CHECK(intersect_ray_triangle({Vector3d(0.5, 0.25, 0), Vector3d(1, 0, 0)}, a, b, c) ==
        std::nullopt);                                                                   // in plane
  CHECK(intersect_ray_triangle({Vector3d(0.5, 0.25, -3), Vector3d(0, 0, 1)}, a, b, c));  // back side
}

TEST_CASE("picking the unit sphere returns the nearest surface point", "[viewer]") {
  const Mesh s = icosphere(3);
  const Vector3d dir = Vector3d(-1, -2, -0.5).normalized();
  const render::Ray r{-5 * dir, dir};
  const auto h = pick(r, s.V, s.F);
  REQUIRE(h);
  // The icosphere is inscribed in the sphere: the hit lies within the level-3 sagitta (~0.01) of -dir.
  CHECK((h->point + dir).norm() < 0.02);
  CHECK(h->t == Approx(4).margin(0.02));
  CHECK((s.V.row(h->vertex).transpose() - h->point).norm() < 0.2);
  CHECK_FALSE(pick({Vector3d(5, 5, 5), Vector3d(1, 0, 0)}, s.V, s.F));
  const auto near = vertices_in_sphere(s.V, Vector3d(0, 0, 1), 0.3);
  REQUIRE_FALSE(near.empty());
  for (int i : near) CHECK(s.V(i, 2) > 0.95);
}

TEST_CASE("gizmo: dragging an axis translates by the mouse's travel along it", "[viewer]") {
  const render::OrbitCamera cam = test_camera();
  const Vector3d c(0.3, 0.1, -0.2);
  const ga::Mot start = ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(0.5, 0, 0)));
  for (int axis = 0; axis < 3; ++axis) {
    const auto m = simulated_drag(cam, 800, 600, GizmoMode::Translate, axis, c, 0.5, start, 0.37);
    REQUIRE(m);
    const Eigen::Isometry3d iso = ga::to_isometry(*m);
    CHECK((iso.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-9);
    CHECK((iso.translation() - (Vector3d(0.5, 0, 0) + 0.37 * Vector3d::Unit(axis))).norm() < 1e-9);
  }
  // Closest point parameter: a ray crossing the x axis at x = 2 from above.
  CHECK(*axis_parameter({Vector3d(2, 0, 5), Vector3d(0, 0, -1)}, Vector3d::Zero(), Vector3d::UnitX()) ==
        Approx(2));
  CHECK_FALSE(axis_parameter({Vector3d(2, 0, 5), Vector3d(1, 0, 0)}, Vector3d::Zero(), Vector3d::UnitX()));
}

TEST_CASE("gizmo: dragging a ring rotates about the axis through the gizmo centre, after the start motor",
          "[viewer]") {
  const render::OrbitCamera cam = test_camera();
  const Vector3d c(0.3, 0.1, -0.2);
  const Eigen::Isometry3d s0(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()));
  const ga::Mot start = ga::from_isometry(s0);
  for (int axis = 0; axis < 3; ++axis) {
    const auto m = simulated_drag(cam, 800, 600, GizmoMode::Rotate, axis, c, 0.5, start, 40.0);
    REQUIRE(m);
    // Expected: x ↦ R (S0 x − c) + c with R the 40° rotation about the axis.
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(40 * std::numbers::pi / 180, Vector3d::Unit(axis)).toRotationMatrix();
    for (const Vector3d& p : {Vector3d(0, 0, 0), Vector3d(1, -2, 0.5), Vector3d(-0.3, 0.7, 2)}) {
      const Vector3d expected = R * (s0 * p - c) + c;
      CHECK((apply(*m, p) - expected).norm() < 1e-9);
    }
  }
  // The centre is fixed by a pure ring drag from the identity.
  const auto m = simulated_drag(cam, 800, 600, GizmoMode::Rotate, 2, c, 0.5, kIdentity, -75.0);
  REQUIRE(m);
  CHECK((apply(*m, c) - c).norm() < 1e-12);
  // Angle wrap: -75° and +285° are the same drag.
  const auto m2 = simulated_drag(cam, 800, 600, GizmoMode::Rotate, 2, c, 0.5, kIdentity, 285.0);
  CHECK((apply(*m, Vector3d(1, 2, 3)) - apply(*m2, Vector3d(1, 2, 3))).norm() < 1e-9);
  // Looking straight down the axis of a translate drag is degenerate: no motor.
  render::OrbitCamera top = test_camera();
  top.up = Vector3d::UnitY(), top.elevation_deg = 0, top.azimuth_deg = 0, top.target = c;
  CHECK_FALSE(simulated_drag(top, 800, 600, GizmoMode::Translate, 2, c, 0.5, kIdentity, 1.0));
}

TEST_CASE("undo stack: undo, redo, a new edit forgets the redo branch, capacity", "[viewer]") {
  UndoStack<int> u(0, 3);
  CHECK_FALSE(u.can_undo());
  u.push(1), u.push(2), u.push(3);
  CHECK(u.current() == 3);
  CHECK(u.undo());
  CHECK(u.undo());
  CHECK(u.current() == 1);
  CHECK(u.redo());
  CHECK(u.current() == 2);
  u.push(7);
  CHECK_FALSE(u.can_redo());
  CHECK(u.current() == 7);
  u.push(8), u.push(9);  // capacity 3: the oldest states are dropped
  int undos = 0;
  while (u.undo()) ++undos;
  CHECK(undos == 3);
  CHECK(u.current() == 2);
}

TEST_CASE("snap worker: only the latest request's result is shown, stale ones are dropped", "[viewer]") {
  Mesh rest = icosphere(3);
  rest.V.col(2) *= 2.5;
  Eigen::MatrixXd edit = rest.V;
  for (Eigen::Index i = 0; i < edit.rows(); ++i) {
    const double a = 0.5 * rest.V(i, 2);
    edit(i, 0) = std::cos(a) * rest.V(i, 0) - std::sin(a) * rest.V(i, 1);
    edit(i, 1) = std::sin(a) * rest.V(i, 0) + std::cos(a) * rest.V(i, 1);
  }
  const double q_edit = quasi_conformal_summary(rest.V, rest.F, edit).q_mean;
  SnapWorker w(rest);
  const auto g1 = w.request(edit, 1.0);
  const auto g2 = w.request(edit, 1.0);  // replaces (or outdates) the first
  REQUIRE(w.wait_idle(120));
  auto r = w.take();
  REQUIRE(r);
  CHECK(r->generation == g2);
  CHECK(g2 > g1);
  CHECK(w.discarded() == 1);
  REQUIRE(r->error.empty());
  CHECK(r->q_mean < q_edit);
  CHECK(r->q_mean < 1.02);
  CHECK(r->Q.size() == rest.F.rows());
  CHECK_FALSE(w.take());  // once
  // A drag starting while a snap runs makes it stale.
  w.request(edit, 0.5);
  w.cancel();
  REQUIRE(w.wait_idle(120));
  CHECK_FALSE(w.take());
  CHECK(w.discarded() == 2);
  // A bad edit is reported, not thrown across the thread.
  w.request(Eigen::MatrixXd::Zero(3, 3), 1.0);
  REQUIRE(w.wait_idle(120));
  r = w.take();
  REQUIRE(r);
  CHECK_FALSE(r->error.empty());
}

TEST_CASE("snap worker, pinned: the pose-keeping cleanup keeps the pins bit for bit, binds once per pin set",
          "[viewer][pinned]") {
  Mesh rest = icosphere(3);
  rest.V.col(2) *= 2.5;
  Eigen::MatrixXd edit = rest.V;  // a twist about z that grows with z, the ends rigid beyond |z| > 1.5
  std::vector<int> pins;
  for (Eigen::Index i = 0; i < edit.rows(); ++i) {
    const double a = 0.8 * std::clamp(rest.V(i, 2), -1.5, 1.5);
    edit(i, 0) = std::cos(a) * rest.V(i, 0) - std::sin(a) * rest.V(i, 1);
    edit(i, 1) = std::sin(a) * rest.V(i, 0) + std::cos(a) * rest.V(i, 1);
    if (std::abs(rest.V(i, 2)) > 1.5) pins.push_back(static_cast<int>(i));
  }
  const double q_edit = quasi_conformal_summary(rest.V, rest.F, edit).q_mean;
  SnapWorker w(rest);
  w.request_pinned(edit, pins);
  REQUIRE(w.wait_idle(120));
  auto r = w.take();
  REQUIRE(r);
  REQUIRE(r->error.empty());
  CHECK(r->pinned);
  CHECK(r->bind_ms > 0);
  double moved = 0;
  for (int p : pins) moved = std::max(moved, (r->V.row(p) - edit.row(p)).norm());
  CHECK(moved == 0.0);
  CHECK(r->q_mean < q_edit);
  CHECK(std::abs(r->volume_ratio - 1.0) < 1e-6);
  w.request_pinned(edit, pins);  // same pins: no new bind
  REQUIRE(w.wait_idle(120));
  r = w.take();
  REQUIRE(r);
  CHECK(r->bind_ms == 0.0);
  // Out-of-range pins are reported, not thrown across the thread.
  w.request_pinned(edit, {static_cast<int>(rest.V.rows())});
  REQUIRE(w.wait_idle(120));
  r = w.take();
  REQUIRE(r);
  CHECK_FALSE(r->error.empty());
}

TEST_CASE("session: pose a handle, undo/redo, save the scene with the pose", "[viewer]") {
  const auto scene = std::filesystem::path(SPINMOTOR_TEST_DATA_DIR) / "scenes" / "sh_tube.json";
  Session s = Session::open(scene);
  REQUIRE(s.has_deformer());
  REQUIRE(s.controls().size() == 2);
  const Eigen::MatrixXd V0 = s.posed();
  const auto tip = s.handle_vertices("tip");
  REQUIRE_FALSE(tip.empty());
  const ga::Mot m =
      ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.5)) * ga::to_isometry(s.motor("tip")));
  s.set_motor("tip", m);
  s.commit_pose();
  const Eigen::MatrixXd V1 = s.posed();
  for (int i : tip)
    CHECK((V1.row(i) - V0.row(i) - Eigen::RowVector3d(0, 0, 0.5)).norm() < 1e-9);  // handles are exact
  CHECK(s.undo());
  CHECK((s.posed() - V0).norm() < 1e-12);
  CHECK(s.redo());
  CHECK((s.posed() - V1).norm() < 1e-12);
  CHECK_THROWS_AS(s.set_motor("nope", m), Error);
  // A moved session keeps a working deformer (it refers to the session's scene, which must not move).
  Session moved = std::move(s);
  moved.set_motor("tip", m);
  CHECK((moved.posed() - V1).norm() < 1e-12);
  s = std::move(moved);
  // Handles made in the viewer (brush selection): a new handle is posed by its own motor.
  const Eigen::MatrixXd R = s.rest().V;  // a copy: add_handle rebinds, which replaces the scene
  std::vector<int> mid;
  for (Eigen::Index i = 0; i < R.rows(); ++i)
    if (std::abs(R(i, 2) - 2.0) < 0.06) mid.push_back(int(i));
  REQUIRE_FALSE(mid.empty());
  CHECK_THROWS_AS(s.add_handle("tip", mid), Error);                     // name taken
  CHECK_THROWS_AS(s.add_handle("x", s.handle_vertices("tip")), Error);  // vertices owned by 'tip'
  CHECK(s.controls().size() == 2);                                      // unchanged after the errors
  s.add_handle("mid", mid);
  REQUIRE(s.controls().size() == 3);
  s.set_motor("mid", ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(0.3, 0, 0))));
  const Eigen::MatrixXd V2 = s.posed();
  for (int i : mid) CHECK((V2.row(i) - R.row(i) - Eigen::RowVector3d(0.3, 0, 0)).norm() < 1e-9);
  for (int i : tip) CHECK((V2.row(i) - V1.row(i)).norm() < 1e-9);  // the tip keeps its pose
  s.remove_handle("mid");
  CHECK(s.controls().size() == 2);
  CHECK((s.posed() - V1).cwiseAbs().maxCoeff() < 1e-9);
  CHECK_THROWS_AS(s.remove_handle("mid"), Error);
  // The saved scene loads again and poses the same mesh.
  const auto out = std::filesystem::path(SPINMOTOR_TEST_DATA_DIR) / "scenes" / "viewer_saved_tmp.json";
  s.save_scene(out);
  Session t = Session::open(out);
  std::filesystem::remove(out);
  CHECK((t.posed() - V1).cwiseAbs().maxCoeff() < 1e-9);
}

#ifdef SPINMOTOR_VIEWER
namespace {
using render::Image;
Image read_png(const std::filesystem::path& p) {
  int w = 0, h = 0, c = 0;
  unsigned char* d = stbi_load(p.string().c_str(), &w, &h, &c, 4);
  REQUIRE(d);
  Image im;
  im.width = w, im.height = h, im.rgba.assign(d, d + std::size_t(w) * h * 4);
  stbi_image_free(d);
  return im;
}
bool white(const Image& im, int x, int y) {
  const auto p = im.pixel(x, y);
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}
double warm(const Image& im) {  // fraction of mesh pixels on the warm half of the Q map (red above blue)
  double mesh = 0, hot = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width * 3 / 4; ++x)
      if (!white(im, x, y)) mesh += 1, hot += im.pixel(x, y)[0] > im.pixel(x, y)[2];
  return mesh > 0 ? hot / mesh : 0;
}
}  // namespace

TEST_CASE("spinmotor-viewer headless under xvfb-run: a gizmo twist shows in Q, the snap removes it",
          "[viewer][xvfb]") {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    WARN("xvfb-run not found: skipping the viewer's headless screenshot test");
    return;
  }
  const auto dir = std::filesystem::temp_directory_path() / "spinmotor_test_viewer";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto scene = std::filesystem::path(SPINMOTOR_TEST_DATA_DIR) / "scenes" / "sh_tube.json";
  auto shot = [&](const std::string& name, const std::string& extra) {
    const auto png = dir / name;
    const std::string cmd = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " --scene " + scene.string() +
                            " --screenshot " + png.string() +
                            " --size 240x180 --color q --up z --camera 0,10 --gizmo tip,rotate,z,90 " +
                            extra + " > " + (dir / (name + ".log")).string() + " 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    return png;
  };
  const auto edit_png = shot("edit.png", ""), snap_png = shot("snap.png", "--snap");
  const Image edit = read_png(edit_png), snap = read_png(snap_png);
  REQUIRE(edit.width == 240);
  REQUIRE(edit.height == 180);
  // Not blank, and the silhouette is where the camera says: the same session state (the scene's pose,
  // then the same gizmo drag seen through the camera framing the rest mesh) rendered by render_mesh
  // with the camera framing the posed mesh covers the same pixels.
  Session s = Session::open(scene);
  render::RenderOptions o;
  o.width = 240, o.height = 180, o.up = Vector3d::UnitZ(), o.azimuth_deg = 0, o.elevation_deg = 10;
  o.style.color = render::ColorMode::Q;
  const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
  const ga::Mot m0 = s.motor("tip");
  const auto m = simulated_drag(cam, 240, 180, GizmoMode::Rotate, 2,
                                posed_centroid(s.rest().V, s.handle_vertices("tip"), m0),
                                0.25 * cam.scene_radius, m0, 90.0);
  REQUIRE(m);
  s.set_motor("tip", *m);
  Mesh posed = s.rest();
  posed.V = s.posed();
  const Image expected = render::render_mesh(posed, &s.rest(), o);
  double both = 0, either = 0, covered = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 180; ++x) {  // left of the colour bar
      const bool a = !white(edit, x, y), b = !white(expected, x, y);
      both += a && b, either += a || b, covered += a;
    }
  CHECK(covered > 0.05 * 180 * 180);
  CHECK(both / either > 0.97);
  // The twist shows in Q; its snap is conformal (blue).
  const double we = warm(edit), ws = warm(snap);
  INFO("warm pixels: edit " << we << ", snap " << ws);
  CHECK(we > 0.3);
  CHECK(ws < 0.05);
  // The window itself: the GLFW + ImGui loop runs a few frames and draws the mesh and the panel.
  const auto win = dir / "window.png";
  const std::string cmd = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " " + scene.string() +
                          " --size 800x500 --up z --smoke-frames 5 --smoke-png " + win.string() + " > " +
                          (dir / "window.log").string() + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const Image w = read_png(win);
  REQUIRE(w.width == 800);
  int panel = 0, mesh = 0;
  for (int y = 0; y < 500; ++y)
    for (int x = 0; x < 800; ++x) {
      const auto p = w.pixel(x, y);
      const bool dark = p[0] < 90 && p[1] < 90 && p[2] < 90;  // ImGui's dark window background
      if (x < 100 && y < 100 && dark) ++panel;
      if (x > 400 && !white(w, x, y) && !dark) ++mesh;  // right of the panel
    }
  CHECK(panel > 2000);
  CHECK(mesh > 500);
  std::filesystem::remove_all(dir);
}
namespace {
std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
/// Pixels covered by a mesh in both pictures over pixels covered in either (left of x_max).
double overlap(const Image& a, const Image& b, int x_max) {
  double both = 0, either = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < x_max; ++x) {
      const bool p = !white(a, x, y), q = !white(b, x, y);
      both += p && q, either += p || q;
    }
  return either > 0 ? both / either : 0;
}
}  // namespace

TEST_CASE("spinmotor-viewer headless: FFD lattice gizmo, IK target drag, box selection, curvature paint",
          "[viewer][xvfb]") {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    WARN("xvfb-run not found: skipping the viewer's headless tool tests");
    return;
  }
  const auto dir = std::filesystem::temp_directory_path() / "spinmotor_test_viewer_tools";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto scenes = std::filesystem::path(SPINMOTOR_TEST_DATA_DIR) / "scenes";
  const int W = 240, H = 180;
  render::RenderOptions o;
  o.width = W, o.height = H, o.up = Vector3d::UnitZ(), o.azimuth_deg = 0, o.elevation_deg = 10;
  o.style.color = render::ColorMode::Normals;
  // Runs the viewer; returns its log. Same camera as `o` (the rest framing), normals colouring.
  auto run = [&](const std::string& name, const std::filesystem::path& scene, const std::string& extra) {
    const auto log = dir / (name + ".log");
    const std::string cmd = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " --scene " + scene.string() +
                            " --screenshot " + (dir / name).string() +
                            " --size 240x180 --up z --camera 0,10 " + extra + " > " + log.string() + " 2>&1";
    const int rc = std::system(cmd.c_str());
    const std::string text = read_text(log);
    INFO(text);
    REQUIRE(rc == 0);
    return text;
  };
  // What the same steps give in process, rendered by render_mesh (the silhouette to match).
  auto expected = [&](Session& s) {
    Mesh posed = s.rest();
    posed.V = s.posed();
    return render::render_mesh(posed, &s.rest(), o);
  };

  SECTION("a lattice control dragged through its gizmo bends the mesh as in process") {
    const auto scene = scenes / "sh_tube.json";
    const std::string log =
        run("ffd.png", scene, "--deformer ffd --color normals --gizmo ffd[1,1,2],translate,x,4");
    Session s = Session::open(scene);
    const DeformerPreset p = deformer_preset("ffd", s.scene());
    s.set_deformer(p.deformer, p.ik);
    const Image before = expected(s);
    const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
    const auto m = simulated_drag(cam, W, H, GizmoMode::Translate, 0, *s.posed_anchor("ffd[1,1,2]"),
                                  0.25 * cam.scene_radius, s.motor("ffd[1,1,2]"), 4.0);
    REQUIRE(m);
    s.set_motor("ffd[1,1,2]", *m);
    const Vector3d a = *s.posed_anchor("ffd[1,1,2]");
    CHECK((a - *s.control_anchor("ffd[1,1,2]") - Vector3d(4.0, 0, 0)).norm() < 1e-6);
    char line[128];
    std::snprintf(line, sizeof line, "anchor at %.6f %.6f %.6f", a.x(), a.y(), a.z());
    CHECK(log.find(line) != std::string::npos);
    const Image shot = read_png(dir / "ffd.png"), after = expected(s);
    CHECK(overlap(shot, after, W) > 0.97);
    CHECK(overlap(shot, before, W) < 0.95);  // the drag visibly bent it
  }
  SECTION("the IK target dragged through its gizmo: the tip follows, as in process") {
    const auto scene = scenes / "ik_tube.json";
    const std::string log = run("ik.png", scene, "--color normals --gizmo ik.target,translate,y,0.6");
    Session s = Session::open(scene);
    const Image before = expected(s);
    const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
    const auto m = simulated_drag(cam, W, H, GizmoMode::Translate, 1, *s.posed_anchor("ik.target"),
                                  0.25 * cam.scene_radius, s.motor("ik.target"), 0.6);
    REQUIRE(m);
    s.set_motor("ik.target", *m);
    const Vector3d t = *s.posed_anchor("ik.target");
    CHECK((t - Vector3d(1.5, 0.6, 3.2)).norm() < 1e-6);
    char line[128];
    std::snprintf(line, sizeof line, "gizmo ik.target: anchor at %.6f %.6f %.6f", t.x(), t.y(), t.z());
    CHECK(log.find(line) != std::string::npos);
    const Image shot = read_png(dir / "ik.png"), after = expected(s);
    CHECK(overlap(shot, after, W) > 0.97);
    CHECK(overlap(shot, before, W) < 0.95);
  }
  SECTION("a box selection of visible vertices becomes a handle that its gizmo moves") {
    const auto scene = scenes / "sh_tube.json";
    const std::string log =
        run("box.png", scene,
            "--color normals --select-box 60,40,180,140 --add-handle mid --gizmo mid,translate,x,0.4");
    Session s = Session::open(scene);
    const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
    const DepthMap depth = DepthMap::render(s.posed(), s.rest().F, cam, W, H);
    const auto sel = vertices_in_box(s.posed(), cam, W, H, {60, 40}, {180, 140}, &depth);
    const auto all = vertices_in_box(s.posed(), cam, W, H, {60, 40}, {180, 140});
    REQUIRE(sel.size() > 20);
    CHECK(sel.size() < all.size());  // the far side of the tube is not selected
    CHECK(log.find("selected " + std::to_string(sel.size()) + " visible vertices") != std::string::npos);
    s.add_handle("mid", sel);
    const auto m = simulated_drag(cam, W, H, GizmoMode::Translate, 0, *s.posed_anchor("mid"),
                                  0.25 * cam.scene_radius, s.motor("mid"), 0.4);
    REQUIRE(m);
    s.set_motor("mid", *m);
    const Eigen::MatrixXd V = s.posed();
    for (int i : sel) CHECK((V.row(i) - s.rest().V.row(i) - Eigen::RowVector3d(0.4, 0, 0)).norm() < 1e-6);
    CHECK(overlap(read_png(dir / "box.png"), expected(s), W) > 0.97);
  }
  SECTION("painted curvature: the spin transformation moves the surface and stays conformal") {
    const auto scene = scenes / "sh_tube.json";
    // Paint where the rest tube's side faces the camera: the pixel of a rest vertex at mid length.
    Session s = Session::open(scene);
    const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
    Eigen::Index best = 0;
    for (Eigen::Index i = 0; i < s.rest().V.rows(); ++i) {  // nearest the eye at z ≈ 2
      const Vector3d p = s.rest().V.row(i).transpose();
      if (std::abs(p.z() - 2) < 0.1 &&
          (p - cam.eye()).norm() < (Vector3d(s.rest().V.row(best)) - cam.eye()).norm())
        best = i;
    }
    const Vector3d px = cam.project(s.rest().V.row(best).transpose(), W, H);
    // The picked surface is the posed one; the paint worker transforms the rest mesh.
    const std::string at = std::to_string(px.x()) + "," + std::to_string(px.y());
    const std::string log = run("paint_q.png", scene, "--color q --paint " + at + ",0.3,1");
    INFO(log);
    CHECK(log.find("paint: dab at face") != std::string::npos);
    const auto pos = log.find("spin transformation Q_mean ");
    REQUIRE(pos != std::string::npos);
    double q = 0, moved = 0;
    REQUIRE(std::sscanf(log.c_str() + pos, "spin transformation Q_mean %lf, max displacement %lf", &q,
                        &moved) == 2);
    CHECK(q < 1.02);      // 1.0116 here (a coarse 962-vertex tube; amount 3 gives 1.125: the discrete
    CHECK(moved > 0.05);  // spin transformation is conformal only up to the mesh's resolution)
    CHECK(warm(read_png(dir / "paint_q.png")) < 0.05);  // conformal: Q colours stay cold
    run("paint_rho.png", scene, "--color rho --paint " + at + ",0.3,1");
    const Image rho = read_png(dir / "paint_rho.png");
    int red = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) red += rho.pixel(x, y)[0] > 150 && rho.pixel(x, y)[1] < 90;
    CHECK(red > 20);  // the painted bump shows in the ρ colouring
  }
  SECTION("bad headless input exits 2, names the problem and writes no picture") {
    const auto scene = scenes / "sh_tube.json";
    struct Bad {
      const char* args;
      const char* says;
    };
    for (const Bad& b :
         {Bad{"--paint 1,1,0.3,1", "misses the mesh"}, Bad{"--paint 120,90,0.3", "expected 4 numbers"},
          Bad{"--select-box 1,2,3", "expected 4 numbers"}, Bad{"--add-handle h", "needs --select-box"},
          Bad{"--gizmo nope,translate,x,1", "not a control"}, Bad{"--snap --paint 120,90,0.3,1", "give one"},
          Bad{"--deformer skin", "skeleton"}}) {
      INFO(b.args);
      const auto png = dir / "bad.png", log = dir / "bad.log";
      const std::string cmd = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " --scene " + scene.string() +
                              " --screenshot " + png.string() + " --size 240x180 --up z --camera 0,10 " +
                              b.args + " > " + log.string() + " 2>&1";
      const int status = std::system(cmd.c_str());
      const std::string text = read_text(log);
      INFO(text);
      REQUIRE(WIFEXITED(status));
      CHECK(WEXITSTATUS(status) == 2);
      CHECK(text.find(b.says) != std::string::npos);
      CHECK_FALSE(std::filesystem::exists(png));
    }
  }
  std::filesystem::remove_all(dir);
}
#endif

}  // namespace test_viewer_logic
