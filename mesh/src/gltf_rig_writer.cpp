// Skinned glTF 2.0 output (gltf_rig_writer.hpp).
#include "spinmotor/mesh/gltf_rig_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "gltf_builder.hpp"
#include "spinmotor/core/error.hpp"

namespace spinmotor {

namespace {

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

template <class M>
bool finite(const M& m) {
  return m.allFinite();
}

}  // namespace

void write_gltf_rig(const std::filesystem::path& path, const GltfRig& rig) {
  const std::string file = path.string();
  const std::string ext = lower_extension(path);
  if (ext != ".gltf" && ext != ".glb") throw Error(file + ": not a glTF file name (expected .gltf or .glb)");
  auto fail = [&](const std::string& what) { return Error(file + ": " + what); };

  // ---- consistency
  const int N = static_cast<int>(rig.nodes.size());
  const Eigen::Index n = rig.mesh.V.rows(), m = rig.mesh.F.rows();
  const int J = static_cast<int>(rig.joint_nodes.size());
  if (n == 0 || m == 0 || rig.mesh.V.cols() != 3 || rig.mesh.F.cols() != 3)
    throw fail("the rig's mesh is empty or malformed");
  if (!finite(rig.mesh.V)) throw fail("the rig's mesh has a non-finite position");
  if (rig.mesh_node < 0 || rig.mesh_node >= N)
    throw fail("mesh node " + std::to_string(rig.mesh_node) + " is not one of the " + std::to_string(N) +
               " nodes");
  if (J == 0) throw fail("the rig has no joints");
  if (J > 65535) throw fail(std::to_string(J) + " joints: JOINTS_n (unsigned short) holds at most 65535");
  if (static_cast<int>(rig.inverse_bind.size()) != J)
    throw fail(std::to_string(rig.inverse_bind.size()) + " inverse bind matrices for " + std::to_string(J) +
               " joints");
  std::vector<char> is_joint(N, 0);
  for (int j = 0; j < J; ++j) {
    const int node = rig.joint_nodes[j];
    if (node < 0 || node >= N)
      throw fail("joint " + std::to_string(j) + " is node " + std::to_string(node) +
                 ", which does not exist");
    if (is_joint[node]) throw fail("node " + std::to_string(node) + " is listed twice as a joint");
    is_joint[node] = 1;
    const Eigen::Matrix4d& ibm = rig.inverse_bind[j];
    if (!finite(ibm) || (ibm.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
      throw fail("inverse bind matrix of joint " + std::to_string(j) +
                 " is not finite or its last row is not (0 0 0 1)");
  }
  for (int i = 0; i < N; ++i) {
    const GltfNode& g = rig.nodes[i];
    const std::string label = "node " + std::to_string(i) + " '" + g.name + "'";
    if (g.parent < -1 || g.parent >= N || g.parent == i)
      throw fail(label + ": parent " + std::to_string(g.parent) + " is not another node");
    int p = i, steps = 0;
    while (p >= 0 && steps <= N) p = rig.nodes[p].parent, ++steps;
    if (p >= 0) throw fail(label + " lies on a cycle of parents");
    if (!finite(g.matrix) || !finite(g.translation) || !finite(g.rotation.coeffs()) || !finite(g.scale))
      throw fail(label + ": a transform value is not finite");
  }
  if (rig.weights.rows() != n || rig.weights.cols() != J)
    throw fail("the weights are " + std::to_string(rig.weights.rows()) + "×" +
               std::to_string(rig.weights.cols()) + ", expected " + std::to_string(n) + "×" +
               std::to_string(J));

  // Influences per vertex, largest first.
  std::vector<std::vector<std::pair<double, int>>> inf(static_cast<size_t>(n));
  for (int j = 0; j < rig.weights.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(rig.weights, j); it; ++it) {
      if (!std::isfinite(it.value()) || it.value() < 0)
        throw fail("vertex " + std::to_string(it.row()) + " has a negative or non-finite weight");
      if (it.value() > 0) inf[it.row()].emplace_back(it.value(), j);
    }
  size_t most = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    if (inf[v].empty()) throw fail("vertex " + std::to_string(v) + " has no positive weight");
    std::sort(inf[v].begin(), inf[v].end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    most = std::max(most, inf[v].size());
  }
  for (size_t a = 0; a < rig.animations.size(); ++a)
    for (size_t c = 0; c < rig.animations[a].channels.size(); ++c) {
      const GltfChannel& ch = rig.animations[a].channels[c];
      const std::string label = "channel " + std::to_string(c) + " of " + rig.animations[a].name;
      const Eigen::Index k = ch.times.size();
      const int cols = ch.path == GltfPath::Rotation ? 4 : 3;
      const Eigen::Index rows = ch.interpolation == GltfInterpolation::CubicSpline ? 3 * k : k;
      if (ch.node < 0 || ch.node >= N)
        throw fail(label + ": node " + std::to_string(ch.node) + " does not exist");
      if (rig.nodes[ch.node].has_matrix)
        throw fail(label + ": animates node '" + rig.nodes[ch.node].name + "', which is given by a matrix");
      if (k == 0 || ch.values.rows() != rows || ch.values.cols() != cols)
        throw fail(label + ": " + std::to_string(ch.values.rows()) + "×" + std::to_string(ch.values.cols()) +
                   " values for " + std::to_string(k) + " key times");
      if (!finite(ch.times) || !finite(ch.values)) throw fail(label + ": a key is not finite");
      for (Eigen::Index i = 1; i < k; ++i)
        if (!(static_cast<float>(ch.times[i]) > static_cast<float>(ch.times[i - 1])))
          throw fail(label + ": key time " + std::to_string(i) +
                     " is not after the previous one (in float32)");
    }

  detail::GltfBuilder b;
  tinygltf::Model& model = b.model;

  // ---- nodes
  for (int i = 0; i < N; ++i) {
    const GltfNode& g = rig.nodes[i];
    tinygltf::Node node;
    node.name = g.name;
    if (g.has_matrix) {
      node.matrix.assign(g.matrix.data(), g.matrix.data() + 16);  // column-major, as Eigen
    } else {
      if (!g.translation.isZero(0.0))
        node.translation = {g.translation.x(), g.translation.y(), g.translation.z()};
      const Eigen::Quaterniond q = g.rotation.normalized();
      if (!q.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs(), 0.0))
        node.rotation = {q.x(), q.y(), q.z(), q.w()};
      if (!g.scale.isOnes(0.0)) node.scale = {g.scale.x(), g.scale.y(), g.scale.z()};
    }
    model.nodes.push_back(node);
  }
  tinygltf::Scene scene;
  for (int i = 0; i < N; ++i) {
    if (rig.nodes[i].parent >= 0)
      model.nodes[rig.nodes[i].parent].children.push_back(i);
    else
      scene.nodes.push_back(i);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.nodes[rig.mesh_node].mesh = 0;
  model.nodes[rig.mesh_node].skin = 0;

  // ---- the skinned mesh
  const detail::CornerSplit split = detail::split_corners(rig.mesh, file, true);
  const size_t nv = split.vertex.size();
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<float> pos(3 * nv);
  for (size_t i = 0; i < nv; ++i)
    for (int c = 0; c < 3; ++c) pos[3 * i + c] = static_cast<float>(rig.mesh.V(split.vertex[i], c));
  prim.attributes["POSITION"] = b.vec3_accessor(pos);
  if (rig.mesh.has_uv()) {
    std::vector<float> tex(2 * nv);
    for (size_t i = 0; i < nv; ++i) {
      tex[2 * i] = static_cast<float>(rig.mesh.UV(split.uv[i], 0));
      tex[2 * i + 1] = static_cast<float>(1.0 - rig.mesh.UV(split.uv[i], 1));
    }
    prim.attributes["TEXCOORD_0"] =
        b.float_accessor(tex, TINYGLTF_TYPE_VEC2, 2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }
  for (size_t set = 0; 4 * set < most; ++set) {
    std::vector<uint16_t> joints(4 * nv, 0);
    std::vector<float> weights(4 * nv, 0.0f);
    for (size_t i = 0; i < nv; ++i) {
      const auto& row = inf[split.vertex[i]];
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
  {
    const int view = b.add_view(split.indices.data(), split.indices.size() * sizeof(uint32_t),
                                TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.indices = b.add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, split.indices.size(),
                                  TINYGLTF_TYPE_SCALAR);
  }
  tinygltf::Mesh mesh;
  mesh.name = rig.mesh_name;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);

  // ---- the skin
  {
    std::vector<float> ibm(16 * static_cast<size_t>(J));
    for (int j = 0; j < J; ++j)
      for (int e = 0; e < 16; ++e) ibm[16 * j + e] = static_cast<float>(rig.inverse_bind[j].data()[e]);
    tinygltf::Skin skin;
    skin.joints = rig.joint_nodes;
    skin.inverseBindMatrices = b.float_accessor(ibm, TINYGLTF_TYPE_MAT4, 16, 0, false);
    model.skins.push_back(skin);
  }

  // ---- animations
  for (const GltfAnimation& a : rig.animations) {
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
      const bool rot = ch.path == GltfPath::Rotation;
      s.output =
          b.float_accessor(values, rot ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, rot ? 4 : 3, 0, false);
      s.interpolation = ch.interpolation == GltfInterpolation::Linear ? "LINEAR"
                        : ch.interpolation == GltfInterpolation::Step ? "STEP"
                                                                      : "CUBICSPLINE";
      anim.samplers.push_back(s);
      tinygltf::AnimationChannel c;
      c.sampler = static_cast<int>(anim.samplers.size() - 1);
      c.target_node = ch.node;
      c.target_path = ch.path == GltfPath::Translation ? "translation" : rot ? "rotation" : "scale";
      anim.channels.push_back(c);
    }
    model.animations.push_back(anim);
  }
  b.write(path, ext == ".glb");
}

}  // namespace spinmotor
