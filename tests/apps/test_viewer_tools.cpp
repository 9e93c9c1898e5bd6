// The viewer's tools, window-free (apps/viewer/core): box and lasso selection with the CPU depth map
// (visible vertices only), curvature painting and its spin transformation, the deformer panel's
// presets and schema-driven options, control anchors (FFD lattice, box cage, spline keys, IK target)
// and the IK target dragged through the gizmo code path. The same steps through the viewer binary
// under Xvfb are in test_viewer_logic.cpp.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/spin/spin_transform.hpp"
#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/lattice_edges.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "spinmotor/viewer/session.hpp"

namespace test_viewer_tools {

using namespace spinmotor;
using namespace spinmotor::viewer;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {
const std::filesystem::path kScenes = std::filesystem::path(SPINMOTOR_TEST_DATA_DIR) / "scenes";

render::OrbitCamera sphere_camera() {
  render::OrbitCamera cam;
  cam.target = Vector3d::Zero();
  cam.distance = 4, cam.azimuth_deg = 20, cam.elevation_deg = 15, cam.scene_radius = 1;
  return cam;
}

Vector3d centroid(const Eigen::MatrixXd& V, const std::vector<int>& idx) {
  Vector3d c = Vector3d::Zero();
  for (int i : idx) c += V.row(i).transpose();
  return c / double(idx.size());
}

ga::Mot translation(const Vector3d& t) {
  return ga::from_isometry(Eigen::Isometry3d(Eigen::Translation3d(t)));
}
}  // namespace

TEST_CASE("point in polygon: convex, concave, outside", "[viewer][selection]") {
  const std::vector<Vector2d> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  CHECK(point_in_polygon({1, 1}, square));
  CHECK_FALSE(point_in_polygon({3, 1}, square));
  CHECK_FALSE(point_in_polygon({-0.1, 1}, square));
  const std::vector<Vector2d> ell = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};  // an L
  CHECK(point_in_polygon({0.5, 2.5}, ell));
  CHECK(point_in_polygon({2.5, 0.5}, ell));
  CHECK_FALSE(point_in_polygon({2, 2}, ell));  // the notch
}

TEST_CASE("depth map of a sphere: the nearest depth at the centre pixel, background elsewhere",
          "[viewer][selection]") {
  const Mesh s = icosphere(4);
  const render::OrbitCamera cam = sphere_camera();
  const DepthMap d = DepthMap::render(s.V, s.F, cam, 320, 240);
  // The centre pixel sees the sphere's nearest point: depth = distance − 1 (less the level-4 sagitta).
  CHECK(d.depth(160, 120) == Approx(cam.distance - 1).margin(5e-3));
  CHECK(std::isinf(d.depth(2, 2)));  // a corner sees nothing
  // Perspective-correct: at every 8th pixel the depth equals an independent ray cast (picking.hpp)
  // through the pixel centre, converted from ray length to eye depth.
  const Vector3d forward = (cam.target - cam.eye()).normalized();
  int hits = 0;
  for (int y = 0; y < 240; y += 8)
    for (int x = 0; x < 320; x += 8) {
      const render::Ray r = cam.pixel_ray(x + 0.5, y + 0.5, 320, 240);
      const auto hit = pick(r, s.V, s.F);
      if (!hit) {
        CHECK(std::isinf(d.depth(x, y)));
        continue;
      }
      CHECK(d.depth(x, y) == Approx(hit->t * r.direction.dot(forward)).epsilon(1e-6));
      ++hits;
    }
  CHECK(hits > 100);
  CHECK_THROWS_AS(DepthMap::render(s.V, s.F, cam, 0, 10), Error);
}

