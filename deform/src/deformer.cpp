#include "spinmotor/deform/deformer.hpp"

#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"

namespace spinmotor {

void check_handles(std::span<const Handle> handles, Eigen::Index n, const char* who) {
  std::vector<int> owner(static_cast<std::size_t>(n), -1);
  for (std::size_t h = 0; h < handles.size(); ++h) {
    const Handle& handle = handles[h];
    if (handle.vertices.size() == 0)
      throw Error(std::string(who) + ": handle '" + handle.name + "' (handle " + std::to_string(h) +
                  ") has no vertex");
    for (Eigen::Index k = 0; k < handle.vertices.size(); ++k) {
      const int v = handle.vertices[k];
      if (v < 0 || v >= n) {
        std::ostringstream s;
        s << who << ": handle '" << handle.name << "' names vertex " << v << " (entry " << k
          << "), out of range [0, " << n << ")";
        throw Error(s.str());
      }
      const int o = owner[v];
      if (o == static_cast<int>(h)) {
        std::ostringstream s;
        s << who << ": handle '" << handle.name << "' lists vertex " << v << " twice";
        throw Error(s.str());
      }
      if (o >= 0) {
        std::ostringstream s;
        s << who << ": handles '" << handles[o].name << "' and '" << handle.name << "' share vertex " << v;
        throw Error(s.str());
      }
      owner[v] = static_cast<int>(h);
    }
  }
}

}  // namespace spinmotor

namespace spinmotor {

std::vector<Control> handle_controls(const Eigen::MatrixXd& V, std::span<const Handle> handles) {
  std::vector<Control> c;
  c.reserve(handles.size());
  for (const Handle& h : handles) c.push_back({h.name, handle_centroid(V, h)});
  return c;
}

void check_motors(std::span<const ga::Mot> motors, std::span<const Control> controls, const char* who) {
  if (motors.size() != controls.size())
    throw Error(std::string(who) + ": expected " + std::to_string(controls.size()) +
                " motors (one per control), got " + std::to_string(motors.size()));
  for (std::size_t j = 0; j < motors.size(); ++j)
    (void)checked_unit_motor(motors[j], std::string(who) + ": motor " + std::to_string(j) + " (control '" +
                                            controls[j].name + "')");
}

}  // namespace spinmotor
