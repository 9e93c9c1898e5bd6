// spinmotor-viewer --screenshot: one frame without interaction, every step through the window's code.
#include "spinmotor/render/gl_api.hpp"  // <GL/glcorearb.h> before GLFW (which then includes no GL header)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "app.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/mesh/metrics/quasi_conformal.hpp"
#include "spinmotor/render/framebuffer.hpp"
#include "spinmotor/render/offscreen_context.hpp"
#include "spinmotor/render/render_mesh.hpp"
#include "spinmotor/viewer/bone_overlay.hpp"
#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"
#include "spinmotor/viewer/picking.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace spinmotor::viewer::app {

namespace {

/// Per-frame timings of a run of any length in bounded memory, for the frame timer's medians: every
/// frame while there are at most kCapacity, then every 2nd, 4th, ... frame (the samples are thinned to
/// every other one each time the buffer is full). The median is exact up to kCapacity frames and, beyond,
/// the median of evenly spaced frames of the whole run.
class FrameSamples {
 public:
  void add(double value) {
    const std::size_t frame = seen_++;
    if (frame % stride_ != 0) return;
    if (v_.size() == kCapacity) {  // keep frames 0, 2·stride, 4·stride, ...: `frame` is one of them
      for (std::size_t k = 0; k < kCapacity / 2; ++k) v_[k] = v_[2 * k];
      v_.resize(kCapacity / 2);
      stride_ *= 2;
    }
    v_.push_back(value);
  }
  /// The upper median (the middle element of the sorted samples); precondition: a sample was added.
  double median() const {
    std::vector<double> v = v_;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  }

