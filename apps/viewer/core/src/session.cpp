#include "spinmotor/viewer/session.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/deform/rig_pins.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/scene/rig_cleanup.hpp"

namespace spinmotor::viewer {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

/// Index of the skin bone called `name`, or −1.
int bone_index(const spinmotor::Rig* skin, const std::string& name) {
  if (!skin) return -1;
  for (std::size_t j = 0; j < skin->skeleton.size(); ++j)
    if (skin->skeleton[j].name == name) return int(j);
  return -1;
}

}  // namespace

nlohmann::json motor_to_json(const ga::Mot& m) {
  const Eigen::Isometry3d iso = ga::to_isometry(m);
  Eigen::Quaterniond q(iso.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  const Eigen::Vector3d t = iso.translation();
  return {{"quaternion", {q.w(), q.x(), q.y(), q.z()}}, {"translate", {t.x(), t.y(), t.z()}}};
}

Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() = default;

Session Session::open(const std::filesystem::path& path) {
  Session s;
  const std::string ext = lower(path.extension().string());
  if (ext == ".gltf" || ext == ".glb") {
    // A rig scene in memory, named after the file (saving it writes {"rig": {"gltf": ...}, ...}).
    const nlohmann::json doc = {{"rig", {{"gltf", path.filename().string()}}},
                                {"deformer", {{"type", "skin"}}}};
    const std::filesystem::path dir = std::filesystem::absolute(path).parent_path();
    *s.scene_ = scene::parse_scene(doc, dir, path.filename().string());
    s.scene_->file = std::filesystem::absolute(path);
    const auto t0 = std::chrono::steady_clock::now();
    s.deformer_ = scene::bind_deformer(*s.scene_);
    s.bind_ms_ = ms_since(t0);
    s.controls_ = s.deformer_->control_names();
    s.pose_ = s.scene_->frames.front();
    if (s.animation() >= 0) s.pose_.time = s.animation_range().first;
  } else if (ext == ".json") {
    *s.scene_ = scene::load_scene(path);
    const auto t0 = std::chrono::steady_clock::now();
    s.deformer_ = scene::bind_deformer(*s.scene_);
    s.bind_ms_ = ms_since(t0);
    s.controls_ = s.deformer_->control_names();
    if (!s.scene_->frames.empty()) s.pose_ = s.scene_->frames.front();
  } else {
    s.scene_->file = path;
    s.scene_->dir = path.parent_path();
    s.scene_->mesh = read_mesh(path);
    s.scene_->mesh_source = path.string();
    s.scene_->doc = {{"mesh", path.filename().string()}};
  }
  s.pose_.path = "/pose";
  s.history_ = UndoStack<scene::Pose>(s.pose_);
  s.V_ = s.scene_->mesh.V;
  return s;
}

void Session::rebind(nlohmann::json doc) {
  // Build everything first: on any error the session is unchanged.
  auto sc = std::make_unique<scene::Scene>(scene::parse_scene(doc, scene_->dir, scene_->name()));
  sc->file = scene_->file;
  const auto t0 = std::chrono::steady_clock::now();
  auto deformer = scene::bind_deformer(*sc);
  std::vector<std::string> controls = deformer->control_names();
  scene::Pose pose = pose_;
  std::erase_if(pose.motors, [&](const auto& kv) {
    return std::find(controls.begin(), controls.end(), kv.first) == controls.end();
  });
  deformer_.reset();  // before the scene it refers to
  scene_ = std::move(sc);
  deformer_ = std::move(deformer);
  bind_ms_ = ms_since(t0);
  controls_ = std::move(controls);
  pose_ = std::move(pose);
  history_ = UndoStack<scene::Pose>(pose_);
  V_ = scene_->mesh.V;
  dirty_ = true;
}

void Session::add_handle(const std::string& name, const std::vector<int>& vertices) {
  if (name.empty()) throw Error("viewer: a handle needs a name");
  if (scene_->handle_index(name) >= 0) throw Error("viewer: there is already a handle named '" + name + "'");
  if (vertices.empty()) throw Error("viewer: handle '" + name + "' selects no vertex");
  nlohmann::json doc = scene_document();
  if (!doc.contains("handles")) doc["handles"] = nlohmann::json::array();
  if (!doc.contains("deformer")) doc["deformer"] = {{"type", "surface-harmonic"}};
  doc["handles"].push_back({{"name", name}, {"select", {{"vertices", vertices}}}});
  rebind(std::move(doc));
}

void Session::remove_handle(const std::string& name) {
  const int h = scene_->handle_index(name);
  if (h < 0) throw Error("viewer: no handle named '" + name + "'");
  nlohmann::json doc = scene_document();
  doc["handles"].erase(doc["handles"].begin() + h);
  if (doc.contains("pose")) doc["pose"].erase(name);
  rebind(std::move(doc));
}

void Session::rename_handle(const std::string& name, const std::string& new_name) {
  const int h = scene_->handle_index(name);
  if (h < 0) throw Error("viewer: no handle named '" + name + "'");
  if (new_name.empty()) throw Error("viewer: a handle needs a name");
  if (new_name == name) return;
  if (scene_->handle_index(new_name) >= 0 ||
      std::find(controls_.begin(), controls_.end(), new_name) != controls_.end())
    throw Error("viewer: there is already a handle or control named '" + new_name + "'");
  nlohmann::json doc = scene_document();
  doc["handles"][h]["name"] = new_name;
  if (doc.contains("pose") && doc["pose"].contains(name)) {
    doc["pose"][new_name] = doc["pose"][name];
    doc["pose"].erase(name);
  }
  if (doc.contains("deformer"))
    for (const char* key : {"from", "to"})
      if (doc["deformer"].value(key, "") == name) doc["deformer"][key] = new_name;
  // The working pose names controls: carry the motor over so that rebind keeps it.
  scene::Pose renamed = pose_;
  if (const auto it = renamed.motors.find(name); it != renamed.motors.end()) {
    renamed.motors[new_name] = it->second;
    renamed.motors.erase(name);
  }
  std::swap(pose_, renamed);
  try {
    rebind(std::move(doc));
  } catch (...) {
    std::swap(pose_, renamed);
    throw;
  }
}

std::optional<Eigen::Vector3d> Session::control_anchor(const std::string& name) const {
  if (deformer_)
    if (auto a = deformer_->control_anchor(name)) return a;
  const int h = scene_->handle_index(name);
  if (h < 0) return std::nullopt;
  return handle_centroid(scene_->mesh.V, scene_->handles[h]);
}

std::optional<Eigen::Vector3d> Session::posed_anchor(const std::string& name) const {
  const auto a = control_anchor(name);
  if (!a) return std::nullopt;
  // A skin bone moves as pose() moves it (inherited motions, a rig's animation): K_j = F_j ~F_j^0.
  if (const int j = bone_index(deformer_ ? deformer_->skin() : nullptr, name); j >= 0) {
    std::vector<ga::Mot> m;
    deformer_->motors(pose_, m);
    return ga::to_isometry(ga::normalize(m[j] * ga::reverse(deformer_->skin()->skeleton[j].rest))) * *a;
  }
  return ga::to_isometry(pose_.motor(name)) * *a;
}

std::vector<std::string> Session::animation_names() const {
  std::vector<std::string> names;
  if (has_rig())
    for (const auto& a : scene_->rig->gltf->animations) names.push_back(a.name);
  return names;
}

std::pair<double, double> Session::animation_range() const {
  if (animation() < 0) return {0.0, 0.0};
  const GltfAnimation& a = scene_->rig->gltf->animations[animation()];
  return {a.start, a.end};
}

void Session::set_time(std::optional<double> t) {
  if (t && animation() < 0) throw Error("viewer: " + scene_->name() + " has no animation to play");
  if (t && !std::isfinite(*t)) throw Error("viewer: the animation time must be finite");
  if (pose_.time == t) return;
  pose_.time = t;
  dirty_ = true;
}

void Session::set_animation(int index) {
  if (!has_rig()) throw Error("viewer: " + scene_->name() + " is not a rig");
  nlohmann::json doc = scene_document();
  doc["rig"]["animation"] = index;
  rebind(std::move(doc));
}

std::vector<PosedBone> Session::posed_bones() {
  const spinmotor::Rig* skin = deformer_ ? deformer_->skin() : nullptr;
  if (!skin) return {};
  std::vector<ga::Mot> m;
  deformer_->motors(pose_, m);
  std::vector<PosedBone> out;
  for (std::size_t j = 0; j < skin->skeleton.size(); ++j) {
    const Bone& b = skin->skeleton[j];
    const Eigen::Isometry3d k = ga::to_isometry(ga::normalize(m[j] * ga::reverse(b.rest)));
    out.push_back({b.name, b.parent, k * b.head, k * b.tail});
  }
  return out;
}

std::vector<int> Session::cleanup_pins() {
  return scene_->handles.empty() ? std::vector<int>{} : handle_vertices();
}

std::shared_ptr<const spinmotor::Rig> Session::cleanup_skin() const {
  if (!scene_->handles.empty() || !deformer_) return nullptr;
  return deformer_->shared_skin();
}

ga::Mot Session::drag_start_motor(const std::string& name) const {
  const spinmotor::Rig* skin = deformer_ ? deformer_->skin() : nullptr;
  const int j = bone_index(skin, name);
  if (j < 0 || pose_.motors.count(name)) return pose_.motor(name);
  for (int p = skin->skeleton[j].parent; p >= 0; p = skin->skeleton[p].parent)
    if (pose_.motors.count(skin->skeleton[p].name)) return pose_.motor(skin->skeleton[p].name);
  return pose_.motor(name);
}

nlohmann::json Session::deformer_block() const { return deformer_ ? scene_->deformer : nlohmann::json(); }

nlohmann::json Session::ik_block() const {
  return scene_->doc.contains("ik") ? scene_->doc["ik"] : nlohmann::json();
}

void Session::set_deformer(const nlohmann::json& deformer, const nlohmann::json& ik) {
  nlohmann::json doc = scene_document();
  doc["deformer"] = deformer;
  if (ik.is_null())
    doc.erase("ik");
  else
    doc["ik"] = ik;
  rebind(std::move(doc));
}

std::vector<int> Session::handle_vertices(const std::string& name) const {
  const int h = scene_->handle_index(name);
  if (h < 0) return {};
  const Eigen::VectorXi& v = scene_->handles[h].vertices;
  return {v.data(), v.data() + v.size()};
}

void Session::set_motor(const std::string& name, const ga::Mot& m) {
  if (std::find(controls_.begin(), controls_.end(), name) == controls_.end())
    throw Error("viewer: no control named '" + name + "' in " + scene_->name());
  pose_.motors[name] = m;
  dirty_ = true;
}

void Session::commit_pose() { history_.push(pose_); }

// The time is playback state, not an edit: undo and redo keep it.
bool Session::undo() {
  if (!history_.undo()) return false;
  const std::optional<double> t = pose_.time;
  pose_ = history_.current();
  pose_.time = t;
  dirty_ = true;
  return true;
}

bool Session::redo() {
  if (!history_.redo()) return false;
  const std::optional<double> t = pose_.time;
  pose_ = history_.current();
  pose_.time = t;
  dirty_ = true;
  return true;
}

const Eigen::MatrixXd& Session::posed() {
  if (dirty_ && deformer_) {
    const auto t0 = std::chrono::steady_clock::now();
    deformer_->pose(pose_, V_);
    pose_ms_ = ms_since(t0);
  }
  dirty_ = false;
  return V_;
}

nlohmann::json Session::scene_document() const {
  nlohmann::json doc = scene_->doc;
  doc.erase("frames");
  nlohmann::json pose = nlohmann::json::object();
  for (const auto& [name, m] : pose_.motors) pose[name] = motor_to_json(m);
  if (!pose.empty() || doc.contains("pose")) doc["pose"] = pose;
  if (has_rig()) {  // the frame on screen
    for (const char* key : {"time", "frames", "fps"}) doc["rig"].erase(key);
    if (pose_.time) doc["rig"]["time"] = *pose_.time;
    if (animation() >= 0) doc["rig"]["animation"] = animation();
  }
  return doc;
}

void Session::save_scene(const std::filesystem::path& path) const {
  write_text_atomic(path, scene_document().dump(2) + "\n");
}

}  // namespace spinmotor::viewer
