// spinmotor-viewer's window: GLFW + OpenGL 3.3 core + Dear ImGui over the window-free core.
#include "spinmotor/render/gl_api.hpp"  // <GL/glcorearb.h> before GLFW (which then includes no GL header)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "app.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/animation_clock.hpp"
#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "spinmotor/viewer/lattice_edges.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace spinmotor::viewer::app {

namespace {

enum class Tool { Brush, Box, Lasso, Paint };
enum class Shown { Edit, Snap, Painted };

struct Viewer {
  Session session;
  render::RenderStyle style;
  render::OrbitCamera cam;
  std::unique_ptr<render::MeshRenderer> renderer;
  std::unique_ptr<SnapWorker> snapper;
  std::unique_ptr<SpinPaintWorker> painter;  ///< made on the first paint
  std::string status;
  double frame_ms = 0;
  bool geometry_dirty = true;
  Shown shown = Shown::Edit;
  Eigen::VectorXd Q;
  double q_edit = 1.0;

  // Controls and their gizmo.
  int control = 0;  ///< index into session.controls()
  GizmoMode gizmo_mode = GizmoMode::Rotate;
  std::optional<GizmoDrag> drag;
  std::vector<std::optional<Eigen::Vector3d>> anchors;  ///< rest anchors, per control (cached per bind)
  std::vector<std::pair<int, int>> lattice;             ///< FFD lattice lines between controls

  // Snap to spin.
  double tradeoff = 1.0;
  bool keep_pose = true;  ///< snap = the pose-keeping cleanup with the handles pinned
  bool auto_snap = true;
  std::optional<SnapOutcome> snapped;

  // Tools (ctrl+drag): selection for new handles, curvature paint.
  Tool tool = Tool::Brush;
  bool visible_only = true;
  float brush = 0.1f;  ///< brush radius (selection and paint), fraction of the scene radius
  std::vector<int> selection;
  bool gesture = false, subtract = false;
  std::vector<Eigen::Vector2d> lasso;
  Eigen::Vector2d box_start = Eigen::Vector2d::Zero();
  std::optional<DepthMap> depth;
  char new_handle[64] = "handle";
  Eigen::VectorXd rho;  ///< painted curvature change per face
  float paint_amount = 2.0f;
  bool auto_apply = true;
  std::optional<PaintOutcome> painted;

  // Animation (rigs): the playback clock, the skeleton overlay, the per-frame cleanup.
  AnimationClock clock;
  bool show_skeleton = true;
  bool cleanup_frames = false;   ///< the pose-keeping cleanup of every frame shown (snap worker)
  std::vector<PosedBone> bones;  ///< posed, refreshed with the geometry

  // Deformer panel.
  int choice = 0;
  nlohmann::json edit_block;
  char block_text[8192] = "";

  char open_path[512] = "", save_path[512] = "", export_path[512] = "", shot_path[512] = "screenshot.png";

  explicit Viewer(Session s) : session(std::move(s)) {}

  std::string control_name() const {
    const auto& c = session.controls();
    return c.empty() ? "" : c[std::clamp(control, 0, int(c.size()) - 1)];
  }

  /// After any (re)bind: cached anchors, lattice lines, the panel's copy of the deformer block.
  void on_rebind() {
    const auto& c = session.controls();
    anchors.clear();
    for (const auto& name : c) anchors.push_back(session.control_anchor(name));
    lattice = ffd_lattice_edges(c);
    control = std::clamp(control, 0, std::max(0, int(c.size()) - 1));
    edit_block = session.deformer_block();
    std::snprintf(block_text, sizeof block_text, "%s",
                  edit_block.is_null() ? "" : edit_block.dump(2).c_str());
    const auto& choices = deformer_choices();
    std::string current = session.scene().deformer_type;
    if (current == "spline" && !session.ik_block().is_null()) current = "spline-ik";
    if (const auto it = std::find(choices.begin(), choices.end(), current); it != choices.end())
      choice = int(it - choices.begin());
    if (rho.size() != session.rest().F.rows()) rho = Eigen::VectorXd::Zero(session.rest().F.rows());
    const auto [start, end] = session.animation_range();
    clock.start = start, clock.end = end;
    clock.time = session.time().value_or(start);
    if (session.animation() < 0) clock.playing = false;
    geometry_dirty = true;
  }

