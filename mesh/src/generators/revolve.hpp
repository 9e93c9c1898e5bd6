#pragma once
// Internal to the generators: surfaces of revolution around the z axis (uv_sphere, tube, capsule)
// and parameter checks. Not installed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor::detail {

/// Throws if a generator would produce more faces than an int can index.
inline void check_face_count(const char* who, std::int64_t faces) {
  if (faces > std::numeric_limits<int>::max() / 3)
    throw Error(std::string(who) + ": the requested mesh is too large (" + std::to_string(faces) + " faces)");
}

inline void require(bool ok, const char* who, const std::string& what) {
  if (!ok) throw Error(std::string(who) + ": " + what);
}

/// One sample of a profile curve in the (ρ, z) half-plane, with its texture coordinate v.
struct ProfilePoint {
  double rho, z, v;
};

/// Revolves a profile (rings ordered from bottom to top, ρ > 0) around the z axis with `sides`
/// vertices per ring; optional pole vertices (ρ = 0) close the bottom and the top with fans.
/// Vertex k·sides + j is ring k at angle 2π j / sides; the bottom pole follows the rings, then the
/// top pole. Faces are CCW seen from outside when the profile runs upwards on the outside (∂φ × ∂s
/// points away from the axis). UV: (j / sides, v) with a duplicated seam column j = sides, and one
/// UV per pole fan face at u = (j + ½) / sides.
inline Mesh revolve(const std::vector<ProfilePoint>& rings, int sides, const ProfilePoint* bottom,
                    const ProfilePoint* top) {
  const int K = static_cast<int>(rings.size());
  const int S = sides;
  const int nv = K * S + (bottom ? 1 : 0) + (top ? 1 : 0);
  const int nf = 2 * (K - 1) * S + (bottom ? S : 0) + (top ? S : 0);
  const int nuv = K * (S + 1) + (bottom ? S : 0) + (top ? S : 0);
  Mesh m;
  m.V.resize(nv, 3);
  m.F.resize(nf, 3);
  m.UV.resize(nuv, 2);
  m.FUV.resize(nf, 3);

  std::vector<double> c(S), s(S);
  for (int j = 0; j < S; ++j) {
    const double phi = 2.0 * std::numbers::pi * j / S;
    c[j] = std::cos(phi);
    s[j] = std::sin(phi);
  }
  for (int k = 0; k < K; ++k) {
    for (int j = 0; j < S; ++j) m.V.row(k * S + j) << rings[k].rho * c[j], rings[k].rho * s[j], rings[k].z;
    for (int j = 0; j <= S; ++j) m.UV.row(k * (S + 1) + j) << static_cast<double>(j) / S, rings[k].v;
  }
  int f = 0;
  auto vid = [S](int k, int j) { return k * S + (j == S ? 0 : j); };
  auto tid = [S](int k, int j) { return k * (S + 1) + j; };
  auto add = [&](int a, int b, int cc, int ta, int tb, int tc) {
    m.F.row(f) << a, b, cc;
    m.FUV.row(f) << ta, tb, tc;
    ++f;
  };
  for (int k = 0; k + 1 < K; ++k)
    for (int j = 0; j < S; ++j) {
      // quad (k, j) (k, j+1) (k+1, j+1) (k+1, j): CCW in (u, v) and seen from outside
      add(vid(k, j), vid(k, j + 1), vid(k + 1, j + 1), tid(k, j), tid(k, j + 1), tid(k + 1, j + 1));
      add(vid(k, j), vid(k + 1, j + 1), vid(k + 1, j), tid(k, j), tid(k + 1, j + 1), tid(k + 1, j));
    }
  int v_next = K * S, t_next = K * (S + 1);
  if (bottom) {
    const int p = v_next++;
    m.V.row(p) << 0.0, 0.0, bottom->z;
    for (int j = 0; j < S; ++j) {
      m.UV.row(t_next) << (j + 0.5) / S, bottom->v;
      add(p, vid(0, j + 1), vid(0, j), t_next, tid(0, j + 1), tid(0, j));
      ++t_next;
    }
  }
  if (top) {
    const int p = v_next++;
    m.V.row(p) << 0.0, 0.0, top->z;
    for (int j = 0; j < S; ++j) {
      m.UV.row(t_next) << (j + 0.5) / S, top->v;
      add(p, vid(K - 1, j), vid(K - 1, j + 1), t_next, tid(K - 1, j), tid(K - 1, j + 1));
      ++t_next;
    }
  }
  return m;
}

}  // namespace spinmotor::detail