TEST_CASE("box and lasso selection: projected inside, and only the visible side with a depth map",
          "[viewer][selection]") {
  const Mesh s = icosphere(3);
  const render::OrbitCamera cam = sphere_camera();
  const int w = 320, h = 240;
  const Vector3d eye = cam.eye();
  // The whole view: every vertex without depth; with depth exactly the vertices facing the eye
  // (p · (eye − p) > 0 on the unit sphere), up to a band at the silhouette: a hidden vertex with
  // cos = −0.25 projects about 3 pixels inside the disk's rim (θ²/2 of the radius), one nearer than
  // the 3×3 window may see background and count as visible (DepthMap::visible).
  const std::vector<int> all = vertices_in_box(s.V, cam, w, h, {0, 0}, {double(w), double(h)});
  CHECK(all.size() == std::size_t(s.V.rows()));
  const DepthMap depth = DepthMap::render(s.V, s.F, cam, w, h);
  const std::vector<int> front = vertices_in_box(s.V, cam, w, h, {double(w), 0}, {0, double(h)}, &depth);
  int wrong = 0;
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    const Vector3d p = s.V.row(i).transpose();
    const double facing = p.dot(eye - p) / (eye - p).norm();
    const bool selected = std::binary_search(front.begin(), front.end(), int(i));
    if ((facing > 0.05 && !selected) || (facing < -0.25 && selected)) {
      ++wrong;
      WARN("vertex " << i << (selected ? " selected" : " not selected") << ", cos " << facing);
    }
  }
  CHECK(wrong == 0);
  CHECK(front.size() > 0.4 * s.V.rows());
  CHECK(front.size() < 0.65 * s.V.rows());
  // Left half of the view, against an independent projection.
  const std::vector<int> left = vertices_in_box(s.V, cam, w, h, {0, 0}, {w / 2.0, double(h)});
  std::vector<int> expect;
  for (Eigen::Index i = 0; i < s.V.rows(); ++i)
    if (cam.project(s.V.row(i).transpose(), w, h).x() <= w / 2.0) expect.push_back(int(i));
  CHECK(left == expect);
  // A lasso triangle, against the same projection and point_in_polygon.
  const std::vector<Vector2d> lasso = {{100, 40}, {260, 120}, {120, 220}};
  const std::vector<int> in = vertices_in_lasso(s.V, cam, w, h, lasso);
  expect.clear();
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    const Vector3d p = cam.project(s.V.row(i).transpose(), w, h);
    if (point_in_polygon(p.head<2>(), lasso)) expect.push_back(int(i));
  }
  CHECK(in == expect);
  CHECK_FALSE(in.empty());
  CHECK(vertices_in_lasso(s.V, cam, w, h, {{0, 0}, {10, 10}}).empty());  // fewer than 3 points
  // Set operations for add / subtract.
  CHECK(selection_union({1, 3, 5}, {2, 3}) == std::vector<int>{1, 2, 3, 5});
  CHECK(selection_difference({1, 3, 5}, {3, 4}) == std::vector<int>{1, 5});
}

TEST_CASE("paint_rho: a smooth bump of the given height and radius", "[viewer][paint]") {
  const Mesh s = icosphere(3);
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(s.F.rows());
  const Vector3d c(0, 0, 1);
  const int touched = paint_rho(s.V, s.F, c, 0.5, 3.0, rho);
  int expect = 0;
  for (Eigen::Index f = 0; f < s.F.rows(); ++f) {
    const Vector3d fc = (s.V.row(s.F(f, 0)) + s.V.row(s.F(f, 1)) + s.V.row(s.F(f, 2))).transpose() / 3.0;
    const double q = (fc - c).squaredNorm() / 0.25;
    if (q < 1) {
      ++expect;
      CHECK(rho[f] == Approx(3.0 * (1 - q) * (1 - q)).epsilon(1e-12));
    } else {
      CHECK(rho[f] == 0);
    }
  }
  CHECK(touched == expect);
  CHECK(touched > 10);
  CHECK(rho.maxCoeff() <= 3.0);
  Eigen::VectorXd wrong(3);
  CHECK_THROWS_AS(paint_rho(s.V, s.F, c, 0.5, 1.0, wrong), Error);
  CHECK_THROWS_AS(paint_rho(s.V, s.F, c, 0.0, 1.0, rho), Error);
  CHECK_THROWS_AS(paint_rho(s.V, s.F, c, 0.5, std::nan(""), rho), Error);
}

