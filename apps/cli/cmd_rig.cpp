// `spinmotor rig`: glTF 2.0 skinned characters (mesh/gltf.hpp, deform/rig_skin.hpp).
//   rig info FILE [--json]      joints, welded vertex count, renormalised weights, animations
//   rig pose FILE (--time T | --frames N | --frames A:B --fps F) [--animation NAME|INDEX]
//            [--blend lbs|dlb|log|pivot-log] --out PATH
//       posed meshes: one file at PATH (--time), or PATH's stem + ".0000", ".0001", ... (--frames N: N
//       frames evenly over the animation; --frames A:B --fps F: frames A..B, frame k at time k / F and
//       numbered k);
//       a .gltf/.glb PATH holds all frames as morph targets driven by a STEP weights animation;
//       [--space scene|mesh]: positions placed in the file's scene, as glTF viewers show them (default),
//       or in its mesh space (the POSITION frame);
//       [--cleanup none|pinned]: the pose-keeping cleanup of every frame.
//   The posing, the cleanup and the glTF baker are scene/rig_pose.hpp's (shared with Python's Rig).
// Bad input (unreadable rig, bad option, scaling joint for a motor blend) exits 2 before anything is
// written; frame sequences are staged in a hidden folder and moved into place only when all are written.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/rig_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace {

using spinmotor::Error;
namespace fs = std::filesystem;

struct RigArgs {
  std::string file;
  bool json = false;
  // pose
  double time = std::nan("");
  std::string frames;           // "N" or "A:B"
  double fps = std::nan("");    // with --frames A:B
  std::string animation = "0";  // an index or a name
  std::string blend = "lbs";
  std::string out;
  std::string cleanup = "none";
  spinmotor::scene::RigCleanupOptions rig_cleanup;  // --cleanup pinned (defaults: scene/rig_cleanup.hpp)
  bool warm_start = true;  // --cleanup pinned with --frames: frame k starts from frame k − 1's correction
  std::string space = "scene";
};

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

nlohmann::json info_json(const spinmotor::GltfRig& rig) {
  using nlohmann::json;
  json j;
  j["file"] = rig.file.string();
  j["mesh"] = {{"name", rig.mesh_name},
               {"node", rig.nodes[rig.mesh_node].name},
               {"file_vertices", rig.file_vertices},
               {"vertices", rig.mesh.num_vertices()},
               {"faces", rig.mesh.num_faces()},
               {"dropped_faces", rig.dropped_faces},
               {"uv", rig.mesh.has_uv()}};
  json joints = json::array();
  for (Eigen::Index k = 0; k < rig.num_joints(); ++k)
    joints.push_back({{"name", rig.joint_names[k]}, {"parent", rig.joint_parents[k]}});
  j["joints"] = joints;
  j["weights"] = {{"renormalised_rows", rig.renormalised_rows},
                  {"min_sum", rig.min_weight_sum},
                  {"weld_mismatches", rig.weld_weight_mismatches},
                  {"weld_max_difference", rig.weld_weight_max_difference},
                  {"max_influences", [&] {
                     Eigen::Index m = 0;
                     const Eigen::SparseMatrix<double, Eigen::RowMajor> r = rig.weights;
                     for (Eigen::Index i = 0; i < r.outerSize(); ++i)
                       m = std::max<Eigen::Index>(m, r.row(i).nonZeros());
                     return m;
                   }()}};
  json anims = json::array();
  for (const auto& a : rig.animations)
    anims.push_back({{"name", a.name},
                     {"channels", a.channels.size()},
                     {"start", a.start},
                     {"end", a.end},
                     {"duration", a.duration()}});
  j["animations"] = anims;
  // Bind pose = rest pose? Largest distance of the rest-pose skinning from POSITION, / bbox diagonal.
  const Eigen::MatrixXd& V = rig.mesh.V;
  const double diag = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  j["rest_pose_error"] =
      std::sqrt((spinmotor::skin_positions(rig, -1, 0.0) - V).rowwise().squaredNorm().maxCoeff()) / diag;
  j["warnings"] = rig.warnings;
  return j;
}

