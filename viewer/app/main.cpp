// spinmotor-viewer [SCENE.json | MESH]: the interactive poser (GLFW + OpenGL 3.3 core + Dear ImGui).
//
// Window: left drag orbits, right drag (or shift+left) pans, wheel zooms; pick a handle in the panel,
// then drag the gizmo's axis arrows (translate) or rings (rotate, R toggles the mode) drawn over the
// mesh; the deformer (bound once) poses every frame and the pose time is shown. When a drag ends the
// edit is snapped to its nearest spin transformation in a worker thread (a stale result is dropped);
// Q before/after are shown and "show snap" displays it. Ctrl+Z / Ctrl+Y undo / redo pose edits.
//
// Headless: spinmotor-viewer --scene S --screenshot out.png [--size WxH] [--camera AZ,EL[,DIST]]
//   [--color q|checker|normals|plain] [--gizmo NAME,translate|rotate,x|y|z,AMOUNT]... [--snap]
//   [--frames N]
// renders one frame (in a hidden GLFW window, e.g. under xvfb-run, or without any display through
// the offscreen EGL/OSMesa context) and exits. --gizmo poses a handle through the gizmo's own code
// path (viewer/core/gizmo.hpp: a press ray and a release ray through the camera). --frames N poses and
// uploads N frames (a rotation growing through the gizmo code path) and prints the frame timer.
#include <CLI/CLI.hpp>

#include "spinmotor/render/gl_api.hpp"  // <GL/glcorearb.h> before GLFW (which then includes no GL header)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "spinmotor/error.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/gl_api.hpp"
#include "spinmotor/render/mesh_renderer.hpp"
#include "spinmotor/render/offscreen_context.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/session.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace {

using namespace spinmotor;
using namespace spinmotor::viewer;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void* glfw_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

struct GizmoSpec {
  std::string handle;
  GizmoMode mode = GizmoMode::Rotate;
  int axis = 2;
  double amount = 0;  ///< degrees (rotate) or scene units (translate)
};

GizmoSpec parse_gizmo(const std::string& s) {
  std::vector<std::string> p;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) p.push_back(item);
  const std::string usage = "--gizmo: expected NAME,translate|rotate,x|y|z,AMOUNT, got '" + s + "'";
  if (p.size() != 4 || (p[1] != "translate" && p[1] != "rotate") || p[2].size() != 1 || p[2][0] < 'x' ||
      p[2][0] > 'z')
    throw Error(usage);
  GizmoSpec g;
  g.handle = p[0];
  g.mode = p[1] == "rotate" ? GizmoMode::Rotate : GizmoMode::Translate;
  g.axis = p[2][0] - 'x';
  std::size_t used = 0;
  try {
    g.amount = std::stod(p[3], &used);
  } catch (...) {
    used = 0;
  }
  if (used != p[3].size() || !std::isfinite(g.amount)) throw Error(usage);
  return g;
}

/// A drag of the gizmo as the mouse would do it: press on the gizmo (axis tip or ring at angle 0),
/// release `amount` further along; both mouse positions become rays through the camera
/// (OrbitCamera::pixel_ray), and drag_motor turns them into the handle's motor, as in the window.
ga::Mot simulate_drag(const Session& s, const render::OrbitCamera& cam, int w, int h, const GizmoSpec& g) {
  const auto verts = s.handle_vertices(g.handle);
  if (verts.empty()) throw Error("--gizmo: '" + g.handle + "' is not a handle of " + s.scene().name());
  const ga::Mot m0 = s.motor(g.handle);
  const Eigen::Vector3d c = posed_centroid(s.rest().V, verts, m0);
  const auto m = simulated_drag(cam, w, h, g.mode, g.axis, c, 0.25 * cam.scene_radius, m0, g.amount);
  if (!m)
    throw Error("--gizmo: the camera looks along the " + std::string(1, char('x' + g.axis)) +
                " axis; pick another");
  return *m;
}

render::ColorMode parse_color(const std::string& c) {
  return c == "q"         ? render::ColorMode::Q
         : c == "checker" ? render::ColorMode::Checker
         : c == "normals" ? render::ColorMode::Normals
                          : render::ColorMode::Plain;
}

