// spinmotor-viewer [SCENE.json | RIG.gltf/.glb | MESH]: the interactive poser (GLFW + OpenGL 3.3 core +
// Dear ImGui).
//
// Window: left drag orbits, right drag (or shift+left) pans, wheel zooms. Every control of the
// deformer (handle, FFD lattice point, cage vertex, bone, spline key, IK target) is a dot; click one
// and drag its gizmo's axis arrows (translate) or rings (rotate; R toggles). The deformer (bound
// once, chosen and tuned in the Deformer panel) poses every frame and the pose time is shown. When a
// drag ends the edit is snapped to its nearest spin transformation in a worker thread (a stale result
// is dropped); Q before/after are shown. Ctrl+drag uses the current tool: brush, box or lasso
// selection of vertices for a new handle (visible vertices only by default; alt subtracts), or the
// curvature paint brush (alt paints negative ρ), whose spin transformation is computed in a second
// worker when the stroke ends. Ctrl+Z / Ctrl+Y undo / redo pose edits. A glTF rig (or a scene with a
// `rig`) gets the Animation panel: its skeleton drawn over the mesh, the animation, a time slider and a
// play button, the skin's blend (and Delta Mush), and "clean up each frame": the pose-keeping cleanup
// (the bones' rigid parts pinned) of every frame shown, in the snap worker (a frame that is no longer
// shown is dropped). Bone gizmos edit the animated pose (docs/scene.md `rig`).
//
// Headless: spinmotor-viewer --scene S --screenshot out.png [--size WxH] [--camera AZ,EL[,DIST]]
//   [--color q|checker|normals|plain|rho] [--deformer CHOICE] [--select-box X0,Y0,X1,Y1 |
//   --select-lasso X,Y,X,Y,X,Y... --add-handle NAME] [--gizmo NAME,translate|rotate,x|y|z,AMOUNT]...
//   [--snap [--keep-pose] | --paint X,Y,RADIUS,AMOUNT...] [--frames N] [--time T|rest] [--animation A]
//   [--skeleton]
// renders one frame (in a hidden GLFW window, e.g. under xvfb-run, or without any display through
// the offscreen EGL/OSMesa context) and exits. Every step goes through the code the window uses:
// --deformer the panel's preset, the selections the pixel regions of the camera framing the rest mesh
// (visible vertices), --gizmo a press ray and a release ray through that camera (apps/viewer/core gizmo.hpp),
// --paint a pick at a pixel and a brush dab, then the spin transformation of the painted ρ. --frames N
// poses and uploads N frames (a rotation growing through the gizmo code path; a rig: N times over its
// animation, with --snap --keep-pose each one cleaned up in the snap worker as the window's "clean up
// each frame" does) and prints the frame timer. --skeleton draws the bones (bone_overlay.hpp).
// Exit codes: 0 ok, 2 bad input, 3 numerical failure, 129 / 130 / 143 a headless run stopped by SIGHUP /
// SIGINT / SIGTERM (between two frames; no screenshot is written, and one line on stderr says after how
// many). Elsewhere a stop signal ends the viewer by that signal.
#include <CLI/CLI.hpp>
#include <iostream>

#include "app.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/interrupt.hpp"
#include "spinmotor/linalg/blas_threads.hpp"
#include "spinmotor/viewer/deformer_presets.hpp"