void run_info(const RigArgs& a) {
  const spinmotor::GltfRig rig = spinmotor::read_gltf(a.file);
  const nlohmann::json j = info_json(rig);
  if (a.json) {
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::cout << rig.file.string() << ": mesh '" << rig.mesh_name << "' (node '"
            << rig.nodes[rig.mesh_node].name << "')\n"
            << "  vertices " << rig.mesh.num_vertices() << " welded from " << rig.file_vertices << ", faces "
            << rig.mesh.num_faces()
            << (rig.dropped_faces ? " (" + std::to_string(rig.dropped_faces) + " dropped)" : "") << ", uv "
            << (rig.mesh.has_uv() ? "yes" : "no") << '\n'
            << "  joints " << rig.num_joints() << ":";
  for (Eigen::Index k = 0; k < rig.num_joints(); ++k)
    std::cout << (k ? ", " : " ") << rig.joint_names[k]
              << (rig.joint_parents[k] >= 0 ? "<" + rig.joint_names[rig.joint_parents[k]] : std::string());
  std::cout << "\n  weights: max " << j["weights"]["max_influences"] << " influences, "
            << rig.renormalised_rows << " rows renormalised (smallest sum " << rig.min_weight_sum << "), "
            << rig.weld_weight_mismatches << " weld mismatches\n";
  std::cout << "  rest pose error " << j["rest_pose_error"].get<double>()
            << " of the diagonal (skinning at the bind pose vs POSITION)\n";
  std::cout << "  animations " << rig.animations.size() << '\n';
  for (size_t k = 0; k < rig.animations.size(); ++k) {
    const auto& an = rig.animations[k];
    char b[160];
    std::snprintf(b, sizeof b, "    %zu '%s': %zu channels, %.4g .. %.4g s (duration %.4g s)\n", k,
                  an.name.c_str(), an.channels.size(), an.start, an.end, an.duration());
    std::cout << b;
  }
  for (const auto& w : rig.warnings) std::cerr << "spinmotor: warning: " << w << '\n';
}

/// --frames: "N" (N ≥ 1 frames evenly over the animation) or "A:B" (frame numbers A ≤ B, with --fps).
struct FrameRange {
  int count = 0;              // N, or B − A + 1
  int first = -1, last = -1;  // A:B (first ≥ 0), else −1
};

FrameRange parse_frames(const std::string& text) {
  auto number = [&](const std::string& t) {
    if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos)
      throw Error("rig pose: --frames '" + text + "': expected N or A:B (whole numbers ≥ 0)");
    return std::stoi(t);
  };
  FrameRange r;
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    r.count = number(text);
    if (r.count < 1) throw Error("rig pose: --frames N needs N ≥ 1");
    return r;
  }
  r.first = number(text.substr(0, colon));
  r.last = number(text.substr(colon + 1));
  if (r.last < r.first) throw Error("rig pose: --frames " + text + ": the last frame comes before the first");
  if (r.last - r.first >= 100000) throw Error("rig pose: --frames " + text + ": more than 100000 frames");
  r.count = r.last - r.first + 1;
  return r;
}

/// --animation: an index into the file's animations, or a name.
int animation_index(const spinmotor::GltfRig& rig, const std::string& which) {
  const int count = static_cast<int>(rig.animations.size());
  if (!which.empty() && which.size() < 10 && which.find_first_not_of("0123456789") == std::string::npos) {
    const int k = std::stoi(which);
    if (k >= count)
      throw Error("rig pose: --animation " + which + " out of range (the file has " + std::to_string(count) +
                  ")");
    return k;
  }
  std::string names;
  for (int k = 0; k < count; ++k) {
    if (rig.animations[k].name == which) return k;
    names += (names.empty() ? "'" : ", '") + rig.animations[k].name + "'";
  }
  throw Error("rig pose: --animation: no animation named '" + which + "' (the file has " + names + ")");
}

