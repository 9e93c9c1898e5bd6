// Icosphere by repeated midpoint subdivision of the icosahedron (generators.hpp).
#include <Eigen/Geometry>
#include <array>

#include "revolve.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/topology.hpp"

namespace spinmotor {
namespace {

// Icosahedron with a vertex at each pole: 0 = north, 1..5 upper ring (z = 1/√5, longitudes 2πi/5),
// 6..10 lower ring (z = −1/√5, longitudes 2π(i + ½)/5), 11 = south. Faces oriented outwards.
void icosahedron(Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize(12, 3);
  const double z = 1.0 / std::sqrt(5.0), rho = 2.0 / std::sqrt(5.0);
  V.row(0) << 0, 0, 1;
  V.row(11) << 0, 0, -1;
  for (int i = 0; i < 5; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 5, b = 2.0 * std::numbers::pi * (i + 0.5) / 5;
    V.row(1 + i) << rho * std::cos(a), rho * std::sin(a), z;
    V.row(6 + i) << rho * std::cos(b), rho * std::sin(b), -z;
  }
  F.resize(20, 3);
  for (int i = 0; i < 5; ++i) {
    const int u0 = 1 + i, u1 = 1 + (i + 1) % 5, l0 = 6 + i, l1 = 6 + (i + 1) % 5;
    F.row(4 * i + 0) << 0, u0, u1;
    F.row(4 * i + 1) << u0, l0, u1;
    F.row(4 * i + 2) << u1, l0, l1;
    F.row(4 * i + 3) << 11, l1, l0;
  }
  for (int f = 0; f < 20; ++f) {  // orient outwards: normal · centroid > 0
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(F(f, 1), F(f, 2));
  }
}

// Spherical UVs of a unit sphere with a duplicated seam at longitude 0 and one UV per pole corner.
void spherical_uv(Mesh& m, int north, int south) {
  const Eigen::Index n = m.V.rows(), nf = m.F.rows();
  const double tol = 1e-12;
  std::vector<double> u(static_cast<size_t>(n)), v(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = m.V(i, 0), y = m.V(i, 1), z = m.V(i, 2);
    double a = (std::abs(y) <= tol && x > 0) ? 0.0 : std::atan2(y, x) / (2.0 * std::numbers::pi);
    if (a < 0) a += 1.0;
    u[i] = a;
    v[i] = 1.0 - std::acos(std::clamp(z / std::sqrt(x * x + y * y + z * z), -1.0, 1.0)) / std::numbers::pi;
  }
  std::vector<std::array<double, 2>> uv(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) uv[i] = {u[i], v[i]};
  std::vector<int> shifted(static_cast<size_t>(n), -1);  // UV row of vertex i at u + 1
  m.FUV = m.F;
  for (Eigen::Index f = 0; f < nf; ++f) {
    std::array<double, 3> fu;
    int pole = -1;
    double lo = 2, hi = -1;
    for (int c = 0; c < 3; ++c) {
      const int i = m.F(f, c);
      if (i == north || i == south) {
        pole = c;
        continue;
      }
      fu[c] = u[i];
      lo = std::min(lo, u[i]);
      hi = std::max(hi, u[i]);
    }
    if (hi - lo > 0.5)  // the face straddles the seam: move its small-u corners to u + 1
      for (int c = 0; c < 3; ++c) {
        const int i = m.F(f, c);
        if (c == pole || u[i] >= 0.5) continue;
        if (shifted[i] < 0) {
          shifted[i] = static_cast<int>(uv.size());
          uv.push_back({u[i] + 1.0, v[i]});
        }
        m.FUV(f, c) = shifted[i];
        fu[c] += 1.0;
      }
    if (pole >= 0) {  // the pole corner takes the mean u of the other two
      const double pu = 0.5 * (fu[(pole + 1) % 3] + fu[(pole + 2) % 3]);
      m.FUV(f, pole) = static_cast<int>(uv.size());
      uv.push_back({pu, v[m.F(f, pole)]});
    }
  }
  m.UV.resize(static_cast<Eigen::Index>(uv.size()), 2);
  for (size_t t = 0; t < uv.size(); ++t) m.UV.row(static_cast<Eigen::Index>(t)) << uv[t][0], uv[t][1];
}

}  // namespace

Mesh icosphere(int level, double radius) {
  const char* who = "icosphere";
  detail::require(level >= 0 && level <= 10, who,
                  "level must be in [0, 10] (got " + std::to_string(level) + ")");
  detail::require(radius > 0.0 && std::isfinite(radius), who, "radius must be positive and finite");
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  icosahedron(V, F);
  const EdgeTopology t0 = edge_topology(F);
  Eigen::MatrixXi E = t0.E, FE = t0.FE;  // FE(f, c): edge opposite corner c
  for (int l = 0; l < level; ++l) {
    const int n = static_cast<int>(V.rows()), k = static_cast<int>(E.rows()), m = static_cast<int>(F.rows());
    // Edge e gets midpoint n + e and splits into child edges 2e (touching E(e,0)) and 2e + 1; face f
    // adds interior edges 2k + 3f + c, c opposite midpoint corner c of the middle face.
    Eigen::MatrixXd V2(n + k, 3);
    V2.topRows(n) = V;
    for (int e = 0; e < k; ++e) V2.row(n + e) = (V.row(E(e, 0)) + V.row(E(e, 1))).normalized();
    Eigen::MatrixXi E2(2 * k + 3 * m, 2), F2(4 * m, 3), FE2(4 * m, 3);
    for (int e = 0; e < k; ++e) {
      E2.row(2 * e) << E(e, 0), n + e;
      E2.row(2 * e + 1) << n + e, E(e, 1);
    }
    auto child = [&](int e, int v) { return E(e, 0) == v ? 2 * e : 2 * e + 1; };
    for (int f = 0; f < m; ++f) {
      const int v0 = F(f, 0), v1 = F(f, 1), v2 = F(f, 2);
      const int e0 = FE(f, 0), e1 = FE(f, 1), e2 = FE(f, 2);
      const int m0 = n + e0, m1 = n + e1, m2 = n + e2;  // midpoint opposite v0, v1, v2
      const int i0 = 2 * k + 3 * f, i1 = i0 + 1, i2 = i0 + 2;
      E2.row(i0) << m1, m2;
      E2.row(i1) << m2, m0;
      E2.row(i2) << m0, m1;
      F2.row(4 * f + 0) << v0, m2, m1;
      FE2.row(4 * f + 0) << i0, child(e1, v0), child(e2, v0);
      F2.row(4 * f + 1) << v1, m0, m2;
      FE2.row(4 * f + 1) << i1, child(e2, v1), child(e0, v1);
      F2.row(4 * f + 2) << v2, m1, m0;
      FE2.row(4 * f + 2) << i2, child(e0, v2), child(e1, v2);
      F2.row(4 * f + 3) << m0, m1, m2;
      FE2.row(4 * f + 3) << i0, i1, i2;
    }
    V = std::move(V2);
    F = std::move(F2);
    E = std::move(E2);
    FE = std::move(FE2);
  }
  Mesh mesh;
  mesh.V = std::move(V);
  mesh.F = std::move(F);
  spherical_uv(mesh, 0, 11);
  mesh.V *= radius;
  return mesh;
}

}  // namespace spinmotor
