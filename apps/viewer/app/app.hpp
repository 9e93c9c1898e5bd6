#pragma once
// spinmotor-viewer's pieces shared by the window (window.cpp, window_input.cpp, window_panels.cpp) and the
// headless screenshot mode (headless.cpp): the command line, and the steps both drive through the same code.
#include <Eigen/Core>
#include <chrono>
#include <string>
#include <vector>

#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/render/mesh_renderer.hpp"
#include "spinmotor/render/orbit_camera.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/session.hpp"

namespace spinmotor::viewer::app {

using Clock = std::chrono::steady_clock;

struct Args {
  std::string doc, screenshot, size = "1280x800", camera, up = "y", color = "checker", q_range = "1,2";
  std::string deformer;                     ///< a deformer_choices() entry to switch to
  std::string select_box, select_lasso;     ///< pixel regions (headless)
  std::string add_handle;                   ///< name of a handle made of the selection (headless)
  std::vector<std::string> gizmos, paints;  ///< NAME,MODE,AXIS,AMOUNT / X,Y,RADIUS,AMOUNT
  bool snap = false, flat = false, wireframe = false;
  int frames = 0;
  double tradeoff = 1.0;
  bool keep_pose = false;  ///< --snap --keep-pose: the pose-keeping cleanup with the handles pinned
  std::string time;        ///< rigs: the animation time (seconds) or "rest"
  std::string animation;   ///< rigs: an animation name or index
  bool skeleton = false;   ///< headless: draw the skin's bones over the picture
  int smoke_frames = 0;    ///< window mode: run this many frames, then exit (smoke test under Xvfb)
  std::string smoke_png;   ///< ... and save the last window frame (mesh + UI) here
};

int run_headless(const Args& a);
int run_window(const Args& a);

/// GLFW's loader for render::load_gl.
void* glfw_proc(const char* name);

/// --gizmo NAME,translate|rotate,x|y|z,AMOUNT (degrees or scene units).
struct GizmoSpec {
  std::string control;
  GizmoMode mode = GizmoMode::Rotate;
  int axis = 2;
  double amount = 0;
};
GizmoSpec parse_gizmo(const std::string& text);

/// Comma-separated finite numbers, exactly `count` of them (or at least `count` and an even number
/// when `at_least`); Error naming `option` otherwise.
std::vector<double> parse_numbers(const std::string& text, const char* option, std::size_t count,
                                  bool at_least = false);

/// The motor a mouse drag of control `g.control`'s gizmo gives (simulated_drag: a press ray and a
/// release ray through `camera`). The gizmo sits at Session::posed_anchor. Error for an unknown
/// control or a camera looking along the axis.
ga::Mot simulate_drag(const Session& s, const render::OrbitCamera& camera, int width, int height,
                      const GizmoSpec& g);

/// --animation NAME|INDEX and --time T|rest applied to a rig session (Error for a session without rig,
/// an unknown animation or a time that is not a number).
void apply_rig_args(const Args& a, Session& s);

/// "q", "checker", "normals", "plain", "rho" → ColorMode.
render::ColorMode parse_color(const std::string& name);

}  // namespace spinmotor::viewer::app