void run_pose(const RigArgs& a) {
  // Validate everything before reading or writing.
  const bool by_time = !std::isnan(a.time);
  if (by_time == !a.frames.empty())
    throw Error("rig pose: give exactly one of --time T and --frames N | A:B");
  if (by_time && !std::isfinite(a.time)) throw Error("rig pose: --time must be finite");
  const FrameRange range = by_time ? FrameRange{1, -1, -1} : parse_frames(a.frames);
  const bool numbered = range.first >= 0;
  if (numbered && !(a.fps > 0 && std::isfinite(a.fps)))
    throw Error("rig pose: --frames A:B needs --fps F > 0 (frame k is at time k / F)");
  if (!numbered && !std::isnan(a.fps)) throw Error("rig pose: --fps goes with --frames A:B");
  if (a.out.empty()) throw Error("rig pose: --out PATH is required");
  const fs::path out(a.out);
  const std::string ext = lower(out.extension().string());
  const bool gltf_out = ext == ".gltf" || ext == ".glb";
  if (!gltf_out) spinmotor::mesh_format(out);  // throws for an unknown extension
  const auto blend = spinmotor::parse_option<spinmotor::SkinBlend>(a.blend, "rig pose: --blend: ");

  const spinmotor::GltfRig rig = spinmotor::read_gltf(a.file);
  for (const auto& w : rig.warnings) std::cerr << "spinmotor: warning: " << w << '\n';
  if (rig.animations.empty()) throw Error(a.file + ": the file has no animation to pose");
  const int animation = animation_index(rig, a.animation);
  const spinmotor::GltfAnimation& anim = rig.animations[animation];

  const int n = range.count;
  std::vector<double> times(n);
  std::vector<int> numbers(n);  // the frame number in output names
  for (int f = 0; f < n; ++f) {
    numbers[f] = numbered ? range.first + f : f;
    times[f] = by_time ? a.time : numbered ? numbers[f] / a.fps : spinmotor::gltf_frame_time(anim, f, n);
  }
  spinmotor::scene::RigPoseOptions po;
  po.animation = animation;
  po.blend = blend;
  po.cleanup = spinmotor::parse_option<spinmotor::scene::RigCleanupMode>(a.cleanup, "rig pose: --cleanup: ");
  po.cleanup_options = a.rig_cleanup;
  po.cleanup_options.cleanup.warm_start = a.warm_start;  // frames are cleaned in time order
  po.space = spinmotor::parse_option<spinmotor::scene::RigSpace>(a.space, "rig pose: --space: ");
  spinmotor::scene::RigPoser poser(rig, po);  // scene/rig_pose.hpp: skin, cleanup, placement
  if (poser.pins().size() > 0)
    std::cerr << "rig pose: cleanup pinned: " << poser.pins().size() << " of " << rig.mesh.V.rows()
              << " vertices pinned (largest margin " << poser.pin_margins().maxCoeff() << "), pose weight "
              << po.cleanup_options.pose_weight << "\n";
  auto pose_frame = [&](int f) { return poser.pose(times[f]); };

  std::vector<fs::path> written;
  if (gltf_out) {
    spinmotor::scene::bake_rig_gltf(out, poser, times, out.stem().string());
    written.push_back(out);
  } else if (by_time) {
    spinmotor::Mesh m = rig.mesh;
    m.V = pose_frame(0);
    spinmotor::write_mesh(out, m);
    written.push_back(out);
  } else {
    // Stage the whole sequence in a hidden folder next to the output, frame by frame, then move it into
    // place: an error (a bad frame, a full disk) leaves no frame behind.
    const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    const fs::path stage = dir / (".spinmotor-rig-" + out.stem().string() + "-" + std::to_string(getpid()));
    const bool dir_existed = fs::exists(dir);
    std::vector<fs::path> targets;
    auto discard = [&] {
      std::error_code ec;
      fs::remove_all(stage, ec);
      if (!dir_existed) fs::remove(dir, ec);  // the (empty) folder this run created
    };
    try {
      fs::create_directories(stage);
      spinmotor::Mesh m = rig.mesh;
      for (int f = 0; f < n; ++f) {
        char num[16];
        std::snprintf(num, sizeof num, ".%04d", numbers[f]);
        const fs::path name = out.stem().string() + num + out.extension().string();
        m.V = pose_frame(f);
        spinmotor::write_mesh(stage / name, m);
        targets.push_back(name);
      }
      for (const auto& name : targets) fs::rename(stage / name, dir / name);
      fs::remove_all(stage);
    } catch (const fs::filesystem_error& e) {
      discard();
      throw Error(std::string("rig pose: cannot write the frames: ") + e.what());
    } catch (...) {
      discard();
      throw;
    }
    for (const auto& name : targets) written.push_back(dir / name);
  }
  std::cout << rig.file.filename().string() << ": " << rig.mesh.num_vertices() << " vertices, "
            << rig.num_joints() << " joints, animation '" << anim.name << "', blend " << a.blend << ", " << n
            << " frame" << (n > 1 ? "s" : "");
  char span[96];
  if (n > 1)
    std::snprintf(span, sizeof span, " (t = %.4g .. %.4g s)", times.front(), times.back());
  else
    std::snprintf(span, sizeof span, " (t = %.4g s)", times.front());
  std::cout << span << '\n';
  if (written.size() <= 3)
    for (const auto& p : written) std::cout << "  wrote " << p.string() << '\n';
  else
    std::cout << "  wrote " << written.front().string() << " .. " << written.back().string() << '\n';
}

