// Bar of "+"-shaped cross section, extruded along z and capped (generators.hpp).
#include <array>

#include "revolve.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

Mesh cross_bar(double length, double half_span, double width, int segments) {
  const char* who = "cross_bar";
  using detail::require;
  require(length > 0.0 && std::isfinite(length), who, "length must be positive and finite");
  require(half_span > 0.0 && std::isfinite(half_span), who, "half_span must be positive and finite");
  require(width > 0.0 && width < 2.0 * half_span, who, "width must be in (0, 2·half_span)");
  require(segments >= 1, who, "segments must be >= 1 (got " + std::to_string(segments) + ")");
  const double a = half_span, w2 = 0.5 * width, h = length / segments;
  const double nw_d = std::max(1.0, std::round(width / h)), na_d = std::max(1.0, std::round((a - w2) / h));
  require(nw_d < 1e5 && na_d < 1e5, who, "the section resolution length/segments is too fine");
  const int nw = static_cast<int>(nw_d), na = static_cast<int>(na_d);

  // The section lives on an (N+1)² lattice of nodes; cell (i, j) belongs to the "+" if it lies in
  // the horizontal or the vertical arm.
  const int N = 2 * na + nw, M = na, P = na + nw;
  std::vector<double> X(N + 1);
  for (int i = 0; i <= N; ++i)
    X[i] = i <= M   ? -a + (a - w2) * i / na
           : i <= P ? -w2 + width * (i - M) / nw
                    : w2 + (a - w2) * (i - P) / na;
  auto inside = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < N && j < N && ((i >= M && i < P) || (j >= M && j < P));
  };
  // Outline, CCW seen from +z: the twelve corners of the "+" walked in unit lattice steps.
  const std::array<std::array<int, 2>, 12> corner{
      {{N, M}, {N, P}, {P, P}, {P, N}, {M, N}, {M, P}, {0, P}, {0, M}, {M, M}, {M, 0}, {P, 0}, {P, M}}};
  std::vector<std::array<int, 2>> outline;
  for (int c = 0; c < 12; ++c) {
    auto [i, j] = corner[c];
    const auto [ti, tj] = corner[(c + 1) % 12];
    while (i != ti || j != tj) {
      outline.push_back({i, j});
      i += (ti > i) - (ti < i);
      j += (tj > j) - (tj < j);
    }
  }
  const int L = static_cast<int>(outline.size());
  std::vector<double> arc(L + 1, 0.0);  // arc length along the outline, arc[L] = perimeter
  for (int o = 0; o < L; ++o) {
    const auto& p = outline[o];
    const auto& q = outline[(o + 1) % L];
    arc[o + 1] = arc[o] + std::hypot(X[q[0]] - X[p[0]], X[q[1]] - X[p[1]]);
  }
  // Lattice node → outline position or interior cap vertex.
  const int K = segments + 1;  // rings along z
  std::vector<int> on_outline((N + 1) * (N + 1), -1), interior((N + 1) * (N + 1), -1);
  for (int o = 0; o < L; ++o) on_outline[outline[o][0] + outline[o][1] * (N + 1)] = o;
  int n_int = 0;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i)
      if (inside(i, j) && inside(i - 1, j) && inside(i, j - 1) && inside(i - 1, j - 1))
        interior[i + j * (N + 1)] = n_int++;
  int cells = 0;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) cells += inside(i, j);
  detail::check_face_count(who, 2 * std::int64_t{segments} * L + 4 * std::int64_t{cells});

  Mesh m;
  const int nv = K * L + 2 * n_int;
  m.V.resize(nv, 3);
  for (int k = 0; k < K; ++k)
    for (int o = 0; o < L; ++o)
      m.V.row(k * L + o) << X[outline[o][0]], X[outline[o][1]], length * k / segments;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i)
      if (const int t = interior[i + j * (N + 1)]; t >= 0) {
        m.V.row(K * L + t) << X[i], X[j], 0.0;
        m.V.row(K * L + n_int + t) << X[i], X[j], length;
      }
  // Isometric atlas: side walls [0, perimeter] × [0, length], caps (2a)² to their right.
  const double gap = 0.1 * a, W = arc[L] + gap + 2 * a, H = std::max(length, 4 * a + gap);
  const double s = 1.0 / std::max(W, H), u0 = (arc[L] + gap) * s, v1 = (2 * a + gap) * s;
  const int nuv_side = K * (L + 1), nodes = (N + 1) * (N + 1);
  m.UV.resize(nuv_side + 2 * nodes, 2);  // cap UVs indexed by lattice node (unused ones stay zero)
  m.UV.setZero();
  for (int k = 0; k < K; ++k)
    for (int o = 0; o <= L; ++o) m.UV.row(k * (L + 1) + o) << arc[o] * s, length * k / segments * s;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i) {
      m.UV.row(nuv_side + i + j * (N + 1)) << u0 + (a - X[i]) * s, (X[j] + a) * s;  // bottom, mirrored
      m.UV.row(nuv_side + nodes + i + j * (N + 1)) << u0 + (X[i] + a) * s, v1 + (X[j] + a) * s;
    }

  const int nf = 2 * segments * L + 4 * cells;
  m.F.resize(nf, 3);
  m.FUV.resize(nf, 3);
  int f = 0;
  for (int k = 0; k < segments; ++k)
    for (int o = 0; o < L; ++o) {
      // outline tangent × ẑ points outwards: (k, o) (k, o+1) (k+1, o+1) (k+1, o) is CCW from outside
      const int o1 = (o + 1) % L;
      const int a0 = k * L + o, b0 = k * L + o1, c0 = (k + 1) * L + o1, d0 = (k + 1) * L + o;
      const int ta = k * (L + 1) + o, tb = ta + 1, tc = tb + L + 1, td = ta + L + 1;
      m.F.row(f) << a0, b0, c0;
      m.FUV.row(f++) << ta, tb, tc;
      m.F.row(f) << a0, c0, d0;
      m.FUV.row(f++) << ta, tc, td;
    }
  auto cap_vertex = [&](int i, int j, bool top) {
    const int node = i + j * (N + 1);
    if (on_outline[node] >= 0) return (top ? segments * L : 0) + on_outline[node];
    return K * L + (top ? n_int : 0) + interior[node];
  };
  for (int top = 0; top < 2; ++top)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        if (!inside(i, j)) continue;
        const int p00 = cap_vertex(i, j, top), p10 = cap_vertex(i + 1, j, top);
        const int p11 = cap_vertex(i + 1, j + 1, top), p01 = cap_vertex(i, j + 1, top);
        const int t0 = nuv_side + top * nodes + i + j * (N + 1);
        const int t00 = t0, t10 = t0 + 1, t11 = t0 + N + 2, t01 = t0 + N + 1;
        if (top) {  // CCW seen from +z
          m.F.row(f) << p00, p10, p11;
          m.FUV.row(f++) << t00, t10, t11;
          m.F.row(f) << p00, p11, p01;
          m.FUV.row(f++) << t00, t11, t01;
        } else {  // CCW seen from −z
          m.F.row(f) << p00, p11, p10;
          m.FUV.row(f++) << t00, t11, t10;
          m.F.row(f) << p00, p01, p11;
          m.FUV.row(f++) << t00, t01, t11;
        }
      }
  return m;
}

}  // namespace spinmotor
