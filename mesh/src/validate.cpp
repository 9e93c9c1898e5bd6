#include "spinmotor/mesh/validate.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "union_find.hpp"

namespace spinmotor {
namespace {

using detail::UnionFind;

std::string plural(Eigen::Index n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string edge_str(const std::array<int, 2>& e) {
  std::string s(1, '(');  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "(" + std::string
  s += std::to_string(e[0]);
  s += ", ";
  s += std::to_string(e[1]);
  s += ')';
  return s;
}

std::string num_str(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

void check_structure(const Mesh& mesh) {
  if (mesh.V.size() > 0 && mesh.V.cols() != 3)
    throw Error("invalid mesh: V has " + std::to_string(mesh.V.cols()) + " columns, expected 3");
  if (mesh.F.size() > 0 && mesh.F.cols() != 3)
    throw Error("invalid mesh: F has " + std::to_string(mesh.F.cols()) + " columns, expected 3 (triangles)");
  const Eigen::Index n = mesh.V.rows();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= n)
        throw Error("invalid mesh: face " + std::to_string(f) + " references vertex " +
                    std::to_string(mesh.F(f, c)) + ", but the mesh has " + std::to_string(n) + " vertices");
}

// Per-vertex flags: finite coordinates, referenced by a face.
struct VertexFlags {
  std::vector<char> finite, referenced;
};

// Counts the non-finite and the unreferenced vertices of `mesh` into r (with the first of each) and
// returns the per-vertex flags.
VertexFlags check_vertices(const Mesh& mesh, MeshReport& r) {
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::MatrixXi& F = mesh.F;
  const Eigen::Index n = V.rows();
  VertexFlags flags{std::vector<char>(static_cast<std::size_t>(n), 1),
                    std::vector<char>(static_cast<std::size_t>(n), 0)};
  std::vector<char>&finite = flags.finite, &referenced = flags.referenced;
  for (Eigen::Index v = 0; v < n; ++v)
    if (!V.row(v).allFinite()) {
      finite[v] = 0;
      if (r.nonfinite_vertices++ == 0) r.first_nonfinite_vertex = static_cast<int>(v);
    }
  for (Eigen::Index i = 0; i < F.size(); ++i) referenced[F.data()[i]] = 1;
  for (Eigen::Index v = 0; v < n; ++v)
    if (!referenced[v] && r.unreferenced_vertices++ == 0) r.first_unreferenced_vertex = static_cast<int>(v);
  return flags;
}

// Counts the finite vertices of V at the exact position of a lower-indexed one into r, with the lowest
// such vertex and the vertex it repeats.
void count_duplicate_vertices(const Eigen::MatrixXd& V, const std::vector<char>& finite, MeshReport& r) {
  const Eigen::Index n = V.rows();
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index v = 0; v < n; ++v)
    if (finite[v]) order.push_back(static_cast<int>(v));
  auto less = [&](int a, int b) {  // lexicographic; -0.0 == 0.0, ties by index
    for (int k = 0; k < 3; ++k)
      if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1, group = 0; i < order.size(); ++i) {
    if (V.row(order[i]) != V.row(order[group])) {
      group = i;
      continue;
    }
    ++r.duplicate_vertices;  // order[group] is the lowest index of this position
    if (r.first_duplicate_vertex < 0 || order[i] < r.first_duplicate_vertex) {
      r.first_duplicate_vertex = order[i];
      r.first_duplicate_of = order[group];
    }
  }
}

// Sets r.mean_face_area (over the faces with three distinct, finite corners) and counts the degenerate
// faces (a repeated vertex index, or an area at most kDegenerateAreaRatio times the mean) into r.
// Returns the indices of the proper faces: those with three distinct vertex indices.
std::vector<int> check_faces(const Mesh& mesh, const std::vector<char>& finite, MeshReport& r) {
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::MatrixXi& F = mesh.F;
  const Eigen::Index m = F.rows();
  std::vector<int> proper;
  proper.reserve(static_cast<std::size_t>(m));
  Eigen::VectorXd area = Eigen::VectorXd::Constant(m, std::nan(""));
  double area_sum = 0;
  Eigen::Index area_count = 0;
  for (Eigen::Index f = 0; f < m; ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || b == c || c == a) continue;
    proper.push_back(static_cast<int>(f));
    if (!finite[a] || !finite[b] || !finite[c]) continue;
    const Eigen::Vector3d e1 = V.row(b) - V.row(a), e2 = V.row(c) - V.row(a);
    area[f] = 0.5 * e1.cross(e2).norm();
    area_sum += area[f];
    ++area_count;
  }
  r.mean_face_area = area_count ? area_sum / static_cast<double>(area_count) : 0.0;
  const double area_floor = kDegenerateAreaRatio * r.mean_face_area;
  for (Eigen::Index f = 0; f < m; ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    const bool repeated = a == b || b == c || c == a;
    if (repeated || area[f] <= area_floor) {  // NaN area (non-finite corner) compares false
      if (r.degenerate_faces++ == 0) {
        r.first_degenerate_face = static_cast<int>(f);
        r.first_degenerate_area = repeated ? 0.0 : area[f];
      }
    }
  }
  return proper;
}

// What the edge pass leaves for the later phases.
struct EdgeChecks {
  EdgeTopology t;                // the edges of the proper faces
  UnionFind corners;             // fans: the corners 3 f + c of Fp joined across manifold edges
  std::vector<char> on_nm_edge;  // per vertex: on a non-manifold edge
};

// The edges of the proper faces Fp (rows of the mesh's faces `proper`) on n vertices: sets r.edges and
// counts boundary, non-manifold and inconsistently oriented edges into r (first of each, faces named by
// mesh index). Returns the edge topology, the corner fans and the vertices on non-manifold edges.
EdgeChecks check_edges(const Eigen::MatrixXi& Fp, const std::vector<int>& proper, Eigen::Index n,
                       MeshReport& r) {
  EdgeChecks ec{edge_topology(Fp), UnionFind(static_cast<std::size_t>(3 * Fp.rows())),
                std::vector<char>(static_cast<std::size_t>(n), 0)};
  const EdgeTopology& t = ec.t;
  r.edges = t.num_edges();
  // Direction of edge e in face f: +1 if the face runs E(e,0) -> E(e,1).
  auto direction = [&](int f, Eigen::Index e) {
    for (int c = 0; c < 3; ++c)
      if (t.FE(f, c) == e) return Fp(f, (c + 1) % 3) == t.E(e, 0) ? 1 : -1;
    return 0;
  };
  auto corner_of = [&](int f, int v) {
    for (int c = 0; c < 3; ++c)
      if (Fp(f, c) == v) return 3 * f + c;
    return -1;
  };
  for (Eigen::Index e = 0; e < t.num_edges(); ++e) {
    const int val = t.valence(e);
    const std::array<int, 2> ab{t.E(e, 0), t.E(e, 1)};
    if (val == 1) {
      if (r.boundary_edges++ == 0) r.first_boundary_edge = ab;
    } else if (val > 2) {
      ec.on_nm_edge[ab[0]] = ec.on_nm_edge[ab[1]] = 1;
      if (r.non_manifold_edges++ == 0) {
        r.first_non_manifold_edge = ab;
        r.non_manifold_edge_faces = val;
      }
    } else {
      const int f0 = t.EF_face[t.EF_offset[e]], f1 = t.EF_face[t.EF_offset[e] + 1];
      if (direction(f0, e) == direction(f1, e) && r.inconsistent_orientation++ == 0) {
        r.first_inconsistent_edge = ab;
        r.inconsistent_edge_faces = {proper[f0], proper[f1]};
      }
      for (int v : ab) ec.corners.unite(corner_of(f0, v), corner_of(f1, v));
    }
  }
  return ec;
}

// Counts the vertices of Fp (on n vertices) with more than one fan of corners and on no non-manifold
// edge into r, with the first of them and its number of fans.
void count_non_manifold_vertices(const Eigen::MatrixXi& Fp, Eigen::Index n, EdgeChecks& ec, MeshReport& r) {
  // A vertex is on one fan iff all its corners share one root; O(m), no sort.
  std::vector<int> root0(static_cast<std::size_t>(n), -1);
  std::vector<char> several(static_cast<std::size_t>(n), 0);
  for (Eigen::Index f = 0; f < Fp.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = Fp(f, c), root = ec.corners.find(static_cast<int>(3 * f + c));
      if (root0[v] < 0)
        root0[v] = root;
      else if (root0[v] != root)
        several[v] = 1;
    }
  for (Eigen::Index v = 0; v < n; ++v)
    if (several[v] && !ec.on_nm_edge[v] && r.non_manifold_vertices++ == 0)
      r.first_non_manifold_vertex = static_cast<int>(v);
  if (r.first_non_manifold_vertex >= 0) {  // count the fans of the first one, for the message
    std::vector<int> roots;
    for (Eigen::Index f = 0; f < Fp.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        if (Fp(f, c) == r.first_non_manifold_vertex)
          roots.push_back(ec.corners.find(static_cast<int>(3 * f + c)));
    std::sort(roots.begin(), roots.end());
    r.non_manifold_vertex_fans = static_cast<int>(std::unique(roots.begin(), roots.end()) - roots.begin());
  }
}

// Per-component figures for the genus, components numbered among the referenced vertices.
struct ComponentSums {
  Eigen::VectorXi label;       // vertex -> label of vertex_components
  std::vector<int> comp_id;    // label -> component, -1 for an unreferenced vertex's label
  std::vector<long long> chi;  // Euler characteristic of each component
  std::vector<int> loops_in;   // boundary loops of each component
};

// The components of the referenced vertices of F (on n vertices) with their Euler characteristics over
// the proper faces Fp and their edges t; sets r.components and r.euler_characteristic (loops_in is left
// at zero for count_boundary_loops).
ComponentSums count_components(const Eigen::MatrixXi& F, const Eigen::MatrixXi& Fp, const EdgeTopology& t,
                               const std::vector<char>& referenced, Eigen::Index n, MeshReport& r) {
  ComponentSums cc;
  int nlabels = 0;
  cc.label = vertex_components(F, n, &nlabels);
  const Eigen::VectorXi& label = cc.label;
  cc.comp_id.assign(static_cast<std::size_t>(nlabels), -1);
  std::vector<int>& comp_id = cc.comp_id;
  for (Eigen::Index v = 0; v < n; ++v)
    if (referenced[v] && comp_id[label[v]] < 0) comp_id[label[v]] = r.components++;
  cc.chi.assign(static_cast<std::size_t>(r.components), 0);
  cc.loops_in.assign(static_cast<std::size_t>(r.components), 0);
  Eigen::Index nref = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (referenced[v]) {
      ++nref;
      ++cc.chi[comp_id[label[v]]];
    }
  for (Eigen::Index e = 0; e < t.num_edges(); ++e) --cc.chi[comp_id[label[t.E(e, 0)]]];
  for (Eigen::Index f = 0; f < Fp.rows(); ++f) ++cc.chi[comp_id[label[Fp(f, 0)]]];
  r.euler_characteristic = static_cast<long long>(nref) - r.edges + Fp.rows();
  return cc;
}

// Counts the boundary loops of the edges t (on n vertices) into r.boundary_loops and per component
// into cc.loops_in.
//
// Boundary loops, counted without following face orientation (so the single boundary circle of a
// Möbius band is one loop): each connected piece of the boundary-edge graph is one loop, plus one
// more for every further pair of boundary edges at a pinched vertex (a figure eight is two loops).
// On an oriented manifold this equals boundary_loops() of topology.hpp.
void count_boundary_loops(const EdgeTopology& t, Eigen::Index n, ComponentSums& cc, MeshReport& r) {
  std::vector<int> bdeg(static_cast<std::size_t>(n), 0);
  UnionFind bgraph(static_cast<std::size_t>(n));
  for (Eigen::Index e = 0; e < t.num_edges(); ++e)
    if (t.valence(e) == 1) {
      ++bdeg[t.E(e, 0)];
      ++bdeg[t.E(e, 1)];
      bgraph.unite(t.E(e, 0), t.E(e, 1));
    }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (bdeg[v] == 0) continue;
    const int extra = bgraph.find(static_cast<int>(v)) == v ? 1 : 0;  // one per piece, at its root
    const int pinch = std::max(0, bdeg[v] / 2 - 1);
    r.boundary_loops += extra + pinch;
    cc.loops_in[cc.comp_id[cc.label[v]]] += extra + pinch;
  }
}

// Sets r.genus (the sum over components of (2 - chi - loops) / 2) or r.genus_note saying why there is
// none: no faces (m == 0), not a manifold, not oriented, faces with a repeated index (fewer than m
// proper faces), or a component whose 2 - chi - loops is negative or odd.
void set_genus(Eigen::Index m, std::size_t proper_faces, const ComponentSums& cc, MeshReport& r) {
  if (m == 0) {
    r.genus_note = "the mesh has no faces";
  } else if (!r.is_manifold()) {
    r.genus_note = "not a manifold";
  } else if (!r.is_oriented()) {
    r.genus_note = "not consistently oriented";
  } else if (static_cast<Eigen::Index>(proper_faces) != m) {
    r.genus_note = "faces with a repeated vertex index";
  } else {
    long long g = 0;
    for (int c = 0; c < r.components; ++c) {
      const long long twice = 2 - cc.chi[c] - cc.loops_in[c];
      if (twice < 0 || twice % 2 != 0) {
        g = -1;
        r.genus_note =
            "component " + std::to_string(c) + " has 2 - chi - boundary loops = " + std::to_string(twice);
        break;
      }
      g += twice / 2;
    }
    r.genus = static_cast<int>(g);
  }
}

}  // namespace