  /// A new frame of the animation (slider or playback): pose it, and clean it up when asked.
  void set_time(std::optional<double> t) {
    try {
      session.set_time(t);
    } catch (const std::exception& e) {
      status = e.what();
      return;
    }
    geometry_dirty = true;
    if (cleanup_frames) {
      keep_pose = true;
      snap_now();
      shown = Shown::Snap;  // the latest cleaned frame (the worker drops frames it has no time for)
    }
  }

  void rebind(const std::function<void()>& change, const std::string& what) {
    try {
      change();
      on_rebind();
      snapped.reset();
      status = what + " (bind " + std::to_string(int(session.bind_ms())) + " ms)";
    } catch (const std::exception& e) {
      status = e.what();
    }
  }

  const Eigen::MatrixXd& shown_positions() {
    if (shown == Shown::Snap && snapped && snapped->V.rows()) return snapped->V;
    if (shown == Shown::Painted && painted && painted->V.rows()) return painted->V;
    return session.posed();
  }

  void refresh_geometry() {
    const Eigen::MatrixXd& V = shown_positions();
    renderer->set_positions(V);
    if (style.color == render::ColorMode::Q) {
      Q = quasi_conformal_error(session.rest().V, session.rest().F, V);
      renderer->set_face_values(Q);
    } else if (style.color == render::ColorMode::Signed) {
      renderer->set_face_values(rho);
    }
    q_edit = quasi_conformal_summary(session.rest().V, session.rest().F, session.posed()).q_mean;
    bones = session.posed_bones();
    geometry_dirty = false;
  }

  void request_snap() {
    if (snapper && auto_snap && session.has_deformer()) snap_now();
  }
  /// The §7.2 snap, or with "keep the pose" the pose-keeping cleanup with every handle pinned.
  void snap_now() {
    if (!snapper) return;
    std::vector<int> pins;
    std::shared_ptr<const scene::SkinBinding> skin;
    if (keep_pose) pins = session.cleanup_pins(), skin = session.cleanup_skin();
    if (skin)
      snapper->request_rig(session.posed(), std::move(skin));
    else if (!pins.empty())
      snapper->request_pinned(session.posed(), std::move(pins));
    else
      snapper->request(session.posed(), tradeoff);
  }

