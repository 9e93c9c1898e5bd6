// Reading a glTF 2.0 skinned character (gltf.hpp): nodes, skins, the skinned pieces with their weights
// and morph targets, welded per piece; the animations are gltf_read_animation.cpp's, accessor decoding
// gltf_model.cpp's.
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "gltf_model.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

namespace {

using detail::GltfAccessors;
using detail::GltfKind;
using detail::GltfRows;

std::string in_quotes(const std::string& s) { return "'" + s + "'"; }

std::string node_label(const tinygltf::Model& m, int i) {
  return "node " + std::to_string(i) + (m.nodes[i].name.empty() ? "" : " " + in_quotes(m.nodes[i].name));
}

// ---- nodes -----------------------------------------------------------------------------------------

GltfNode read_node(const GltfAccessors& acc, int i) {
  const tinygltf::Node& n = acc.model.nodes[i];
  GltfNode g;
  g.name = n.name.empty() ? "node " + std::to_string(i) : n.name;
  const std::string label = node_label(acc.model, i);
  auto check = [&](const std::vector<double>& v, size_t size, const char* what) {
    if (v.size() != size)
      acc.fail(label + ": " + what + " has " + std::to_string(v.size()) + " numbers, expected " +
               std::to_string(size));
    for (double x : v)
      if (!std::isfinite(x)) acc.fail(label + ": " + what + " is not finite");
  };
  if (!n.matrix.empty()) {
    check(n.matrix, 16, "matrix");
    g.has_matrix = true;
    g.matrix = Eigen::Map<const Eigen::Matrix4d>(n.matrix.data());  // column-major, as Eigen
    if ((g.matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
      acc.fail(label + ": matrix last row is not (0 0 0 1)");
  }
  if (!n.translation.empty()) {
    check(n.translation, 3, "translation");
    g.translation = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
  }
  if (!n.rotation.empty()) {
    check(n.rotation, 4, "rotation");
    const Eigen::Vector4d q(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
    if (q.norm() < 1e-6) acc.fail(label + ": rotation is the zero quaternion");
    const Eigen::Vector4d u = q.normalized();
    g.rotation = Eigen::Quaterniond(u[3], u[0], u[1], u[2]);
  }
  if (!n.scale.empty()) {
    check(n.scale, 3, "scale");
    g.scale = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
  }
  for (double w : n.weights)
    if (!std::isfinite(w)) acc.fail(label + ": weights are not finite");
  return g;
}

/// Every node, with parents from `children` (two parents or a cycle is an error).
std::vector<GltfNode> read_nodes(const GltfAccessors& acc) {
  const tinygltf::Model& m = acc.model;
  const int N = static_cast<int>(m.nodes.size());
  std::vector<GltfNode> nodes;
  nodes.reserve(N);
  for (int i = 0; i < N; ++i) nodes.push_back(read_node(acc, i));
  for (int i = 0; i < N; ++i)
    for (int c : m.nodes[i].children) {
      if (c < 0 || c >= N) acc.fail(node_label(m, i) + ": child " + std::to_string(c) + " does not exist");
      if (nodes[c].parent >= 0)
        acc.fail(node_label(m, c) + " has two parents (" + nodes[nodes[c].parent].name + ", " +
                 nodes[i].name + ")");
      nodes[c].parent = i;
    }
  for (int i = 0; i < N; ++i) {  // cycles: walking up from any node must reach a root in < N steps
    int p = i, steps = 0;
    while (p >= 0 && steps <= N) p = nodes[p].parent, ++steps;
    if (p >= 0) acc.fail(node_label(m, i) + " lies on a cycle of children");
  }
  return nodes;
}

/// The nodes of the default scene (scene 0 without `scene`; every node when the file has no scene).
std::vector<char> scene_nodes(const GltfAccessors& acc, const std::vector<GltfNode>& nodes) {
  const tinygltf::Model& m = acc.model;
  const int N = static_cast<int>(nodes.size());
  if (m.scenes.empty()) return std::vector<char>(N, 1);
  const int s = m.defaultScene >= 0 ? m.defaultScene : 0;
  if (s >= static_cast<int>(m.scenes.size())) acc.fail("scene " + std::to_string(s) + " does not exist");
  std::vector<char> in(N, 0);
  for (int r : m.scenes[s].nodes) {
    if (r < 0 || r >= N)
      acc.fail("scene " + std::to_string(s) + ": node " + std::to_string(r) + " does not exist");
    in[r] = 1;
  }
  for (int i = 0; i < N; ++i)  // descendants of a root in the scene
    for (int p = i; p >= 0 && !in[i]; p = nodes[p].parent)
      if (in[p]) in[i] = 1;
  return in;
}

// ---- pieces and skins -------------------------------------------------------------------------------

std::string piece_name(const tinygltf::Model& m, int node) {
  const tinygltf::Node& n = m.nodes[node];
  if (!n.name.empty()) return n.name;
  if (n.mesh >= 0 && n.mesh < static_cast<int>(m.meshes.size()) && !m.meshes[n.mesh].name.empty())
    return m.meshes[n.mesh].name;
  return "mesh " + std::to_string(n.mesh);
}

/// The skinned nodes to read, in node order: every one of the scene, or those named (node or mesh name).
std::vector<int> select_pieces(const GltfAccessors& acc, const std::vector<char>& in_scene,
                               const std::vector<std::string>& names) {
  const tinygltf::Model& m = acc.model;
  std::vector<int> all;
  for (int i = 0; i < static_cast<int>(m.nodes.size()); ++i)
    if (in_scene[i] && m.nodes[i].mesh >= 0 && m.nodes[i].skin >= 0) {
      if (m.nodes[i].mesh >= static_cast<int>(m.meshes.size()))
        acc.fail(node_label(m, i) + ": mesh " + std::to_string(m.nodes[i].mesh) + " does not exist");
      if (m.nodes[i].skin >= static_cast<int>(m.skins.size()))
        acc.fail(node_label(m, i) + ": skin " + std::to_string(m.nodes[i].skin) + " does not exist");
      all.push_back(i);
    }
  if (all.empty()) acc.fail("no skinned mesh (no node of the scene has both 'mesh' and 'skin')");
  if (names.empty()) return all;
  std::vector<int> out;
  for (const std::string& want : names) {
    bool found = false;
    for (int i : all)
      if (m.nodes[i].name == want || m.meshes[m.nodes[i].mesh].name == want) {
        if (std::find(out.begin(), out.end(), i) == out.end()) out.push_back(i);
        found = true;
      }
    if (!found) {
      std::string list;
      for (int i : all) list += (list.empty() ? "" : ", ") + in_quotes(piece_name(m, i));
      acc.fail("no skinned mesh named " + in_quotes(want) + " (the file has " + list + ")");
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The skins the pieces use, their joints merged into the rig's joint list (one entry per distinct node
/// and inverse bind matrix), and each piece's skin.
void read_skins(const GltfAccessors& acc, const std::vector<int>& piece_nodes, GltfRig& rig) {
  const tinygltf::Model& m = acc.model;
  const int N = static_cast<int>(m.nodes.size());
  std::map<int, int> skin_slot;  // file skin -> rig.skins index
  for (int node : piece_nodes) {
    const int fs = m.nodes[node].skin;
    if (skin_slot.count(fs)) continue;
    const tinygltf::Skin& skin = m.skins[fs];
    const std::string label =
        "skin " + std::to_string(fs) + (skin.name.empty() ? "" : " " + in_quotes(skin.name));
    GltfSkin out;
    out.name = skin.name.empty() ? "skin " + std::to_string(fs) : skin.name;
    out.file_index = fs;
    out.skeleton = skin.skeleton >= 0 && skin.skeleton < N ? skin.skeleton : -1;
    const int J = static_cast<int>(skin.joints.size());
    if (J == 0) acc.fail(label + ": no joints");
    std::vector<Eigen::Matrix4d> ibm(J, Eigen::Matrix4d::Identity());
    if (skin.inverseBindMatrices >= 0) {
      const GltfRows rows = acc.read(skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4, GltfKind::Float,
                                     "inverseBindMatrices of " + label);
      if (rows.rows() < J)
        acc.fail("accessor " + std::to_string(skin.inverseBindMatrices) + " (inverseBindMatrices of " +
                 label + "): " + std::to_string(rows.rows()) + " matrices for " + std::to_string(J) +
                 " joints");
      for (int j = 0; j < J; ++j) {
        ibm[j] = Eigen::Map<const Eigen::Matrix4d>(rows.row(j).data());  // column-major
        if ((ibm[j].row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
          acc.fail("accessor " + std::to_string(skin.inverseBindMatrices) + " (inverseBindMatrices of " +
                   label + "): matrix " + std::to_string(j) + " has last row not (0 0 0 1)");
      }
    }
    std::set<int> seen;
    for (int j = 0; j < J; ++j) {
      const int n = skin.joints[j];
      if (n < 0 || n >= N)
        acc.fail(label + ": joint " + std::to_string(j) + " is node " + std::to_string(n) +
                 ", which does not exist");
      if (!seen.insert(n).second) acc.fail(label + ": " + node_label(m, n) + " is listed twice");
      int entry = -1;
      const double scale = std::max(1.0, ibm[j].cwiseAbs().maxCoeff());
      for (size_t e = 0; e < rig.joint_nodes.size() && entry < 0; ++e)
        if (rig.joint_nodes[e] == n && (rig.inverse_bind[e] - ibm[j]).cwiseAbs().maxCoeff() <= 1e-6 * scale)
          entry = static_cast<int>(e);
      if (entry < 0) {
        entry = static_cast<int>(rig.joint_nodes.size());
        rig.joint_nodes.push_back(n);
        rig.joint_names.push_back(rig.nodes[n].name);
        rig.joint_skins.push_back(static_cast<int>(rig.skins.size()));
        rig.inverse_bind.push_back(ibm[j]);
      }
      out.joints.push_back(entry);
    }
    skin_slot[fs] = static_cast<int>(rig.skins.size());
    rig.skins.push_back(std::move(out));
  }
  const int J = static_cast<int>(rig.joint_nodes.size());
  rig.joint_parents.assign(J, -1);
  for (int j = 0; j < J; ++j)
    for (int p = rig.nodes[rig.joint_nodes[j]].parent; p >= 0 && rig.joint_parents[j] < 0;
         p = rig.nodes[p].parent)
      for (int k = 0; k < J; ++k)
        if (rig.joint_nodes[k] == p) {
          rig.joint_parents[j] = k;
          break;
        }
  for (int node : piece_nodes) {
    GltfPiece piece;
    piece.name = piece_name(m, node);
    piece.node = node;
    piece.mesh = m.nodes[node].mesh;
    piece.skin = skin_slot.at(m.nodes[node].skin);
    rig.pieces.push_back(std::move(piece));
  }
}

// ---- one piece's primitives, in file vertices --------------------------------------------------------

/// A piece as the file stores it: file vertices (its primitives concatenated) and their triangles.
struct FileGeometry {
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> UV;
  std::vector<std::vector<std::pair<int, double>>> W;  // file vertex -> (rig joint, weight)
  std::vector<double> tolerance;                       // per file vertex: the storage precision of its sum
  std::vector<std::array<int, 3>> T;                   // triangles in the piece's file vertices
  std::vector<std::vector<Eigen::Vector3d>> D;         // per morph target, per file vertex
  bool any_uv = false, all_uv = true;
};

/// The triangles of a primitive's index list (glTF 2.0 §3.7.2.1: strips and fans as the spec orders them).
std::vector<std::array<int, 3>> triangles_of(const std::vector<int>& idx, int mode, const std::string& label,
                                             const GltfAccessors& acc) {
  std::vector<std::array<int, 3>> t;
  const size_t n = idx.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0) acc.fail(label + ": " + std::to_string(n) + " indices, not a multiple of 3 (TRIANGLES)");
    for (size_t k = 0; k < n; k += 3) t.push_back({idx[k], idx[k + 1], idx[k + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < n; ++i) t.push_back({idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]});
  } else {  // TRIANGLE_FAN
    for (size_t i = 0; i + 2 < n; ++i) t.push_back({idx[i + 1], idx[i + 2], idx[0]});
  }
  return t;
}

int attribute(const std::map<std::string, int>& attrs, const std::string& name) {
  const auto it = attrs.find(name);
  return it == attrs.end() ? -1 : it->second;
}

/// JOINTS_n/WEIGHTS_n of a primitive into g.W (joints mapped to the rig's list through the skin).
void read_weights(const GltfAccessors& acc, const tinygltf::Primitive& prim, const std::string& plabel,
                  const GltfSkin& skin, const std::string& skin_label, size_t base, Eigen::Index nv,
                  FileGeometry& g) {
  if (attribute(prim.attributes, "JOINTS_0") < 0 || attribute(prim.attributes, "WEIGHTS_0") < 0)
    acc.fail(plabel + ": a skinned primitive needs JOINTS_0 and WEIGHTS_0");
  const int J = static_cast<int>(skin.joints.size());
  for (int set = 0;; ++set) {
    const std::string js = "JOINTS_" + std::to_string(set), ws = "WEIGHTS_" + std::to_string(set);
    const int ja = attribute(prim.attributes, js), wa = attribute(prim.attributes, ws);
    if (ja < 0 && wa < 0) break;
    if (ja < 0 || wa < 0) acc.fail(plabel + ": " + js + " and " + ws + " must come together");
    const GltfRows jv = acc.read(ja, TINYGLTF_TYPE_VEC4, GltfKind::JointIndex, js + " of " + plabel);
    const GltfRows wv = acc.read(wa, TINYGLTF_TYPE_VEC4, GltfKind::FloatOrNormalized, ws + " of " + plabel);
    if (jv.rows() != nv || wv.rows() != nv)
      acc.fail(plabel + ": " + js + " / " + ws + " have " + std::to_string(jv.rows()) + " / " +
               std::to_string(wv.rows()) + " elements for " + std::to_string(nv) + " vertices");
    const double step = acc.half_step(wa);
    for (Eigen::Index i = 0; i < nv; ++i)
      for (int k = 0; k < 4; ++k) {
        const int j = static_cast<int>(jv(i, k));
        const double w = wv(i, k);
        if (w < 0.0)
          acc.fail("accessor " + std::to_string(wa) + " (" + ws + " of " + plabel + "): vertex " +
                   std::to_string(i) + " has a negative weight");
        g.tolerance[base + i] += step;
        if (w == 0.0) continue;
        if (j >= J)
          acc.fail("accessor " + std::to_string(ja) + " (" + js + " of " + plabel + "): vertex " +
                   std::to_string(i) + " names joint " + std::to_string(j) + ", but " + skin_label + " has " +
                   std::to_string(J) + " joints");
        auto& row = g.W[base + i];
        const int e = skin.joints[j];
        const auto it = std::find_if(row.begin(), row.end(), [&](const auto& x) { return x.first == e; });
        if (it == row.end())
          row.emplace_back(e, w);
        else
          it->second += w;  // a joint named twice: the spec sums the influences
      }
  }
}

/// The morph targets' POSITION displacements of a primitive into g.D (T targets for every primitive).
void read_targets(const GltfAccessors& acc, const tinygltf::Primitive& prim, const std::string& plabel,
                  Eigen::Index nv, FileGeometry& g) {
  if (prim.targets.size() != g.D.size())
    acc.fail(plabel + ": " + std::to_string(prim.targets.size()) +
             " morph targets, the mesh's first primitive has " + std::to_string(g.D.size()));
  for (size_t t = 0; t < g.D.size(); ++t) {
    const int a = attribute(prim.targets[t], "POSITION");
    if (a < 0) {
      g.D[t].resize(g.D[t].size() + nv, Eigen::Vector3d::Zero());
      continue;
    }
    const std::string tl = "POSITION of morph target " + std::to_string(t) + " of " + plabel;
    const GltfRows d = acc.read(a, TINYGLTF_TYPE_VEC3, GltfKind::Position, tl);
    if (d.rows() != nv)
      acc.fail("accessor " + std::to_string(a) + " (" + tl + "): " + std::to_string(d.rows()) +
               " elements for " + std::to_string(nv) + " vertices");
    for (Eigen::Index i = 0; i < nv; ++i) g.D[t].emplace_back(d(i, 0), d(i, 1), d(i, 2));
  }
}

/// The vertex indices of a primitive (0..nv−1 without `indices`), range-checked.
std::vector<int> primitive_indices(const GltfAccessors& acc, const tinygltf::Primitive& prim,
                                   const std::string& plabel, Eigen::Index nv) {
  std::vector<int> idx;
  if (prim.indices < 0) {
    idx.resize(nv);
    for (Eigen::Index k = 0; k < nv; ++k) idx[k] = static_cast<int>(k);
    return idx;
  }
  const GltfRows iv =
      acc.read(prim.indices, TINYGLTF_TYPE_SCALAR, GltfKind::UnsignedIndex, "indices of " + plabel);
  idx.resize(iv.rows());
  for (Eigen::Index k = 0; k < iv.rows(); ++k) {
    if (iv(k, 0) >= static_cast<double>(nv))
      acc.fail("accessor " + std::to_string(prim.indices) + " (indices of " + plabel + "): index " +
               std::to_string(k) + " = " + std::to_string(static_cast<long long>(iv(k, 0))) +
               " is out of range (" + std::to_string(nv) + " vertices)");
    idx[k] = static_cast<int>(iv(k, 0));
  }
  return idx;
}

/// One primitive appended to g (file vertices, UVs, weights, morph displacements, triangles).
void read_primitive(const GltfAccessors& acc, const tinygltf::Primitive& prim, const std::string& plabel,
                    const GltfSkin& skin, const std::string& skin_label, FileGeometry& g) {
  const int pos = attribute(prim.attributes, "POSITION");
  if (pos < 0) acc.fail(plabel + ": no POSITION attribute");
  const GltfRows pv = acc.read(pos, TINYGLTF_TYPE_VEC3, GltfKind::Position, "POSITION of " + plabel);
  const size_t base = g.P.size();
  const Eigen::Index nv = pv.rows();
  for (Eigen::Index i = 0; i < nv; ++i) g.P.emplace_back(pv(i, 0), pv(i, 1), pv(i, 2));
  const int tc = attribute(prim.attributes, "TEXCOORD_0");
  if (tc >= 0) {
    g.any_uv = true;
    const GltfRows uv =
        acc.read(tc, TINYGLTF_TYPE_VEC2, GltfKind::FloatOrNormalized, "TEXCOORD_0 of " + plabel);
    if (uv.rows() != nv)
      acc.fail("accessor " + std::to_string(tc) + " (TEXCOORD_0 of " + plabel +
               "): " + std::to_string(uv.rows()) + " elements for " + std::to_string(nv) + " vertices");
    for (Eigen::Index i = 0; i < nv; ++i) g.UV.emplace_back(uv(i, 0), 1.0 - uv(i, 1));
  } else {
    g.all_uv = false;
    for (Eigen::Index i = 0; i < nv; ++i) g.UV.emplace_back(0.0, 0.0);
  }
  g.W.resize(g.P.size());
  g.tolerance.resize(g.P.size(), 1e-5);
  read_weights(acc, prim, plabel, skin, skin_label, base, nv, g);
  read_targets(acc, prim, plabel, nv, g);
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  for (const auto& t : triangles_of(primitive_indices(acc, prim, plabel, nv), mode, plabel, acc))
    g.T.push_back(
        {static_cast<int>(base) + t[0], static_cast<int>(base) + t[1], static_cast<int>(base) + t[2]});
}

/// Every primitive of a piece; skipped (LINES, POINTS) ones noted in rig.warnings.
FileGeometry read_piece_file(const GltfAccessors& acc, GltfRig& rig, GltfPiece& piece) {
  const tinygltf::Mesh& gm = acc.model.meshes[piece.mesh];
  const GltfSkin& skin = rig.skins[piece.skin];
  const std::string mesh_label = "mesh " + in_quotes(gm.name.empty() ? piece.name : gm.name);
  FileGeometry g;
  g.D.resize(gm.primitives.empty() ? 0 : gm.primitives[0].targets.size());
  int skipped = 0;
  for (size_t p = 0; p < gm.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = gm.primitives[p];
    const std::string plabel = "primitive " + std::to_string(p) + " of " + mesh_label;
    piece.primitive_start.push_back(rig.file_vertices + static_cast<Eigen::Index>(g.P.size()));
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
      ++skipped;
      continue;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN)
      acc.fail(plabel + ": mode " + std::to_string(mode) + " is not a glTF primitive mode");
    read_primitive(acc, prim, plabel, skin, "skin " + in_quotes(skin.name), g);
  }
  if (skipped > 0)
    rig.warnings.push_back(mesh_label + ": " + std::to_string(skipped) +
                           " primitives of lines or points skipped (only triangles are a surface)");
  if (g.T.empty()) acc.fail(mesh_label + " has no triangles");
  if (g.any_uv && !g.all_uv)
    rig.warnings.push_back(mesh_label + ": some primitives have no TEXCOORD_0: their UVs are set to (0, 0)");
  return g;
}

// ---- welding ------------------------------------------------------------------------------------------

struct PositionKey {
  std::array<double, 3> p;
  bool operator==(const PositionKey& o) const { return p == o.p; }
};
struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    size_t h = 1469598103934665603ull;
    for (double d : k.p) {
      uint64_t b;
      std::memcpy(&b, &d, 8);
      h = (h ^ b) * 1099511628211ull;
      h ^= h >> 29;
    }
    return h;
  }
};

/// Renormalises g.W's rows (counting those off by more than their storage precision) and records the
/// range of the counted sums. Throws for an all-zero row.
void renormalise(const GltfAccessors& acc, const std::string& piece, FileGeometry& g, GltfRig& rig,
                 std::pair<double, double>& off_range) {
  for (size_t i = 0; i < g.W.size(); ++i) {
    double s = 0.0;
    for (const auto& e : g.W[i]) s += e.second;
    if (!(s > 0.0))
      acc.fail("mesh " + in_quotes(piece) + ": file vertex " + std::to_string(i) +
               " has all skin weights zero");
    rig.min_weight_sum = std::min(rig.min_weight_sum, s);
    rig.max_weight_sum = std::max(rig.max_weight_sum, s);
    if (std::abs(s - 1.0) > g.tolerance[i]) {
      ++rig.renormalised_rows;
      off_range.first = std::min(off_range.first, s), off_range.second = std::max(off_range.second, s);
    }
    for (auto& e : g.W[i]) e.second /= s;
    std::sort(g.W[i].begin(), g.W[i].end());
  }
}

/// Max |w_a − w_b| over the union of joints of two sorted weight rows.
double weight_difference(const std::vector<std::pair<int, double>>& a,
                         const std::vector<std::pair<int, double>>& b) {
  double diff = 0.0;
  size_t p = 0, q = 0;
  while (p < a.size() || q < b.size()) {
    if (q == b.size() || (p < a.size() && a[p].first < b[q].first))
      diff = std::max(diff, a[p++].second);
    else if (p == a.size() || b[q].first < a[p].first)
      diff = std::max(diff, b[q++].second);
    else
      diff = std::max(diff, std::abs(a[p++].second - b[q++].second));
  }
  return diff;
}

/// Welded surface data of one piece, appended to the rig's accumulators.
struct Accumulator {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector2d> UV;
  std::vector<std::array<int, 3>> F, FUV;
  std::vector<Eigen::Triplet<double>> W;
  std::vector<int> to_surface, to_file;
  bool any_uv = false;
};

void weld_piece(const FileGeometry& g, GltfPiece& piece, GltfRig& rig, Accumulator& out) {
  const int surface0 = static_cast<int>(out.V.size()), file0 = static_cast<int>(out.to_surface.size());
  std::unordered_map<PositionKey, int, PositionHash> first;
  first.reserve(g.P.size());
  std::vector<int> local(g.P.size()), representative;
  for (size_t i = 0; i < g.P.size(); ++i) {
    const PositionKey key{{g.P[i].x() + 0.0, g.P[i].y() + 0.0, g.P[i].z() + 0.0}};  // + 0.0 turns −0 into +0
    const auto [it, inserted] = first.emplace(key, static_cast<int>(representative.size()));
    if (inserted) representative.push_back(static_cast<int>(i));
    local[i] = it->second;
    out.to_surface.push_back(surface0 + it->second);
    out.UV.push_back(g.UV[i]);
    if (!inserted) {
      const double d = weight_difference(g.W[representative[it->second]], g.W[i]);
      if (d > 1e-6) ++rig.weld_weight_mismatches;
      rig.weld_weight_max_difference = std::max(rig.weld_weight_max_difference, d);
    }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(representative.size());
  for (Eigen::Index v = 0; v < n; ++v) {
    out.V.push_back(g.P[representative[v]]);
    out.to_file.push_back(file0 + representative[v]);
    for (const auto& [j, w] : g.W[representative[v]])
      out.W.emplace_back(surface0 + static_cast<int>(v), j, w);
  }
  piece.first_vertex = surface0, piece.vertices = n;
  piece.first_face = static_cast<Eigen::Index>(out.F.size());
  for (const auto& t : g.T) {
    const int a = local[t[0]], b = local[t[1]], c = local[t[2]];
    if (a == b || b == c || a == c) {
      ++piece.dropped_faces;
      continue;
    }
    out.F.push_back({surface0 + a, surface0 + b, surface0 + c});
    out.FUV.push_back({file0 + t[0], file0 + t[1], file0 + t[2]});
  }
  piece.faces = static_cast<Eigen::Index>(out.F.size()) - piece.first_face;
  if (piece.faces == 0)
    throw Error(rig.file.string() + ": mesh " + in_quotes(piece.name) + ": every triangle is degenerate");
  piece.targets.assign(g.D.size(), Eigen::MatrixXd(n, 3));
  for (size_t t = 0; t < g.D.size(); ++t)
    for (Eigen::Index v = 0; v < n; ++v) piece.targets[t].row(v) = g.D[t][representative[v]].transpose();
  out.any_uv = out.any_uv || g.any_uv;
}

/// Names and default weights of a piece's morph targets (node `weights`, else mesh `weights`, else 0).
void target_defaults(const GltfAccessors& acc, GltfPiece& piece) {
  const tinygltf::Mesh& gm = acc.model.meshes[piece.mesh];
  const tinygltf::Node& node = acc.model.nodes[piece.node];
  const size_t T = piece.targets.size();
  piece.default_weights = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(T));
  const std::vector<double>& w = !node.weights.empty() ? node.weights : gm.weights;
  if (!w.empty() && w.size() != T)
    acc.fail(node_label(acc.model, piece.node) + ": " + std::to_string(w.size()) + " morph weights for " +
             std::to_string(T) + " targets");
  for (size_t t = 0; t < w.size(); ++t) piece.default_weights[static_cast<Eigen::Index>(t)] = w[t];
  const tinygltf::Value names =
      gm.extras.Has("targetNames") ? gm.extras.Get("targetNames") : tinygltf::Value();
  for (size_t t = 0; t < T; ++t) {
    std::string name = "target " + std::to_string(t);
    if (names.IsArray() && t < names.ArrayLen() && names.Get(static_cast<int>(t)).IsString())
      name = names.Get(static_cast<int>(t)).Get<std::string>();
    piece.target_names.push_back(name);
  }
}

/// Reads and welds every piece into rig.mesh / rig.weights / rig.file_to_surface.
void read_pieces(const GltfAccessors& acc, GltfRig& rig) {
  Accumulator acc_out;
  std::pair<double, double> off{std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity()};
  rig.min_weight_sum = std::numeric_limits<double>::infinity();
  rig.max_weight_sum = -std::numeric_limits<double>::infinity();
  for (GltfPiece& piece : rig.pieces) {
    FileGeometry g = read_piece_file(acc, rig, piece);
    renormalise(acc, piece.name, g, rig, off);
    piece.first_file_vertex = rig.file_vertices;
    piece.file_vertices = static_cast<Eigen::Index>(g.P.size());
    weld_piece(g, piece, rig, acc_out);
    target_defaults(acc, piece);
    rig.file_vertices += piece.file_vertices;
    rig.dropped_faces += piece.dropped_faces;
  }
  const Eigen::Index n = static_cast<Eigen::Index>(acc_out.V.size()),
                     m = static_cast<Eigen::Index>(acc_out.F.size());
  rig.mesh.V.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) rig.mesh.V.row(v) = acc_out.V[v].transpose();
  rig.mesh.F.resize(m, 3);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) rig.mesh.F(f, k) = acc_out.F[f][k];
  if (acc_out.any_uv) {
    rig.mesh.UV.resize(rig.file_vertices, 2);
    for (Eigen::Index i = 0; i < rig.file_vertices; ++i) rig.mesh.UV.row(i) = acc_out.UV[i].transpose();
    rig.mesh.FUV.resize(m, 3);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) rig.mesh.FUV(f, k) = acc_out.FUV[f][k];
  }
  rig.file_to_surface = Eigen::Map<const Eigen::VectorXi>(acc_out.to_surface.data(), rig.file_vertices);
  rig.surface_to_file = Eigen::Map<const Eigen::VectorXi>(acc_out.to_file.data(), n);
  rig.weights.resize(n, rig.num_joints());
  rig.weights.setFromTriplets(acc_out.W.begin(), acc_out.W.end());
  if (rig.renormalised_rows > 0) {
    std::ostringstream os;
    os.precision(7);
    os << rig.renormalised_rows << " of " << rig.file_vertices << " vertices had skin weights summing to "
       << off.first << " .. " << off.second << " instead of 1: renormalised";
    rig.warnings.push_back(os.str());
  }
  if (rig.weld_weight_mismatches > 0) {
    std::ostringstream os;
    os << rig.weld_weight_mismatches
       << " file vertices welded to a vertex at the same position had other skin weights "
       << "(max difference " << rig.weld_weight_max_difference << "): the first one's weights are used";
    rig.warnings.push_back(os.str());
  }
  if (rig.dropped_faces > 0)
    rig.warnings.push_back(std::to_string(rig.dropped_faces) +
                           " triangles with two equal corner positions were dropped");
}

}  // namespace

int GltfRig::piece_of_vertex(Eigen::Index v) const {
  for (size_t p = 0; p < pieces.size(); ++p)
    if (v >= pieces[p].first_vertex && v < pieces[p].first_vertex + pieces[p].vertices)
      return static_cast<int>(p);
  throw Error(file.string() + ": vertex " + std::to_string(v) + " is not a vertex of the rig's surface");
}

std::string GltfRig::vertex_label(Eigen::Index v) const {
  const GltfPiece& piece = pieces[piece_of_vertex(v)];
  const Eigen::Index fv = surface_to_file.size() > v ? surface_to_file[v] : piece.first_file_vertex;
  const Eigen::Index end = piece.first_file_vertex + piece.file_vertices;
  for (size_t p = piece.primitive_start.size(); p-- > 0;) {
    const Eigen::Index next = p + 1 < piece.primitive_start.size() ? piece.primitive_start[p + 1] : end;
    if (piece.primitive_start[p] <= fv && fv < next)
      return "mesh " + in_quotes(piece.name) + " primitive " + std::to_string(p) + " vertex " +
             std::to_string(fv - piece.primitive_start[p]);
  }
  return "mesh " + in_quotes(piece.name) + " vertex " + std::to_string(fv - piece.first_file_vertex);
}

GltfRig read_gltf(const std::filesystem::path& path, const GltfReadOptions& options) {
  const tinygltf::Model model = detail::load_gltf_model(path);
  GltfAccessors acc{model, path.string()};
  acc.quantized = std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                            "KHR_mesh_quantization") != model.extensionsUsed.end();
  GltfRig rig;
  rig.file = path;
  rig.nodes = read_nodes(acc);
  const std::vector<int> piece_nodes = select_pieces(acc, scene_nodes(acc, rig.nodes), options.meshes);
  read_skins(acc, piece_nodes, rig);
  read_pieces(acc, rig);
  for (size_t ai = 0; ai < model.animations.size(); ++ai)
    rig.animations.push_back(detail::read_gltf_animation(acc, rig, ai, rig.ignored_channels));
  return rig;
}

std::vector<std::pair<std::string, std::string>> gltf_skinned_meshes(const std::filesystem::path& path) {
  const tinygltf::Model model = detail::load_gltf_model(path);
  const GltfAccessors acc{model, path.string()};
  const std::vector<GltfNode> nodes = read_nodes(acc);
  std::vector<std::pair<std::string, std::string>> out;
  for (int i : select_pieces(acc, scene_nodes(acc, nodes), {}))
    out.emplace_back(nodes[i].name, model.meshes[model.nodes[i].mesh].name);
  return out;
}

}  // namespace spinmotor
