#pragma once
// Internal to the mesh module: the pieces the glTF writers share (gltf_morph_animation.cpp's baked animation,
// gltf_rig_writer.cpp's skinned rig) — one buffer of 4-byte aligned views with their accessors, the
// split of a welded mesh with per-corner UVs back into glTF vertices, and the atomic serialisation.
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor::detail {

struct GltfBuilder {
  tinygltf::Model model;
  std::vector<unsigned char> bytes;  ///< the one buffer

  GltfBuilder() {
    model.asset.version = "2.0";
    model.asset.generator = "spinmotor";
  }

  /// A buffer view of `size` bytes at the next 4-byte boundary. target: 0 (animation data, IBMs),
  /// TINYGLTF_TARGET_ARRAY_BUFFER (vertex attributes) or TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER.
  int add_view(const void* data, size_t size, int target) {
    while (bytes.size() % 4) bytes.push_back(0);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = bytes.size();
    bv.byteLength = size;
    bv.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), p, p + size);
    model.bufferViews.push_back(bv);
    return static_cast<int>(model.bufferViews.size() - 1);
  }
  int add_accessor(int view, int component_type, size_t count, int type, std::vector<double> mn = {},
                   std::vector<double> mx = {}) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component_type;
    a.count = count;
    a.type = type;
    a.minValues = std::move(mn);
    a.maxValues = std::move(mx);
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  }
  /// Float data of `components` per element (type VEC2/VEC3/VEC4/MAT4/SCALAR); with_bounds: min and max
  /// per component (required for POSITION and animation inputs).
  int float_accessor(const std::vector<float>& v, int type, int components, int target, bool with_bounds) {
    std::vector<double> mn, mx;
    if (with_bounds) {
      mn.assign(components, std::numeric_limits<double>::infinity());
      mx.assign(components, -std::numeric_limits<double>::infinity());
      for (size_t i = 0; i < v.size(); ++i)
        mn[i % components] = std::min<double>(mn[i % components], v[i]),
               mx[i % components] = std::max<double>(mx[i % components], v[i]);
    }
    const int view = add_view(v.data(), v.size() * sizeof(float), target);
    return add_accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, v.size() / components, type, std::move(mn),
                        std::move(mx));
  }
  int vec3_accessor(const std::vector<float>& xyz) {
    return float_accessor(xyz, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
  }
  /// TEXCOORD_0 of glTF vertices whose UV rows are `rows` (v flipped back to glTF's top-left origin).
  int uv_accessor(const Eigen::MatrixXd& UV, const std::vector<int>& rows) {
    std::vector<float> tex(2 * rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      tex[2 * i] = static_cast<float>(UV(rows[i], 0));
      tex[2 * i + 1] = static_cast<float>(1.0 - UV(rows[i], 1));
    }
    return float_accessor(tex, TINYGLTF_TYPE_VEC2, 2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }
  /// uint32 triangle indices.
  int index_accessor(const std::vector<uint32_t>& indices) {
    const int view =
        add_view(indices.data(), indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    return add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, indices.size(), TINYGLTF_TYPE_SCALAR);
  }

  /// Adds the buffer and writes the model as .gltf (buffer as a data: URI) or .glb, atomically.
  void write(const std::filesystem::path& path, bool glb) {
    while (bytes.size() % 4) bytes.push_back(0);
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes);
    model.buffers.push_back(std::move(buffer));
    tinygltf::TinyGLTF writer;
    std::ostringstream os;
    if (!writer.WriteGltfSceneToStream(&model, os, !glb, glb))
      throw Error(path.string() + ": tinygltf could not serialise the model");
    write_text_atomic(path, os.str());
  }
};

/// mesh.extras.targetNames (the morph target names Blender and three.js read).
inline void set_target_names(tinygltf::Mesh& mesh, const std::vector<std::string>& names) {
  tinygltf::Value::Array list;
  for (const std::string& n : names) list.emplace_back(n);
  tinygltf::Value::Object extras;
  extras["targetNames"] = tinygltf::Value(std::move(list));
  mesh.extras = tinygltf::Value(std::move(extras));
}

/// glTF vertices of a mesh with per-corner UVs: one per distinct (vertex, UV index) pair of the corners
/// (UVs split vertices at seams; without UVs one per vertex). vertex_order = false: in order of first
/// use by the corners (vertices no face uses are left out). vertex_order = true: glTF vertex v is mesh
/// vertex v (with the UV of its first corner; every vertex, used or not), the seam duplicates follow —
/// so a reader that welds equal positions in file order gets the mesh's vertex order back.
struct CornerSplit {
  std::vector<int> vertex, uv;    ///< per glTF vertex: the mesh vertex and its UV row (0 without UVs)
  std::vector<uint32_t> indices;  ///< 3 per face: the glTF vertex of each corner
};

/// Throws Error "<file>: face f ..." for a vertex or UV index out of range.
inline CornerSplit split_corners(const Mesh& rest, const std::string& file, bool vertex_order = false) {
  const Eigen::Index n = rest.V.rows(), m = rest.F.rows();
  const bool uv = rest.has_uv();
  CornerSplit out;
  out.indices.resize(static_cast<size_t>(3 * m));
  std::unordered_map<uint64_t, uint32_t> id;
  auto key = [](int v, int t) { return (static_cast<uint64_t>(v) << 32) | static_cast<uint32_t>(t); };
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      if (rest.F(f, k) < 0 || rest.F(f, k) >= n)
        throw Error(file + ": face " + std::to_string(f) + " index out of range");
      if (uv && (rest.FUV(f, k) < 0 || rest.FUV(f, k) >= rest.UV.rows()))
        throw Error(file + ": face " + std::to_string(f) + " uv index out of range");
    }
  if (vertex_order) {
    std::vector<int> first_uv(static_cast<size_t>(n), -1);
    for (Eigen::Index f = 0; f < m && uv; ++f)
      for (int k = 0; k < 3; ++k)
        if (first_uv[rest.F(f, k)] < 0) first_uv[rest.F(f, k)] = rest.FUV(f, k);
    for (Eigen::Index v = 0; v < n; ++v) {
      const int t = std::max(first_uv[v], 0);
      id.emplace(key(static_cast<int>(v), t), static_cast<uint32_t>(v));
      out.vertex.push_back(static_cast<int>(v)), out.uv.push_back(t);
    }
  }
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = rest.F(f, k), t = uv ? rest.FUV(f, k) : 0;
      const auto [it, inserted] = id.emplace(key(v, t), static_cast<uint32_t>(out.vertex.size()));
      if (inserted) out.vertex.push_back(v), out.uv.push_back(t);
      out.indices[static_cast<size_t>(3 * f + k)] = it->second;
    }
  return out;
}

}  // namespace spinmotor::detail