TEST_CASE("paint worker: rho = 0 keeps the mesh, a painted bump moves it and stays conformal",
          "[viewer][paint]") {
  const Mesh s = icosphere(3);
  SpinPaintWorker worker(s);
  worker.request(Eigen::VectorXd::Zero(s.F.rows()));
  REQUIRE(worker.wait_idle(120));
  auto flat = worker.take();
  REQUIRE(flat);
  REQUIRE(flat->error.empty());
  CHECK(flat->bind_ms > 0);
  CHECK((flat->V - s.V).cwiseAbs().maxCoeff() < 1e-6);
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(s.F.rows());
  paint_rho(s.V, s.F, Vector3d(0, 0, 1), 0.6, 2.0, rho);
  worker.request(rho);
  REQUIRE(worker.wait_idle(120));
  auto bump = worker.take();
  REQUIRE(bump);
  REQUIRE(bump->error.empty());
  CHECK(bump->bind_ms == 0);  // bound once
  const double moved = std::sqrt((bump->V - s.V).rowwise().squaredNorm().maxCoeff());
  INFO("max displacement " << moved << ", Q_mean " << bump->q_mean);
  CHECK(moved > 0.05);
  CHECK(bump->q_mean < 1.02);  // a spin transformation: conformal by construction
  CHECK(bump->q_mean == Approx(quasi_conformal_summary(s.V, s.F, bump->V).q_mean));
  // A bad ρ is an error in the outcome, not a crash of the worker.
  worker.request(Eigen::VectorXd::Constant(3, 1.0));
  REQUIRE(worker.wait_idle(60));
  auto bad = worker.take();
  REQUIRE(bad);
  CHECK_FALSE(bad->error.empty());
  CHECK(bad->V.rows() == 0);
}

TEST_CASE("paint worker on an open tube: the boundary keeps its tangents, the bump stays conformal",
          "[viewer][paint]") {
  // Without a boundary condition the smallest eigenvector of D − ρ on an open tube is not the
  // near-identity one: Q_mean 2.1–2.7 for any bump (measured before the fix).
  const Mesh s = tube(1.0, 4.0, 41, 24, false);
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(s.F.rows());
  paint_rho(s.V, s.F, Vector3d(1, 0, 2), 0.8, 0.5, rho);
  const double q_free = quasi_conformal_summary(s.V, s.F, SpinTransform(s).solve(rho).V).q_mean;
  SpinPaintWorker worker(s);
  worker.request(rho);
  REQUIRE(worker.wait_idle(120));
  auto r = worker.take();
  REQUIRE(r);
  REQUIRE(r->error.empty());
  const double moved = std::sqrt((r->V - s.V).rowwise().squaredNorm().maxCoeff());
  INFO("max displacement " << moved << ", Q_mean " << r->q_mean << ", free boundary Q_mean " << q_free);
  CHECK(moved > 0.02);
  CHECK(moved < 0.5);
  CHECK(r->q_mean < 1.02);
  CHECK(q_free > 1.2);  // the failure the boundary condition removes
}

TEST_CASE("ffd lattice edges: neighbours one step apart on one axis", "[viewer]") {
  std::vector<std::string> names;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c)
        names.push_back("ffd[" + std::to_string(a) + "," + std::to_string(b) + "," + std::to_string(c) + "]");
  names.push_back("tip");
  names.push_back("ffd[0,0,0]x");
  const auto e = ffd_lattice_edges(names);
  CHECK(e.size() == 54);  // 3 axes × 2 steps × 9 lines
  for (const auto& [i, j] : e) {
    CHECK(i < j);
    CHECK(j < 27);
  }
  CHECK(ffd_lattice_edges({"ffd[0,0,0]", "ffd[1,0,0]"}).size() == 1);
  CHECK(ffd_lattice_edges({"ffd[0,0,0]", "ffd[1,1,0]"}).empty());
}

TEST_CASE("deformer options come from the scene schema", "[viewer][deformer]") {
  const auto ffd = deformer_options("ffd", {});
  auto find = [](const std::vector<DeformerOption>& v, const std::string& k) {
    const auto it = std::find_if(v.begin(), v.end(), [&](const DeformerOption& o) { return o.key == k; });
    REQUIRE(it != v.end());
    return *it;
  };
  CHECK(find(ffd, "lattice").kind == DeformerOption::Kind::Integers3);
  CHECK(find(ffd, "lattice").minimum == 2);
  CHECK(find(ffd, "basis").choices == std::vector<std::string>{"bezier", "bspline"});
  const auto sh = deformer_options("surface-harmonic", {});
  CHECK(find(sh, "weights").choices == std::vector<std::string>{"mean-value", "cotan"});  // through a $ref
  const auto spline = deformer_options("spline", {"base", "tip"});
  CHECK(find(spline, "from").kind == DeformerOption::Kind::Handle);
  CHECK(find(spline, "to").choices == std::vector<std::string>{"base", "tip"});
  CHECK(find(spline, "degree").maximum == 15);
  CHECK(find(deformer_options("arap", {}), "clamp_negative_weights").kind == DeformerOption::Kind::Boolean);
  CHECK_THROWS_AS(deformer_options("nope", {}), Error);
}