  void request_paint() {
    if (!painter) painter = std::make_unique<SpinPaintWorker>(session.rest());
    painter->request(rho);
  }
};

ImVec2 to_imvec(const Eigen::Vector3d& p) { return ImVec2(float(p.x()), float(p.y())); }

// ---- gestures ----------------------------------------------------------------------------------

void begin_gesture(Viewer& v, const ImVec2& mouse, int w, int h) {
  v.gesture = true;
  v.subtract = ImGui::GetIO().KeyAlt;
  v.lasso.assign(1, Eigen::Vector2d(mouse.x, mouse.y));
  v.box_start = Eigen::Vector2d(mouse.x, mouse.y);
  v.depth.reset();
  if ((v.tool == Tool::Box || v.tool == Tool::Lasso) && v.visible_only)
    v.depth = DepthMap::render(v.shown_positions(), v.session.rest().F, v.cam, w, h);
}

void continue_gesture(Viewer& v, const ImVec2& mouse, const render::Ray& ray) {
  const Eigen::Vector2d m(mouse.x, mouse.y);
  if (v.tool == Tool::Lasso) {
    if ((m - v.lasso.back()).norm() > 2) v.lasso.push_back(m);
    return;
  }
  if (v.tool == Tool::Box) return;
  if (ImGui::GetIO().MouseDelta.x == 0 && ImGui::GetIO().MouseDelta.y == 0 && !ImGui::IsMouseClicked(0))
    return;
  const Eigen::MatrixXd& V = v.shown_positions();
  const auto hit = pick(ray, V, v.session.rest().F);
  if (!hit) return;
  const double radius = v.brush * v.cam.scene_radius;
  if (v.tool == Tool::Brush) {
    const auto dab = vertices_in_sphere(V, hit->point, radius);
    v.selection = v.subtract ? selection_difference(v.selection, dab) : selection_union(v.selection, dab);
  } else {  // Paint: one dab per mouse move, ρ in 1/length
    paint_rho(V, v.session.rest().F, hit->point, radius, (v.subtract ? -0.1 : 0.1) * v.paint_amount, v.rho);
    if (v.style.color == render::ColorMode::Signed) v.geometry_dirty = true;
  }
}

void end_gesture(Viewer& v, const ImVec2& mouse, int w, int h) {
  v.gesture = false;
  const Eigen::MatrixXd& V = v.shown_positions();
  const DepthMap* depth = v.depth ? &*v.depth : nullptr;
  std::vector<int> region;
  if (v.tool == Tool::Box)
    region = vertices_in_box(V, v.cam, w, h, v.box_start, Eigen::Vector2d(mouse.x, mouse.y), depth);
  else if (v.tool == Tool::Lasso)
    region = vertices_in_lasso(V, v.cam, w, h, v.lasso, depth);
  if (v.tool == Tool::Box || v.tool == Tool::Lasso)
    v.selection =
        v.subtract ? selection_difference(v.selection, region) : selection_union(v.selection, region);
  if (v.tool == Tool::Paint && v.auto_apply) v.request_paint();
  v.lasso.clear();
  v.depth.reset();
}

// ---- the view: controls, gizmo, selection, mouse -------------------------------------------------

void draw_and_handle_input(Viewer& v, int w, int h) {
  ImGuiIO& io = ImGui::GetIO();
  ImDrawList* dl = ImGui::GetBackgroundDrawList();  // over the mesh, under the panels
  const ImVec2 mouse = io.MousePos;
  const render::Ray ray = v.cam.pixel_ray(mouse.x, mouse.y, w, h);
  auto to_screen = [&](const Eigen::Vector3d& p) { return to_imvec(v.cam.project(p, w, h)); };
  const ImU32 colours[3] = {IM_COL32(220, 50, 50, 255), IM_COL32(50, 180, 50, 255),
                            IM_COL32(60, 90, 230, 255)};

  // Selection in progress and made.
  if (!v.selection.empty()) {
    const Eigen::MatrixXd& V = v.shown_positions();
    const std::size_t step = std::max<std::size_t>(1, v.selection.size() / 4000);
    for (std::size_t i = 0; i < v.selection.size(); i += step)
      dl->AddCircleFilled(to_screen(V.row(v.selection[i]).transpose()), 2.0f, IM_COL32(255, 200, 0, 255));
  }
  if (v.gesture && v.tool == Tool::Box)
    dl->AddRect(ImVec2(float(v.box_start.x()), float(v.box_start.y())), mouse, IM_COL32(255, 200, 0, 255));
  if (v.gesture && v.tool == Tool::Lasso && v.lasso.size() > 1) {
    std::vector<ImVec2> pts;
    for (const auto& p : v.lasso) pts.emplace_back(float(p.x()), float(p.y()));
    dl->AddPolyline(pts.data(), int(pts.size()), IM_COL32(255, 200, 0, 255), ImDrawFlags_Closed, 1.5f);
  }
  if ((v.tool == Tool::Brush || v.tool == Tool::Paint) && io.KeyCtrl && !io.WantCaptureMouse)
    dl->AddCircle(mouse, 6.0f, IM_COL32(255, 200, 0, 255));

  // Controls: a dot per control (lattice lines between FFD controls), the current one's gizmo.
  const auto& names = v.session.controls();
  std::vector<std::optional<ImVec2>> dots(names.size());
  if (!v.bones.empty() && v.bones.size() == names.size()) {  // a skin: its controls are its bones, posed
    for (std::size_t i = 0; i < names.size(); ++i) dots[i] = to_screen(v.bones[i].head);
    if (v.show_skeleton)
      for (const PosedBone& b : v.bones)
        dl->AddLine(to_screen(b.head), to_screen(b.tail), IM_COL32(255, 140, 0, 230), 2.5f);
  } else if (names.size() <= 4096) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (i < v.anchors.size() && v.anchors[i])
        dots[i] = to_screen(ga::to_isometry(v.session.motor(names[i])) * *v.anchors[i]);
  }
  for (const auto& [i, j] : v.lattice)
    if (dots[i] && dots[j]) dl->AddLine(*dots[i], *dots[j], IM_COL32(90, 90, 90, 160), 1.0f);
  int hover_dot = -1;
  double best_dot = 7.0;
  for (std::size_t i = 0; i < dots.size(); ++i) {
    if (!dots[i]) continue;
    const bool current = int(i) == v.control;
    dl->AddCircleFilled(*dots[i], current ? 6.0f : 4.0f,
                        current ? IM_COL32(255, 200, 0, 255) : IM_COL32(40, 40, 40, 220));
    const double d = std::hypot(mouse.x - dots[i]->x, mouse.y - dots[i]->y);
    if (d < best_dot) best_dot = d, hover_dot = int(i);
  }

