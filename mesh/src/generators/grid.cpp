// Planar grid and torus (generators.hpp).
#include "revolve.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

using detail::require;

Mesh grid(const Eigen::Vector2d& size, const Eigen::Vector2i& n) {
  const char* who = "grid";
  require(size.allFinite() && size.x() > 0.0 && size.y() > 0.0, who, "size must be positive and finite");
  require(
      n.x() >= 2 && n.y() >= 2, who,
      "n must be >= 2 vertices per axis (got " + std::to_string(n.x()) + " x " + std::to_string(n.y()) + ")");
  const int nx = n.x(), ny = n.y();
  detail::check_face_count(who, 2 * std::int64_t{nx} * ny);
  Mesh m;
  m.V.resize(nx * ny, 3);
  m.UV.resize(nx * ny, 2);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double u = static_cast<double>(i) / (nx - 1), v = static_cast<double>(j) / (ny - 1);
      m.V.row(i + j * nx) << (u - 0.5) * size.x(), (v - 0.5) * size.y(), 0.0;
      m.UV.row(i + j * nx) << u, v;
    }
  m.F.resize(2 * (nx - 1) * (ny - 1), 3);
  int f = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = i + j * nx, b = a + 1, c = b + nx, d = a + nx;
      m.F.row(f++) << a, b, c;
      m.F.row(f++) << a, c, d;
    }
  m.FUV = m.F;
  return m;
}

Mesh torus(double R, double r, int u, int v) {
  const char* who = "torus";
  require(std::isfinite(R) && std::isfinite(r) && r > 0.0 && R > r, who,
          "radii must satisfy 0 < r < R (got R = " + std::to_string(R) + ", r = " + std::to_string(r) + ")");
  require(u >= 3 && v >= 3, who,
          "u and v must be >= 3 (got " + std::to_string(u) + ", " + std::to_string(v) + ")");
  detail::check_face_count(who, 2 * std::int64_t{u} * v);
  Mesh m;
  m.V.resize(u * v, 3);
  std::vector<double> cp(u), sp(u), cq(v), sq(v);
  for (int i = 0; i < u; ++i) {
    cp[i] = std::cos(2.0 * std::numbers::pi * i / u);
    sp[i] = std::sin(2.0 * std::numbers::pi * i / u);
  }
  for (int j = 0; j < v; ++j) {
    cq[j] = std::cos(2.0 * std::numbers::pi * j / v);
    sq[j] = std::sin(2.0 * std::numbers::pi * j / v);
  }
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      const double rho = R + r * cq[j];
      m.V.row(i * v + j) << rho * cp[i], rho * sp[i], r * sq[j];
    }
  m.UV.resize((u + 1) * (v + 1), 2);
  for (int i = 0; i <= u; ++i)
    for (int j = 0; j <= v; ++j)
      m.UV.row(i * (v + 1) + j) << static_cast<double>(i) / u, static_cast<double>(j) / v;
  m.F.resize(2 * u * v, 3);
  m.FUV.resize(2 * u * v, 3);
  int f = 0;
  auto vid = [u, v](int i, int j) { return (i % u) * v + (j % v); };
  auto tid = [v](int i, int j) { return i * (v + 1) + j; };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      // ∂φ × ∂ψ points outwards, so (i, j) (i+1, j) (i+1, j+1) (i, j+1) is CCW from outside.
      m.F.row(f) << vid(i, j), vid(i + 1, j), vid(i + 1, j + 1);
      m.FUV.row(f++) << tid(i, j), tid(i + 1, j), tid(i + 1, j + 1);
      m.F.row(f) << vid(i, j), vid(i + 1, j + 1), vid(i, j + 1);
      m.FUV.row(f++) << tid(i, j), tid(i + 1, j + 1), tid(i, j + 1);
    }
  return m;
}

}  // namespace spinmotor
