// The viewer on a glTF rig (apps/viewer/core): a .glb opened as a session (the project's procedural limb
// written to a temporary file), the time and the animation, the posed skeleton against closed forms, a
// bone gizmo editing the animated pose, undo keeping the time, saving and reopening, the per-frame
// cleanup's pins in the snap worker, the playback clock and the bone overlay. With xvfb-run: the
// viewer's headless screenshot of the rig with its skeleton and the per-frame cleanup.
#include <unistd.h>

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
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/procedural_rig.hpp"
#include "spinmotor/scene/deformer_registry.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"
#include "spinmotor/viewer/animation_clock.hpp"
#include "spinmotor/viewer/bone_overlay.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/session.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace test_viewer_rig {

using namespace spinmotor;
using namespace spinmotor::viewer;
using Eigen::Vector3d;

namespace {

namespace fs = std::filesystem;

struct LimbFile {
  fs::path dir, file;
  LimbFile() : dir(fs::temp_directory_path() / ("spinmotor_viewer_rig_" + std::to_string(getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    file = dir / "limb.glb";
    write_gltf_rig(
        file, limb_rig({.length = 3.0, .rings = 48, .sides = 16, .joints = 3}));  // joints at z = 0, 1, 2
  }
  ~LimbFile() { fs::remove_all(dir); }
};

Eigen::Matrix3d rot_x(double degrees) {
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Vector3d::UnitX()).toRotationMatrix();
}

}  // namespace

TEST_CASE("viewer rig session: a .glb opens as a skin scene posed by its animation's time", "[viewer][rig]") {
  LimbFile f;
  Session s = Session::open(f.file);
  REQUIRE(s.has_rig());
  CHECK(s.scene().name() == "limb.glb");
  CHECK(s.controls() == std::vector<std::string>{"joint0", "joint1", "joint2"});
  CHECK(s.animation_names() == std::vector<std::string>{"bend", "twist"});
  CHECK(s.animation() == 0);
  CHECK(s.animation_range() == std::pair{0.0, 2.0});
  REQUIRE(s.time());
  CHECK(*s.time() == 0.0);  // the start of the first animation: the rest pose for this one
  CHECK((s.posed() - s.rest().V).cwiseAbs().maxCoeff() <= 1e-6);

  // At t = 1 the skin deformer (default blend: DLB) poses exactly what it poses bound by hand.
  s.set_time(1.0);
  const GltfRig rig = read_gltf(f.file);
  RigSkinner d(rig, SkinBlend::DLB);
  Eigen::MatrixXd V;
  d.pose(0, 1.0, V);
  CHECK((s.posed() - V).cwiseAbs().maxCoeff() <= 1e-12);
  // The posed skeleton in closed form (60° about x at each inner joint): heads e, e + R e; the last
  // bone's tail (a leaf: its parent's length along its own y) is e + R e + R² (0, 1, 0)... its y axis
  // turned twice.
  const std::vector<PosedBone> bones = s.posed_bones();
  REQUIRE(bones.size() == 3);
  const Vector3d e(0, 0, 1);
  const Eigen::Matrix3d R = rot_x(60);
  CHECK((bones[0].head - Vector3d::Zero()).norm() <= 1e-6);
  CHECK((bones[1].head - e).norm() <= 1e-6);
  CHECK((bones[2].head - (e + R * e)).norm() <= 1e-6);
  CHECK((bones[1].tail - bones[2].head).norm() <= 1e-6);
  CHECK((bones[2].tail - (e + R * e + R * R * Vector3d::UnitY())).norm() <= 1e-6);
  CHECK(bones[2].parent == 1);
  // The gizmo of joint2 sits at its posed head.
  CHECK((*s.posed_anchor("joint2") - bones[2].head).norm() <= 1e-12);

  // Rest pose, errors.
  s.set_time(std::nullopt);
  CHECK((s.posed() - s.rest().V).cwiseAbs().maxCoeff() <= 1e-6);
  CHECK_THROWS_AS(s.set_time(std::nan("")), Error);

  // The other animation: the twist turns joint2 about z; the time is kept across the rebind.
  s.set_time(1.0);
  s.set_animation(1);
  CHECK(s.animation() == 1);
  CHECK(*s.time() == 1.0);
  d.pose(1, 1.0, V);
  CHECK((s.posed() - V).cwiseAbs().maxCoeff() <= 1e-12);
  CHECK_THROWS_AS(s.set_animation(2), Error);
}

TEST_CASE("viewer rig session: a bone gizmo edits the animated pose, undo keeps the time, save and reopen",
          "[viewer][rig]") {
  LimbFile f;
  Session s = Session::open(f.file);
  s.set_time(1.0);
  const std::vector<PosedBone> before = s.posed_bones();
  // Rotate joint1 by 30° about z around its posed head (the drag as the mouse makes it).
  render::OrbitCamera cam;
  cam.target = Vector3d(0, 0, 1.5), cam.up = Vector3d::UnitZ(), cam.distance = 8, cam.azimuth_deg = 30,
  cam.elevation_deg = 60, cam.scene_radius = 2;
  const auto m = simulated_drag(cam, 400, 300, GizmoMode::Rotate, 2, *s.posed_anchor("joint1"), 0.5,
                                s.drag_start_motor("joint1"), 30.0);
  REQUIRE(m);
  s.set_motor("joint1", *m);
  s.commit_pose();
  const std::vector<PosedBone> after = s.posed_bones();
  // joint1's head stays (the ring turns about it), joint0 is untouched, joint2 inherits the edit: its
  // head turns 30° about the z line through joint1's head.
  CHECK((after[1].head - before[1].head).norm() <= 1e-9);
  CHECK((after[0].tail - before[0].tail).norm() <= 1e-12);
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(std::numbers::pi / 6, Vector3d::UnitZ()).toRotationMatrix();
  CHECK((after[2].head - (before[1].head + Rz * (before[2].head - before[1].head))).norm() <= 1e-6);
  // joint2 has no entry: a drag on it starts from the motion it inherits.
  CHECK(ga::to_isometry(s.drag_start_motor("joint2")).isApprox(ga::to_isometry(*m), 1e-12));
  const Eigen::MatrixXd edited = s.posed();

  // Undo takes the edit back, not the time; redo brings it again.
  s.set_time(0.5);
  REQUIRE(s.undo());
  CHECK(*s.time() == 0.5);
  s.set_time(1.0);
  CHECK((s.posed_bones()[2].head - before[2].head).norm() <= 1e-9);
  REQUIRE(s.redo());
  CHECK((s.posed() - edited).cwiseAbs().maxCoeff() <= 1e-12);

  // Saved next to the file: {"rig": {"gltf", "animation", "time"}, "pose": {...}}; reopening it shows
  // the same frame.
  const fs::path saved = f.dir / "limb-edited.json";
  s.save_scene(saved);
  std::ifstream in(saved);
  const nlohmann::json doc = nlohmann::json::parse(in);
  CHECK(doc["rig"]["gltf"] == "limb.glb");
  CHECK(doc["rig"]["time"] == 1.0);
  CHECK(doc["pose"].contains("joint1"));
  Session t = Session::open(saved);
  CHECK((t.posed() - edited).cwiseAbs().maxCoeff() <= 1e-9);
}

TEST_CASE("viewer rig cleanup: the worker binds the rig cleanup through its door, bit for bit",
          "[viewer][rig]") {
  LimbFile f;
  Session s = Session::open(f.file);
  s.set_time(1.0);
  CHECK(s.cleanup_pins().empty());  // no handles: the skin's cleanup, not pinned handles
  const auto skin = s.cleanup_skin();
  REQUIRE(skin);
  const GltfRig rig = read_gltf(f.file);
  const RigSkin rs = rig_skin(rig);
  scene::RigCleanup door = scene::RigCleanup::bind(s.rest(), rs.rig.weights, rs.rig.skeleton);
  CHECK(door.pins().size() > 100);
  SnapWorker w(s.rest());
  const Eigen::MatrixXd posed = s.posed();
  // Frames requested faster than they are cleaned: only the latest is shown.
  for (double t : {0.2, 0.4, 0.6}) {
    s.set_time(t);
    w.request_rig(s.posed(), skin);
  }
  s.set_time(1.0);
  w.request_rig(s.posed(), skin);
  REQUIRE(w.wait_idle(120));
  const auto r = w.take();
  REQUIRE(r);
  REQUIRE(r->error.empty());
  CHECK(r->pinned);
  CHECK(r->pins == door.pins().size());
  Eigen::MatrixXd expected;
  door(posed, expected);
  CHECK(r->V == expected);  // the same door, the same result
  double moved = 0;
  for (int v : door.pins()) moved = std::max(moved, (r->V.row(v) - posed.row(v)).cwiseAbs().maxCoeff());
  CHECK(moved == 0.0);
  CHECK((r->V - posed).cwiseAbs().maxCoeff() > 1e-4);  // the blend bands were cleaned up
  CHECK(r->volume_ratio == Approx(1.0).margin(1e-3));
}

TEST_CASE("animation clock: plays at speed, loops or stops at the end", "[viewer][rig]") {
  AnimationClock c{.start = 1.0, .end = 3.0};
  c.time = 1.0;
  CHECK_FALSE(c.advance(0.5));  // paused
  c.playing = true;
  CHECK(c.advance(0.5));
  CHECK(c.time == Approx(1.5));
  c.speed = 2.0;
  CHECK(c.advance(0.9));
  CHECK(c.time == Approx(1.3));  // 1.5 + 1.8 = 3.3 wraps to 1.3
  c.loop = false;
  CHECK(c.advance(5.0));
  CHECK(c.time == 3.0);
  CHECK_FALSE(c.playing);
  AnimationClock still{.start = 2.0, .end = 2.0};
  still.playing = true;
  still.time = 2.0;
  CHECK_FALSE(still.advance(1.0));
}

TEST_CASE("bone overlay: lines from posed head to tail through the camera", "[viewer][rig]") {
  render::Image im;
  im.width = 100, im.height = 80;
  im.rgba.assign(std::size_t(100) * 80 * 4, 255);
  render::OrbitCamera cam;
  cam.target = Vector3d::Zero(), cam.distance = 5, cam.azimuth_deg = 0, cam.elevation_deg = 0;
  // A bone across the view (x from −1 to 1) in front of the target.
  const std::vector<PosedBone> bones = {{"b", -1, Vector3d(-1, 0, 0), Vector3d(1, 0, 0)}};
  CHECK(draw_bones(im, bones, cam) > 0);
  const Vector3d a = cam.project(bones[0].head, 100, 80), b = cam.project(bones[0].tail, 100, 80);
  const auto mid = im.pixel(int((a.x() + b.x()) / 2), int((a.y() + b.y()) / 2));
  CHECK((mid[0] == kBoneColour[0] && mid[1] == kBoneColour[1] && mid[2] == kBoneColour[2]));
  CHECK(im.pixel(50, 5)[1] == 255);  // far from the line: untouched
  // Behind the eye: nothing drawn.
  render::Image blank = im;
  CHECK(draw_bones(blank, {{"c", -1, Vector3d(0, 0, 6), Vector3d(0, 0, 7)}}, cam) == 0);
}

#ifdef SPINMOTOR_VIEWER
TEST_CASE("spinmotor-viewer headless on a .glb: skeleton, animation time, per-frame cleanup",
          "[viewer][xvfb]") {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    WARN("xvfb-run not found: skipping the viewer's headless rig test");
    return;
  }
  LimbFile f;
  auto run = [&](const std::string& args) {
    const fs::path log = f.dir / "log.txt";
    const std::string cmd = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " " + f.file.string() + " " +
                            args + " > " + log.string() + " 2>&1";
    const int code = std::system(cmd.c_str());
    std::ifstream in(log);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    INFO(text);
    REQUIRE(code == 0);
    return text;
  };
  const std::string shot = (f.dir / "rig.png").string();
  std::string out =
      run("--screenshot " + shot + " --size 200x160 --up z --time 1 --animation bend --skeleton");
  CHECK_THAT(out, Catch::Contains("rig: 3 joints, animation 0 of 2, time 1.0"));
  CHECK_THAT(out, Catch::Contains("skeleton: 3 bones"));
  CHECK(fs::exists(shot));
  out =
      run("--screenshot " + shot + " --size 200x160 --up z --animation twist --frames 6 --snap --keep-pose");
  CHECK_THAT(out, Catch::Contains("animation over 6 frames (t = 0 .. 2 s)"));
  CHECK_THAT(out, Catch::Contains("cleanup per frame: 6 requested"));
  // The window (GLFW + ImGui, with the Animation panel) runs a few frames on the rig.
  out = run("--size 700x500 --up z --smoke-frames 3");
  CHECK_THAT(out, Catch::Contains("window: 3 frames"));
  // Bad input exits 2.
  const std::string bad = "xvfb-run -a " + std::string(SPINMOTOR_VIEWER) + " " + f.file.string() +
                          " --screenshot " + shot + " --animation wave > /dev/null 2>&1";
  const int status = std::system(bad.c_str());
  CHECK(WEXITSTATUS(status) == 2);
}
#endif

}  // namespace test_viewer_rig
