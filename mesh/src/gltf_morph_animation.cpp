// Baked morph-target animations (gltf.hpp): written as one mesh node with a target per frame and a
// one-hot STEP weights animation, and read back.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_map>

#include "gltf_builder.hpp"
#include "gltf_model.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {

namespace {

using detail::GltfAccessors;
using detail::GltfKind;
using detail::GltfRows;

void check_baked_input(const std::string& file, const Mesh& rest, const std::vector<Eigen::MatrixXd>& frames,
                       const std::vector<double>& times, const Eigen::Matrix4d& node_matrix) {
  const Eigen::Index n = rest.V.rows(), m = rest.F.rows();
  if (n == 0 || m == 0 || rest.V.cols() != 3 || rest.F.cols() != 3)
    throw Error(file + ": the rest mesh is empty or malformed");
  if (frames.empty()) throw Error(file + ": no frames to write");
  if (!node_matrix.allFinite() ||
      (node_matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw Error(file + ": the node matrix is not a finite affine matrix");
  if (frames.size() != times.size())
    throw Error(file + ": " + std::to_string(frames.size()) + " frames but " + std::to_string(times.size()) +
                " times");
  for (size_t f = 0; f < frames.size(); ++f) {
    if (frames[f].rows() != n || frames[f].cols() != 3)
      throw Error(file + ": frame " + std::to_string(f) + " is " + std::to_string(frames[f].rows()) + "×" +
                  std::to_string(frames[f].cols()) + ", expected " + std::to_string(n) + "×3");
    if (!frames[f].allFinite())
      throw Error(file + ": frame " + std::to_string(f) + " has a non-finite position");
    if (!std::isfinite(times[f]) || (f > 0 && !(times[f] > times[f - 1])))
      throw Error(file + ": time of frame " + std::to_string(f) +
                  " is not finite or not after the previous one");
  }
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k)
      if (rest.F(f, k) < 0 || rest.F(f, k) >= n)
        throw Error(file + ": face " + std::to_string(f) + " index out of range");
}

/// The STEP weights animation: key f at times[f], output one-hot on target f (frames² floats).
tinygltf::Animation one_hot_animation(detail::GltfBuilder& b, const std::vector<double>& times,
                                      const std::string& name) {
  const size_t nframes = times.size();
  std::vector<float> t(times.begin(), times.end());
  const int input = b.float_accessor(t, TINYGLTF_TYPE_SCALAR, 1, 0, true);
  std::vector<float> w(nframes * nframes, 0.0f);
  for (size_t f = 0; f < nframes; ++f) w[f * nframes + f] = 1.0f;
  const int output = b.float_accessor(w, TINYGLTF_TYPE_SCALAR, 1, 0, false);
  tinygltf::AnimationSampler s;
  s.input = input;
  s.output = output;
  s.interpolation = "STEP";
  tinygltf::AnimationChannel c;
  c.sampler = 0;
  c.target_node = 0;
  c.target_path = "weights";
  tinygltf::Animation a;
  a.name = name;
  a.samplers.push_back(s);
  a.channels.push_back(c);
  return a;
}

}  // namespace

void write_gltf_morph_animation(const std::filesystem::path& path, const Mesh& rest,
                                const std::vector<Eigen::MatrixXd>& frames, const std::vector<double>& times,
                                const std::string& name, const Eigen::Matrix4d& node_matrix,
                                const std::vector<GltfMorphPiece>& pieces_in) {
  const std::string file = path.string();
  const std::string ext = detail::gltf_extension(path);
  if (ext != ".gltf" && ext != ".glb") throw Error(file + ": not a glTF file name (expected .gltf or .glb)");
  check_baked_input(file, rest, frames, times, node_matrix);
  const std::vector<GltfMorphPiece> pieces =
      pieces_in.empty() ? std::vector<GltfMorphPiece>{{name, 0, rest.V.rows(), 0, rest.F.rows()}} : pieces_in;
  detail::GltfBuilder b;
  tinygltf::Node root;
  root.name = name;
  if (!node_matrix.isIdentity(0.0))
    root.matrix.assign(node_matrix.data(), node_matrix.data() + 16);  // column-major
  b.model.nodes.push_back(root);
  std::vector<std::string> names;
  for (size_t f = 0; f < frames.size(); ++f) {
    char label[32];
    std::snprintf(label, sizeof label, "frame %04zu", f);
    names.emplace_back(label);
  }
  for (const GltfMorphPiece& p : pieces) {
    if (p.first_vertex < 0 || p.vertices <= 0 || p.first_vertex + p.vertices > rest.V.rows() ||
        p.first_face < 0 || p.faces <= 0 || p.first_face + p.faces > rest.F.rows())
      throw Error(file + ": piece '" + p.name + "' lies outside the mesh");
    Mesh local;
    local.V = rest.V.middleRows(p.first_vertex, p.vertices);
    local.F = rest.F.middleRows(p.first_face, p.faces).array() - static_cast<int>(p.first_vertex);
    if (rest.has_uv()) local.UV = rest.UV, local.FUV = rest.FUV.middleRows(p.first_face, p.faces);
    // glTF vertices: one per distinct (vertex, uv index) corner pair, ordered by vertex, so that welding
    // equal positions back (read_gltf_morph_animation) returns the vertices in `rest`'s order.
    const detail::CornerSplit split = detail::split_corners(local, file + ": piece '" + p.name + "'", true);
    const size_t nv = split.vertex.size();
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    std::vector<float> pos(3 * nv);
    for (size_t i = 0; i < nv; ++i)
      for (int c = 0; c < 3; ++c) pos[3 * i + c] = static_cast<float>(local.V(split.vertex[i], c));
    prim.attributes["POSITION"] = b.vec3_accessor(pos);
    if (local.has_uv()) prim.attributes["TEXCOORD_0"] = b.uv_accessor(local.UV, split.uv);
    prim.indices = b.index_accessor(split.indices);
    // Morph targets: POSITION displacements (float32: the positions read back as rest + displacement).
    for (const Eigen::MatrixXd& frame : frames) {
      std::vector<float> d(3 * nv);
      for (size_t i = 0; i < nv; ++i)
        for (int c = 0; c < 3; ++c)
          d[3 * i + c] = static_cast<float>(frame(p.first_vertex + split.vertex[i], c) -
                                            static_cast<double>(pos[3 * i + c]));
      prim.targets.push_back({{"POSITION", b.vec3_accessor(d)}});
    }
    tinygltf::Mesh mesh;
    mesh.name = p.name;
    mesh.primitives.push_back(prim);
    mesh.weights.assign(frames.size(), 0.0);
    mesh.weights[0] = 1.0;
    detail::set_target_names(mesh, names);
    b.model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = p.name;
    node.mesh = static_cast<int>(b.model.meshes.size() - 1);
    b.model.nodes[0].children.push_back(static_cast<int>(b.model.nodes.size()));
    b.model.nodes.push_back(node);
  }
  tinygltf::Scene scene;
  scene.nodes = {0};
  b.model.scenes.push_back(scene);
  b.model.defaultScene = 0;
  tinygltf::Animation a = one_hot_animation(b, times, name);
  for (size_t p = 0; p < pieces.size(); ++p) {
    tinygltf::AnimationChannel c = a.channels[0];
    c.target_node = static_cast<int>(p + 1);
    if (p == 0)
      a.channels[0] = c;
    else
      a.channels.push_back(c);
  }
  b.model.animations.push_back(a);
  b.write(path, ext == ".glb");
}

// ---- read back -------------------------------------------------------------------------------------------

namespace {

/// Every node whose mesh has morph targets, in index order.
std::vector<int> morph_nodes(const GltfAccessors& acc) {
  const tinygltf::Model& m = acc.model;
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(m.nodes.size()); ++i) {
    const int mi = m.nodes[i].mesh;
    if (mi < 0 || mi >= static_cast<int>(m.meshes.size())) continue;
    for (const auto& prim : m.meshes[mi].primitives)
      if (!prim.targets.empty()) {
        out.push_back(i);
        break;
      }
  }
  if (out.empty()) acc.fail("no mesh with morph targets (not a baked animation)");
  return out;
}

/// The node's global matrix: the chain of parents' rest matrices (two parents or a cycle is an error).
Eigen::Matrix4d rest_global(const GltfAccessors& acc, int node) {
  const tinygltf::Model& m = acc.model;
  const int N = static_cast<int>(m.nodes.size());
  std::vector<int> parent(N, -1);
  for (int i = 0; i < N; ++i)
    for (int c : m.nodes[i].children) {
      if (c < 0 || c >= N)
        acc.fail("node " + std::to_string(i) + ": child " + std::to_string(c) + " does not exist");
      if (parent[c] >= 0) acc.fail("node " + std::to_string(c) + " has two parents");
      parent[c] = i;
    }
  auto local = [&](int i) {
    const tinygltf::Node& nd = m.nodes[i];
    const std::string label = "node " + std::to_string(i);
    auto check = [&](const std::vector<double>& v, size_t size, const char* what) {
      if (v.size() != size) acc.fail(label + ": " + what + " has " + std::to_string(v.size()) + " numbers");
      for (double x : v)
        if (!std::isfinite(x)) acc.fail(label + ": " + what + " is not finite");
    };
    if (!nd.matrix.empty()) {
      check(nd.matrix, 16, "matrix");
      return Eigen::Matrix4d(Eigen::Map<const Eigen::Matrix4d>(nd.matrix.data()));
    }
    Eigen::Matrix4d out = Eigen::Matrix4d::Identity();
    Eigen::Vector3d sc = Eigen::Vector3d::Ones();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (!nd.translation.empty())
      check(nd.translation, 3, "translation"),
          out.topRightCorner<3, 1>() = Eigen::Vector3d(nd.translation.data());
    if (!nd.scale.empty()) check(nd.scale, 3, "scale"), sc = Eigen::Vector3d(nd.scale.data());
    if (!nd.rotation.empty()) {
      check(nd.rotation, 4, "rotation");
      const Eigen::Vector4d r(nd.rotation.data());
      if (r.norm() < 1e-6) acc.fail(label + ": rotation is the zero quaternion");
      const Eigen::Vector4d u = r.normalized();
      q = Eigen::Quaterniond(u[3], u[0], u[1], u[2]);
    }
    out.topLeftCorner<3, 3>() = q.toRotationMatrix() * sc.asDiagonal();
    return out;
  };
  Eigen::Matrix4d g = Eigen::Matrix4d::Identity();
  int steps = 0;
  for (int i = node; i >= 0; i = parent[i]) {
    if (++steps > N) acc.fail("node " + std::to_string(node) + " lies on a cycle of children");
    g = local(i) * g;
  }
  return g;
}

/// The mesh's file vertices: base positions, UVs, triangles and per-target displacements.
struct MorphFile {
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> UV;
  std::vector<std::array<int, 3>> T;
  std::vector<std::vector<Eigen::Vector3d>> D;
  bool any_uv = false;
};

int attr(const std::map<std::string, int>& attrs, const std::string& name) {
  const auto it = attrs.find(name);
  return it == attrs.end() ? -1 : it->second;
}

void read_morph_primitive(const GltfAccessors& acc, const tinygltf::Primitive& prim,
                          const std::string& plabel, MorphFile& g) {
  if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
    acc.fail(plabel + ": mode " + std::to_string(prim.mode) + " is not supported (only TRIANGLES, mode 4)");
  if (prim.targets.size() != g.D.size())
    acc.fail(plabel + ": " + std::to_string(prim.targets.size()) + " morph targets, primitive 0 has " +
             std::to_string(g.D.size()));
  const int pos = attr(prim.attributes, "POSITION");
  if (pos < 0) acc.fail(plabel + ": no POSITION attribute");
  const GltfRows pv = acc.read(pos, TINYGLTF_TYPE_VEC3, GltfKind::Float, "POSITION of " + plabel);
  const int base = static_cast<int>(g.P.size());
  const Eigen::Index nv = pv.rows();
  for (Eigen::Index i = 0; i < nv; ++i) g.P.emplace_back(pv(i, 0), pv(i, 1), pv(i, 2));
  const int tc = attr(prim.attributes, "TEXCOORD_0");
  GltfRows uv;
  if (tc >= 0) {
    g.any_uv = true;
    uv = acc.read(tc, TINYGLTF_TYPE_VEC2, GltfKind::FloatOrNormalized, "TEXCOORD_0 of " + plabel);
    if (uv.rows() != nv)
      acc.fail("TEXCOORD_0 of " + plabel + ": " + std::to_string(uv.rows()) + " elements for " +
               std::to_string(nv) + " vertices");
  }
  for (Eigen::Index i = 0; i < nv; ++i)
    g.UV.emplace_back(tc >= 0 ? uv(i, 0) : 0.0, tc >= 0 ? 1.0 - uv(i, 1) : 0.0);
  for (size_t f = 0; f < g.D.size(); ++f) {
    const std::string tlabel = "POSITION of morph target " + std::to_string(f) + " of " + plabel;
    const int ta = attr(prim.targets[f], "POSITION");
    if (ta < 0) acc.fail(tlabel + ": missing");
    const GltfRows dv = acc.read(ta, TINYGLTF_TYPE_VEC3, GltfKind::Float, tlabel);
    if (dv.rows() != nv)
      acc.fail(tlabel + ": " + std::to_string(dv.rows()) + " elements for " + std::to_string(nv) +
               " vertices");
    for (Eigen::Index i = 0; i < nv; ++i) g.D[f].emplace_back(dv(i, 0), dv(i, 1), dv(i, 2));
  }
  std::vector<int> idx;
  if (prim.indices >= 0) {
    const GltfRows iv =
        acc.read(prim.indices, TINYGLTF_TYPE_SCALAR, GltfKind::UnsignedIndex, "indices of " + plabel);
    for (Eigen::Index k = 0; k < iv.rows(); ++k) {
      if (iv(k, 0) >= static_cast<double>(nv))
        acc.fail("indices of " + plabel + ": index " + std::to_string(k) + " is out of range (" +
                 std::to_string(nv) + " vertices)");
      idx.push_back(static_cast<int>(iv(k, 0)));
    }
  } else {
    for (Eigen::Index k = 0; k < nv; ++k) idx.push_back(static_cast<int>(k));
  }
  if (idx.size() % 3 != 0)
    acc.fail(plabel + ": " + std::to_string(idx.size()) + " indices, not a multiple of 3 (TRIANGLES)");
  for (size_t k = 0; k < idx.size(); k += 3)
    g.T.push_back({base + idx[k], base + idx[k + 1], base + idx[k + 2]});
}

struct KeyHash {
  size_t operator()(const std::array<double, 3>& k) const {
    size_t h = 1469598103934665603ull;
    for (double d : k) {
      uint64_t b;
      std::memcpy(&b, &d, 8);
      h = (h ^ b) * 1099511628211ull;
      h ^= h >> 29;
    }
    return h;
  }
};

/// Welds equal base positions of one node (as read_gltf) and appends the node's surface to `out`; a
/// welded vertex takes its first file vertex's frames.
void weld_morph(const GltfAccessors& acc, const std::string& mlabel, const MorphFile& g,
                GltfMorphAnimation& out, Eigen::Index uv0) {
  const Eigen::Index nf = static_cast<Eigen::Index>(g.P.size());
  std::unordered_map<std::array<double, 3>, int, KeyHash> first;
  std::vector<int> surface(static_cast<size_t>(nf)), representative;
  for (Eigen::Index i = 0; i < nf; ++i) {
    const std::array<double, 3> key{g.P[i].x() + 0.0, g.P[i].y() + 0.0, g.P[i].z() + 0.0};
    const auto [it, inserted] = first.emplace(key, static_cast<int>(representative.size()));
    if (inserted) representative.push_back(static_cast<int>(i));
    surface[static_cast<size_t>(i)] = it->second;
  }
  const Eigen::Index n = static_cast<Eigen::Index>(representative.size()), v0 = out.mesh.V.rows(),
                     f0 = out.mesh.F.rows();
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : g.T)
    if (surface[t[0]] != surface[t[1]] && surface[t[1]] != surface[t[2]] && surface[t[0]] != surface[t[2]])
      kept.push_back(t);
  if (kept.empty()) acc.fail(mlabel + ": every triangle is degenerate");
  const Eigen::Index m = static_cast<Eigen::Index>(kept.size());
  out.mesh.V.conservativeResize(v0 + n, 3);
  for (Eigen::Index v = 0; v < n; ++v) out.mesh.V.row(v0 + v) = g.P[representative[v]].transpose();
  out.mesh.F.conservativeResize(f0 + m, 3);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) out.mesh.F(f0 + f, k) = static_cast<int>(v0) + surface[kept[f][k]];
  out.mesh.UV.conservativeResize(uv0 + nf, 2);
  for (Eigen::Index i = 0; i < nf; ++i) out.mesh.UV.row(uv0 + i) = g.UV[i].transpose();
  out.mesh.FUV.conservativeResize(f0 + m, 3);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) out.mesh.FUV(f0 + f, k) = static_cast<int>(uv0) + kept[f][k];
  out.frames.resize(g.D.size());
  for (size_t f = 0; f < g.D.size(); ++f) {
    out.frames[f].conservativeResize(v0 + n, 3);
    for (Eigen::Index v = 0; v < n; ++v)
      out.frames[f].row(v0 + v) = (g.P[representative[v]] + g.D[f][representative[v]]).transpose();
  }
  out.pieces.push_back({mlabel, v0, n, f0, m});
}