struct Args {
  std::string doc, screenshot, size = "1280x800", camera, up = "y", color = "checker", q_range = "1,2";
  std::vector<std::string> gizmos;
  bool snap = false, flat = false, wireframe = false;
  int frames = 0;
  double tradeoff = 1.0;
  int smoke_frames = 0;   ///< window mode: run this many frames, then exit (smoke test under Xvfb)
  std::string smoke_png;  ///< ... and save the last window frame (mesh + UI) here
};

// ---- headless -----------------------------------------------------------------------------------

int run_headless(const Args& a) {
  render::RenderOptions o;
  render::parse_size(a.size, o);
  if (!a.camera.empty()) render::parse_camera(a.camera, o);
  render::parse_q_range(a.q_range, o);
  o.up = Eigen::Vector3d::Unit(a.up[0] - 'x');
  o.style.color = parse_color(a.color);
  o.style.smooth = !a.flat;
  o.style.wireframe = a.wireframe;
  std::vector<GizmoSpec> gizmos;
  for (const auto& g : a.gizmos) gizmos.push_back(parse_gizmo(g));

  Session s = Session::open(a.doc);
  const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
  for (const auto& g : gizmos) {
    s.set_motor(g.handle, simulate_drag(s, cam, o.width, o.height, g));
    s.commit_pose();
  }
  Eigen::MatrixXd V = s.posed();
  std::printf("%s: %lld vertices, %lld faces; bind %.1f ms, pose %.2f ms\n", s.scene().name().c_str(),
              (long long)V.rows(), (long long)s.rest().F.rows(), s.bind_ms(), s.pose_ms());
  const double q_edit = quasi_conformal_summary(s.rest().V, s.rest().F, V).q_mean;
  if (a.snap) {
    SnapWorker worker(s.rest());
    worker.request(V, a.tradeoff);
    worker.wait_idle(600);
    auto r = worker.take();
    if (!r || !r->error.empty()) throw Error("snap failed: " + (r ? r->error : std::string("no result")));
    std::printf("snap: Q_mean %.4f -> %.4f (bind %.0f ms, snap %.0f ms)\n", q_edit, r->q_mean, r->bind_ms,
                r->snap_ms);
    V = r->V;
  } else {
    std::printf("Q_mean %.4f\n", q_edit);
  }

  // A hidden GLFW window (X server or Xvfb) when there is one, else the offscreen context.
  GLFWwindow* window = nullptr;
  std::unique_ptr<render::OffscreenContext> offscreen;
  std::string backend;
  if (glfwInit()) {
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    window = glfwCreateWindow(64, 64, "spinmotor-viewer", nullptr, nullptr);
  }
  if (window) {
    glfwMakeContextCurrent(window);
    render::load_gl(glfw_proc);
    backend = "glfw";
  } else {
    offscreen = std::make_unique<render::OffscreenContext>();
    backend = offscreen->description();
  }
  // The gizmo drags above used the camera framing the rest mesh (what a user sees when the viewer
  // opens); the picture frames what is shown.
  const render::OrbitCamera shot = render::render_camera(V, o);
  {
    render::MeshRenderer renderer;
    render::Framebuffer fb(o.width, o.height, o.samples);
    Mesh shown = s.rest();
    renderer.set_mesh(shown);
    renderer.set_positions(V);
    if (o.style.color == render::ColorMode::Q)
      renderer.set_face_values(quasi_conformal_error(s.rest().V, s.rest().F, V));
    fb.bind();
    if (a.frames > 0) {
      // The frame timer: pose (deformer) + upload (normals, float conversion, buffer update) + draw.
      const std::string h = s.controls().empty() ? "" : s.controls().front();
      if (h.empty() || s.handle_vertices(h).empty()) throw Error("--frames needs a scene with a handle");
      std::vector<double> pose_ms, upload_ms, draw_ms, frame_ms;
      const ga::Mot m0 = s.motor(h);
      int axis = 0;  // the ring that faces the camera best
      (cam.eye() - cam.target).cwiseAbs().maxCoeff(&axis);
      for (int f = 0; f < a.frames; ++f) {
        const auto t0 = Clock::now();
        GizmoSpec g{h, GizmoMode::Rotate, axis, 30.0 * (f + 1) / a.frames};
        s.set_motor(h, m0);
        s.set_motor(h, simulate_drag(s, cam, o.width, o.height, g));
        const Eigen::MatrixXd& Vf = s.posed();
        pose_ms.push_back(s.pose_ms());
        const auto t1 = Clock::now();
        renderer.set_positions(Vf);
        upload_ms.push_back(ms_since(t1));
        const auto t2 = Clock::now();
        renderer.draw(cam, o.width, o.height, o.style);
        render::gl.Finish();
        draw_ms.push_back(ms_since(t2));
        frame_ms.push_back(ms_since(t0));
      }
      auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      std::printf(
          "frame timer over %d frames (%s, %dx%d): pose %.2f ms, upload %.2f ms, pose+upload %.2f ms, "
          "draw %.2f ms, frame %.2f ms (medians)\n",
          a.frames, backend.c_str(), o.width, o.height, median(pose_ms), median(upload_ms),
          [&] {
            std::vector<double> pu(pose_ms.size());
            for (std::size_t i = 0; i < pu.size(); ++i) pu[i] = pose_ms[i] + upload_ms[i];
            return median(pu);
          }(),
          median(draw_ms), median(frame_ms));
    }
    renderer.draw(shot, o.width, o.height, o.style);
    render::Image im = fb.read();
    if (o.style.color == render::ColorMode::Q && o.color_bar)
      render::draw_color_bar(im, o.style.q_min, o.style.q_max);
    render::write_png(a.screenshot, im);
    std::printf("wrote %s (%dx%d, %s)\n", a.screenshot.c_str(), o.width, o.height, backend.c_str());
  }
  if (window) glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

// ---- interactive ----------------------------------------------------------------------------------

struct Viewer {
  Session session;
  render::RenderStyle style;
  render::OrbitCamera cam;
  std::unique_ptr<render::MeshRenderer> renderer;
  std::unique_ptr<SnapWorker> worker;
  int handle = 0;  ///< index into session.controls()
  GizmoMode gizmo_mode = GizmoMode::Rotate;
  std::optional<GizmoDrag> drag;
  double tradeoff = 1.0;
  bool auto_snap = true, show_snap = false;
  std::optional<SnapOutcome> snapped;
  double q_edit = 1.0;
  Eigen::VectorXd Q;
  bool geometry_dirty = true;
  std::string status;
  char save_path[512] = "", export_path[512] = "", shot_path[512] = "screenshot.png";
  double frame_ms = 0;
  std::vector<int> selection;  ///< brush selection (ctrl+click) for a new handle
  float brush = 0.1f;          ///< brush radius, fraction of the scene radius
  char new_handle[64] = "handle";

  explicit Viewer(Session s) : session(std::move(s)) {}

  std::string handle_name() const {
    const auto& c = session.controls();
    return c.empty() ? "" : c[std::clamp(handle, 0, int(c.size()) - 1)];
  }

  const Eigen::MatrixXd& shown_positions() {
    if (show_snap && snapped && snapped->V.rows()) return snapped->V;
    return session.posed();
  }

  void refresh_geometry() {
    const Eigen::MatrixXd& V = shown_positions();
    renderer->set_positions(V);
    if (style.color == render::ColorMode::Q) {
      Q = quasi_conformal_error(session.rest().V, session.rest().F, V);
      renderer->set_face_values(Q);
    }
    q_edit = quasi_conformal_summary(session.rest().V, session.rest().F, session.posed()).q_mean;
    geometry_dirty = false;
  }

  void request_snap() {
    if (!worker || !auto_snap) return;
    worker->request(session.posed(), tradeoff);
  }
};

void draw_gizmo_and_handle_input(Viewer& v, int w, int h) {
  ImGuiIO& io = ImGui::GetIO();
  ImDrawList* dl = ImGui::GetBackgroundDrawList();  // over the mesh, under the panels
  const std::string name = v.handle_name();
  const auto verts = v.session.handle_vertices(name);
  const ImVec2 mouse = io.MousePos;
  const render::Ray ray = v.cam.pixel_ray(mouse.x, mouse.y, w, h);
  const ImU32 colours[3] = {IM_COL32(220, 50, 50, 255), IM_COL32(50, 180, 50, 255),
                            IM_COL32(60, 90, 230, 255)};
  int hover_axis = -1;
  if (!v.selection.empty()) {
    const Eigen::MatrixXd& V = v.session.posed();
    const std::size_t step = std::max<std::size_t>(1, v.selection.size() / 4000);
    for (std::size_t i = 0; i < v.selection.size(); i += step) {
      const Eigen::Vector3d p = v.cam.project(V.row(v.selection[i]).transpose(), w, h);
      dl->AddCircleFilled(ImVec2(float(p.x()), float(p.y())), 2.0f, IM_COL32(255, 200, 0, 255));
    }
  }
  if (!verts.empty()) {
    const Eigen::Vector3d c = posed_centroid(v.session.rest().V, verts, v.session.motor(name));
    const double r = 0.25 * v.cam.scene_radius;
    auto to_screen = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d s = v.cam.project(p, w, h);
      return ImVec2(float(s.x()), float(s.y()));
    };
    double best = 8.0;  // pixels
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = Eigen::Vector3d::Unit(k);
      std::vector<ImVec2> pts;
      if (v.gizmo_mode == GizmoMode::Translate) {
        pts = {to_screen(c), to_screen(c + r * a)};
      } else {
        const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
        for (int i = 0; i <= 64; ++i) {
          const double phi = 2 * std::numbers::pi * i / 64;
          pts.push_back(to_screen(c + r * (std::cos(phi) * e1 + std::sin(phi) * e2)));
        }
      }
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const ImVec2 p = pts[i], q = pts[i + 1];
        const float dx = q.x - p.x, dy = q.y - p.y, len2 = dx * dx + dy * dy;
        const float t =
            len2 > 0 ? std::clamp(((mouse.x - p.x) * dx + (mouse.y - p.y) * dy) / len2, 0.0f, 1.0f) : 0;
        const double d = std::hypot(mouse.x - (p.x + t * dx), mouse.y - (p.y + t * dy));
        if (d < best) best = d, hover_axis = k;
      }
      const bool active = v.drag && v.drag->axis == a;
      dl->AddPolyline(pts.data(), int(pts.size()), colours[k], 0, active ? 4.0f : 2.5f);
      if (v.gizmo_mode == GizmoMode::Translate) dl->AddCircleFilled(pts.back(), 5.0f, colours[k]);
    }
    if (!io.WantCaptureMouse && hover_axis >= 0 && ImGui::IsMouseClicked(0) && !v.drag) {
      v.drag = begin_drag(v.gizmo_mode, hover_axis, c, v.session.motor(name), ray);
      if (v.worker) v.worker->cancel();
      v.snapped.reset();
    }
  }
  if (v.drag) {
    if (ImGui::IsMouseDown(0)) {
      v.session.set_motor(name, drag_motor(*v.drag, ray));
      v.geometry_dirty = true;
    } else {
      v.drag.reset();
      v.session.commit_pose();
      v.request_snap();
    }
    return;
  }
  if (io.WantCaptureMouse) return;
  // Brush: ctrl+click adds the vertices within the brush radius of the picked surface point.
  if (io.KeyCtrl && ImGui::IsMouseClicked(0)) {
    const Eigen::MatrixXd& V = v.session.posed();
    if (const auto hit = pick(ray, V, v.session.rest().F)) {
      const auto add = vertices_in_sphere(V, hit->point, v.brush * v.cam.scene_radius);
      std::vector<int> merged;
      std::set_union(v.selection.begin(), v.selection.end(), add.begin(), add.end(),
                     std::back_inserter(merged));
      v.selection = std::move(merged);
    }
    return;
  }
  const ImVec2 d = io.MouseDelta;
  if (ImGui::IsMouseDragging(1) || (ImGui::IsMouseDragging(0) && io.KeyShift))
    v.cam.pan(d.x, d.y, w, h);
  else if (ImGui::IsMouseDragging(0))
    v.cam.orbit(-0.4 * d.x, 0.4 * d.y);
  if (io.MouseWheel != 0) v.cam.zoom(std::pow(0.9, io.MouseWheel));
}

