// spinmotor-viewer's panels: display, animation, deformer, pose, tools, snap and files, in the one
// "spinmotor" window.
#include <imgui.h>

#include <algorithm>
#include <exception>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "window.hpp"

namespace spinmotor::viewer::app {

namespace {

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

}  // namespace

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

}  // namespace spinmotor::viewer::app
