// Bar of "+"-shaped cross section, extruded along z and capped (generators.hpp).
#include <array>

#include "revolve.hpp"
#include "spinmotor/mesh/generators.hpp"

namespace spinmotor {

namespace {

/// The "+" section on an (N+1)² lattice of nodes (node (i, j) is i + j (N+1)): cell (i, j) belongs to
/// the "+" if it lies in the horizontal or the vertical arm, cells [M, P) across.
struct CrossSection {
  int N = 0, M = 0, P = 0;
  std::vector<double> X;                    ///< node coordinate along x and along y
  std::vector<std::array<int, 2>> outline;  ///< boundary nodes, CCW seen from +z
  std::vector<double> arc;                  ///< arc length along the outline, arc[L] = perimeter
  std::vector<int> on_outline;              ///< per node: its outline position, or -1
  std::vector<int> interior;                ///< per node: its interior cap vertex, or -1
  int n_int = 0;                            ///< interior cap vertices per cap
  int cells = 0;                            ///< cells of the "+"

  int L() const { return static_cast<int>(outline.size()); }
  /// Whether cell (i, j) is in the "+" (false off the lattice).
  bool inside(int i, int j) const {
    return i >= 0 && j >= 0 && i < N && j < N && ((i >= M && i < P) || (j >= M && j < P));
  }
};

/// The outline of the "+" on the lattice of `c`: its twelve corners walked in unit lattice steps, CCW
/// seen from +z.
std::vector<std::array<int, 2>> walk_outline(const CrossSection& c) {
  const int N = c.N, M = c.M, P = c.P;
  const std::array<std::array<int, 2>, 12> corner{
      {{N, M}, {N, P}, {P, P}, {P, N}, {M, N}, {M, P}, {0, P}, {0, M}, {M, M}, {M, 0}, {P, 0}, {P, M}}};
  std::vector<std::array<int, 2>> outline;
  for (int k = 0; k < 12; ++k) {
    auto [i, j] = corner[k];
    const auto [ti, tj] = corner[(k + 1) % 12];
    while (i != ti || j != tj) {
      outline.push_back({i, j});
      i += (ti > i) - (ti < i);
      j += (tj > j) - (tj < j);
    }
  }
  return outline;
}

/// The section of arm half-span a and width `width`, each arm na cells long and nw cells wide: lattice,
/// outline with its arc length, and the numbering of the nodes on the outline and inside the caps.
CrossSection cross_section(double a, double width, int na, int nw) {
  const double w2 = 0.5 * width;
  CrossSection c;
  c.N = 2 * na + nw, c.M = na, c.P = na + nw;
  const int N = c.N, M = c.M, P = c.P;
  c.X.resize(N + 1);
  for (int i = 0; i <= N; ++i)
    c.X[i] = i <= M   ? -a + (a - w2) * i / na
             : i <= P ? -w2 + width * (i - M) / nw
                      : w2 + (a - w2) * (i - P) / na;
  c.outline = walk_outline(c);
  const int L = c.L();
  c.arc.assign(L + 1, 0.0);
  for (int o = 0; o < L; ++o) {
    const auto& p = c.outline[o];
    const auto& q = c.outline[(o + 1) % L];
    c.arc[o + 1] = c.arc[o] + std::hypot(c.X[q[0]] - c.X[p[0]], c.X[q[1]] - c.X[p[1]]);
  }
  // Lattice node → outline position or interior cap vertex.
  c.on_outline.assign((N + 1) * (N + 1), -1);
  c.interior.assign((N + 1) * (N + 1), -1);
  for (int o = 0; o < L; ++o) c.on_outline[c.outline[o][0] + c.outline[o][1] * (N + 1)] = o;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i)
      if (c.inside(i, j) && c.inside(i - 1, j) && c.inside(i, j - 1) && c.inside(i - 1, j - 1))
        c.interior[i + j * (N + 1)] = c.n_int++;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) c.cells += c.inside(i, j);
  return c;
}

/// m.V: segments + 1 rings of the outline along z in [0, length], then the interior vertices of the
/// bottom and of the top cap.
void cross_bar_positions(const CrossSection& c, double length, int segments, Mesh& m) {
  const int N = c.N, L = c.L(), K = segments + 1;
  m.V.resize(K * L + 2 * c.n_int, 3);
  for (int k = 0; k < K; ++k)
    for (int o = 0; o < L; ++o)
      m.V.row(k * L + o) << c.X[c.outline[o][0]], c.X[c.outline[o][1]], length * k / segments;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i)
      if (const int t = c.interior[i + j * (N + 1)]; t >= 0) {
        m.V.row(K * L + t) << c.X[i], c.X[j], 0.0;
        m.V.row(K * L + c.n_int + t) << c.X[i], c.X[j], length;
      }
}

/// m.UV, an isometric atlas: side walls [0, perimeter] × [0, length] (K (L+1) coordinates), the caps
/// (2a)² to their right, indexed by lattice node (unused ones stay zero), all scaled into [0, 1]².
void cross_bar_uvs(const CrossSection& c, double a, double length, int segments, Mesh& m) {
  const int N = c.N, L = c.L(), K = segments + 1;
  const std::vector<double>& X = c.X;
  const double gap = 0.1 * a, W = c.arc[L] + gap + 2 * a, H = std::max(length, 4 * a + gap);
  const double s = 1.0 / std::max(W, H), u0 = (c.arc[L] + gap) * s, v1 = (2 * a + gap) * s;
  const int nuv_side = K * (L + 1), nodes = (N + 1) * (N + 1);
  m.UV.resize(nuv_side + 2 * nodes, 2);  // cap UVs indexed by lattice node (unused ones stay zero)
  m.UV.setZero();
  for (int k = 0; k < K; ++k)
    for (int o = 0; o <= L; ++o) m.UV.row(k * (L + 1) + o) << c.arc[o] * s, length * k / segments * s;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i) {
      m.UV.row(nuv_side + i + j * (N + 1)) << u0 + (a - X[i]) * s, (X[j] + a) * s;  // bottom, mirrored
      m.UV.row(nuv_side + nodes + i + j * (N + 1)) << u0 + (X[i] + a) * s, v1 + (X[j] + a) * s;
    }
}

/// m.F and m.FUV: two triangles per side-wall quad, then two per cell of the bottom and the top cap,
/// all CCW seen from outside.
void cross_bar_faces(const CrossSection& c, int segments, Mesh& m) {
  const int N = c.N, L = c.L(), K = segments + 1;
  const int nuv_side = K * (L + 1), nodes = (N + 1) * (N + 1);
  const int nf = 2 * segments * L + 4 * c.cells;
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
    if (c.on_outline[node] >= 0) return (top ? segments * L : 0) + c.on_outline[node];
    return K * L + (top ? c.n_int : 0) + c.interior[node];
  };
  for (int top = 0; top < 2; ++top)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        if (!c.inside(i, j)) continue;
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
}

}  // namespace

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
  const CrossSection c = cross_section(a, width, na, nw);
  detail::check_face_count(who, 2 * std::int64_t{segments} * c.L() + 4 * std::int64_t{c.cells});
  Mesh m;
  cross_bar_positions(c, length, segments, m);
  cross_bar_uvs(c, a, length, segments, m);
  cross_bar_faces(c, segments, m);
  return m;
}

}  // namespace spinmotor