MeshReport validate(const Mesh& mesh) {
  check_structure(mesh);
  const Eigen::MatrixXi& F = mesh.F;
  const Eigen::Index n = mesh.V.rows(), m = F.rows();
  MeshReport r;
  r.vertices = n;
  r.faces = m;
  const VertexFlags flags = check_vertices(mesh, r);
  count_duplicate_vertices(mesh.V, flags.finite, r);
  const std::vector<int> proper = check_faces(mesh, flags.finite, r);
  Eigen::MatrixXi Fp(static_cast<Eigen::Index>(proper.size()), 3);
  for (std::size_t i = 0; i < proper.size(); ++i) Fp.row(static_cast<Eigen::Index>(i)) = F.row(proper[i]);
  EdgeChecks ec = check_edges(Fp, proper, n, r);
  count_non_manifold_vertices(Fp, n, ec, r);
  ComponentSums cc = count_components(F, Fp, ec.t, flags.referenced, n, r);
  count_boundary_loops(ec.t, n, cc, r);
  set_genus(m, proper.size(), cc, r);
  return r;
}

std::string MeshReport::defects_summary() const {
  std::vector<std::string> s;
  if (nonfinite_vertices)
    s.push_back(plural(nonfinite_vertices, "non-finite vertex", "non-finite vertices") + ": vertex " +
                std::to_string(first_nonfinite_vertex) + " has a NaN or infinite coordinate");
  if (non_manifold_edges)
    s.push_back(plural(non_manifold_edges, "non-manifold edge", "non-manifold edges") + ": edge " +
                edge_str(first_non_manifold_edge) + " is shared by " +
                std::to_string(non_manifold_edge_faces) + " faces");
  if (non_manifold_vertices)
    s.push_back(plural(non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") + ": vertex " +
                std::to_string(first_non_manifold_vertex) + " joins " +
                std::to_string(non_manifold_vertex_fans) + " separate fans of faces");
  if (inconsistent_orientation)
    s.push_back(
        plural(inconsistent_orientation, "inconsistently oriented edge", "inconsistently oriented edges") +
        ": faces " + std::to_string(inconsistent_edge_faces[0]) + " and " +
        std::to_string(inconsistent_edge_faces[1]) + " both traverse edge " +
        edge_str(first_inconsistent_edge) + " in the same direction");
  if (degenerate_faces)
    s.push_back(plural(degenerate_faces, "degenerate face", "degenerate faces") + ": face " +
                std::to_string(first_degenerate_face) +
                (first_degenerate_area == 0 ? std::string(" has zero area")
                                            : " has area " + num_str(first_degenerate_area)) +
                " (mean face area " + num_str(mean_face_area) + ")");
  if (duplicate_vertices)
    s.push_back(plural(duplicate_vertices, "duplicate vertex", "duplicate vertices") + ": vertex " +
                std::to_string(first_duplicate_vertex) + " has the same coordinates as vertex " +
                std::to_string(first_duplicate_of));
  if (unreferenced_vertices)
    s.push_back(plural(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices") + ": vertex " +
                std::to_string(first_unreferenced_vertex) + " is in no face");
  std::string out;
  for (const auto& x : s) out += (out.empty() ? "" : "; ") + x;
  return out;
}

void require(const MeshReport& r, const Requirements& req, std::string_view operation) {
  const std::string op(operation);
  auto fail = [&](const std::string& needs, const std::string& why) {
    throw Error(op + " needs " + needs + ": " + why);
  };
  if (r.faces < req.min_faces)
    fail("at least " + plural(req.min_faces, "face", "faces"), "the mesh has " + std::to_string(r.faces));
  if (req.finite && r.nonfinite_vertices)
    fail("finite vertex coordinates", "vertex " + std::to_string(r.first_nonfinite_vertex) +
                                          " has a NaN or infinite coordinate (" +
                                          plural(r.nonfinite_vertices, "such vertex", "such vertices") + ")");
  if ((req.manifold || req.genus0) && r.non_manifold_edges)
    fail("a manifold mesh", "edge " + edge_str(r.first_non_manifold_edge) + " is shared by " +
                                std::to_string(r.non_manifold_edge_faces) + " faces (" +
                                plural(r.non_manifold_edges, "non-manifold edge", "non-manifold edges") +
                                ")");
  if ((req.manifold || req.genus0) && r.non_manifold_vertices)
    fail("a manifold mesh",
         "vertex " + std::to_string(r.first_non_manifold_vertex) + " joins " +
             std::to_string(r.non_manifold_vertex_fans) + " separate fans of faces (" +
             plural(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") + ")");
  if ((req.oriented || req.genus0) && r.inconsistent_orientation)
    fail("consistently oriented faces", "faces " + std::to_string(r.inconsistent_edge_faces[0]) + " and " +
                                            std::to_string(r.inconsistent_edge_faces[1]) +
                                            " both traverse edge " + edge_str(r.first_inconsistent_edge) +
                                            " in the same direction");
  if (req.no_degenerate && r.degenerate_faces)
    fail("non-degenerate faces",
         "face " + std::to_string(r.first_degenerate_face) +
             (r.first_degenerate_area == 0 ? std::string(" has zero area")
                                           : " has area " + num_str(r.first_degenerate_area)) +
             " (mean face area " + num_str(r.mean_face_area) + "; " +
             plural(r.degenerate_faces, "degenerate face", "degenerate faces") + ")");
  if (req.closed && r.boundary_edges)
    fail("a closed mesh", "edge " + edge_str(r.first_boundary_edge) + " is on a boundary (" +
                              plural(r.boundary_edges, "boundary edge", "boundary edges") + " in " +
                              plural(r.boundary_loops, "loop", "loops") + ")");
  if (req.single_component && r.components != 1)
    fail("a single connected component", "the mesh has " + std::to_string(r.components));
  if (req.genus0 && r.genus != 0)
    fail("a genus-0 surface", r.genus < 0 ? "the genus is not defined (" + r.genus_note + ")"
                                          : "the mesh has genus " + std::to_string(r.genus));
  if (req.no_unreferenced && r.unreferenced_vertices)
    fail("every vertex in a face",
         "vertex " + std::to_string(r.first_unreferenced_vertex) + " is in no face (" +
             plural(r.unreferenced_vertices, "unreferenced vertex", "unreferenced vertices") +
             "; remove_unreferenced_vertices() drops them)");
  if (req.no_duplicates && r.duplicate_vertices)
    fail("distinct vertex positions",
         "vertex " + std::to_string(r.first_duplicate_vertex) + " has the same coordinates as vertex " +
             std::to_string(r.first_duplicate_of) + " (merge_duplicate_vertices() merges them)");
}

MeshReport require(const Mesh& mesh, const Requirements& req, std::string_view operation) {
  MeshReport r;
  try {
    r = validate(mesh);
  } catch (const Error& e) {
    throw Error(std::string(operation) + ": " + e.what());
  }
  require(r, req, operation);
  return r;
}

}  // namespace spinmotor
