#pragma once
// spinmotor-viewer's window state (window.cpp: its methods and the frame loop), shared with the view's
// input handling (window_input.cpp) and the panels (window_panels.cpp).
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app.hpp"
#include "spinmotor/render/mesh_renderer.hpp"
#include "spinmotor/render/orbit_camera.hpp"
#include "spinmotor/viewer/animation_clock.hpp"
#include "spinmotor/viewer/curvature_paint.hpp"
#include "spinmotor/viewer/gizmo.hpp"
#include "spinmotor/viewer/selection.hpp"
#include "spinmotor/viewer/session.hpp"
#include "spinmotor/viewer/snap_worker.hpp"

namespace spinmotor::viewer::app {

enum class Tool { Brush, Box, Lasso, Paint };
enum class Shown { Edit, Snap, Painted };

/// Everything the window shows and edits: the session, the renderer and camera, the workers, the
/// tools' and panels' state.
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

  /// The current control's name ("" without controls).
  std::string control_name() const;
  /// After any (re)bind: cached anchors, lattice lines, the panel's copy of the deformer block.
  void on_rebind();
  /// A new frame of the animation (slider or playback): pose it, and clean it up when asked.
  void set_time(std::optional<double> t);
  /// Runs `change` (a rebind of the session) and on_rebind; the status says `what` and the bind time,
  /// or the error.
  void rebind(const std::function<void()>& change, const std::string& what);
  /// The positions shown: the snap, the painted result or the edit.
  const Eigen::MatrixXd& shown_positions();
  /// Uploads the shown positions (and the face values of the colour mode); refreshes Q and the bones.
  void refresh_geometry();
  /// snap_now when a snap is asked for after every drag.
  void request_snap();
  /// The §7.2 snap, or with "keep the pose" the pose-keeping cleanup with every handle pinned.
  void snap_now();
  /// The spin transformation of the painted rho (the paint worker, made on the first paint).
  void request_paint();
};

/// The view under the panels: the selection, the controls' dots and the current control's gizmo drawn
/// over the mesh; mouse input (gizmo drags, ctrl+drag gestures, picking a control, the camera) applied
/// to `v`. w, h: the window size in screen coordinates.
void draw_and_handle_input(Viewer& v, int w, int h);

/// The "spinmotor" panel window and its sections; w, h: the framebuffer size (screenshots, reframing).
void panel(Viewer& v, int w, int h);

}  // namespace spinmotor::viewer::app
