// `spinmotor rig`: glTF 2.0 skinned characters (mesh/gltf.hpp, deform/gltf_skin.hpp, scene/rig_pose.hpp).
//   rig info FILE [--mesh NAME]... [--json]   pieces, skins, joints, morph targets, weights, animations
//   rig pose FILE (--time T | --frames N | --frames A:B --fps F) [--animation NAME|INDEX] [--mesh NAME]...
//            [--blend lbs|dlb|log|pivot-log] [--space scene|mesh] [--cleanup none|pinned ...] --out PATH
//            [--rest-out PATH] [--bake frames|correctives [--max-error E]] [--json]
//       posed meshes: one file at PATH (--time), or PATH's stem + ".0000", ".0001", ... (--frames N: N
//       frames evenly over the animation; --frames A:B --fps F: frames A..B, frame k at time k / F and
//       numbered k); OBJ files hold one object per piece. A .gltf/.glb PATH holds every frame as morph
//       targets (--bake frames, one node per piece) or the rig itself with a few corrective morph targets
//       that reproduce the cleaned animation on any engine that plays skinning and morph targets
//       (--bake correctives, deform/gltf_correctives.hpp).
//   The posing, the cleanup and the glTF bakers are scene/rig_pose.hpp's (shared with Python's Rig).
// Bad input (unreadable rig, bad option) exits 2 before anything is written; frame sequences are staged
// in a hidden folder and moved into place only when all are written.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/option_names.hpp"
#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/deform/gltf_correctives.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/mesh/gltf.hpp"
#include "spinmotor/mesh/gltf_rig_writer.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"
#include "spinmotor/scene/rig_pose.hpp"