  const std::string name = v.control_name();
  const GizmoMode mode = name == "ik.target" ? GizmoMode::Translate : v.gizmo_mode;  // a point: no rotation
  int hover_axis = -1;
  if (const auto centre = name.empty() ? std::nullopt : v.session.posed_anchor(name)) {
    const Eigen::Vector3d c = *centre;
    const double r = 0.25 * v.cam.scene_radius;
    double best = 8.0;  // pixels
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = Eigen::Vector3d::Unit(k);
      std::vector<ImVec2> pts;
      if (mode == GizmoMode::Translate) {
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
      if (mode == GizmoMode::Translate) dl->AddCircleFilled(pts.back(), 5.0f, colours[k]);
    }
    if (!io.WantCaptureMouse && !io.KeyCtrl && hover_axis >= 0 && ImGui::IsMouseClicked(0) && !v.drag) {
      v.drag = begin_drag(mode, hover_axis, c, v.session.drag_start_motor(name), ray);
      if (v.snapper) v.snapper->cancel();
      v.snapped.reset();
      if (v.shown == Shown::Snap) v.shown = Shown::Edit;
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
  if (v.gesture) {
    if (ImGui::IsMouseDown(0))
      continue_gesture(v, mouse, ray);
    else
      end_gesture(v, mouse, w, h);
    return;
  }
  if (io.WantCaptureMouse) return;
  if (io.KeyCtrl && ImGui::IsMouseClicked(0)) {
    begin_gesture(v, mouse, w, h);
    continue_gesture(v, mouse, ray);
    return;
  }
  if (hover_dot >= 0 && ImGui::IsMouseClicked(0)) {
    v.control = hover_dot;
    return;
  }
  const ImVec2 d = io.MouseDelta;
  if (ImGui::IsMouseDragging(1) || (ImGui::IsMouseDragging(0) && io.KeyShift))
    v.cam.pan(d.x, d.y, w, h);
  else if (ImGui::IsMouseDragging(0))
    v.cam.orbit(-0.4 * d.x, 0.4 * d.y);
  if (io.MouseWheel != 0) v.cam.zoom(std::pow(0.9, io.MouseWheel));
}

// ---- panels -------------------------------------------------------------------------------------

void display_panel(Viewer& v) {
  if (!ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int mode = int(v.style.color);
  const char* modes[] = {"normals", "checker", "Q (quasi-conformal error)", "plain", "painted rho"};
  if (ImGui::Combo("colour", &mode, modes, 5))
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
  float sr = float(v.style.signed_range);
  if (ImGui::SliderFloat("rho range", &sr, 0.1f, 50.0f, "%.1f", ImGuiSliderFlags_Logarithmic))
    v.style.signed_range = sr;
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
  int shown = int(v.shown);
  ImGui::Text("show");
  ImGui::SameLine();
  bool changed = ImGui::RadioButton("edit", &shown, 0);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("snap", &shown, 1);
  ImGui::SameLine();
  changed |= ImGui::RadioButton("painted", &shown, 2);
  if (changed) v.shown = Shown(shown), v.geometry_dirty = true;
}

void tools_panel(Viewer& v) {
  if (!ImGui::CollapsingHeader("Select and paint (ctrl+drag)", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int tool = int(v.tool);
  ImGui::RadioButton("brush", &tool, 0);
  ImGui::SameLine();
  ImGui::RadioButton("box", &tool, 1);
  ImGui::SameLine();
  ImGui::RadioButton("lasso", &tool, 2);
  ImGui::SameLine();
  ImGui::RadioButton("paint rho", &tool, 3);
  v.tool = Tool(tool);
  ImGui::SliderFloat("brush radius", &v.brush, 0.01f, 0.5f);
  ImGui::Checkbox("visible vertices only (box, lasso)", &v.visible_only);
  ImGui::Text("selection: %zu vertices (alt+drag subtracts)", v.selection.size());
  ImGui::InputText("name", v.new_handle, sizeof v.new_handle);
  if (ImGui::Button("new handle"))
    v.rebind(
        [&] {
          v.session.add_handle(v.new_handle, v.selection);
          v.selection.clear();
          v.control = int(v.session.controls().size()) - 1;
        },
        std::string("added handle ") + v.new_handle);
  ImGui::SameLine();
  if (ImGui::Button("clear selection")) v.selection.clear();
  ImGui::SameLine();
  if (ImGui::Button("rename") && !v.control_name().empty()) {
    const std::string from = v.control_name(), to = v.new_handle;
    v.rebind([&] { v.session.rename_handle(from, to); }, "renamed " + from + " to " + to);
  }
  ImGui::SameLine();
  if (ImGui::Button("delete handle") && !v.control_name().empty()) {
    const std::string name = v.control_name();
    v.rebind([&] { v.session.remove_handle(name); }, "deleted handle " + name);
  }
  ImGui::Separator();
  ImGui::SliderFloat("paint amount", &v.paint_amount, 0.1f, 20.0f, "%.1f", ImGuiSliderFlags_Logarithmic);
  ImGui::Checkbox("apply when a stroke ends", &v.auto_apply);
  if (ImGui::Button("apply spin transformation")) v.request_paint();
  ImGui::SameLine();
  if (ImGui::Button("clear rho")) v.rho.setZero(), v.painted.reset(), v.geometry_dirty = true;
  if (v.painter && v.painter->busy())
    ImGui::Text("solving (D - rho) lambda = gamma lambda ...");
  else if (v.painted && v.painted->error.empty())
    ImGui::Text("painted: Q_mean %.4f (bind %.0f ms, solve %.0f ms)", v.painted->q_mean, v.painted->bind_ms,
                v.painted->solve_ms);
  else if (v.painted)
    ImGui::TextWrapped("spin transformation failed: %s", v.painted->error.c_str());
}

void deformer_panel(Viewer& v) {
  if (!ImGui::CollapsingHeader("Deformer", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const auto& choices = deformer_choices();
  std::vector<const char*> items;
  for (const auto& c : choices) items.push_back(c.c_str());
  ImGui::Combo("type", &v.choice, items.data(), int(items.size()));
  ImGui::SameLine();
  if (ImGui::Button("switch")) {
    const std::string c = choices[v.choice];
    v.rebind(
        [&] {
          const DeformerPreset p = deformer_preset(c, v.session.scene());
          v.session.set_deformer(p.deformer, p.ik);
          v.control = 0;
        },
        "deformer " + c);
  }
  if (!v.session.has_deformer()) {
    ImGui::TextWrapped("no deformer: make a handle (ctrl+drag, new handle) or switch to one");
    return;
  }
  ImGui::Text("%s: bind %.0f ms, pose %.2f ms, %zu controls", v.session.scene().deformer_type.c_str(),
              v.session.bind_ms(), v.session.pose_ms(), v.session.controls().size());
  // Widgets for the schema's keys of this type (deformer_options), editing a copy of the block.
  std::vector<std::string> handles;
  for (const auto& h : v.session.scene().handles) handles.push_back(h.name);
  nlohmann::json& b = v.edit_block;
  for (const DeformerOption& o : deformer_options(v.session.scene().deformer_type, handles)) {
    ImGui::PushID(o.key.c_str());
    switch (o.kind) {
      case DeformerOption::Kind::Choice:
      case DeformerOption::Kind::Handle: {
        const std::string now = b.contains(o.key) ? b[o.key].get<std::string>() : "(default)";
        if (ImGui::BeginCombo(o.key.c_str(), now.c_str())) {
          if (o.kind == DeformerOption::Kind::Choice && ImGui::Selectable("(default)", !b.contains(o.key)))
            b.erase(o.key);
          for (const auto& c : o.choices)
            if (ImGui::Selectable(c.c_str(), c == now)) b[o.key] = c;
          ImGui::EndCombo();
        }
        break;
      }
      case DeformerOption::Kind::Integer: {
        int x = b.contains(o.key) ? b[o.key].get<int>() : int(std::max(o.minimum, 0.0));
        if (ImGui::InputInt(o.key.c_str(), &x)) b[o.key] = int(std::clamp(double(x), o.minimum, o.maximum));
        break;
      }
      case DeformerOption::Kind::Number: {
        double x = b.contains(o.key) ? b[o.key].get<double>() : std::max(o.minimum, 0.0);
        if (ImGui::InputDouble(o.key.c_str(), &x, 0, 0, "%.6g"))
          b[o.key] = std::clamp(x, o.minimum, o.maximum);
        break;
      }
      case DeformerOption::Kind::Boolean: {
        bool x = b.value(o.key, false);
        if (ImGui::Checkbox(o.key.c_str(), &x)) b[o.key] = x;
        break;
      }
      case DeformerOption::Kind::Integers3: {
        int x[3] = {2, 2, 2};
        if (b.contains(o.key))
          for (int k = 0; k < 3; ++k) x[k] = b[o.key][k].get<int>();
        if (ImGui::InputInt3(o.key.c_str(), x))
          b[o.key] = {int(std::max(double(x[0]), o.minimum)), int(std::max(double(x[1]), o.minimum)),
                      int(std::max(double(x[2]), o.minimum))};
        break;
      }
    }
    ImGui::PopID();
  }
  if (ImGui::Button("apply options")) {
    const nlohmann::json block = b;
    v.rebind([&] { v.session.set_deformer(block, v.session.ik_block()); },
             "rebound " + block.value("type", ""));
  }
  if (ImGui::TreeNode("deformer block as JSON (every key of docs/scene.md)")) {
    ImGui::InputTextMultiline("##block", v.block_text, sizeof v.block_text, ImVec2(-1, 160));
    if (ImGui::Button("apply JSON")) {
      const std::string text = v.block_text;
      v.rebind([&] { v.session.set_deformer(nlohmann::json::parse(text), v.session.ik_block()); },
               "rebound from JSON");
    }
    ImGui::TreePop();
  }
  if (!v.session.ik_block().is_null()) {
    if (const auto t = v.session.posed_anchor("ik.target"))
      ImGui::Text("IK target %.3f %.3f %.3f: drag the ik.target gizmo", t->x(), t->y(), t->z());
  }
}

void pose_panel(Viewer& v) {
  if (!v.session.has_deformer() || !ImGui::CollapsingHeader("Pose", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const auto& c = v.session.controls();
  if (ImGui::BeginListBox("controls", ImVec2(-1, 90))) {
    ImGuiListClipper clipper;
    clipper.Begin(int(c.size()));
    while (clipper.Step())
      for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i)
        if (ImGui::Selectable(c[i].c_str(), i == v.control)) v.control = i;
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
  if (ImGui::Button("reset control") && !v.control_name().empty()) {
    v.session.set_motor(v.control_name(), ga::from_isometry(Eigen::Isometry3d::Identity()));
    v.session.commit_pose();
    v.geometry_dirty = true;
    v.request_snap();
  }
}

/// Rigs: the animation, a time slider and play button, the skin's blend, the per-frame cleanup.
void animation_panel(Viewer& v) {
  if (!v.session.has_rig() || !ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::TextDisabled("glTF rig: %zu joints (Cesium sample models: CC BY 4.0, Cesium)",
                      v.session.controls().size());
  const std::vector<std::string> names = v.session.animation_names();
  if (names.empty()) {
    ImGui::Text("no animation: the rest pose");
  } else {
    int a = v.session.animation();
    std::vector<const char*> items;
    for (const auto& n : names) items.push_back(n.c_str());
    if (ImGui::Combo("animation", &a, items.data(), int(items.size())) && a != v.session.animation())
      v.rebind([&] { v.session.set_animation(a); }, "animation " + names[a]);
    float t = float(v.clock.time);
    if (ImGui::SliderFloat("time (s)", &t, float(v.clock.start), float(v.clock.end), "%.3f"))
      v.clock.time = t, v.set_time(v.clock.time);
    if (ImGui::Button(v.clock.playing ? "pause" : "play")) v.clock.playing = !v.clock.playing;
    ImGui::SameLine();
    ImGui::Checkbox("loop", &v.clock.loop);
    ImGui::SameLine();
    if (ImGui::Button("rest pose")) v.clock.playing = false, v.set_time(std::nullopt);
    float speed = float(v.clock.speed);
    if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic))
      v.clock.speed = speed;
  }
  ImGui::Checkbox("skeleton", &v.show_skeleton);
  // The skin's blend and Delta Mush (the deformer block's "blend" and "mush").
  const nlohmann::json block = v.session.deformer_block();
  const auto& blends = option_values<SkinBlend>();
  const std::vector<std::string> mushes = {"none", "delta-mush", "direct-delta-mush"};
  const std::string mush = block.value("mush", "none");
  std::string blend = block.value("blend", std::string(option_name(SkinDeformer::Options{}.blend)));
  int bi = int(std::find(blends.begin(), blends.end(), blend) - blends.begin());
  int mi = int(std::find(mushes.begin(), mushes.end(), mush) - mushes.begin());
  std::vector<const char*> bitems, mitems;
  for (const auto& b : blends) bitems.push_back(b.c_str());
  for (const auto& m : mushes) mitems.push_back(m.c_str());
  const bool ddm = mush == "direct-delta-mush";  // blends the bone matrices itself
  ImGui::BeginDisabled(ddm);
  const bool new_blend = ImGui::Combo("blend", &bi, bitems.data(), int(bitems.size()));
  ImGui::EndDisabled();
  const bool new_mush = ImGui::Combo("mush", &mi, mitems.data(), int(mitems.size()));
  if (new_blend || new_mush) {
    nlohmann::json b = block;
    b["mush"] = mushes[mi];
    if (mushes[mi] == "direct-delta-mush")
      b.erase("blend");
    else
      b["blend"] = blends[bi];
    if (mushes[mi] == "none") b.erase("mush_iterations");
    v.rebind([&] { v.session.set_deformer(b, nullptr); }, "skin " + b.value("blend", "") + " " + mushes[mi]);
  }
  if (ImGui::Checkbox("clean up each frame (rigid parts pinned)", &v.cleanup_frames)) {
    if (v.cleanup_frames)
      v.set_time(v.session.time());
    else if (v.shown == Shown::Snap)
      v.shown = Shown::Edit, v.geometry_dirty = true;
  }
  if (v.cleanup_frames && v.snapper)
    ImGui::Text("cleanup: %llu frames dropped (no time for them)",
                (unsigned long long)v.snapper->discarded());
}

void snap_panel(Viewer& v) {
  if (!ImGui::CollapsingHeader("Snap to spin", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::Checkbox("snap when a drag ends", &v.auto_snap);
  if (ImGui::Checkbox("keep the pose (handles, or a skin's rigid parts, pinned)", &v.keep_pose))
    v.request_snap();
  if (!v.keep_pose) {
    float t = float(v.tradeoff);
    if (ImGui::SliderFloat("tradeoff", &t, 0, 1)) v.tradeoff = t;
    if (ImGui::IsItemDeactivatedAfterEdit()) v.request_snap();
  }
  if (ImGui::Button("snap now")) v.snap_now();
  ImGui::Text("Q_mean edit %.4f", v.q_edit);
  if (v.snapper && v.snapper->busy())
    ImGui::Text("snapping...");
  else if (v.snapped && v.snapped->error.empty())
    ImGui::Text(v.snapped->pinned ? "Q_mean cleaned %.4f (%.0f ms, volume %.3f of rest)"
                                  : "Q_mean snap %.4f (%.0f ms)",
                v.snapped->q_mean, v.snapped->snap_ms, v.snapped->volume_ratio);
  else if (v.snapped)
    ImGui::TextWrapped("snap failed: %s", v.snapped->error.c_str());
}

/// Replaces the document: a new session, its mesh uploaded, workers bound to it, the camera reframed.
void open_document(Viewer& v, const std::string& path, int w, int h) {
  Session s = Session::open(path);  // throws before anything changes
  v.drag.reset();
  v.gesture = false;
  v.snapper = std::make_unique<SnapWorker>(s.rest());  // the old workers finish and stop
  v.painter.reset();
  v.snapped.reset();
  v.painted.reset();
  v.selection.clear();
  v.rho.resize(0);
  v.shown = Shown::Edit;
  v.session = std::move(s);
  v.renderer->set_mesh(v.session.rest());
  render::RenderOptions o;
  o.width = w, o.height = h, o.up = v.cam.up;
  o.azimuth_deg = v.cam.azimuth_deg, o.elevation_deg = v.cam.elevation_deg;
  v.cam = render::render_camera(v.session.posed(), o);
  v.control = 0;
  v.on_rebind();
  v.status = "opened " + path;
}

void files_panel(Viewer& v, int w, int h) {
  if (!ImGui::CollapsingHeader("Files")) return;
  ImGui::InputText("open", v.open_path, sizeof v.open_path);
  ImGui::SameLine();
  if (ImGui::Button("load")) try {
      open_document(v, v.open_path, w, h);
    } catch (const std::exception& e) {
      v.status = e.what();
    }
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

void panel(Viewer& v, int w, int h) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("spinmotor");
  ImGui::Text("%s: %lld vertices, %lld faces", v.session.scene().name().c_str(),
              (long long)v.session.rest().V.rows(), (long long)v.session.rest().F.rows());
  ImGui::Text("frame %.1f ms", v.frame_ms);
  display_panel(v);
  animation_panel(v);
  deformer_panel(v);
  pose_panel(v);
  tools_panel(v);
  snap_panel(v);
  files_panel(v, w, h);
  if (!v.status.empty()) ImGui::TextWrapped("%s", v.status.c_str());
  ImGui::End();
}

render::Image read_window(int fw, int fh) {
  render::Image im;
  im.width = fw, im.height = fh, im.rgba.resize(std::size_t(fw) * fh * 4);
  std::vector<std::uint8_t> rows(im.rgba.size());
  render::gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  render::gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  render::gl.ReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  for (int y = 0; y < fh; ++y)
    std::copy_n(&rows[std::size_t(fh - 1 - y) * fw * 4], std::size_t(fw) * 4,
                &im.rgba[std::size_t(y) * fw * 4]);
  return im;
}

}  // namespace

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
    v.snapper = std::make_unique<SnapWorker>(v.session.rest());
    v.tradeoff = a.tradeoff;
    if (!a.deformer.empty())
      v.rebind(
          [&] {
            const DeformerPreset p = deformer_preset(a.deformer, v.session.scene());
            v.session.set_deformer(p.deformer, p.ik);
          },
          "deformer " + a.deformer);
    v.on_rebind();
    const std::string stem = v.session.scene().file.stem().string();
    std::snprintf(v.save_path, sizeof v.save_path, "%s",
                  (v.session.scene().dir / (stem + "-edited.json")).c_str());
    std::snprintf(v.open_path, sizeof v.open_path, "%s", v.save_path);
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
      if (v.clock.advance(v.frame_ms / 1000.0)) v.set_time(v.clock.time);
      if (auto r = v.snapper->take()) {
        v.snapped = std::move(*r);
        if (v.shown == Shown::Snap) v.geometry_dirty = true;
      }
      if (v.painter)
        if (auto r = v.painter->take()) {
          v.painted = std::move(*r);
          if (v.painted->error.empty()) v.shown = Shown::Painted;
          v.geometry_dirty = true;
        }
      draw_and_handle_input(v, w, h);
      panel(v, fw, fh);
      if (v.geometry_dirty) v.refresh_geometry();
      ImGui::Render();
      render::gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
      v.renderer->draw(v.cam, fw, fh, v.style);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      if (a.smoke_frames > 0 && frame >= a.smoke_frames) {
        if (!a.smoke_png.empty()) render::write_png(a.smoke_png, read_window(fw, fh));
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

}  // namespace spinmotor::viewer::app