const spinmotor::cli::RegisterCommand register_rig{
    "rig", "glTF 2.0 skinned characters: print a rig's contents, pose its animation with a skinning blend",
    [](CLI::App& sub) {
      sub.require_subcommand(1);
      auto a = std::make_shared<RigArgs>();
      CLI::App* info =
          sub.add_subcommand("info", "Joints, welded vertices, renormalised weights, animations");
      info->add_option("file", a->file, "glTF file (.gltf or .glb)")->required();
      info->add_flag("--json", a->json, "Print as JSON");
      info->callback([a] { run_info(*a); });

      CLI::App* pose = sub.add_subcommand("pose", "Pose the rig's animation and write the skinned meshes");
      pose->add_option("file", a->file, "glTF file (.gltf or .glb)")->required();
      pose->add_option("--time", a->time, "One frame at time T (seconds; clamped to the animation's range)");
      pose->add_option(
          "--frames", a->frames,
          "N: N frames evenly over the animation (first to last key time, numbered from 0); A:B: "
          "frames A to B at --fps (frame k at time k / fps, numbered k)");
      pose->add_option("--fps", a->fps, "Frames per second of --frames A:B");
      pose->add_option("--animation", a->animation, "Animation index or name (default 0, the first)");
      pose->add_option(
              "--blend", a->blend,
              "Skinning blend (default lbs): lbs, dlb (dual quaternion / motor linear), log, pivot-log")
          ->check(CLI::IsMember(spinmotor::option_values<spinmotor::SkinBlend>()));
      pose->add_option(
              "--out", a->out,
              "Output: .obj/.ply/.off/.stl (with --frames: out/frame.obj -> out/frame.0000.obj ...), or "
              ".gltf/.glb (all frames as morph targets)")
          ->required();
      pose->add_option(
              "--space", a->space,
              "Output coordinates: scene (the mesh node's global matrix applied, as glTF viewers show the "
              "file, e.g. Y-up for the Khronos samples; default) or mesh (the file's POSITION frame)")
          ->check(CLI::IsMember(spinmotor::option_values<spinmotor::scene::RigSpace>()));
      pose->add_option(
              "--cleanup", a->cleanup,
              "Post-skinning cleanup of each frame: none, or pinned (the pose-keeping conformal cleanup "
              "with the bones' rigid parts pinned)")
          ->check(CLI::IsMember(spinmotor::option_values<spinmotor::scene::RigCleanupMode>()));
      pose->add_option("--pin-threshold", a->rig_cleanup.pin_threshold,
                       "--cleanup pinned: a vertex is rigid when one joint's weight is at least this")
          ->check(CLI::Range(0.5, 1.0))
          ->capture_default_str();
      pose->add_option("--pin-margin", a->rig_cleanup.pin_margin,
                       "--cleanup pinned: rigid vertices closer than this to a blended one are left free "
                       "(default, per bone: a quarter of the widest blend band of its joints)");
      pose->add_option("--pose-weight", a->rig_cleanup.pose_weight,
                       "--cleanup pinned: γ ≥ 0 of the attraction that holds the soft parts near the skinned "
                       "pose (1 on rigid parts, 0 mid-joint; 0 = pins only)")
          ->check(CLI::NonNegativeNumber)
          ->capture_default_str();
      pose->add_flag("--warm-start,!--no-warm-start", a->warm_start,
                     "--cleanup pinned with --frames: start each frame's cleanup from the previous frame's "
                     "correction (default; 2.9-4x fewer steps on a 30-frame bend, docs/performance.md), or "
                     "clean every frame from its skinned pose alone");
      pose->callback([a] { run_pose(*a); });
      const std::string examples =
          "Examples:\n"
          "  spinmotor rig info ../shared/rigs/CesiumMan.gltf --json\n"
          "  spinmotor rig pose ../shared/rigs/RiggedFigure.gltf --frames 24 --blend dlb --out "
          "out/frame.obj\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --frames 0:48 --fps 24 --out out/walk.obj\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --time 1.2 --space scene --out posed.ply\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --frames 24 --cleanup pinned --out "
          "out/clean.obj\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --frames 49 --out out/baked.glb  # Blender: "
          "shape keys";
      sub.footer(examples);
      info->footer(examples);
      pose->footer(examples);
    }};

}  // namespace