namespace {

using nlohmann::json;
using spinmotor::Error;
namespace fs = std::filesystem;

struct RigArgs {
  std::string file;
  std::vector<std::string> meshes;
  bool json = false;
  // pose
  double time = std::nan("");
  std::string frames;           // "N" or "A:B"
  double fps = std::nan("");    // with --frames A:B
  std::string animation = "0";  // an index or a name
  std::string blend = "lbs";
  std::string out, rest_out;
  std::string cleanup = "none";
  spinmotor::scene::RigCleanupOptions rig_cleanup;  // --cleanup pinned (defaults: scene/rig_cleanup.hpp)
  bool warm_start = true;  // --cleanup pinned with --frames: frame k starts from frame k − 1's correction
  std::string space = "scene";
  std::string bake = "frames";
  double max_error = spinmotor::CorrectiveOptions{}.max_error;
};

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

spinmotor::GltfRig read_rig(const RigArgs& a) {
  spinmotor::GltfReadOptions o;
  o.meshes = a.meshes;
  return spinmotor::read_gltf(a.file, o);
}

json pieces_json(const spinmotor::GltfRig& rig) {
  json pieces = json::array();
  for (const spinmotor::GltfPiece& p : rig.pieces)
    pieces.push_back({{"name", p.name},
                      {"node", rig.nodes[p.node].name},
                      {"skin", rig.skins[p.skin].name},
                      {"vertices", p.vertices},
                      {"file_vertices", p.file_vertices},
                      {"faces", p.faces},
                      {"primitives", p.primitive_start.size()},
                      {"dropped_faces", p.dropped_faces},
                      {"morph_targets", p.target_names}});
  return pieces;
}

json info_json(const spinmotor::GltfRig& rig) {
  json j;
  j["file"] = rig.file.string();
  j["pieces"] = pieces_json(rig);
  j["surface"] = {{"vertices", rig.mesh.num_vertices()},
                  {"file_vertices", rig.file_vertices},
                  {"faces", rig.mesh.num_faces()},
                  {"dropped_faces", rig.dropped_faces},
                  {"uv", rig.mesh.has_uv()}};
  json skins = json::array();
  for (const spinmotor::GltfSkin& s : rig.skins)
    skins.push_back({{"name", s.name}, {"joints", s.joints.size()}});
  j["skins"] = skins;
  json joints = json::array();
  for (Eigen::Index k = 0; k < rig.num_joints(); ++k)
    joints.push_back({{"name", rig.joint_names[k]}, {"parent", rig.joint_parents[k]}});
  j["joints"] = joints;
  Eigen::Index most = 0;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = rig.weights;
  for (Eigen::Index i = 0; i < rows.outerSize(); ++i)
    most = std::max<Eigen::Index>(most, rows.row(i).nonZeros());
  j["weights"] = {{"renormalised_rows", rig.renormalised_rows},
                  {"min_sum", rig.min_weight_sum},
                  {"max_sum", rig.max_weight_sum},
                  {"weld_mismatches", rig.weld_weight_mismatches},
                  {"weld_max_difference", rig.weld_weight_max_difference},
                  {"max_influences", most}};
  json anims = json::array();
  for (const auto& a : rig.animations)
    anims.push_back({{"name", a.name},
                     {"channels", a.channels.size()},
                     {"start", a.start},
                     {"end", a.end},
                     {"duration", a.duration()}});
  j["animations"] = anims;
  j["ignored_channels"] = rig.ignored_channels;
  // Is the file's rest pose its bind pose? (gltf_skin.hpp: how far the joints' rest matrices differ.)
  const spinmotor::GltfBindPose bp = spinmotor::gltf_bind_pose(rig);
  j["bind_pose_deviation"] = bp.deviation;
  if (bp.joint >= 0 && bp.deviation > 1e-4) j["bind_pose_worst_joint"] = rig.joint_names[bp.joint];
  j["warnings"] = rig.warnings;
  return j;
}

void print_info(const spinmotor::GltfRig& rig, const json& j) {
  std::cout << rig.file.string() << ": " << rig.pieces.size() << " skinned mesh"
            << (rig.pieces.size() == 1 ? "" : "es") << ", " << rig.mesh.num_vertices()
            << " vertices welded from " << rig.file_vertices << ", " << rig.mesh.num_faces() << " faces, uv "
            << (rig.mesh.has_uv() ? "yes" : "no") << '\n';
  for (const spinmotor::GltfPiece& p : rig.pieces) {
    std::cout << "  mesh '" << p.name << "': " << p.vertices << " vertices (" << p.file_vertices
              << " in the file), " << p.faces << " faces, " << p.primitive_start.size()
              << " primitives, skin '" << rig.skins[p.skin].name << "'";
    if (p.num_targets() > 0) {
      std::cout << ", morph targets:";
      for (const auto& t : p.target_names) std::cout << ' ' << t;
    }
    std::cout << '\n';
  }
  std::cout << "  joints " << rig.num_joints() << ":";
  for (Eigen::Index k = 0; k < rig.num_joints(); ++k)
    std::cout << (k ? ", " : " ") << rig.joint_names[k]
              << (rig.joint_parents[k] >= 0 ? "<" + rig.joint_names[rig.joint_parents[k]] : std::string());
  std::cout << "\n  weights: at most " << j["weights"]["max_influences"] << " influences, "
            << rig.renormalised_rows << " rows renormalised, " << rig.weld_weight_mismatches
            << " weld mismatches\n";
  const double dev = j["bind_pose_deviation"].get<double>();
  std::cout << "  rest pose = bind pose to " << dev << " of the diagonal\n";
  std::cout << "  animations " << rig.animations.size() << '\n';
  for (size_t k = 0; k < rig.animations.size(); ++k) {
    const auto& an = rig.animations[k];
    char b[200];
    std::snprintf(b, sizeof b, "    %zu '%s': %zu channels, %.4g .. %.4g s (duration %.4g s)\n", k,
                  an.name.c_str(), an.channels.size(), an.start, an.end, an.duration());
    std::cout << b;
  }
  if (dev > 1e-3)
    std::cerr << "spinmotor: warning: the file's rest pose is not its bind pose (joint '"
              << j["bind_pose_worst_joint"].get<std::string>() << "' moves the surface by " << dev
              << " of the diagonal): its rest mesh is the bind pose\n";
}

void run_info(const RigArgs& a) {
  const spinmotor::GltfRig rig = read_rig(a);
  const json j = info_json(rig);
  if (a.json) {
    std::cout << j.dump(2) << '\n';
    return;
  }
  print_info(rig, j);
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

/// What run_pose needs, checked before anything is read or written.
struct PosePlan {
  FrameRange range;
  bool by_time = false, numbered = false, gltf_out = false, correctives = false;
  fs::path out;
};

PosePlan plan_pose(const RigArgs& a) {
  PosePlan p;
  p.by_time = !std::isnan(a.time);
  if (p.by_time == !a.frames.empty())
    throw Error("rig pose: give exactly one of --time T and --frames N | A:B");
  if (p.by_time && !std::isfinite(a.time)) throw Error("rig pose: --time must be finite");
  p.range = p.by_time ? FrameRange{1, -1, -1} : parse_frames(a.frames);
  p.numbered = p.range.first >= 0;
  if (p.numbered && !(a.fps > 0 && std::isfinite(a.fps)))
    throw Error("rig pose: --frames A:B needs --fps F > 0 (frame k is at time k / F)");
  if (!p.numbered && !std::isnan(a.fps)) throw Error("rig pose: --fps goes with --frames A:B");
  if (a.out.empty()) throw Error("rig pose: --out PATH is required");
  p.out = a.out;
  const std::string ext = lower(p.out.extension().string());
  p.gltf_out = ext == ".gltf" || ext == ".glb";
  if (!p.gltf_out) spinmotor::mesh_format(p.out);  // throws for an unknown extension
  if (!a.rest_out.empty()) spinmotor::mesh_format(a.rest_out);
  p.correctives = a.bake == "correctives";
  if (p.correctives && !p.gltf_out) throw Error("rig pose: --bake correctives writes a .gltf or .glb");
  if (p.correctives && a.space != "scene")
    throw Error("rig pose: --bake correctives is in scene space (drop --space)");
  if (!(a.max_error > 0) || !std::isfinite(a.max_error))
    throw Error("rig pose: --max-error must be positive");
  return p;
}

/// Frame sequences: stage every frame in a hidden folder next to the output, then move them into place,
/// so that an error (a bad frame, a full disk) leaves no frame behind.
std::vector<fs::path> write_sequence(const fs::path& out, const std::vector<int>& numbers,
                                     const std::function<void(int, const fs::path&)>& write_frame) {
  const fs::path dir = out.parent_path().empty() ? fs::path(".") : out.parent_path();
  const fs::path stage = dir / (".spinmotor-rig-" + out.stem().string() + "-" + std::to_string(getpid()));
  const bool dir_existed = fs::exists(dir);
  std::vector<fs::path> targets, written;
  auto discard = [&] {
    std::error_code ec;
    fs::remove_all(stage, ec);
    if (!dir_existed) fs::remove(dir, ec);  // the (empty) folder this run created
  };
  try {
    fs::create_directories(stage);
    for (size_t f = 0; f < numbers.size(); ++f) {
      char num[16];
      std::snprintf(num, sizeof num, ".%04d", numbers[f]);
      const fs::path name = out.stem().string() + num + out.extension().string();
      write_frame(static_cast<int>(f), stage / name);
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
  return written;
}

/// The pieces' report of a bound cleanup (stderr, and --json).
json cleanup_report(const spinmotor::GltfRig& rig, const spinmotor::scene::RigCleanup& c) {
  json pieces = json::array();
  std::map<std::string, int> counts;
  for (const auto& p : c.pieces()) {
    const std::string status(spinmotor::option_name(p.status));
    ++counts[status];
    pieces.push_back(
        {{"first_vertex", rig.vertex_label(p.vertices.front())},
         {"vertices", p.vertices.size()},
         {"faces", p.faces},
         {"pins", p.pins},
         {"degenerate_faces", p.degenerate},
         {"status", status},
         {"keep", p.status == spinmotor::scene::RigPieceStatus::Cleaned ? json(spinmotor::option_name(p.keep))
                                                                        : json()}});
  }
  return {{"pins", c.pins().size()},
          {"cleaned_vertices", c.cleaned_vertices()},
          {"pose_weight", c.options().cleanup.pose_weight},
          {"largest_margin", c.margins().size() ? c.margins().maxCoeff() : 0.0},
          {"statuses", counts},
          {"pieces", pieces}};
}

/// One frame's quality figures against the rest surface. The volume ratio is the whole surface's when it
/// is closed; with the cleanup, the one over the closed pieces it cleans (RigCleanupResult).
json frame_json(const spinmotor::Mesh& rest, const Eigen::MatrixXd& skinned, const Eigen::MatrixXd& V,
                double t, const spinmotor::scene::RigPoser& poser) {
  spinmotor::MetricsOptions mo;
  mo.willmore = false;
  mo.skip_degenerate_rest = true;
  const spinmotor::DeformationMetrics before = spinmotor::compute_metrics(rest.V, rest.F, skinned, mo);
  const auto& r = poser.last_cleanup();
  const json volume = poser.cleanup()       ? json(r.edit_volume_ratio)
                      : before.volume_ratio ? json(*before.volume_ratio)
                                            : json();
  json j = {{"time", t},
            {"skinned",
             {{"q_mean", spinmotor::detail::finite_or_null(before.q_mean)},
              {"q_max", spinmotor::detail::finite_or_null(before.q_max)},
              {"volume_ratio", volume}}}};
  if (!poser.cleanup()) return j;
  const spinmotor::DeformationMetrics after = spinmotor::compute_metrics(rest.V, rest.F, V, mo);
  const spinmotor::VertexDistances drift =
      spinmotor::vertex_distances(skinned, V, spinmotor::Alignment::None);
  j["cleaned"] = {{"q_mean", spinmotor::detail::finite_or_null(after.q_mean)},
                  {"q_max", spinmotor::detail::finite_or_null(after.q_max)},
                  {"volume_ratio", r.volume_ratio},
                  {"drift_rms", drift.rms},
                  {"drift_max", drift.max},
                  {"iterations", r.iterations},
                  {"converged", r.converged},
                  {"ms", r.total_ms}};
  return j;
}

spinmotor::scene::RigPoseOptions pose_options(const RigArgs& a, int animation) {
  spinmotor::scene::RigPoseOptions po;
  po.animation = animation;
  po.blend = spinmotor::parse_option<spinmotor::SkinBlend>(a.blend, "rig pose: --blend: ");
  po.cleanup = spinmotor::parse_option<spinmotor::scene::RigCleanupMode>(a.cleanup, "rig pose: --cleanup: ");
  po.cleanup_options = a.rig_cleanup;
  po.cleanup_options.cleanup.warm_start = a.warm_start;  // frames are cleaned in time order
  po.space = spinmotor::parse_option<spinmotor::scene::RigSpace>(a.space, "rig pose: --space: ");
  return po;
}

void run_pose(const RigArgs& a) {
  const PosePlan plan = plan_pose(a);  // everything checked before reading or writing
  const spinmotor::GltfRig rig = read_rig(a);
  for (const auto& w : rig.warnings) std::cerr << "spinmotor: warning: " << w << '\n';
  if (rig.animations.empty()) throw Error(a.file + ": the file has no animation to pose");
  const int animation = animation_index(rig, a.animation);
  const spinmotor::GltfAnimation& anim = rig.animations[animation];
  const int n = plan.range.count;
  std::vector<double> times(n);
  std::vector<int> numbers(n);  // the frame number in output names
  for (int f = 0; f < n; ++f) {
    numbers[f] = plan.numbered ? plan.range.first + f : f;
    times[f] = plan.by_time    ? a.time
               : plan.numbered ? numbers[f] / a.fps
                               : spinmotor::gltf_frame_time(anim, f, n);
  }
  spinmotor::scene::RigPoser poser(rig, pose_options(a, animation));
  json report = {{"file", rig.file.string()},
                 {"animation", anim.name},
                 {"blend", a.blend},
                 {"pieces", pieces_json(rig)}};
  if (const auto* c = poser.cleanup()) {
    report["cleanup"] = cleanup_report(rig, *c);
    const json& cr = report["cleanup"];
    std::cerr << "rig pose: cleanup pinned: " << c->pins().size() << " of " << rig.mesh.V.rows()
              << " vertices pinned, " << c->pieces().size() << " pieces (" << cr["statuses"].dump()
              << "), pose weight " << c->options().cleanup.pose_weight << "\n";
  }
  // Pose every frame (in time order: the cleanup's warm start), keeping the figures.
  const spinmotor::Mesh& rest = poser.rig_skin().rest;
  std::vector<Eigen::MatrixXd> posed(n);
  json frames = json::array();
  for (int f = 0; f < n; ++f) {
    Eigen::MatrixXd skinned;
    poser.skin(times[f], skinned);
    posed[f] = poser.clean(skinned);
    if (a.json) frames.push_back(frame_json(rest, skinned, posed[f], times[f], poser));
  }
  std::vector<fs::path> written;
  const spinmotor::Mesh rest_out = poser.rest();
  if (plan.correctives) {
    spinmotor::CorrectiveOptions co;
    co.max_error = a.max_error;
    const spinmotor::CorrectiveRig cr = spinmotor::corrective_rig(rig, animation, times, posed, co);
    spinmotor::write_gltf_rig(plan.out, cr.rig);
    report["correctives"] = {{"targets", cr.targets},
                             {"max_error", cr.max_error},
                             {"rms_error", cr.rms_error},
                             {"bound_met", cr.bound_met},
                             {"bytes", fs::file_size(plan.out)}};
    std::cerr << "rig pose: corrective targets per mesh " << json(cr.targets).dump() << ", max error "
              << cr.max_error << " of the diagonal (bound " << a.max_error
              << (cr.bound_met ? ", met" : ", NOT met: too few targets") << ")\n";
    written.push_back(plan.out);
  } else {
    for (auto& V : posed) poser.to_space(V);
    if (plan.gltf_out) {
      std::vector<spinmotor::GltfMorphPiece> pieces;
      for (const auto& p : rig.pieces)
        pieces.push_back({p.name, p.first_vertex, p.vertices, p.first_face, p.faces});
      const Eigen::Matrix4d node = Eigen::Matrix4d::Identity();
      spinmotor::write_gltf_morph_animation(
          plan.out, rest_out, posed, times, plan.out.stem().string(),
          a.space == "scene" ? node : poser.rig_skin().bind[rig.pieces[0].skin], pieces);
      written.push_back(plan.out);
    } else {
      spinmotor::WriteOptions wo;
      for (const auto& p : rig.pieces) wo.objects.emplace_back(p.name, p.first_face);
      auto write_frame = [&](int f, const fs::path& path) {
        spinmotor::Mesh m = rest_out;
        m.V = posed[f];
        spinmotor::write_mesh(path, m, wo);
      };
      if (plan.by_time) {
        write_frame(0, plan.out);
        written.push_back(plan.out);
      } else {
        written = write_sequence(plan.out, numbers, write_frame);
      }
    }
  }
  if (!a.rest_out.empty()) {
    spinmotor::WriteOptions wo;
    for (const auto& p : rig.pieces) wo.objects.emplace_back(p.name, p.first_face);
    spinmotor::write_mesh(a.rest_out, rest_out, wo);
    written.push_back(a.rest_out);
  }
  if (a.json) {
    report["frames"] = frames;
    json w = json::array();
    for (const auto& p : written) w.push_back(p.string());
    report["written"] = w;
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::cout << rig.file.filename().string() << ": " << rig.pieces.size() << " meshes, "
            << rig.mesh.num_vertices() << " vertices, " << rig.num_joints() << " joints, animation '"
            << anim.name << "', blend " << a.blend << ", " << n << " frame" << (n > 1 ? "s" : "");
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

void add_pose_options(CLI::App* pose, const std::shared_ptr<RigArgs>& a) {
  pose->add_option("file", a->file, "glTF file (.gltf or .glb)")->required();
  pose->add_option("--mesh", a->meshes,
                   "Pose only this skinned mesh (node or mesh name; repeat for several)");
  pose->add_option("--time", a->time, "One frame at time T (seconds; clamped to the animation's range)");
  pose->add_option("--frames", a->frames,
                   "N: N frames evenly over the animation (first to last key time, numbered from 0); A:B: "
                   "frames A to B at --fps (frame k at time k / fps, numbered k)");
  pose->add_option("--fps", a->fps, "Frames per second of --frames A:B");
  pose->add_option("--animation", a->animation, "Animation index or name (default 0, the first)");
  pose->add_option(
          "--blend", a->blend,
          "Skinning blend (default lbs, the glTF formula): lbs, dlb (dual quaternion / motor linear), log, "
          "pivot-log")
      ->check(CLI::IsMember(spinmotor::option_values<spinmotor::SkinBlend>()));
  pose->add_option(
          "--out", a->out,
          "Output: .obj/.ply/.off/.stl (with --frames: out/frame.obj -> out/frame.0000.obj ...; OBJ: one "
          "object per mesh), or .gltf/.glb (see --bake)")
      ->required();
  pose->add_option(
      "--rest-out", a->rest_out,
      "Also write the rest surface (the bind pose, in --space), e.g. for `spinmotor metrics REST POSED`");
  pose->add_option(
          "--space", a->space,
          "Output coordinates: scene (the file's scene, as glTF viewers and Blender show it; default) or "
          "mesh (each mesh's POSITION frame)")
      ->check(CLI::IsMember(spinmotor::option_values<spinmotor::scene::RigSpace>()));
  pose->add_option(
          "--cleanup", a->cleanup,
          "Post-skinning cleanup of each frame: none, or pinned (the pose-keeping conformal cleanup with the "
          "bones' rigid parts pinned)")
      ->check(CLI::IsMember(spinmotor::option_values<spinmotor::scene::RigCleanupMode>()));
  pose->add_option("--pin-threshold", a->rig_cleanup.pin_threshold,
                   "--cleanup pinned: a vertex is rigid when one joint's weight is at least this")
      ->check(CLI::Range(0.5, 1.0))
      ->capture_default_str();
  pose->add_option(
      "--pin-margin", a->rig_cleanup.pin_margin,
      "--cleanup pinned: rigid vertices closer than this to a blended one are left free (default, per "
      "bone: a quarter of the widest blend band of its joints)");
  pose->add_option(
          "--pose-weight", a->rig_cleanup.cleanup.pose_weight,
          "--cleanup pinned: γ ≥ 0 of the attraction that holds the soft parts near the skinned pose (1 on "
          "rigid parts, 0 mid-joint; 0 = pins only)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  pose->add_flag(
      "--warm-start,!--no-warm-start", a->warm_start,
      "--cleanup pinned with --frames: start each frame's cleanup from the previous frame's correction "
      "(default), or clean every frame from its skinned pose alone");
  pose->add_option(
          "--bake", a->bake,
          "A .gltf/.glb output holds: frames (every frame as a morph target, default) or correctives (the "
          "rig itself with a few corrective morph targets and their weights, for engines that play "
          "skinning and morph targets)")
      ->check(CLI::IsMember({"frames", "correctives"}));
  pose->add_option(
          "--max-error", a->max_error,
          "--bake correctives: the largest error allowed against the posed frames, as a fraction of the "
          "bounding-box diagonal")
      ->capture_default_str();
  pose->add_flag("--json", a->json,
                 "Print the pieces, the cleanup's report and every frame's figures as JSON");
}

const spinmotor::cli::RegisterCommand register_rig{
    "rig", "glTF 2.0 skinned characters: print a rig's contents, pose its animation with a skinning blend",
    [](CLI::App& sub) {
      sub.require_subcommand(1);
      auto a = std::make_shared<RigArgs>();
      CLI::App* info =
          sub.add_subcommand("info", "Skinned meshes, joints, weights, morph targets, animations");
      info->add_option("file", a->file, "glTF file (.gltf or .glb)")->required();
      info->add_option("--mesh", a->meshes,
                       "Read only this skinned mesh (node or mesh name; repeat for several)");
      info->add_flag("--json", a->json, "Print as JSON");
      info->callback([a] { run_info(*a); });
      CLI::App* pose = sub.add_subcommand("pose", "Pose the rig's animation and write the skinned meshes");
      add_pose_options(pose, a);
      pose->callback([a] { run_pose(*a); });
      const std::string examples =
          "Examples:\n"
          "  spinmotor rig info ../shared/rigs/Fox.glb --json\n"
          "  spinmotor rig pose ../shared/rigs/RiggedFigure.gltf --frames 24 --blend dlb --out "
          "out/frame.obj\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --frames 0:48 --fps 24 --out out/walk.obj\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --time 1.2 --out posed.ply --rest-out "
          "rest.ply\n"
          "  spinmotor rig pose ../shared/rigs/CesiumMan.gltf --frames 24 --cleanup pinned --out "
          "out/clean.obj\n"
          "  spinmotor rig pose ../shared/rigs/Fox.glb --animation Survey --frames 60 --cleanup pinned --out "
          "fox.glb --bake correctives";
      sub.footer(examples);
      info->footer(examples);
      pose->footer(examples);
    }};

}  // namespace
