// spinmotor-viewer's window: GLFW + OpenGL 3.3 core + Dear ImGui over the window-free core; the viewer's
// state (window.hpp) and the frame loop.
#include "spinmotor/render/gl_api.hpp"  // <GL/glcorearb.h> before GLFW (which then includes no GL header)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "spinmotor/viewer/lattice_edges.hpp"
#include "window.hpp"

namespace spinmotor::viewer::app {

// ---- the viewer's state --------------------------------------------------------------------------

std::string Viewer::control_name() const {
  const auto& c = session.controls();
  return c.empty() ? "" : c[std::clamp(control, 0, int(c.size()) - 1)];
}

void Viewer::on_rebind() {
  const auto& c = session.controls();
  anchors.clear();
  for (const auto& name : c) anchors.push_back(session.control_anchor(name));
  lattice = ffd_lattice_edges(c);
  control = std::clamp(control, 0, std::max(0, int(c.size()) - 1));
  edit_block = session.deformer_block();
  std::snprintf(block_text, sizeof block_text, "%s", edit_block.is_null() ? "" : edit_block.dump(2).c_str());
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

void Viewer::set_time(std::optional<double> t) {
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

void Viewer::rebind(const std::function<void()>& change, const std::string& what) {
  try {
    change();
    on_rebind();
    snapped.reset();
    status = what + " (bind " + std::to_string(int(session.bind_ms())) + " ms)";
  } catch (const std::exception& e) {
    status = e.what();
  }
}

const Eigen::MatrixXd& Viewer::shown_positions() {
  if (shown == Shown::Snap && snapped && snapped->V.rows()) return snapped->V;
  if (shown == Shown::Painted && painted && painted->V.rows()) return painted->V;
  return session.posed();
}

void Viewer::refresh_geometry() {
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

void Viewer::request_snap() {
  if (snapper && auto_snap && session.has_deformer()) snap_now();
}
void Viewer::snap_now() {
  if (!snapper) return;
  std::vector<int> pins;
  std::shared_ptr<const spinmotor::Rig> skin;
  if (keep_pose) pins = session.cleanup_pins(), skin = session.cleanup_skin();
  if (skin)
    snapper->request_rig(session.posed(), std::move(skin));
  else if (!pins.empty())
    snapper->request_pinned(session.posed(), std::move(pins));
  else
    snapper->request(session.posed(), tradeoff);
}

void Viewer::request_paint() {
  if (!painter) painter = std::make_unique<SpinPaintWorker>(session.rest());
  painter->request(rho);
}

namespace {

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