TEST_CASE("deformer presets bind on a two-handle scene, with their controls and anchors",
          "[viewer][deformer]") {
  Session s = Session::open(kScenes / "sh_tube.json");  // tube r = 0.5, z ∈ [0, 4], handles base, tip
  const Eigen::MatrixXd R = s.rest().V;
  const Eigen::RowVector3d lo = R.colwise().minCoeff(), hi = R.colwise().maxCoeff();
  struct Expect {
    const char* choice;
    std::size_t controls;
  };
  for (const Expect& e : {Expect{"spline", 4}, Expect{"spline-ik", 1}, Expect{"ffd", 27}, Expect{"cage", 8},
                          Expect{"arap", 2}, Expect{"surface-harmonic", 2}}) {
    INFO(e.choice);
    const DeformerPreset p = deformer_preset(e.choice, s.scene());
    s.set_deformer(p.deformer, p.ik);
    REQUIRE(s.controls().size() == e.controls);
    for (const auto& c : s.controls()) CHECK(s.control_anchor(c));
    CHECK(s.posed().allFinite());
  }
  CHECK_THROWS_WITH(deformer_preset("skin", s.scene()), Catch::Contains("skeleton"));
  CHECK_THROWS_AS(deformer_preset("nope", s.scene()), Error);
  CHECK(s.controls().size() == 2);  // a failed switch changes nothing

  // FFD: the lattice's corner and centre controls sit at the box corners and centre.
  DeformerPreset p = deformer_preset("ffd", s.scene());
  s.set_deformer(p.deformer, p.ik);
  const Vector3d c000 = *s.control_anchor("ffd[0,0,0]"), c222 = *s.control_anchor("ffd[2,2,2]");
  CHECK((c000.array() < lo.transpose().array()).all());
  CHECK((c222.array() > hi.transpose().array()).all());
  CHECK((*s.control_anchor("ffd[1,1,1]") - 0.5 * (lo + hi).transpose()).norm() < 1e-12);
  // Its gizmo: translating the centre control moves its anchor by exactly that, and the mesh.
  // Bézier weights are non-negative and the blend of pure translations is their weighted sum: every
  // vertex moves along +y only, by 0.4 times its weight of that control.
  s.set_motor("ffd[1,1,1]", translation({0, 0.4, 0}));
  CHECK((*s.posed_anchor("ffd[1,1,1]") - *s.control_anchor("ffd[1,1,1]") - Vector3d(0, 0.4, 0)).norm() <
        1e-12);
  const Eigen::MatrixXd D = s.posed() - R;
  CHECK(D.col(0).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(D.col(2).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(D.col(1).minCoeff() > -1e-12);
  CHECK(D.col(1).maxCoeff() > 0.01);
  CHECK(D.col(1).maxCoeff() <= 0.4 * 0.125 + 1e-12);  // B(½)³ = (½)³ is the centre control's largest weight

  // Box cage: 8 corners around the mesh; moving them all by t translates the mesh by t (mean-value
  // coordinates reproduce affine maps).
  p = deformer_preset("cage", s.scene());
  s.set_deformer(p.deformer, p.ik);
  for (const auto& c : s.controls()) {
    const Vector3d a = *s.control_anchor(c);
    CHECK(((a.array() < lo.transpose().array()) || (a.array() > hi.transpose().array())).all());
    s.set_motor(c, translation({0.3, -0.2, 0.1}));
  }
  CHECK(((s.posed() - R).rowwise() - Eigen::RowVector3d(0.3, -0.2, 0.1)).cwiseAbs().maxCoeff() < 1e-9);

  // Spline keys sit on the line between the end handles' centroids, at j/3.
  p = deformer_preset("spline", s.scene());
  s.set_deformer(p.deformer, p.ik);
  const Vector3d base = centroid(R, s.handle_vertices("base")), tip = centroid(R, s.handle_vertices("tip"));
  CHECK((*s.control_anchor("key1") - (base + (tip - base) / 3.0)).norm() < 1e-12);
  // Saved and reloaded, the box cage and the keys survive as scene JSON.
  const auto out = kScenes / "viewer_tools_tmp.json";
  s.save_scene(out);
  Session t = Session::open(out);
  std::filesystem::remove(out);
  CHECK(t.controls() == s.controls());
}

TEST_CASE("renaming a handle renames it in the pose and the spline's from/to, keeping the shape",
          "[viewer][deformer]") {
  Session s = Session::open(kScenes / "sh_tube.json");
  const DeformerPreset p = deformer_preset("spline", s.scene());
  s.set_deformer(p.deformer, p.ik);
  s.set_motor("key3", translation({0, 0.5, 0}));
  const Eigen::MatrixXd before = s.posed();
  s.rename_handle("tip", "end");
  CHECK(s.deformer_block()["to"] == "end");
  CHECK(s.handle_vertices("tip").empty());
  CHECK_FALSE(s.handle_vertices("end").empty());
  CHECK((s.posed() - before).cwiseAbs().maxCoeff() < 1e-12);  // same deformer, same pose
  CHECK_THROWS_AS(s.rename_handle("nope", "x"), Error);
  CHECK_THROWS_AS(s.rename_handle("end", "base"), Error);  // taken
  CHECK_THROWS_AS(s.rename_handle("end", ""), Error);
  CHECK(s.deformer_block()["to"] == "end");  // unchanged after the errors
  // A posed handle keeps its motor under the new name (surface-harmonic: handles are controls).
  Session h = Session::open(kScenes / "sh_tube.json");
  const Eigen::MatrixXd posed = h.posed();
  const ga::Mot m = h.motor("tip");
  h.rename_handle("tip", "end");
  CHECK((h.posed() - posed).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(ga::to_isometry(h.motor("end")).isApprox(ga::to_isometry(m)));
  CHECK(h.scene_document()["pose"].contains("end"));
  CHECK_FALSE(h.scene_document()["pose"].contains("tip"));
}

TEST_CASE("the IK target is a control: dragging its gizmo re-solves FABRIK and the tip follows",
          "[viewer][ik]") {
  Session s = Session::open(kScenes / "ik_tube.json");  // tube r = 0.25, target (1.5, 0, 3.2)
  REQUIRE(s.controls() == std::vector<std::string>{"ik.target"});
  const auto tip = s.handle_vertices("tip");
  const Vector3d target0 = *s.control_anchor("ik.target");
  CHECK((target0 - Vector3d(1.5, 0, 3.2)).norm() < 1e-15);
  CHECK((centroid(s.posed(), tip) - target0).norm() < 0.25 / 100);
  // A translate drag of the target's gizmo along y, through a camera, as the mouse does it.
  render::OrbitCamera cam;
  cam.target = Vector3d(0, 0, 2);
  cam.distance = 9, cam.azimuth_deg = 30, cam.elevation_deg = 20, cam.scene_radius = 2.5;
  const auto m =
      simulated_drag(cam, 640, 480, GizmoMode::Translate, 1, target0, 0.5, s.motor("ik.target"), 0.6);
  REQUIRE(m);
  s.set_motor("ik.target", *m);
  s.commit_pose();
  const Vector3d target1 = *s.posed_anchor("ik.target");
  CHECK((target1 - target0 - Vector3d(0, 0.6, 0)).norm() < 1e-9);
  const Vector3d c1 = centroid(s.posed(), tip);
  INFO("tip " << c1.transpose() << ", target " << target1.transpose());
  CHECK((c1 - target1).norm() < 0.25 / 100);
  CHECK(s.undo());
  CHECK((centroid(s.posed(), tip) - target0).norm() < 0.25 / 100);
  // Saved with the dragged target and reloaded: the tip lands there again.
  CHECK(s.redo());
  const auto out = kScenes / "viewer_ik_tmp.json";
  s.save_scene(out);
  Session t = Session::open(out);
  std::filesystem::remove(out);
  CHECK((centroid(t.posed(), tip) - target1).norm() < 0.25 / 100);
}

}  // namespace test_viewer_tools