/// Target f's time: the first key of the first `weights` channel on the node where target f weighs most.
void morph_times(const GltfAccessors& acc, int node, size_t targets, std::vector<double>& times) {
  times.resize(targets);
  for (size_t f = 0; f < targets; ++f) times[f] = static_cast<double>(f);
  const tinygltf::Model& m = acc.model;
  for (size_t ai = 0; ai < m.animations.size(); ++ai)
    for (const auto& ch : m.animations[ai].channels) {
      if (ch.target_node != node || ch.target_path != "weights") continue;
      const std::string label =
          "animation " + std::to_string(ai) + " (weights of node " + std::to_string(node) + ")";
      if (ch.sampler < 0 || ch.sampler >= static_cast<int>(m.animations[ai].samplers.size()))
        acc.fail(label + ": sampler does not exist");
      const tinygltf::AnimationSampler& sm = m.animations[ai].samplers[ch.sampler];
      const GltfRows tin = acc.read(sm.input, TINYGLTF_TYPE_SCALAR, GltfKind::Float, "input of " + label);
      const GltfRows wout =
          acc.read(sm.output, TINYGLTF_TYPE_SCALAR, GltfKind::FloatOrNormalized, "output of " + label);
      const Eigen::Index keys = tin.rows(), nt = static_cast<Eigen::Index>(targets);
      const Eigen::Index per = sm.interpolation == "CUBICSPLINE" ? 3 : 1;
      if (wout.rows() != keys * nt * per)
        acc.fail(label + ": " + std::to_string(wout.rows()) + " weights for " + std::to_string(keys) +
                 " keys and " + std::to_string(nt) + " targets");
      std::vector<bool> seen(targets, false);
      for (Eigen::Index k = 0; k < keys; ++k) {
        const Eigen::Index row0 = (k * per + (per == 3 ? 1 : 0)) * nt;
        Eigen::Index best = 0;
        for (Eigen::Index f = 1; f < nt; ++f)
          if (wout(row0 + f, 0) > wout(row0 + best, 0)) best = f;
        if (!seen[best]) seen[best] = true, times[best] = tin(k, 0);
      }
      for (size_t f = 0; f < targets; ++f)
        if (!seen[f])
          acc.fail(label + ": morph target " + std::to_string(f) +
                   " is never the largest weight (not a baked frame sequence)");
      return;
    }
}

}  // namespace