 private:
  static constexpr std::size_t kCapacity = 4096;  // even: thinning keeps the next frame's index on the grid
  std::vector<double> v_;
  std::size_t stride_ = 1, seen_ = 0;
};

/// --select-box / --select-lasso: the visible vertices in a pixel region of `cam`.
std::vector<int> select_region(const Args& a, Session& s, const render::OrbitCamera& cam, int w, int h) {
  const Eigen::MatrixXd& V = s.posed();
  const auto t0 = Clock::now();
  const DepthMap depth = DepthMap::render(V, s.rest().F, cam, w, h);
  const double depth_ms = ms_since(t0);
  const auto t1 = Clock::now();
  std::vector<int> sel;
  if (!a.select_box.empty()) {
    const auto b = parse_numbers(a.select_box, "--select-box", 4);
    sel = vertices_in_box(V, cam, w, h, {b[0], b[1]}, {b[2], b[3]}, &depth);
  } else {
    const auto p = parse_numbers(a.select_lasso, "--select-lasso", 6, true);
    std::vector<Eigen::Vector2d> lasso;
    for (std::size_t i = 0; i + 1 < p.size(); i += 2) lasso.emplace_back(p[i], p[i + 1]);
    sel = vertices_in_lasso(V, cam, w, h, lasso, &depth);
  }
  std::printf("selected %zu visible vertices (depth map %.1f ms, selection %.1f ms)\n", sel.size(), depth_ms,
              ms_since(t1));
  return sel;
}

/// --paint X,Y,RADIUS,AMOUNT...: brush dabs at pixels of `cam` (radius a fraction of the scene
/// radius), then the spin transformation of the painted ρ (the paint worker, waited for).
PaintOutcome paint(const Args& a, Session& s, const render::OrbitCamera& cam, int w, int h,
                   Eigen::VectorXd& rho) {
  const Eigen::MatrixXd V = s.posed();
  rho = Eigen::VectorXd::Zero(s.rest().F.rows());
  for (const std::string& spec : a.paints) {
    const auto p = parse_numbers(spec, "--paint", 4);
    const auto hit = pick(cam.pixel_ray(p[0], p[1], w, h), V, s.rest().F);
    if (!hit)
      throw Error("--paint: pixel " + spec.substr(0, spec.find(',', spec.find(',') + 1)) +
                  " misses the mesh");
    const int touched = paint_rho(V, s.rest().F, hit->point, p[2] * cam.scene_radius, p[3], rho);
    std::printf("paint: dab at face %lld, %d faces\n", (long long)hit->face, touched);
  }
  SpinPaintWorker worker(s.rest());
  worker.request(rho);
  worker.wait_idle(600);
  auto r = worker.take();
  if (!r || !r->error.empty())
    throw Error("paint: spin transformation failed: " + (r ? r->error : std::string("no result")));
  return std::move(*r);
}

/// The picture's options from the command line: size, camera, Q range, up axis, colour, shading.
render::RenderOptions headless_options(const Args& a) {
  render::RenderOptions o;
  render::parse_size(a.size, o);
  if (!a.camera.empty()) render::parse_camera(a.camera, o);
  render::parse_q_range(a.q_range, o);
  o.up = Eigen::Vector3d::Unit(a.up[0] - 'x');
  o.style.color = parse_color(a.color);
  o.style.smooth = !a.flat;
  o.style.wireframe = a.wireframe;
  return o;
}

/// The --gizmo drags, parsed; throws on a bad one, on --snap with --paint, or on --add-handle without
/// a selection.
std::vector<GizmoSpec> headless_gizmos(const Args& a) {
  std::vector<GizmoSpec> gizmos;
  for (const auto& g : a.gizmos) gizmos.push_back(parse_gizmo(g));
  if (a.snap && !a.paints.empty()) throw Error("--snap and --paint show different results: give one");
  if (!a.add_handle.empty() && a.select_box.empty() && a.select_lasso.empty())
    throw Error("--add-handle needs --select-box or --select-lasso");
  return gizmos;
}

/// Opens the document with the rig's --animation and --time and the --deformer preset, printing what
/// it opened.
Session open_headless_session(const Args& a) {
  Session s = Session::open(a.doc);
  apply_rig_args(a, s);
  if (s.has_rig())
    std::printf("rig: %zu joints, animation %d of %zu, time %s\n", s.controls().size(), s.animation(),
                s.animation_names().size(), s.time() ? std::to_string(*s.time()).c_str() : "rest");
  if (!a.deformer.empty()) {
    const DeformerPreset p = deformer_preset(a.deformer, s.scene());
    s.set_deformer(p.deformer, p.ik);
    std::printf("deformer %s: %zu controls, bind %.1f ms\n", a.deformer.c_str(), s.controls().size(),
                s.bind_ms());
  }
  return s;
}

/// The edits in the pixels of `cam` (o: its picture size): the selection and the handle made of it,
/// then every gizmo drag (one committed pose each), printing each.
void apply_headless_edits(const Args& a, Session& s, const render::OrbitCamera& cam,
                          const render::RenderOptions& o, const std::vector<GizmoSpec>& gizmos) {
  if (!a.select_box.empty() || !a.select_lasso.empty()) {
    const std::vector<int> sel = select_region(a, s, cam, o.width, o.height);
    if (!a.add_handle.empty()) {
      s.add_handle(a.add_handle, sel);
      std::printf("handle %s: %zu vertices, bind %.1f ms\n", a.add_handle.c_str(), sel.size(), s.bind_ms());
    }
  }
  for (const auto& g : gizmos) {
    s.set_motor(g.control, simulate_drag(s, cam, o.width, o.height, g));
    s.commit_pose();
    const Eigen::Vector3d p = *s.posed_anchor(g.control);
    std::printf("gizmo %s: anchor at %.6f %.6f %.6f\n", g.control.c_str(), p.x(), p.y(), p.z());
  }
}

/// --snap: the snap of the posed positions V (with --keep-pose the pose-keeping cleanup, the handles or
/// the skin's rigid parts pinned) in the snap worker, waited for; prints Q_mean from q_edit and returns
/// the snapped positions. Throws when there is nothing to pin or the snap fails.
Eigen::MatrixXd headless_snap(const Args& a, Session& s, const Eigen::MatrixXd& V, double q_edit) {
  SnapWorker worker(s.rest());
  if (a.keep_pose) {
    const std::vector<int> pins = s.cleanup_pins();
    auto skin = s.cleanup_skin();
    if (pins.empty() && !skin)
      throw Error("--keep-pose: nothing to pin (no handle, and the deformer is not a skin)");
    if (skin)
      worker.request_rig(V, std::move(skin));
    else
      worker.request_pinned(V, pins);
  } else
    worker.request(V, a.tradeoff);
  worker.wait_idle(600);
  auto r = worker.take();
  if (!r || !r->error.empty()) throw Error("snap failed: " + (r ? r->error : std::string("no result")));
  if (r->pinned)
    std::printf(
        "cleanup (%zu vertices pinned): Q_mean %.4f -> %.4f, volume %.4f of rest (bind %.0f ms, cleanup "
        "%.0f ms)\n",
        static_cast<size_t>(r->pins), q_edit, r->q_mean, r->volume_ratio, r->bind_ms, r->snap_ms);
  else
    std::printf("snap: Q_mean %.4f -> %.4f (bind %.0f ms, snap %.0f ms)\n", q_edit, r->q_mean, r->bind_ms,
                r->snap_ms);
  return r->V;
}

/// --paint: the dabs and their spin transformation (paint), printing its quality and how far it moved
/// the mesh; returns the painted positions and leaves the painted ρ in `rho`.
Eigen::MatrixXd headless_paint(const Args& a, Session& s, const render::OrbitCamera& cam,
                               const render::RenderOptions& o, Eigen::VectorXd& rho) {
  const PaintOutcome r = paint(a, s, cam, o.width, o.height, rho);
  const double moved = std::sqrt((r.V - s.rest().V).rowwise().squaredNorm().maxCoeff()) / cam.scene_radius;
  std::printf(
      "paint: spin transformation Q_mean %.4f, max displacement %.4f of the scene radius (bind %.0f ms, "
      "solve %.0f ms)\n",
      r.q_mean, moved, r.bind_ms, r.solve_ms);
  return r.V;
}

/// The OpenGL context of the picture: a hidden GLFW window (X server or Xvfb) when there is one, else
/// the offscreen context; `backend` names it.
struct HeadlessContext {
  GLFWwindow* window = nullptr;
  std::unique_ptr<render::OffscreenContext> offscreen;
  std::string backend;
};

/// Makes the context current and loads OpenGL through it.
HeadlessContext make_headless_context() {
  HeadlessContext c;
  if (glfwInit()) {
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    c.window = glfwCreateWindow(64, 64, "spinmotor-viewer", nullptr, nullptr);
  }
  if (c.window) {
    glfwMakeContextCurrent(c.window);
    render::load_gl(glfw_proc);
    c.backend = "glfw";
  } else {
    c.offscreen = std::make_unique<render::OffscreenContext>();
    c.backend = c.offscreen->description();
  }
  return c;
}

/// --frames N on a rig: plays the animation, frame f at time start + f/(N−1) of the range, posed, drawn
/// through `cam` and timed (stopping early on a signal). With --snap --keep-pose every frame is handed to
/// the snap worker as the window's "clean up each frame" does (a request replaces a queued one: the
/// worker cleans the frames it can, the latest one last). Unless interrupted, prints the medians, sets V
/// to the last frame (cleaned up when asked) and uploads it. Returns the frames posed and drawn.
int play_animation(const Args& a, Session& s, render::MeshRenderer& renderer, const render::OrbitCamera& cam,
                   const render::RenderOptions& o, Eigen::MatrixXd& V) {
  int done = 0;
  const auto [t0, t1] = s.animation_range();
  std::unique_ptr<SnapWorker> cleaner;
  std::vector<int> pins;
  std::shared_ptr<const spinmotor::Rig> skin;
  if (a.snap && a.keep_pose)
    cleaner = std::make_unique<SnapWorker>(s.rest()), pins = s.cleanup_pins(), skin = s.cleanup_skin();
  FrameSamples pose_ms, draw_ms;
  int requested = 0;
  for (int f = 0; f < a.frames && !interrupted(); ++f, ++done) {
    s.set_time(a.frames > 1 ? t0 + (t1 - t0) * f / (a.frames - 1) : t0);
    const Eigen::MatrixXd& Vf = s.posed();
    pose_ms.add(s.pose_ms());
    if (cleaner) {
      if (skin)
        cleaner->request_rig(Vf, skin);
      else
        cleaner->request_pinned(Vf, pins);
      ++requested;
    }
    const auto t2 = Clock::now();
    renderer.set_positions(Vf);
    renderer.draw(cam, o.width, o.height, o.style);
    render::gl.Finish();
    draw_ms.add(ms_since(t2));
  }
  // Stopped by a signal: nothing more to show (the cleaner's destructor waits for the frame it is
  // cleaning and drops the queued one).
  if (!interrupted()) {
    std::printf(
        "animation over %d frames (t = %.4g .. %.4g s): pose %.2f ms, upload + draw %.2f ms (medians)\n",
        a.frames, t0, t1, pose_ms.median(), draw_ms.median());
    if (cleaner) {
      cleaner->wait_idle(600);
      auto r = cleaner->take();
      if (!r || !r->error.empty())
        throw Error("cleanup failed: " + (r ? r->error : std::string("no result")));
      std::printf("cleanup per frame: %d requested, %llu dropped as stale, last frame Q_mean %.4f -> %.4f\n",
                  requested, (unsigned long long)cleaner->discarded(),
                  quasi_conformal_summary(s.rest().V, s.rest().F, s.posed()).q_mean, r->q_mean);
      V = r->V;
    } else {
      V = s.posed();
    }
    renderer.set_positions(V);
    if (o.style.color == render::ColorMode::Q)
      renderer.set_face_values(quasi_conformal_error(s.rest().V, s.rest().F, V));
  }
  return done;
}

/// --frames N without a rig, the frame timer: pose (deformer) + upload (normals, float conversion,
/// buffer update) + draw of a rotation of the first control growing through the gizmo code path
/// (stopping early on a signal); unless interrupted, prints the medians (`backend` named). Throws
/// without a control. Returns the frames posed and drawn.
int time_frames(const Args& a, Session& s, render::MeshRenderer& renderer, const render::OrbitCamera& cam,
                const render::RenderOptions& o, const std::string& backend) {
  int done = 0;
  const std::string h = s.controls().empty() ? "" : s.controls().front();
  if (h.empty()) throw Error("--frames needs a scene with a control");
  FrameSamples pose_ms, upload_ms, pu_ms, draw_ms, frame_ms;
  const ga::Mot m0 = s.motor(h);
  int axis = 0;  // the ring that faces the camera best
  (cam.eye() - cam.target).cwiseAbs().maxCoeff(&axis);
  for (int f = 0; f < a.frames && !interrupted(); ++f, ++done) {
    const auto t0 = Clock::now();
    GizmoSpec g{h, GizmoMode::Rotate, axis, 30.0 * (f + 1) / a.frames};
    s.set_motor(h, m0);
    s.set_motor(h, simulate_drag(s, cam, o.width, o.height, g));
    const Eigen::MatrixXd& Vf = s.posed();
    const double pose = s.pose_ms();
    const auto t1 = Clock::now();
    renderer.set_positions(Vf);
    const double upload = ms_since(t1);
    pose_ms.add(pose);
    upload_ms.add(upload);
    pu_ms.add(pose + upload);
    const auto t2 = Clock::now();
    renderer.draw(cam, o.width, o.height, o.style);
    render::gl.Finish();
    draw_ms.add(ms_since(t2));
    frame_ms.add(ms_since(t0));
  }
  if (!interrupted())
    std::printf(
        "frame timer over %d frames (%s, %dx%d): pose %.2f ms, upload %.2f ms, pose+upload %.2f ms, "
        "draw %.2f ms, frame %.2f ms (medians)\n",
        a.frames, backend.c_str(), o.width, o.height, pose_ms.median(), upload_ms.median(), pu_ms.median(),
        draw_ms.median(), frame_ms.median());
  return done;
}

/// Draws the picture through `shot` into fb, with the skeleton (--skeleton) and the Q colour bar, and
/// writes it to --screenshot. Throws on --skeleton without a skin.
void write_screenshot(const Args& a, Session& s, render::MeshRenderer& renderer, render::Framebuffer& fb,
                      const render::OrbitCamera& shot, const render::RenderOptions& o,
                      const std::string& backend) {
  renderer.draw(shot, o.width, o.height, o.style);
  render::Image im = fb.read();
  if (a.skeleton) {
    const std::vector<PosedBone> bones = s.posed_bones();
    if (bones.empty()) throw Error("--skeleton: the deformer is not a skin");
    std::printf("skeleton: %zu bones, %d pixels\n", bones.size(), draw_bones(im, bones, shot));
  }
  if (o.style.color == render::ColorMode::Q && o.color_bar)
    render::draw_color_bar(im, o.style.q_min, o.style.q_max);
  render::write_png(a.screenshot, im);
  std::printf("wrote %s (%dx%d, %s)\n", a.screenshot.c_str(), o.width, o.height, backend.c_str());
}

}  // namespace

