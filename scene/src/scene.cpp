#include "spinmotor/scene/scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/gltf_animation.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/scene/json_schema.hpp"

namespace spinmotor::scene {

using nlohmann::json;

const json& scene_schema() {
  static const json s = json::parse(scene_schema_text());
  return s;
}

namespace {

const JsonSchema& validator() {
  static const JsonSchema v(scene_schema());
  return v;
}

Eigen::Vector3d vec3(const json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

template <class T>
T value_or(const json& obj, const char* key, T fallback) {
  const auto it = obj.find(key);
  return it == obj.end() ? fallback : it->get<T>();
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

// ---- Pose / Scene helpers ----------------------------------------------------------------------------

ga::Mot Pose::motor(const std::string& name) const {
  const auto it = motors.find(name);
  return it == motors.end() ? ga::Mot(1, 0, 0, 0, 0, 0, 0, 0) : it->second;
}

std::string Pose::entry_path(const std::string& name) const { return path + "/" + pointer_token(name); }

std::string Scene::name() const { return file.empty() ? std::string("scene") : file.filename().string(); }

Error Scene::error(const std::string& pointer, const std::string& message) const {
  return Error(name() + ": " + display_path(pointer) + ": " + message);
}

int Scene::handle_index(const std::string& n) const {
  for (std::size_t i = 0; i < handles.size(); ++i)
    if (handles[i].name == n) return static_cast<int>(i);
  return -1;
}

const Handle& Scene::handle(const std::string& n, const std::string& pointer) const {
  const int i = handle_index(n);
  if (i < 0) {
    std::vector<std::string> names;
    for (const auto& h : handles) names.push_back("'" + h.name + "'");
    throw error(pointer, "no handle named '" + n + "'" +
                             (names.empty() ? std::string(" (the scene has no handles)")
                                            : " (handles: " + join(names) + ")"));
  }
  return handles[i];
}

// ---- motors --------------------------------------------------------------------------------------------

ga::Mot parse_motor(const json& j, const std::string& pointer, const std::string& scene_name) {
  auto fail = [&](const std::string& sub, const std::string& msg) {
    return Error(scene_name + ": " + pointer + sub + ": " + msg);
  };
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  if (auto it = j.find("translate"); it != j.end()) t = vec3(*it);
  if (auto it = j.find("matrix"); it != j.end()) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = (*it)[4 * r + c].get<double>();
    if (!m.allFinite()) throw fail("/matrix", "not finite");
    if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
      throw fail("/matrix", "not a rigid motion: the last row must be 0 0 0 1");
    Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
    iso.linear() = m.topLeftCorner<3, 3>();
    iso.translation() = m.topRightCorner<3, 1>();
    try {
      return ga::from_isometry(iso);
    } catch (const Error& e) {
      throw fail("/matrix", std::string("not a rigid motion (") + e.what() + ")");
    }
  }
  if (auto it = j.find("quaternion"); it != j.end()) {
    Eigen::Vector4d q((*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>(),
                      (*it)[3].get<double>());
    const double n = q.norm();
    if (!(n > 0.0) || !std::isfinite(n))
      throw fail("/quaternion", "must be a non-zero finite quaternion [w, x, y, z]");
    q /= n;
    return ga::motor(ga::Rot(q[0], q[1], q[2], q[3]), ga::translator(t));
  }
  ga::Rot r(1, 0, 0, 0);
  Eigen::Vector3d about = Eigen::Vector3d::Zero();
  if (auto it = j.find("rotate"); it != j.end()) {
    const Eigen::Vector3d axis = vec3((*it)["axis"]);
    const double degrees = (*it)["degrees"].get<double>();
    if (!(axis.norm() > 0.0) || !axis.allFinite())
      throw fail("/rotate/axis", "must be a non-zero finite vector");
    if (!std::isfinite(degrees)) throw fail("/rotate/degrees", "not finite");
    r = ga::rotor(axis, degrees * M_PI / 180.0);
    if (auto a = it->find("about"); a != it->end()) about = vec3(*a);
  }
  if (!t.allFinite() || !about.allFinite()) throw fail("", "not finite");
  // Rotate about `about`, then translate: x ↦ R (x − a) + a + t.
  return ga::motor(r, ga::translator(about + t - ga::rotate(r, about)));
}

// ---- loading ---------------------------------------------------------------------------------------------

namespace {

Mesh make_mesh(const Scene& s, const json& m) {
  if (m.is_string()) {
    std::filesystem::path p = m.get<std::string>();
    if (p.is_relative()) p = s.dir / p;
    try {
      return read_mesh(p);
    } catch (const Error& e) {
      throw s.error("/mesh", e.what());
    }
  }
  const std::string g = m["generate"].get<std::string>();
  try {
    if (g == "icosphere") return icosphere(value_or(m, "level", 4), value_or(m, "radius", 1.0));
    if (g == "uv-sphere")
      return uv_sphere(value_or(m, "rings", 64), value_or(m, "sectors", 128), value_or(m, "radius", 1.0));
    if (g == "tube")
      return tube(value_or(m, "radius", 1.0), value_or(m, "length", 10.0), value_or(m, "rings", 200),
                  value_or(m, "sides", 64), value_or(m, "capped", false));
    if (g == "torus") {
      const double R = value_or(m, "R", 2.0), r = value_or(m, "r", 1.0);
      if (!(r < R)) throw s.error("/mesh/r", "the torus needs r < R");
      return torus(R, r, value_or(m, "u", 128), value_or(m, "v", 64));
    }
    if (g == "grid") {
      Eigen::Vector2d size(2, 2);
      Eigen::Vector2i n(100, 100);
      if (m.contains("size")) size << m["size"][0].get<double>(), m["size"][1].get<double>();
      if (m.contains("n")) n << m["n"][0].get<int>(), m["n"][1].get<int>();
      return grid(size, n);
    }
    if (g == "cross-bar")
      return cross_bar(value_or(m, "length", 4.0), value_or(m, "half_span", 0.5), value_or(m, "width", 0.25),
                       value_or(m, "segments", 64));
    if (g == "capsule")
      return capsule(value_or(m, "radius", 1.0), value_or(m, "length", 2.0), value_or(m, "rings", 64),
                     value_or(m, "sides", 64));
  } catch (const Error& e) {
    if (std::string(e.what()).rfind(s.name(), 0) == 0) throw;
    throw s.error("/mesh", e.what());
  }
  throw s.error("/mesh/generate", "unknown generator '" + g + "'");
}

// The `rig` block (docs/scene.md): read the glTF file, pick the animation, list the frame times.
RigSpec make_rig(const Scene& s, const json& r) {
  RigSpec rig;
  rig.file = r["gltf"].get<std::string>();
  if (rig.file.is_relative()) rig.file = s.dir / rig.file;
  try {
    rig.gltf = std::make_shared<const GltfRig>(read_gltf(rig.file));
    rig.skin = std::make_shared<const RigSkin>(rig_skin(*rig.gltf));
  } catch (const Error& e) {
    throw s.error("/rig/gltf", e.what());
  }
  const GltfRig& g = *rig.gltf;
  const int count = static_cast<int>(g.animations.size());
  if (auto a = r.find("animation"); a != r.end()) {
    if (count == 0) throw s.error("/rig/animation", rig.file.filename().string() + " has no animation");
    if (a->is_string()) {
      std::string names;
      for (int k = 0; k < count && rig.animation < 0; ++k)
        if (g.animations[k].name == a->get<std::string>()) rig.animation = k;
      for (const auto& an : g.animations) names += (names.empty() ? "'" : ", '") + an.name + "'";
      if (rig.animation < 0)
        throw s.error("/rig/animation",
                      "no animation named '" + a->get<std::string>() + "' (the file has " + names + ")");
    } else {
      rig.animation = a->get<int>();
      if (rig.animation >= count)
        throw s.error("/rig/animation", "animation " + std::to_string(rig.animation) +
                                            " out of range (the file has " + std::to_string(count) + ")");
    }
  } else if (count > 0) {
    rig.animation = 0;
  }
  const bool time = r.contains("time"), frames = r.contains("frames"), fps = r.contains("fps");
  if (time && frames) throw s.error("/rig/frames", "give `time` (one frame) or `frames`, not both");
  if ((time || frames) && rig.animation < 0)
    throw s.error(time ? "/rig/time" : "/rig/frames",
                  rig.file.filename().string() + " has no animation to pose");
  if (fps && !(frames && r["frames"].is_array()))
    throw s.error("/rig/fps", "`fps` goes with `frames`: [first, last] (frame numbers)");
  if (time) {
    const double t = r["time"].get<double>();
    if (!std::isfinite(t)) throw s.error("/rig/time", "not finite");
    rig.times.push_back(t);
  } else if (frames && r["frames"].is_array()) {
    const int first = r["frames"][0].get<int>(), last = r["frames"][1].get<int>();
    if (last < first) throw s.error("/rig/frames", "the last frame comes before the first");
    if (last - first >= 100000) throw s.error("/rig/frames", "more than 100000 frames");
    if (!fps) throw s.error("/rig/frames", "frames [first, last] need `fps` (frame k is at time k / fps)");
    const double rate = r["fps"].get<double>();
    for (int k = first; k <= last; ++k) rig.times.push_back(k / rate);
  } else if (frames) {
    const int n = r["frames"].get<int>();
    for (int f = 0; f < n; ++f) rig.times.push_back(gltf_frame_time(g.animations[rig.animation], f, n));
  }
  return rig;
}

Handle select_handle(const Scene& s, const json& h, const std::string& at) {
  const Eigen::MatrixXd& V = s.mesh.V;
  const Eigen::Index n = V.rows();
  const json& sel = h["select"];
  const std::string name = h["name"].get<std::string>();
  std::vector<int> v;
  if (auto it = sel.find("vertices"); it != sel.end()) {
    for (std::size_t k = 0; k < it->size(); ++k) {
      const long long i = (*it)[k].get<long long>();
      if (i >= n)
        throw s.error(at + "/select/vertices/" + std::to_string(k), "vertex " + std::to_string(i) +
                                                                        " is out of range (the mesh has " +
                                                                        std::to_string(n) + " vertices)");
      v.push_back(static_cast<int>(i));
    }
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  } else if (auto it = sel.find("box"); it != sel.end()) {
    const Eigen::Vector3d lo = vec3((*it)["min"]), hi = vec3((*it)["max"]);
    for (Eigen::Index i = 0; i < n; ++i)
      if ((V.row(i).transpose().array() >= lo.array()).all() &&
          (V.row(i).transpose().array() <= hi.array()).all())
        v.push_back(static_cast<int>(i));
  } else if (auto it = sel.find("sphere"); it != sel.end()) {
    const Eigen::Vector3d c = vec3((*it)["center"]);
    const double r = (*it)["radius"].get<double>();
    for (Eigen::Index i = 0; i < n; ++i)
      if ((V.row(i).transpose() - c).norm() <= r) v.push_back(static_cast<int>(i));
  } else if (auto it = sel.find("plane"); it != sel.end()) {
    const Eigen::Vector3d p = vec3((*it)["point"]), nn = vec3((*it)["normal"]);
    if (!(nn.norm() > 0.0)) throw s.error(at + "/select/plane/normal", "must be a non-zero vector");
    for (Eigen::Index i = 0; i < n; ++i)
      if ((V.row(i).transpose() - p).dot(nn) >= 0.0)
        v.push_back(static_cast<int>(i));  // the side n points to
  } else {                                 // all
    v.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = static_cast<int>(i);
  }
  if (v.empty()) throw s.error(at + "/select", "handle '" + name + "' selects no vertex");
  return Handle{name, Eigen::Map<Eigen::VectorXi>(v.data(), static_cast<Eigen::Index>(v.size()))};
}

Pose make_pose(const Scene& s, const json& p, const std::string& at) {
  Pose pose;
  pose.path = at;
  for (const auto& [name, m] : p.items()) pose.motors[name] = parse_motor(m, pose.entry_path(name), s.name());
  return pose;
}

// Validates `doc` against the scene schema; throws the first five errors (and how many more) under
// s.name().
void check_schema(const Scene& s, const json& doc) {
  const std::vector<SchemaError> errors = validator().validate(doc);
  if (!errors.empty()) {
    std::string msg = display_path(errors[0].path) + ": " + errors[0].message;
    for (std::size_t i = 1; i < std::min<std::size_t>(errors.size(), 5); ++i)
      msg += "\n  " + display_path(errors[i].path) + ": " + errors[i].message;
    if (errors.size() > 5) msg += "\n  (" + std::to_string(errors.size() - 5) + " more)";
    throw Error(s.name() + ": " + msg);
  }
}

// Sets s.mesh and s.mesh_source (and s.rig for a `rig` scene) from `mesh`, a mesh file or generator, or
// `rig`, the surface of a glTF character; throws unless exactly one is given and the mesh is finite and
// deformable.
void read_mesh_or_rig(Scene& s, const json& doc) {
  if (doc.contains("mesh") == doc.contains("rig"))
    throw s.error(doc.contains("rig") ? "/rig" : "/mesh",
                  doc.contains("rig")
                      ? "give `mesh` or `rig`, not both"
                      : "missing `mesh` (a mesh file or generator) or `rig` (a glTF character)");
  if (doc.contains("rig")) {
    s.rig = make_rig(s, doc["rig"]);
    s.mesh = s.rig->skin->rest;
    s.mesh_source = doc["rig"]["gltf"].get<std::string>();
  } else {
    s.mesh = make_mesh(s, doc["mesh"]);
    s.mesh_source =
        doc["mesh"].is_string() ? doc["mesh"].get<std::string>() : doc["mesh"]["generate"].get<std::string>();
  }
  try {
    require(s.mesh, {.finite = true}, "deform");
  } catch (const Error& e) {
    throw s.error("/mesh", e.what());
  }
}

// Appends the `handles` entries (selected on s.mesh) to s.handles; throws on an empty selection, a
// duplicate name or a vertex two handles share.
void read_handles(Scene& s, const json& doc) {
  if (auto it = doc.find("handles"); it != doc.end()) {
    std::vector<int> owner(static_cast<std::size_t>(s.mesh.V.rows()), -1);
    for (std::size_t h = 0; h < it->size(); ++h) {
      const std::string at = "/handles/" + std::to_string(h);
      Handle handle = select_handle(s, (*it)[h], at);
      if (s.handle_index(handle.name) >= 0)
        throw s.error(at + "/name", "duplicate handle name '" + handle.name + "'");
      for (Eigen::Index k = 0; k < handle.vertices.size(); ++k) {
        const int v = handle.vertices[k];
        if (owner[v] >= 0)
          throw s.error(at, "handle '" + handle.name + "' shares vertex " + std::to_string(v) +
                                " with handle '" + s.handles[owner[v]].name + "' (/handles/" +
                                std::to_string(owner[v]) + ")");
        owner[v] = static_cast<int>(h);
      }
      s.handles.push_back(std::move(handle));
    }
  }
}

// Sets s.frames, s.animated and s.first_frame from `pose` or `frames` (a `rig` scene: one frame per
// animation time, `pose` as edits on each); throws on both given, or on what a `rig` scene does not take.
void read_frames(Scene& s, const json& doc) {
  if (doc.contains("pose") && doc.contains("frames"))
    throw s.error("/frames", "give either `pose` or `frames`, not both");
  if (s.rig) {
    // One frame per animation time (or the rest pose); `pose` entries are edits on every frame.
    if (doc.contains("frames"))
      throw s.error("/frames", "a `rig` scene takes its frames from the animation (rig.time or rig.frames)");
    if (doc.contains("skeleton"))
      throw s.error("/skeleton", "a `rig` scene takes its skeleton from the glTF file");
    if (s.deformer["type"] != "skin")
      throw s.error("/deformer/type", "a `rig` scene is posed by the skin deformer (\"type\": \"skin\")");
    const Pose edits = doc.contains("pose") ? make_pose(s, doc["pose"], "/pose") : Pose{{}, "/pose", {}};
    s.animated = doc["rig"].contains("frames");
    if (s.animated && doc["rig"]["frames"].is_array()) s.first_frame = doc["rig"]["frames"][0].get<int>();
    if (s.rig->times.empty()) s.frames.push_back(edits);
    for (double t : s.rig->times) {
      s.frames.push_back(edits);
      s.frames.back().time = t;
    }
  } else if (auto it = doc.find("frames"); it != doc.end()) {
    s.animated = true;
    for (std::size_t f = 0; f < it->size(); ++f)
      s.frames.push_back(make_pose(s, (*it)[f], "/frames/" + std::to_string(f)));
  } else if (auto p = doc.find("pose"); p != doc.end()) {
    s.frames.push_back(make_pose(s, *p, "/pose"));
  } else {
    s.frames.push_back(Pose{{}, "/pose", {}});
  }
}

// The `ik` block `j`: chain, target, tolerance, iterations and the optional end orientation; throws on a
// zero-length bone or a zero orientation.
IkSpec make_ik(const Scene& s, const json& j) {
  IkSpec ik;
  const json& c = j["chain"];
  ik.chain.resize(static_cast<Eigen::Index>(c.size()), 3);
  for (std::size_t i = 0; i < c.size(); ++i)
    ik.chain.row(static_cast<Eigen::Index>(i)) = vec3(c[i]).transpose();
  for (Eigen::Index i = 0; i + 1 < ik.chain.rows(); ++i)
    if (!((ik.chain.row(i + 1) - ik.chain.row(i)).norm() > 0.0))
      throw s.error("/ik/chain/" + std::to_string(i + 1),
                    "joint coincides with the previous joint (zero-length bone)");
  ik.target = vec3(j["target"]);
  ik.tolerance = value_or(j, "tolerance", 1e-4);
  ik.iterations = value_or(j, "iterations", 50);
  if (auto o = j.find("orientation"); o != j.end()) {
    if (o->contains("quaternion")) {
      const json& q = (*o)["quaternion"];
      Eigen::Vector4d v(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
      if (!(v.norm() > 0.0)) throw s.error("/ik/orientation/quaternion", "must be non-zero");
      v.normalize();
      ik.orientation = ga::Rot(v[0], v[1], v[2], v[3]);
    } else {
      const Eigen::Vector3d axis = vec3((*o)["axis"]);
      if (!(axis.norm() > 0.0)) throw s.error("/ik/orientation/axis", "must be a non-zero vector");
      ik.orientation = ga::rotor(axis, (*o)["degrees"].get<double>() * M_PI / 180.0);
    }
  }
  return ik;
}

// Throws when the `snap` block `j` holds a key its mode (`mode`) does not take, or pin_threshold or
// pin_margin without "pins": "weights".
void check_snap_keys(const Scene& s, const json& j, SnapMode mode) {
  const bool pins = j.contains("pins"), shape = mode == SnapMode::Shape, pinned = mode == SnapMode::Pinned;
  if (!(mode == SnapMode::Free) && (j.contains("tradeoff") || j.contains("smooth_rho")))
    throw s.error("/snap",
                  "`tradeoff` and `smooth_rho` belong to mode \"free\"; mode \"shape\" takes `steps` and "
                  "`area_constraint`, mode \"pinned\" takes `pins`, `keep`, `iterations` and `pose_weight`");
  if (!shape && (j.contains("steps") || j.contains("area_constraint")))
    throw s.error("/snap", "`steps` and `area_constraint` belong to mode \"shape\"");
  if (!pinned && (pins || j.contains("keep") || j.contains("iterations") || j.contains("pose_weight")))
    throw s.error("/snap", "`pins`, `keep`, `iterations` and `pose_weight` belong to mode \"pinned\"");
  const bool weights = pins && j["pins"] == "weights";
  for (const char* key : {"pin_threshold", "pin_margin"})
    if (j.contains(key) && !weights)
      throw s.error(std::string("/snap/") + key, "belongs to \"pins\": \"weights\"");
}

// Reads the pinned mode's keys of the `snap` block `j` into `snap`: the pins (the skin's rigid parts with
// "pins": "weights", else handles: all of them or those named), keep, iterations and pose_weight. Throws
// on weight pins without the skin deformer, an unknown handle name, no handle to pin or an unknown keep.
void read_pinned_snap(const Scene& s, const json& j, SnapSpec& snap) {
  const bool pins = j.contains("pins");
  if (pins && j["pins"] == "weights") {
    // Pins: the rigid parts of the skin's weights (found when the skin deformer binds, run.cpp).
    if (s.deformer_type != "skin")
      throw s.error("/snap/pins",
                    "\"weights\" pins the rigid parts of a skin: the deformer must be \"skin\"");
    snap.pin_weights = true;
    snap.pin_threshold = value_or(j, "pin_threshold", snap.pin_threshold);
    snap.pin_margin = value_or(j, "pin_margin", snap.pin_margin);
  } else {
    // Pins: "handles" (every handle's vertices) or a list of handle names.
    const nlohmann::json p = pins ? j["pins"] : nlohmann::json("handles");
    if (p.is_string()) {
      for (std::size_t h = 0; h < s.handles.size(); ++h) snap.pin_handles.push_back(static_cast<int>(h));
    } else {
      for (std::size_t k = 0; k < p.size(); ++k)
        snap.pin_handles.push_back(
            s.handle_index(s.handle(p[k].get<std::string>(), "/snap/pins/" + std::to_string(k)).name));
    }
    if (snap.pin_handles.empty())
      throw s.error("/snap/pins", "mode \"pinned\" needs at least one handle to pin (this scene has none)");
  }
  if (j.contains("keep")) {
    try {
      snap.keep = parse_option<CleanupKeep>(j["keep"].get<std::string>());
    } catch (const Error& e) {
      throw s.error("/snap/keep", e.what());
    }
  }
  snap.iterations = value_or(j, "iterations", snap.iterations);
  if (j.contains("pose_weight")) snap.pose_weight = value_or(j, "pose_weight", 0.0);
}

// The `snap` block `j` (its presence asks for the snap unless "enabled": false): the mode (pinned when
// "pins" is given, else free, unless `mode` says), each mode's keys. Throws on an unknown mode and
// through check_snap_keys and read_pinned_snap.
SnapSpec make_snap(const Scene& s, const json& j) {
  SnapSpec snap;
  snap.enabled = value_or(j, "enabled", true);
  snap.tradeoff = value_or(j, "tradeoff", 1.0);
  snap.mode = j.contains("pins") ? SnapMode::Pinned : SnapMode::Free;
  if (j.contains("mode")) {
    try {
      snap.mode = parse_option<SnapMode>(j["mode"].get<std::string>());
    } catch (const Error& e) {
      throw s.error("/snap/mode", e.what());
    }
  }
  snap.smooth_rho = value_or(j, "smooth_rho", 0);
  snap.steps = value_or(j, "steps", 4);
  snap.area_constraint = value_or(j, "area_constraint", 0.0);
  check_snap_keys(s, j, snap.mode);
  if (snap.mode == SnapMode::Pinned) read_pinned_snap(s, j, snap);
  return snap;
}

// The `output` block `j`: mesh, metrics and colour paths; throws on a mesh path of no known format or a
// colour path that is not .ply.
OutputSpec make_output(const Scene& s, const json& j) {
  OutputSpec output;
  if (j.contains("mesh")) {
    output.mesh = j["mesh"].get<std::string>();
    try {
      mesh_format(*output.mesh);
    } catch (const Error& e) {
      throw s.error("/output/mesh", e.what());
    }
  }
  if (j.contains("metrics")) output.metrics = j["metrics"].get<std::string>();
  if (j.contains("colors")) {
    output.colors = j["colors"].get<std::string>();
    if (output.colors->extension() != ".ply")
      throw s.error("/output/colors", "the colour output is a .ply file");
  }
  return output;
}

}  // namespace

Scene parse_scene(const json& doc, const std::filesystem::path& dir, const std::string& name) {
  Scene s;
  s.dir = dir;
  s.file = name;  // name() prints its filename
  check_schema(s, doc);
  s.doc = doc;
  read_mesh_or_rig(s, doc);
  read_handles(s, doc);
  // Deformer block (its keys are read by the deformer type at bind).
  s.deformer = doc["deformer"];
  s.deformer_type = s.deformer["type"].get<std::string>();
  read_frames(s, doc);
  if (auto it = doc.find("ik"); it != doc.end()) s.ik = make_ik(s, *it);
  if (auto it = doc.find("snap"); it != doc.end()) s.snap = make_snap(s, *it);
  if (auto it = doc.find("output"); it != doc.end()) s.output = make_output(s, *it);
  return s;
}

Scene load_scene(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot read scene file " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  json doc;
  try {
    doc = json::parse(text.str());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number beyond double (1e400)
    throw Error(file.filename().string() + ": invalid JSON: " + e.what());
  }
  const std::filesystem::path abs = std::filesystem::absolute(file);
  Scene s = parse_scene(doc, abs.parent_path(), abs.filename().string());
  s.file = abs;
  return s;
}

}  // namespace spinmotor::scene