GltfMorphAnimation read_gltf_morph_animation(const std::filesystem::path& path) {
  const tinygltf::Model model = detail::load_gltf_model(path);
  const GltfAccessors acc{model, path.string()};
  const std::vector<int> nodes = morph_nodes(acc);
  GltfMorphAnimation out;
  out.mesh.V.resize(0, 3), out.mesh.F.resize(0, 3), out.mesh.UV.resize(0, 2), out.mesh.FUV.resize(0, 3);
  out.name = model.meshes[model.nodes[nodes[0]].mesh].name;
  out.node_matrix = rest_global(acc, nodes[0]);
  bool any_uv = false;
  size_t targets = 0;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const tinygltf::Mesh& gmesh = model.meshes[model.nodes[nodes[k]].mesh];
    const std::string mlabel =
        "mesh '" + (gmesh.name.empty() ? std::to_string(model.nodes[nodes[k]].mesh) : gmesh.name) + "'";
    MorphFile g;
    g.D.resize(gmesh.primitives.empty() ? 0 : gmesh.primitives[0].targets.size());
    if (k == 0) targets = g.D.size();
    if (g.D.size() != targets)
      acc.fail(mlabel + ": " + std::to_string(g.D.size()) + " morph targets, the first mesh has " +
               std::to_string(targets));
    for (size_t pi = 0; pi < gmesh.primitives.size(); ++pi)
      read_morph_primitive(acc, gmesh.primitives[pi], "primitive " + std::to_string(pi) + " of " + mlabel, g);
    if (g.T.empty()) acc.fail(mlabel + " has no triangles");
    any_uv = any_uv || g.any_uv;
    weld_morph(acc, gmesh.name.empty() ? mlabel : gmesh.name, g, out, out.mesh.UV.rows());
  }
  if (!any_uv) out.mesh.UV.resize(0, 2), out.mesh.FUV.resize(0, 3);
  morph_times(acc, nodes[0], targets, out.times);
  return out;
}

}  // namespace spinmotor
