// Skinned glTF 2.0 output (gltf_rig_writer.hpp).
#include "spinmotor/mesh/gltf_rig_writer.hpp"

#include <algorithm>
#include <cmath>

#include "gltf_builder.hpp"
#include "gltf_model.hpp"
#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

struct Checker {
  std::string file;
  Error fail(const std::string& what) const { return Error(file + ": " + what); }
};

void check_nodes(const Checker& c, const GltfRig& rig) {
  const int N = static_cast<int>(rig.nodes.size());
  for (int i = 0; i < N; ++i) {
    const GltfNode& g = rig.nodes[i];
    const std::string label = "node " + std::to_string(i) + " '" + g.name + "'";
    if (g.parent < -1 || g.parent >= N || g.parent == i)
      throw c.fail(label + ": parent " + std::to_string(g.parent) + " is not another node");
    int p = i, steps = 0;
    while (p >= 0 && steps <= N) p = rig.nodes[p].parent, ++steps;
    if (p >= 0) throw c.fail(label + " lies on a cycle of parents");
    if (!g.matrix.allFinite() || !g.translation.allFinite() || !g.rotation.coeffs().allFinite() ||
        !g.scale.allFinite())
      throw c.fail(label + ": a transform value is not finite");
  }
}

void check_joints(const Checker& c, const GltfRig& rig) {
  const int N = static_cast<int>(rig.nodes.size()), J = static_cast<int>(rig.joint_nodes.size());
  if (J == 0) throw c.fail("the rig has no joints");
  if (J > 65535) throw c.fail(std::to_string(J) + " joints: JOINTS_n (unsigned short) holds at most 65535");
  if (static_cast<int>(rig.inverse_bind.size()) != J)
    throw c.fail(std::to_string(rig.inverse_bind.size()) + " inverse bind matrices for " + std::to_string(J) +
                 " joints");
  for (int j = 0; j < J; ++j) {
    if (rig.joint_nodes[j] < 0 || rig.joint_nodes[j] >= N)
      throw c.fail("joint " + std::to_string(j) + " is node " + std::to_string(rig.joint_nodes[j]) +
                   ", which does not exist");
    const Eigen::Matrix4d& ibm = rig.inverse_bind[j];
    if (!ibm.allFinite() || (ibm.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
      throw c.fail("inverse bind matrix of joint " + std::to_string(j) +
                   " is not finite or its last row is not (0 0 0 1)");
  }
  if (rig.skins.empty()) throw c.fail("the rig has no skin");
  for (size_t s = 0; s < rig.skins.size(); ++s) {
    std::vector<char> seen(N, 0);
    for (int e : rig.skins[s].joints) {
      if (e < 0 || e >= J)
        throw c.fail("skin " + std::to_string(s) + " lists joint " + std::to_string(e) + " of " +
                     std::to_string(J));
      if (seen[rig.joint_nodes[e]]++)
        throw c.fail("skin " + std::to_string(s) + " lists node " + std::to_string(rig.joint_nodes[e]) +
                     " twice");
    }
  }
}

void check_pieces(const Checker& c, const GltfRig& rig) {
  const Eigen::Index n = rig.mesh.V.rows(), m = rig.mesh.F.rows();
  if (n == 0 || m == 0 || rig.mesh.V.cols() != 3 || rig.mesh.F.cols() != 3)
    throw c.fail("the rig's mesh is empty or malformed");
  if (!rig.mesh.V.allFinite()) throw c.fail("the rig's mesh has a non-finite position");
  if (rig.pieces.empty()) throw c.fail("the rig has no piece");
  Eigen::Index v = 0, f = 0;
  for (const GltfPiece& p : rig.pieces) {
    const std::string label = "piece '" + p.name + "'";
    if (p.node < 0 || p.node >= static_cast<int>(rig.nodes.size()))
      throw c.fail(label + ": node " + std::to_string(p.node) + " does not exist");
    if (p.skin < 0 || p.skin >= static_cast<int>(rig.skins.size()))
      throw c.fail(label + ": skin " + std::to_string(p.skin) + " does not exist");
    if (p.first_vertex != v || p.first_face != f || p.vertices <= 0 || p.faces <= 0)
      throw c.fail(label + ": its vertex and face ranges do not follow the previous piece's");
    v += p.vertices, f += p.faces;
    for (Eigen::Index k = p.first_face; k < p.first_face + p.faces && k < m; ++k)
      for (int q = 0; q < 3; ++q)
        if (rig.mesh.F(k, q) < p.first_vertex || rig.mesh.F(k, q) >= p.first_vertex + p.vertices)
          throw c.fail(label + ": face " + std::to_string(k) + " uses a vertex of another piece");
    if (p.default_weights.size() != p.num_targets() || p.target_names.size() != p.targets.size())
      throw c.fail(label + ": " + std::to_string(p.num_targets()) + " morph targets with " +
                   std::to_string(p.default_weights.size()) + " weights and " +
                   std::to_string(p.target_names.size()) + " names");
    for (const Eigen::MatrixXd& t : p.targets)
      if (t.rows() != p.vertices || t.cols() != 3 || !t.allFinite())
        throw c.fail(label + ": a morph target is not a finite " + std::to_string(p.vertices) + "×3 field");
  }
  if (v != n || f != m)
    throw c.fail("the pieces cover " + std::to_string(v) + " of " + std::to_string(n) + " vertices and " +
                 std::to_string(f) + " of " + std::to_string(m) + " faces");
  if (rig.weights.rows() != n || rig.weights.cols() != rig.num_joints())
    throw c.fail("the weights are " + std::to_string(rig.weights.rows()) + "×" +
                 std::to_string(rig.weights.cols()) + ", expected " + std::to_string(n) + "×" +
                 std::to_string(rig.num_joints()));
}

void check_channels(const Checker& c, const GltfRig& rig) {
  const int N = static_cast<int>(rig.nodes.size());
  for (size_t a = 0; a < rig.animations.size(); ++a)
    for (size_t k = 0; k < rig.animations[a].channels.size(); ++k) {
      const GltfChannel& ch = rig.animations[a].channels[k];
      const std::string label = "channel " + std::to_string(k) + " of " + rig.animations[a].name;
      if (ch.node < 0 || ch.node >= N)
        throw c.fail(label + ": node " + std::to_string(ch.node) + " does not exist");
      Eigen::Index cols = ch.path == GltfPath::Rotation ? 4 : 3;
      if (ch.path == GltfPath::Weights) {
        const auto it = std::find_if(rig.pieces.begin(), rig.pieces.end(),
                                     [&](const GltfPiece& p) { return p.node == ch.node; });
        if (it == rig.pieces.end())
          throw c.fail(label + ": weights of node " + std::to_string(ch.node) + ", which holds no piece");
        cols = it->num_targets();
      } else if (rig.nodes[ch.node].has_matrix) {
        throw c.fail(label + ": animates node '" + rig.nodes[ch.node].name + "', which is given by a matrix");
      }
      const Eigen::Index keys = ch.times.size(),
                         rows = ch.interpolation == GltfInterpolation::CubicSpline ? 3 * keys : keys;
      if (keys == 0 || ch.values.rows() != rows || ch.values.cols() != cols)
        throw c.fail(label + ": " + std::to_string(ch.values.rows()) + "×" +
                     std::to_string(ch.values.cols()) + " values for " + std::to_string(keys) + " key times");
      if (!ch.times.allFinite() || !ch.values.allFinite()) throw c.fail(label + ": a key is not finite");
      for (Eigen::Index i = 1; i < keys; ++i)
        if (!(static_cast<float>(ch.times[i]) > static_cast<float>(ch.times[i - 1])))
          throw c.fail(label + ": key time " + std::to_string(i) +
                       " is not after the previous one (in float32)");
    }
}

/// Influences per surface vertex in its piece's skin numbering, largest first.
std::vector<std::vector<std::pair<double, int>>> influences(const Checker& c, const GltfRig& rig) {
  const Eigen::Index n = rig.mesh.V.rows();
  std::vector<int> piece_of(static_cast<size_t>(n));
  for (size_t p = 0; p < rig.pieces.size(); ++p)
    std::fill_n(piece_of.begin() + rig.pieces[p].first_vertex, rig.pieces[p].vertices, static_cast<int>(p));
  std::vector<std::vector<int>> slot(rig.skins.size(), std::vector<int>(rig.joint_nodes.size(), -1));
  for (size_t s = 0; s < rig.skins.size(); ++s)
    for (size_t k = 0; k < rig.skins[s].joints.size(); ++k)
      slot[s][rig.skins[s].joints[k]] = static_cast<int>(k);
  std::vector<std::vector<std::pair<double, int>>> inf(static_cast<size_t>(n));
  for (int j = 0; j < rig.weights.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(rig.weights, j); it; ++it) {
      if (!std::isfinite(it.value()) || it.value() < 0)
        throw c.fail("vertex " + std::to_string(it.row()) + " has a negative or non-finite weight");
      if (it.value() == 0) continue;
      const int k = slot[rig.pieces[piece_of[it.row()]].skin][it.col()];
      if (k < 0)
        throw c.fail("vertex " + std::to_string(it.row()) + " is weighted on joint " +
                     std::to_string(it.col()) + ", which its piece's skin does not list");
      inf[it.row()].emplace_back(it.value(), k);
    }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (inf[v].empty()) throw c.fail("vertex " + std::to_string(v) + " has no positive weight");
    std::sort(inf[v].begin(), inf[v].end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
  }
  return inf;
}

tinygltf::Node node_of(const GltfNode& g) {
  tinygltf::Node node;
  node.name = g.name;
  if (g.has_matrix) {
    node.matrix.assign(g.matrix.data(), g.matrix.data() + 16);  // column-major, as Eigen
    return node;
  }
  if (!g.translation.isZero(0.0))
    node.translation = {g.translation.x(), g.translation.y(), g.translation.z()};
  const Eigen::Quaterniond q = g.rotation.normalized();
  if (!q.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs(), 0.0))
    node.rotation = {q.x(), q.y(), q.z(), q.w()};
  if (!g.scale.isOnes(0.0)) node.scale = {g.scale.x(), g.scale.y(), g.scale.z()};
  return node;
}

/// The glTF mesh of one piece (its primitive with positions, UVs, skin sets, targets, indices).
tinygltf::Mesh piece_mesh(detail::GltfBuilder& b, const GltfRig& rig, const GltfPiece& p,
                          const std::vector<std::vector<std::pair<double, int>>>& inf,
                          const std::string& file) {
  Mesh local;
  local.V = rig.mesh.V.middleRows(p.first_vertex, p.vertices);
  local.F = rig.mesh.F.middleRows(p.first_face, p.faces).array() - static_cast<int>(p.first_vertex);
  if (rig.mesh.has_uv()) local.UV = rig.mesh.UV, local.FUV = rig.mesh.FUV.middleRows(p.first_face, p.faces);
  const detail::CornerSplit split = detail::split_corners(local, file, true);
  const size_t nv = split.vertex.size();
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<float> pos(3 * nv);
  for (size_t i = 0; i < nv; ++i)
    for (int c = 0; c < 3; ++c) pos[3 * i + c] = static_cast<float>(local.V(split.vertex[i], c));
  prim.attributes["POSITION"] = b.vec3_accessor(pos);
  if (local.has_uv()) prim.attributes["TEXCOORD_0"] = b.uv_accessor(local.UV, split.uv);
  size_t most = 0;
  for (Eigen::Index v = 0; v < p.vertices; ++v) most = std::max(most, inf[p.first_vertex + v].size());
  for (size_t set = 0; 4 * set < most; ++set) {
    std::vector<uint16_t> joints(4 * nv, 0);
    std::vector<float> weights(4 * nv, 0.0f);
    for (size_t i = 0; i < nv; ++i) {
      const auto& row = inf[p.first_vertex + split.vertex[i]];
      for (size_t k = 0; k < 4 && 4 * set + k < row.size(); ++k) {
        joints[4 * i + k] = static_cast<uint16_t>(row[4 * set + k].second);
        weights[4 * i + k] = static_cast<float>(row[4 * set + k].first);
      }
    }
    const int jv = b.add_view(joints.data(), joints.size() * sizeof(uint16_t), TINYGLTF_TARGET_ARRAY_BUFFER);
    prim.attributes["JOINTS_" + std::to_string(set)] =
        b.add_accessor(jv, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, nv, TINYGLTF_TYPE_VEC4);
    prim.attributes["WEIGHTS_" + std::to_string(set)] =
        b.float_accessor(weights, TINYGLTF_TYPE_VEC4, 4, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }
  for (const Eigen::MatrixXd& t : p.targets) {
    std::vector<float> d(3 * nv);
    for (size_t i = 0; i < nv; ++i)
      for (int c = 0; c < 3; ++c) d[3 * i + c] = static_cast<float>(t(split.vertex[i], c));
    prim.targets.push_back({{"POSITION", b.vec3_accessor(d)}});
  }
  prim.indices = b.index_accessor(split.indices);
  tinygltf::Mesh mesh;
  mesh.name = p.name;
  mesh.primitives.push_back(prim);
  if (!p.targets.empty()) {
    mesh.weights.assign(p.default_weights.data(), p.default_weights.data() + p.default_weights.size());
    detail::set_target_names(mesh, p.target_names);
  }
  return mesh;
}

tinygltf::Animation animation_of(detail::GltfBuilder& b, const GltfAnimation& a) {
  tinygltf::Animation anim;
  anim.name = a.name;
  for (const GltfChannel& ch : a.channels) {
    const std::vector<float> times(ch.times.data(), ch.times.data() + ch.times.size());
    std::vector<float> values(static_cast<size_t>(ch.values.size()));
    for (Eigen::Index r = 0; r < ch.values.rows(); ++r)
      for (Eigen::Index c = 0; c < ch.values.cols(); ++c)
        values[static_cast<size_t>(r * ch.values.cols() + c)] = static_cast<float>(ch.values(r, c));
    tinygltf::AnimationSampler s;
    s.input = b.float_accessor(times, TINYGLTF_TYPE_SCALAR, 1, 0, true);
    const int type = ch.path == GltfPath::Rotation  ? TINYGLTF_TYPE_VEC4
                     : ch.path == GltfPath::Weights ? TINYGLTF_TYPE_SCALAR
                                                    : TINYGLTF_TYPE_VEC3;
    const int comps = ch.path == GltfPath::Rotation ? 4 : ch.path == GltfPath::Weights ? 1 : 3;
    s.output = b.float_accessor(values, type, comps, 0, false);
    s.interpolation = ch.interpolation == GltfInterpolation::Linear ? "LINEAR"
                      : ch.interpolation == GltfInterpolation::Step ? "STEP"
                                                                    : "CUBICSPLINE";
    anim.samplers.push_back(s);
    tinygltf::AnimationChannel c;
    c.sampler = static_cast<int>(anim.samplers.size() - 1);
    c.target_node = ch.node;
    c.target_path = ch.path == GltfPath::Translation ? "translation"
                    : ch.path == GltfPath::Rotation  ? "rotation"
                    : ch.path == GltfPath::Scale     ? "scale"
                                                     : "weights";
    anim.channels.push_back(c);
  }
  return anim;
}

}  // namespace

void write_gltf_rig(const std::filesystem::path& path, const GltfRig& rig) {
  const std::string file = path.string();
  const std::string ext = detail::gltf_extension(path);
  if (ext != ".gltf" && ext != ".glb") throw Error(file + ": not a glTF file name (expected .gltf or .glb)");
  const Checker c{file};
  check_nodes(c, rig);
  check_joints(c, rig);
  check_pieces(c, rig);
  check_channels(c, rig);
  const auto inf = influences(c, rig);

  detail::GltfBuilder b;
  tinygltf::Model& model = b.model;
  for (const GltfNode& g : rig.nodes) model.nodes.push_back(node_of(g));
  tinygltf::Scene scene;
  for (int i = 0; i < static_cast<int>(rig.nodes.size()); ++i) {
    if (rig.nodes[i].parent >= 0)
      model.nodes[rig.nodes[i].parent].children.push_back(i);
    else
      scene.nodes.push_back(i);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  for (size_t p = 0; p < rig.pieces.size(); ++p) {
    model.meshes.push_back(piece_mesh(b, rig, rig.pieces[p], inf, file));
    model.nodes[rig.pieces[p].node].mesh = static_cast<int>(p);
    model.nodes[rig.pieces[p].node].skin = rig.pieces[p].skin;
  }
  for (const GltfSkin& s : rig.skins) {
    std::vector<float> ibm(16 * s.joints.size());
    tinygltf::Skin skin;
    skin.name = s.name;
    for (size_t k = 0; k < s.joints.size(); ++k) {
      skin.joints.push_back(rig.joint_nodes[s.joints[k]]);
      for (int e = 0; e < 16; ++e)
        ibm[16 * k + e] = static_cast<float>(rig.inverse_bind[s.joints[k]].data()[e]);
    }
    if (s.skeleton >= 0) skin.skeleton = s.skeleton;
    skin.inverseBindMatrices = b.float_accessor(ibm, TINYGLTF_TYPE_MAT4, 16, 0, false);
    model.skins.push_back(skin);
  }
  for (const GltfAnimation& a : rig.animations) model.animations.push_back(animation_of(b, a));
  b.write(path, ext == ".glb");
}

}  // namespace spinmotor