int run_headless(const Args& a) {
  render::RenderOptions o = headless_options(a);
  const std::vector<GizmoSpec> gizmos = headless_gizmos(a);
  Session s = open_headless_session(a);
  // The camera framing the rest mesh: what a user sees when the viewer opens. Selections, picks and
  // gizmo drags happen in its pixels; the picture frames what is shown.
  const render::OrbitCamera cam = render::render_camera(s.rest().V, o);
  apply_headless_edits(a, s, cam, o, gizmos);
  Eigen::MatrixXd V = s.posed();
  std::printf("%s: %lld vertices, %lld faces; bind %.1f ms, pose %.2f ms\n", s.scene().name().c_str(),
              (long long)V.rows(), (long long)s.rest().F.rows(), s.bind_ms(), s.pose_ms());
  const double q_edit = quasi_conformal_summary(s.rest().V, s.rest().F, V).q_mean;
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(s.rest().F.rows());
  if (a.snap)
    V = headless_snap(a, s, V, q_edit);
  else if (!a.paints.empty())
    V = headless_paint(a, s, cam, o, rho);
  else
    std::printf("Q_mean %.4f\n", q_edit);

  HeadlessContext context = make_headless_context();
  const render::OrbitCamera shot = render::render_camera(V, o);
  int status = 0;
  {
    render::MeshRenderer renderer;
    render::Framebuffer fb(o.width, o.height, o.samples);
    renderer.set_mesh(s.rest());
    renderer.set_positions(V);
    if (o.style.color == render::ColorMode::Q)
      renderer.set_face_values(quasi_conformal_error(s.rest().V, s.rest().F, V));
    if (o.style.color == render::ColorMode::Signed) {
      renderer.set_face_values(rho);
      o.style.signed_range = std::max(rho.cwiseAbs().maxCoeff(), 1e-12);
    }
    fb.bind();
    // From here a signal (SIGINT, SIGTERM, SIGHUP) stops the frame loop between two frames, and nothing is
    // written: the screenshot shows a run's last frame, so a stopped run has none (exit 128 + signal).
    const InterruptGuard guard;
    int done = 0;  // frames posed and drawn
    if (a.frames > 0 && s.animation() >= 0)
      done = play_animation(a, s, renderer, cam, o, V);
    else if (a.frames > 0)
      done = time_frames(a, s, renderer, cam, o, context.backend);
    if (const int sig = interrupted()) {
      std::fprintf(stderr,
                   "spinmotor-viewer: interrupted by %s after %d of %d frames; no screenshot written\n",
                   signal_name(sig).c_str(), done, a.frames);
      status = interrupted_exit_code(sig);
    } else {
      write_screenshot(a, s, renderer, fb, shot, o, context.backend);
    }
  }
  if (context.window) glfwDestroyWindow(context.window);
  glfwTerminate();
  return status;
}

}  // namespace spinmotor::viewer::app
