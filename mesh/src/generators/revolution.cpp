// Surfaces of revolution: uv_sphere, tube (open or capped) and capsule (generators.hpp).
#include "revolve.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

using detail::ProfilePoint;
using detail::require;

Mesh uv_sphere(int rings, int sectors, double radius) {
  const char* who = "uv_sphere";
  require(rings >= 1, who, "rings must be >= 1 (got " + std::to_string(rings) + ")");
  require(sectors >= 3, who, "sectors must be >= 3 (got " + std::to_string(sectors) + ")");
  require(radius > 0.0 && std::isfinite(radius), who, "radius must be positive and finite");
  detail::check_face_count(who, 2 * std::int64_t{rings} * sectors);
  std::vector<ProfilePoint> p(static_cast<size_t>(rings));
  for (int k = 0; k < rings; ++k) {
    const double theta = std::numbers::pi * (rings - k) / (rings + 1);  // polar angle from +z
    p[k] = {radius * std::sin(theta), radius * std::cos(theta), static_cast<double>(k + 1) / (rings + 1)};
  }
  const ProfilePoint south{0.0, -radius, 0.0}, north{0.0, radius, 1.0};
  return detail::revolve(p, sectors, &south, &north);
}

Mesh tube(double radius, double length, int rings, int sides, bool capped) {
  const char* who = "tube";
  require(radius > 0.0 && std::isfinite(radius), who, "radius must be positive and finite");
  require(length > 0.0 && std::isfinite(length), who, "length must be positive and finite");
  require(rings >= 2, who, "rings must be >= 2 (got " + std::to_string(rings) + ")");
  require(sides >= 3, who, "sides must be >= 3 (got " + std::to_string(sides) + ")");
  detail::check_face_count(who, 2 * std::int64_t{rings} * sides);
  // v is the arc length along the profile (centre → rim → side → rim → centre when capped).
  const double total = capped ? 2.0 * radius + length : length;
  const double v0 = capped ? radius : 0.0;
  std::vector<ProfilePoint> p(static_cast<size_t>(rings));
  for (int k = 0; k < rings; ++k) {
    const double z = length * k / (rings - 1);
    p[k] = {radius, z, (v0 + z) / total};
  }
  if (!capped) return detail::revolve(p, sides, nullptr, nullptr);
  const ProfilePoint bottom{0.0, 0.0, 0.0}, top{0.0, length, 1.0};
  return detail::revolve(p, sides, &bottom, &top);
}

Mesh capsule(double radius, double length, int rings, int sides) {
  const char* who = "capsule";
  require(radius > 0.0 && std::isfinite(radius), who, "radius must be positive and finite");
  require(length >= 0.0 && std::isfinite(length), who, "length must be >= 0 and finite");
  require(rings >= 1, who, "rings must be >= 1 (got " + std::to_string(rings) + ")");
  require(sides >= 3, who, "sides must be >= 3 (got " + std::to_string(sides) + ")");
  detail::check_face_count(who, 2 * std::int64_t{rings} * sides);
  const double quarter = 0.5 * std::numbers::pi * radius;  // arc length of a quarter meridian
  const double total = 2.0 * quarter + length;
  std::vector<ProfilePoint> p(static_cast<size_t>(rings));
  for (int k = 0; k < rings; ++k) {
    const double s = total * (k + 1) / (rings + 1);  // arc length from the south pole
    const double v = static_cast<double>(k + 1) / (rings + 1);
    if (s < quarter) {  // southern hemisphere, centred at z = 0
      const double a = s / radius;
      p[k] = {radius * std::sin(a), -radius * std::cos(a), v};
    } else if (s <= quarter + length) {  // cylinder
      p[k] = {radius, s - quarter, v};
    } else {  // northern hemisphere, centred at z = length
      const double a = (s - quarter - length) / radius;
      p[k] = {radius * std::cos(a), length + radius * std::sin(a), v};
    }
  }
  const ProfilePoint south{0.0, -radius, 0.0}, north{0.0, length + radius, 1.0};
  return detail::revolve(p, sides, &south, &north);
}

}  // namespace spinmotor
