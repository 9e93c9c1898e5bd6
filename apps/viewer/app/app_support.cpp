#include <sstream>

#include "app.hpp"
#include "spinmotor/render/gl_api.hpp"  // <GL/glcorearb.h> before GLFW (which then includes no GL header)
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cmath>

#include "spinmotor/core/error.hpp"

namespace spinmotor::viewer::app {

void* glfw_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

namespace {
std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> p;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) p.push_back(item);
  return p;
}
bool to_double(const std::string& s, double& out) {
  std::size_t used = 0;
  try {
    out = std::stod(s, &used);
  } catch (...) {
    return false;
  }
  return used == s.size() && std::isfinite(out);
}
}  // namespace

void apply_rig_args(const Args& a, Session& s) {
  if (a.animation.empty() && a.time.empty()) return;
  if (!s.has_rig())
    throw Error("--animation and --time need a glTF rig (a .gltf/.glb, or a scene with `rig`)");
  if (!a.animation.empty()) {
    const std::vector<std::string> names = s.animation_names();
    int index = -1;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == a.animation) index = int(k);
    double number = 0;
    if (index < 0 && to_double(a.animation, number) && number >= 0 && number == std::floor(number) &&
        number < double(names.size()))
      index = int(number);
    if (index < 0) throw Error("--animation: no animation '" + a.animation + "' in " + s.scene().name());
    if (index != s.animation()) s.set_animation(index);
  }
  if (a.time == "rest") {
    s.set_time(std::nullopt);
  } else if (!a.time.empty()) {
    double t = 0;
    if (!to_double(a.time, t)) throw Error("--time: expected seconds or 'rest', got '" + a.time + "'");
    s.set_time(t);
  }
}

GizmoSpec parse_gizmo(const std::string& s) {
  std::vector<std::string> p = split(s);
  // Control names may hold commas ("ffd[1,2,0]"): the last three fields are mode, axis, amount.
  while (p.size() > 4) p[0] += "," + p[1], p.erase(p.begin() + 1);
  const std::string usage = "--gizmo: expected NAME,translate|rotate,x|y|z,AMOUNT, got '" + s + "'";
  if (p.size() != 4 || (p[1] != "translate" && p[1] != "rotate") || p[2].size() != 1 || p[2][0] < 'x' ||
      p[2][0] > 'z')
    throw Error(usage);
  GizmoSpec g;
  g.control = p[0];
  g.mode = p[1] == "rotate" ? GizmoMode::Rotate : GizmoMode::Translate;
  g.axis = p[2][0] - 'x';
  if (!to_double(p[3], g.amount)) throw Error(usage);
  return g;
}

std::vector<double> parse_numbers(const std::string& text, const char* option, std::size_t count,
                                  bool at_least) {
  std::vector<double> out;
  for (const std::string& item : split(text)) {
    double v = 0;
    if (!to_double(item, v)) throw Error(std::string(option) + ": '" + item + "' is not a finite number");
    out.push_back(v);
  }
  const bool ok = at_least ? out.size() >= count && out.size() % 2 == 0 : out.size() == count;
  if (!ok)
    throw Error(std::string(option) + ": expected " + (at_least ? "at least " : "") + std::to_string(count) +
                (at_least ? " numbers (pairs)" : " numbers") + ", got " + std::to_string(out.size()));
  return out;
}

ga::Mot simulate_drag(const Session& s, const render::OrbitCamera& cam, int w, int h, const GizmoSpec& g) {
  const auto centre = s.posed_anchor(g.control);
  if (!centre) throw Error("--gizmo: '" + g.control + "' is not a control of " + s.scene().name());
  const auto m = simulated_drag(cam, w, h, g.mode, g.axis, *centre, 0.25 * cam.scene_radius,
                                s.motor(g.control), g.amount);
  if (!m)
    throw Error("--gizmo: the camera looks along the " + std::string(1, char('x' + g.axis)) +
                " axis; pick another");
  return *m;
}

render::ColorMode parse_color(const std::string& c) {
  return c == "q"         ? render::ColorMode::Q
         : c == "checker" ? render::ColorMode::Checker
         : c == "normals" ? render::ColorMode::Normals
         : c == "rho"     ? render::ColorMode::Signed
                          : render::ColorMode::Plain;
}

}  // namespace spinmotor::viewer::app
