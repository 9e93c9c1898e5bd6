// spinmotor-viewer's view: the selection, the controls and the gizmo drawn over the mesh, and the mouse
// (gizmo drags, ctrl+drag selection and paint gestures, picking a control, the camera).
#include <imgui.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "window.hpp"

namespace spinmotor::viewer::app {

namespace {

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

/// Draws the selection (every vertex, thinned to about 4000 dots), the box or lasso in progress and
/// the brush cursor into `dl`; mouse: the cursor, w, h: the window size.
void draw_selection(Viewer& v, ImDrawList* dl, const ImVec2& mouse, int w, int h) {
  const ImGuiIO& io = ImGui::GetIO();
  auto to_screen = [&](const Eigen::Vector3d& p) { return to_imvec(v.cam.project(p, w, h)); };
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
}

/// Draws a dot per control into `dl` (a skin's: at its posed bones, with the skeleton when shown; else
/// at the posed anchors, for at most 4096 controls) and the FFD lattice lines. Returns the control whose
/// dot is within 7 pixels of the mouse (the nearest), or -1.
int draw_control_dots(Viewer& v, ImDrawList* dl, const ImVec2& mouse, int w, int h) {
  auto to_screen = [&](const Eigen::Vector3d& p) { return to_imvec(v.cam.project(p, w, h)); };
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
  return hover_dot;
}

/// Draws the current control's gizmo into `dl` (translation arrows, or rotation rings; a point such as
/// ik.target only translates) and starts a drag when an axis within 8 pixels of the mouse is clicked
/// (cancelling the snap in progress). ray: the mouse's pick ray.
void draw_gizmo(Viewer& v, ImDrawList* dl, const ImVec2& mouse, const render::Ray& ray, int w, int h) {
  const ImGuiIO& io = ImGui::GetIO();
  auto to_screen = [&](const Eigen::Vector3d& p) { return to_imvec(v.cam.project(p, w, h)); };
  const ImU32 colours[3] = {IM_COL32(220, 50, 50, 255), IM_COL32(50, 180, 50, 255),
                            IM_COL32(60, 90, 230, 255)};
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
}

/// Applies the mouse to `v` after drawing: a gizmo drag in progress (released: committed and snapped),
/// a gesture in progress, a ctrl+click starting a gesture, a click on the control dot `hover_dot`, else
/// the camera (orbit, pan, zoom). Nothing when the panels have the mouse.
void handle_mouse(Viewer& v, const ImVec2& mouse, const render::Ray& ray, int hover_dot, int w, int h) {
  ImGuiIO& io = ImGui::GetIO();
  const std::string name = v.control_name();
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

}  // namespace

void draw_and_handle_input(Viewer& v, int w, int h) {
  ImGuiIO& io = ImGui::GetIO();
  ImDrawList* dl = ImGui::GetBackgroundDrawList();  // over the mesh, under the panels
  const ImVec2 mouse = io.MousePos;
  const render::Ray ray = v.cam.pixel_ray(mouse.x, mouse.y, w, h);
  draw_selection(v, dl, mouse, w, h);
  const int hover_dot = draw_control_dots(v, dl, mouse, w, h);
  draw_gizmo(v, dl, mouse, ray, w, h);
  handle_mouse(v, mouse, ray, hover_dot, w, h);
}

}  // namespace spinmotor::viewer::app