void panel(Viewer& v, GLFWwindow* window, int w, int h) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("spinmotor");
  ImGui::Text("%s: %lld vertices, %lld faces", v.session.scene().name().c_str(),
              (long long)v.session.rest().V.rows(), (long long)v.session.rest().F.rows());
  ImGui::Text("frame %.1f ms", v.frame_ms);
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    int mode = int(v.style.color);
    const char* modes[] = {"normals", "checker", "Q (quasi-conformal error)", "plain"};
    if (ImGui::Combo("colour", &mode, modes, 4))
      v.style.color = render::ColorMode(mode), v.geometry_dirty = true;
    ImGui::Checkbox("smooth", &v.style.smooth);
    ImGui::SameLine();
    ImGui::Checkbox("wireframe", &v.style.wireframe);
    float cells = float(v.style.checker_cells);
    if (ImGui::SliderFloat("checker cells", &cells, 1, 64)) v.style.checker_cells = cells;
    float qr[2] = {float(v.style.q_min), float(v.style.q_max)};
    if (ImGui::DragFloat2("Q range", qr, 0.01f, 1.0f, 10.0f)) {
      v.style.q_min = std::max(1.0f, qr[0]);
      v.style.q_max = std::max(qr[1], qr[0] + 0.01f);
    }
    if (v.style.color == render::ColorMode::Q) {  // colour bar
      ImDrawList* dl = ImGui::GetWindowDrawList();
      const ImVec2 p = ImGui::GetCursorScreenPos();
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3f c = render::q_colormap(i / 199.0);
        dl->AddRectFilled(ImVec2(p.x + i, p.y), ImVec2(p.x + i + 1, p.y + 12),
                          IM_COL32(int(255 * c[0]), int(255 * c[1]), int(255 * c[2]), 255));
      }
      ImGui::Dummy(ImVec2(200, 14));
      ImGui::Text("%.2f %*s %.2f (log scale)", v.style.q_min, 18, "", v.style.q_max);
    }
  }
  if (ImGui::CollapsingHeader("Handles", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::SliderFloat("brush", &v.brush, 0.01f, 0.5f);
    ImGui::Text("ctrl+click: select (%zu vertices)", v.selection.size());
    ImGui::InputText("name", v.new_handle, sizeof v.new_handle);
    if (ImGui::Button("new handle")) try {
        v.session.add_handle(v.new_handle, v.selection);
        v.selection.clear();
        v.handle = int(v.session.controls().size()) - 1;
        if (!v.worker) v.worker = std::make_unique<SnapWorker>(v.session.rest());
        v.geometry_dirty = true;
        v.status = std::string("added handle ") + v.new_handle;
      } catch (const std::exception& e) {
        v.status = e.what();
      }
    ImGui::SameLine();
    if (ImGui::Button("clear selection")) v.selection.clear();
    ImGui::SameLine();
    if (ImGui::Button("delete handle") && !v.handle_name().empty()) try {
        v.session.remove_handle(v.handle_name());
        v.handle = 0;
        v.geometry_dirty = true;
      } catch (const std::exception& e) {
        v.status = e.what();
      }
  }
  if (v.session.has_deformer() && ImGui::CollapsingHeader("Pose", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("deformer %s: bind %.0f ms, pose %.2f ms", v.session.scene().deformer_type.c_str(),
                v.session.bind_ms(), v.session.pose_ms());
    const auto& c = v.session.controls();
    if (ImGui::BeginListBox("handles", ImVec2(-1, 90))) {
      for (int i = 0; i < int(c.size()); ++i)
        if (ImGui::Selectable(c[i].c_str(), i == v.handle)) v.handle = i;
      ImGui::EndListBox();
    }
    int gm = v.gizmo_mode == GizmoMode::Translate ? 0 : 1;
    ImGui::RadioButton("translate", &gm, 0);
    ImGui::SameLine();
    ImGui::RadioButton("rotate (R)", &gm, 1);
    v.gizmo_mode = gm == 0 ? GizmoMode::Translate : GizmoMode::Rotate;
    if (ImGui::Button("undo") && v.session.undo()) v.geometry_dirty = true, v.request_snap();
    ImGui::SameLine();
    if (ImGui::Button("redo") && v.session.redo()) v.geometry_dirty = true, v.request_snap();
    ImGui::SameLine();
    if (ImGui::Button("reset handle")) {
      v.session.set_motor(v.handle_name(), ga::from_isometry(Eigen::Isometry3d::Identity()));
      v.session.commit_pose();
      v.geometry_dirty = true;
      v.request_snap();
    }
  }
  if (ImGui::CollapsingHeader("Snap to spin", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("snap when a drag ends", &v.auto_snap);
    float t = float(v.tradeoff);
    if (ImGui::SliderFloat("tradeoff", &t, 0, 1)) v.tradeoff = t;
    if (ImGui::IsItemDeactivatedAfterEdit()) v.request_snap();
    if (ImGui::Button("snap now") && v.worker) v.worker->request(v.session.posed(), v.tradeoff);
    ImGui::SameLine();
    if (ImGui::Checkbox("show snap", &v.show_snap)) v.geometry_dirty = true;
    ImGui::Text("Q_mean edit %.4f", v.q_edit);
    if (v.worker && v.worker->busy())
      ImGui::Text("snapping...");
    else if (v.snapped && v.snapped->error.empty())
      ImGui::Text("Q_mean snap %.4f (%.0f ms)", v.snapped->q_mean, v.snapped->snap_ms);
    else if (v.snapped)
      ImGui::TextWrapped("snap failed: %s", v.snapped->error.c_str());
  }
  if (ImGui::CollapsingHeader("Files")) {
    ImGui::InputText("scene", v.save_path, sizeof v.save_path);
    ImGui::SameLine();
    if (ImGui::Button("save")) try {
        v.session.save_scene(v.save_path);
        v.status = std::string("saved ") + v.save_path;
      } catch (const std::exception& e) {
        v.status = e.what();
      }
    ImGui::InputText("mesh", v.export_path, sizeof v.export_path);
    ImGui::SameLine();
    if (ImGui::Button("export")) try {
        Mesh out = v.session.rest();
        out.V = v.shown_positions();
        write_mesh(v.export_path, out);
        v.status = std::string("exported ") + v.export_path;
      } catch (const std::exception& e) {
        v.status = e.what();
      }
    ImGui::InputText("png", v.shot_path, sizeof v.shot_path);
    ImGui::SameLine();
    if (ImGui::Button("screenshot")) try {
        render::Framebuffer fb(w, h);
        fb.bind();
        v.renderer->draw(v.cam, w, h, v.style);
        render::Image im = fb.read();
        if (v.style.color == render::ColorMode::Q) render::draw_color_bar(im, v.style.q_min, v.style.q_max);
        render::write_png(v.shot_path, im);
        v.status = std::string("wrote ") + v.shot_path;
      } catch (const std::exception& e) {
        v.status = e.what();
      }
  }
  if (!v.status.empty()) ImGui::TextWrapped("%s", v.status.c_str());
  ImGui::End();
  (void)window;
}

int run_window(const Args& a) {
  Session s = Session::open(a.doc);
  if (!glfwInit()) throw Error("GLFW: cannot initialise (no display? use --screenshot for headless mode)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  render::RenderOptions o;
  render::parse_size(a.size, o);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "spinmotor-viewer", nullptr, nullptr);
  if (!window) throw Error("GLFW: cannot create an OpenGL 3.3 core window");
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  render::load_gl(glfw_proc);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  {
    Viewer v(std::move(s));
    v.style.color = parse_color(a.color);
    if (!a.camera.empty()) render::parse_camera(a.camera, o);
    o.up = Eigen::Vector3d::Unit(a.up[0] - 'x');
    v.cam = render::render_camera(v.session.posed(), o);  // frames the scene as posed
    v.renderer = std::make_unique<render::MeshRenderer>();
    v.renderer->set_mesh(v.session.rest());
    if (v.session.has_deformer()) v.worker = std::make_unique<SnapWorker>(v.session.rest());
    v.tradeoff = a.tradeoff;
    const std::string stem = v.session.scene().file.stem().string();
    std::snprintf(v.save_path, sizeof v.save_path, "%s",
                  (v.session.scene().dir / (stem + "-edited.json")).c_str());
    std::snprintf(v.export_path, sizeof v.export_path, "%s", (stem + "-posed.obj").c_str());
    for (int frame = 1; !glfwWindowShouldClose(window); ++frame) {
      const auto t0 = Clock::now();
      glfwPollEvents();
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      int w, h, fw, fh;
      glfwGetWindowSize(window, &w, &h);
      glfwGetFramebufferSize(window, &fw, &fh);
      if (w <= 0 || h <= 0) {
        ImGui::EndFrame();
        continue;
      }
      ImGuiIO& io = ImGui::GetIO();
      if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_R))
          v.gizmo_mode = v.gizmo_mode == GizmoMode::Rotate ? GizmoMode::Translate : GizmoMode::Rotate;
        if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Z) && v.session.undo())
          v.geometry_dirty = true, v.request_snap();
        if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Y) && v.session.redo())
          v.geometry_dirty = true, v.request_snap();
      }
      if (v.worker)
        if (auto r = v.worker->take()) {
          v.snapped = std::move(*r);
          if (v.show_snap) v.geometry_dirty = true;
        }
      draw_gizmo_and_handle_input(v, w, h);
      panel(v, window, fw, fh);
      if (v.geometry_dirty) v.refresh_geometry();
      ImGui::Render();
      render::gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
      v.renderer->draw(v.cam, fw, fh, v.style);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      if (a.smoke_frames > 0 && frame >= a.smoke_frames) {
        if (!a.smoke_png.empty()) {
          render::Image im;
          im.width = fw, im.height = fh, im.rgba.resize(std::size_t(fw) * fh * 4);
          std::vector<std::uint8_t> rows(im.rgba.size());
          render::gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
          render::gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
          render::gl.ReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
          for (int y = 0; y < fh; ++y)
            std::copy_n(&rows[std::size_t(fh - 1 - y) * fw * 4], std::size_t(fw) * 4,
                        &im.rgba[std::size_t(y) * fw * 4]);
          render::write_png(a.smoke_png, im);
        }
        std::printf("window: %d frames, last %.1f ms\n", frame, v.frame_ms);
        break;
      }
      glfwSwapBuffers(window);
      v.frame_ms = ms_since(t0);
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"spinmotor-viewer: pose a mesh with CGA motor handles and snap it to a spin transformation"};
  Args a;
  app.add_option("DOC", a.doc, "Scene file (.json, SCENE.md) or mesh file");
  app.add_option("--scene", a.doc, "Scene file (same as DOC)");
  app.add_option("--screenshot", a.screenshot, "Headless: render one frame to this PNG and exit");
  app.add_option("--size", a.size, "Window / image size WxH")->capture_default_str();
  app.add_option("--camera", a.camera, "AZ,EL[,DIST]: orbit camera (degrees about the up axis, distance)");
  app.add_option("--up", a.up, "Up axis")->check(CLI::IsMember({"x", "y", "z"}))->capture_default_str();
  app.add_option("--color", a.color, "q, checker, normals or plain")
      ->check(CLI::IsMember({"q", "checker", "normals", "plain"}))
      ->capture_default_str();
  app.add_option("--q-range", a.q_range, "LO,HI: Q colour range")->capture_default_str();
  app.add_flag("--flat", a.flat, "Flat shading");
  app.add_flag("--wireframe", a.wireframe, "Draw edges");
  app.add_option("--gizmo", a.gizmos, "Headless: NAME,translate|rotate,x|y|z,AMOUNT: drag a handle's gizmo")
      ->take_all();
  app.add_flag("--snap", a.snap, "Headless: show the conformal snap of the posed mesh");
  app.add_option("--tradeoff", a.tradeoff, "Snap tradeoff in [0, 1]")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--frames", a.frames,
                 "Headless: pose + upload + draw this many frames and print the frame timer")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--smoke-frames", a.smoke_frames, "Window mode: exit after this many frames (tests)");
  app.add_option("--smoke-png", a.smoke_png,
                 "Window mode with --smoke-frames: save the last frame (with the UI)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (a.doc.empty()) throw Error("a scene or mesh file is required (spinmotor-viewer SCENE.json | MESH)");
    if (!a.screenshot.empty()) return run_headless(a);
    if (a.snap || !a.gizmos.empty() || a.frames > 0)
      throw Error("--gizmo, --snap and --frames need --screenshot");
    return run_window(a);
  } catch (const Error& e) {
    std::cerr << "spinmotor-viewer: error: " << e.what() << "\n";
    return e.kind() == Error::Kind::Numerical ? 3 : 2;
  } catch (const std::exception& e) {
    std::cerr << "spinmotor-viewer: error: " << e.what() << "\n";
    return 3;
  }
}