int main(int argc, char** argv) {
  // SIGINT, SIGTERM, SIGHUP: taken by a thread of their own, never by a dependency's handler (METIS
  // traps SIGTERM while the snap worker orders); OpenBLAS's load-time workers start again blocking them.
  spinmotor::take_stop_signals();
  spinmotor::join_idle_blas_workers();
  CLI::App app{"spinmotor-viewer: pose a mesh with CGA motor handles and snap it to a spin transformation"};
  spinmotor::viewer::app::Args a;
  app.add_option("DOC", a.doc, "Scene file (.json, docs/scene.md), glTF rig (.gltf/.glb) or mesh file");
  app.add_option("--scene", a.doc, "Scene file (same as DOC)");
  app.add_option("--screenshot", a.screenshot, "Headless: render one frame to this PNG and exit");
  app.add_option("--size", a.size, "Window / image size WxH")->capture_default_str();
  app.add_option("--camera", a.camera, "AZ,EL[,DIST]: orbit camera (degrees about the up axis, distance)");
  app.add_option("--up", a.up, "Up axis")->check(CLI::IsMember({"x", "y", "z"}))->capture_default_str();
  app.add_option("--color", a.color, "q, checker, normals, plain or rho (the painted curvature change)")
      ->check(CLI::IsMember({"q", "checker", "normals", "plain", "rho"}))
      ->capture_default_str();
  app.add_option("--q-range", a.q_range, "LO,HI: Q colour range")->capture_default_str();
  app.add_flag("--flat", a.flat, "Flat shading");
  app.add_flag("--wireframe", a.wireframe, "Draw edges");
  app.add_option("--gizmo", a.gizmos,
                 "Headless: NAME,translate|rotate,x|y|z,AMOUNT: drag a control's gizmo (handle, lattice "
                 "point, ik.target...)")
      ->take_all();
  app.add_option("--deformer", a.deformer, "Switch to this deformer (the panel's preset)")
      ->check(CLI::IsMember(spinmotor::viewer::deformer_choices()));
  app.add_option("--select-box", a.select_box,
                 "Headless: X0,Y0,X1,Y1: select the visible vertices in this pixel box");
  app.add_option("--select-lasso", a.select_lasso,
                 "Headless: X,Y,X,Y,X,Y...: select the visible vertices in this lasso");
  app.add_option("--add-handle", a.add_handle, "Headless: make a handle of the selection, with this name");
  app.add_option("--paint", a.paints,
                 "Headless: X,Y,RADIUS,AMOUNT: paint rho at a pixel (radius: fraction of the scene radius); "
                 "repeatable; then show the spin transformation")
      ->take_all();
  app.add_flag("--snap", a.snap, "Headless: show the conformal snap of the posed mesh");
  app.add_flag(
      "--keep-pose", a.keep_pose,
      "With --snap: the pose-keeping cleanup instead (every handle pinned where the deformer put it)");
  app.add_option("--tradeoff", a.tradeoff, "Snap tradeoff in [0, 1]")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--time", a.time,
                 "Rigs (.gltf/.glb or a scene with `rig`): the animation time in seconds, or rest");
  app.add_option("--animation", a.animation, "Rigs: the animation to play (name or index)");
  app.add_flag("--skeleton", a.skeleton, "Headless: draw the skin's bones over the picture");
  app.add_option(
         "--frames", a.frames,
         "Headless: pose + upload + draw this many frames and print the frame timer (a rig plays "
         "its animation; with --snap --keep-pose each frame is cleaned up in the worker). SIGINT or SIGTERM "
         "stops it between frames: no screenshot, exit 130 or 143")
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
    if (a.doc.empty())
      throw spinmotor::Error("a scene or mesh file is required (spinmotor-viewer SCENE.json | MESH)");
    if (!a.screenshot.empty()) return spinmotor::viewer::app::run_headless(a);
    if (a.snap || !a.gizmos.empty() || a.frames > 0 || !a.paints.empty() || !a.select_box.empty() ||
        !a.select_lasso.empty() || !a.add_handle.empty() || a.skeleton)
      throw spinmotor::Error(
          "--gizmo, --snap, --paint, --select-*, --add-handle, --skeleton and --frames need --screenshot");
    return spinmotor::viewer::app::run_window(a);
  } catch (const spinmotor::Error& e) {
    std::cerr << "spinmotor-viewer: error: " << e.what() << "\n";
    return e.kind() == spinmotor::Error::Kind::Numerical ? 3 : 2;
  } catch (const std::exception& e) {
    std::cerr << "spinmotor-viewer: error: " << e.what() << "\n";
    return 3;
  }
}
