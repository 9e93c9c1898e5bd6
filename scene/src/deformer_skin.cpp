// Scene deformer "skin": SkinDeformer on the scene's top-level `skeleton`, one pose entry per bone name.
//   {"type": "skin", "weights": "harmonic" | "<file>", "blend": "lbs" | "dlb" | "log" | "pivot-log",
//    "joint_fraction": f}
// Defaults: harmonic weights (bone_harmonic_weights with joint_fraction, default 0.25), the blend of
// SkinDeformer::Options (dlb). A pose entry
// is the world-space motion of its bone; a bone without an entry keeps its parent's (docs/scene.md).
// Weight files (relative to the scene file): "*.json" is docs/scene.md's {"bones": [names], "weights": [[w
// per bone] per vertex]} (errors name the file and the JSON pointer); any other extension is the text format
// of read_skin_weights (errors name file:line).
#include <fstream>
#include <map>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/delta_mush.hpp"
#include "spinmotor/deform/direct_delta_mush.hpp"
#include "spinmotor/deform/gltf_skin.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga/rotor_fit.hpp"
#include "spinmotor/scene/deformer_registry.hpp"

namespace spinmotor::scene {

namespace {

Eigen::MatrixXd read_json_weights(const Scene& s, const std::filesystem::path& path,
                                  const std::vector<Bone>& bones) {
  const std::string who = path.string();
  std::ifstream in(path);
  if (!in) throw s.error("/deformer/weights", who + ": cannot open the weight file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e400
    throw s.error("/deformer/weights", who + ": " + e.what());
  }
  auto fail = [&](const std::string& ptr, const std::string& msg) {
    throw s.error("/deformer/weights", who + ": " + ptr + ": " + msg);
  };
  if (!j.is_object() || !j.contains("bones") || !j.contains("weights") || !j["bones"].is_array() ||
      !j["weights"].is_array())
    fail("", "expected {\"bones\": [names], \"weights\": [[w per bone] per vertex]}");
  std::map<std::string, int> index;
  for (std::size_t b = 0; b < bones.size(); ++b) index[bones[b].name] = static_cast<int>(b);
  std::vector<int> column;
  std::vector<bool> seen(bones.size(), false);
  for (std::size_t c = 0; c < j["bones"].size(); ++c) {
    const auto& n = j["bones"][c];
    const std::string ptr = "/bones/" + std::to_string(c);
    if (!n.is_string() || !index.count(n.get<std::string>())) fail(ptr, "not a bone of the skeleton");
    const int b = index[n.get<std::string>()];
    if (seen[b]) fail(ptr, "bone named twice");
    seen[b] = true;
    column.push_back(b);
  }
  for (std::size_t b = 0; b < bones.size(); ++b)
    if (!seen[b]) fail("/bones", "does not name bone '" + bones[b].name + "'");
  const Eigen::Index n = s.mesh.V.rows();
  if (static_cast<Eigen::Index>(j["weights"].size()) != n)
    fail("/weights",
         std::to_string(j["weights"].size()) + " rows for a mesh of " + std::to_string(n) + " vertices");
  Eigen::MatrixXd W(n, bones.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& row = j["weights"][i];
    const std::string ptr = "/weights/" + std::to_string(i);
    if (!row.is_array() || row.size() != column.size())
      fail(ptr, "expected " + std::to_string(column.size()) + " numbers");
    for (std::size_t c = 0; c < column.size(); ++c) {
      if (!row[c].is_number() || row[c].get<double>() < 0.0)
        fail(ptr + "/" + std::to_string(c), "expected a number ≥ 0");
      W(i, column[c]) = row[c].get<double>();
    }
    if (!(W.row(i).sum() > 0.0)) fail(ptr, "vertex " + std::to_string(i) + " has no positive weight");
  }
  return W;
}

/// Figures of a rig scene for the metrics: the file, its counts and the animation.
nlohmann::json rig_report(const Scene& s) {
  if (!s.rig) return nlohmann::json::object();
  const GltfRig& g = *s.rig->gltf;
  nlohmann::json r = {{"file", s.rig->file.string()},
                      {"joints", g.num_joints()},
                      {"file_vertices", g.file_vertices},
                      {"renormalised_rows", g.renormalised_rows}};
  if (s.rig->animation >= 0) {
    const GltfAnimation& a = g.animations[s.rig->animation];
    r["animation"] = {{"name", a.name}, {"index", s.rig->animation}, {"start", a.start}, {"end", a.end}};
  }
  return {{"rig", r}};
}

/// The motor of a rig's pose transform. Scene files pose bones with motors: a joint transform that scales
/// (by more than exporters' float noise) is an error naming the joint and the time.
ga::Mot rigid_joint_motor(const SkinDeformer::Affine& T, const std::string& bone, double t) {
  const Eigen::Matrix3d L = T.leftCols<3>();
  if (!T.allFinite() || (L.transpose() * L - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      !(L.determinant() > 0)) {
    std::ostringstream s;
    s << "joint '" << bone << "' scales or shears at t = " << t
      << ": a scene's skin poses bones with rigid motions (`spinmotor rig pose` skins such rigs)";
    throw Error(s.str());
  }
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = ga::closest_rotation(L);  // the float noise of a rigid L projected onto SO(3)
  M.translation() = T.col(3);
  return ga::normalize(ga::from_isometry(M));
}

/// The skeleton of a scene file's `skeleton` block.
std::vector<Bone> scene_bones(const Scene& s) {
  if (!s.doc.contains("skeleton")) throw s.error("/skeleton", "the skin deformer needs a skeleton");
  const nlohmann::json& jb = s.doc["skeleton"]["bones"];
  std::vector<Bone> bones;
  std::map<std::string, int> index;
  for (std::size_t j = 0; j < jb.size(); ++j) {
    Bone b;
    b.name = jb[j]["name"].get<std::string>();
    const auto h = jb[j]["head"].get<std::vector<double>>(), t = jb[j]["tail"].get<std::vector<double>>();
    b.head = {h[0], h[1], h[2]};
    b.tail = {t[0], t[1], t[2]};
    if (!index.emplace(b.name, static_cast<int>(j)).second)
      throw s.error("/skeleton/bones/" + std::to_string(j) + "/name", "bone '" + b.name + "' is named twice");
    bones.push_back(b);
  }
  for (std::size_t j = 0; j < jb.size(); ++j)
    if (jb[j].contains("parent") && !jb[j]["parent"].is_null()) {
      const std::string p = jb[j]["parent"].get<std::string>();
      if (!index.count(p))
        throw s.error("/skeleton/bones/" + std::to_string(j) + "/parent", "no bone named '" + p + "'");
      bones[j].parent = index[p];
    }
  try {
    check_skeleton(bones);
  } catch (const Error& e) {
    throw s.error("/skeleton", e.what());
  }
  return bones;
}

}  // namespace

std::unique_ptr<SceneDeformer> bind_skin(const Scene& s) {
  // The skeleton and (by default) the weights: a glTF rig's joints and skin, or the scene's skeleton.
  std::vector<Bone> bones;
  Eigen::MatrixXd rig_weights;
  if (s.rig) {
    bones = s.rig->skin->rig.skeleton;
    rig_weights = Eigen::MatrixXd(s.rig->skin->rig.weights);
  } else {
    bones = scene_bones(s);
  }
  const nlohmann::json& b = s.deformer;
  SkinDeformer::Options o;
  o.blend = deformer_option(s, "blend", o.blend);
  const std::string weights = b.value("weights", s.rig ? "" : "harmonic");
  Eigen::MatrixXd W;
  try {
    if (weights.empty()) {
      W = std::move(rig_weights);  // the glTF file's skin
    } else if (weights == "harmonic") {
      W = bone_harmonic_weights(s.mesh, bones, b.value("joint_fraction", 0.25));
    } else {
      const std::filesystem::path path = s.dir / weights;
      W = path.extension() == ".json" ? read_json_weights(s, path, bones)
                                      : read_skin_weights(path, bones, s.mesh.V.rows());
    }
    // A pose entry is the world motion of its bone; a bone without one keeps its parent's. A rig's
    // frame is the animation at pose.time (the pose transforms T_j(t), gltf_skin.hpp) with those motions
    // applied on top: bone j moves by E_j T_j(t).
    std::shared_ptr<const GltfRig> gltf = s.rig ? s.rig->gltf : nullptr;
    std::shared_ptr<const RigSkin> skin = s.rig ? s.rig->skin : nullptr;
    const int anim = s.rig ? s.rig->animation : -1;
    auto motors = [bones, gltf, skin, anim](const Pose& pose, std::vector<ga::Mot>& out) {
      std::vector<ga::Mot> given(bones.size(), ga::Mot(1, 0, 0, 0, 0, 0, 0, 0));
      std::vector<bool> has(bones.size(), false);
      for (std::size_t j = 0; j < bones.size(); ++j)
        if (const auto it = pose.motors.find(bones[j].name); it != pose.motors.end())
          given[j] = it->second, has[j] = true;
      out = inherit_bone_motions(bones, given, has);
      if (gltf && pose.time) {
        const std::vector<SkinDeformer::Affine> T = rig_joint_transforms(*gltf, *skin, anim, *pose.time);
        for (std::size_t j = 0; j < bones.size(); ++j)
          out[j] = ga::normalize(out[j] * rigid_joint_motor(T[j], bones[j].name, *pose.time));
      }
    };
    // The deformers bind through the deformer shape (deformer.hpp), the scene keeps the same rig.
    auto rig = std::make_shared<Rig>();
    rig->skeleton = bones;
    rig->weights = W.sparseView();
    auto report = [n = bones.size()](const AnyDeformer&, std::span<const ga::Mot>, const Eigen::MatrixXd&) {
      return nlohmann::json{{"max_handle_error", nullptr}, {"skin", {{"bones", n}}}};
    };
    // "mush": the skin cleaned up by Delta Mush or Direct Delta Mush (the baselines of the pose-keeping
    // cleanup), with "mush_iterations" smoothing iterations (default: the deformer's Options).
    const MushKind mush = deformer_option(s, "mush", MushKind::None);
    if (mush == MushKind::None && b.contains("mush_iterations"))
      throw s.error("/deformer/mush_iterations",
                    "belongs to a skin with \"mush\": \"delta-mush\" or \"direct-delta-mush\"");
    if (mush == MushKind::Delta) {
      DeltaMushDeformer::Options mo;
      mo.blend = o.blend;
      mo.iterations = b.value("mush_iterations", mo.iterations);
      auto d = std::make_unique<SceneDeformer>(s, DeltaMushDeformer::bind(s.mesh, *rig, mo), report,
                                               rig_report(s), motors);
      d->set_skin(std::move(rig));
      return d;
    }
    if (mush == MushKind::Direct) {
      if (b.contains("blend"))
        throw s.error("/deformer/blend", "Direct Delta Mush blends the bone matrices itself: remove `blend`");
      DirectDeltaMushDeformer::Options mo;
      mo.iterations = b.value("mush_iterations", mo.iterations);
      auto d = std::make_unique<SceneDeformer>(s, DirectDeltaMushDeformer::bind(s.mesh, *rig, mo), report,
                                               rig_report(s), motors);
      d->set_skin(std::move(rig));
      return d;
    }
    auto d = std::make_unique<SceneDeformer>(s, SkinDeformer::bind(s.mesh, *rig, o), report, rig_report(s),
                                             motors);
    d->set_skin(std::move(rig));
    return d;
  } catch (const Error& e) {
    const std::string msg = e.what();
    if (msg.rfind(s.name() + ":", 0) == 0) throw;
    throw Error(s.name() + ": /deformer/weights: " + msg, e.kind());
  }
}

}  // namespace spinmotor::scene
