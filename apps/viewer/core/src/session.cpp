#include "spinmotor/viewer/session.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/core/stopwatch.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor::viewer {
namespace {}  // namespace

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
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".json") {
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
  return ga::to_isometry(pose_.motor(name)) * *a;
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

bool Session::undo() {
  if (!history_.undo()) return false;
  pose_ = history_.current();
  dirty_ = true;
  return true;
}

bool Session::redo() {
  if (!history_.redo()) return false;
  pose_ = history_.current();
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
  return doc;
}

void Session::save_scene(const std::filesystem::path& path) const {
  write_text_atomic(path, scene_document().dump(2) + "\n");
}

}  // namespace spinmotor::viewer
