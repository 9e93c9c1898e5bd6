#pragma once
// Internal to the mesh module: a parsed glTF file (tinygltf, with side files restricted to the file's
// folder) and its accessors decoded into doubles with every check the readers share (glTF 2.0 §3.6
// "Binary data storage": buffer views inside buffers, accessors inside views, strides, sparse
// substitution, normalised integers, finiteness).
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor::detail {

using GltfRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The parsed file (.gltf with data: URIs or side files, or .glb; images are not decoded). Throws Error
/// "<file>: ..." for a missing file, another extension, a side file outside the file's folder, tinygltf's
/// parse error, or a required extension that changes geometry (Draco, meshopt).
tinygltf::Model load_gltf_model(const std::filesystem::path& path);

/// Lower-case extension of a path (".gltf", ".glb", ...).
std::string gltf_extension(const std::filesystem::path& path);

/// Component types an accessor may have for its role (glTF 2.0 §3.7.2.1 and §3.11 tables;
/// KHR_mesh_quantization widens Position and TexCoord).
enum class GltfKind {
  Float,              ///< float only
  Position,           ///< float, or any integer type with KHR_mesh_quantization
  FloatOrNormalized,  ///< float or normalised unsigned byte/short (weights, UVs, morph weights)
  Rotation,           ///< float or any normalised integer (animated rotations)
  UnsignedIndex,      ///< unsigned byte/short/int, not normalised (indices)
  JointIndex,         ///< unsigned byte/short, not normalised (JOINTS_n)
};

struct GltfAccessors {
  const tinygltf::Model& model;
  std::string file;
  bool quantized = false;  ///< KHR_mesh_quantization is used

  [[noreturn]] void fail(const std::string& what) const;

  /// Accessor `index` as count×components doubles (sparse substitution applied, all finite). `use`
  /// names its role in messages ("POSITION of primitive 0 of mesh 'Body'"), `type` the required
  /// accessor type (TINYGLTF_TYPE_*).
  GltfRows read(int index, int type, GltfKind kind, const std::string& use) const;

  /// Half the storage step of one normalised component of accessor `index` (0 for floats).
  double half_step(int index) const;

 private:
  std::pair<const unsigned char*, size_t> view_bytes(int view, const std::string& label) const;
  void read_elements(int view, size_t offset, size_t count, int c, int ct, bool normalized,
                     const std::string& label, GltfRows& out, const std::vector<size_t>* rows) const;
};

/// Animation `ai` of the file (gltf_read_animation.cpp): channels on the rig's nodes; `ignored` counts
/// the channels skipped (paths the rig does not play).
GltfAnimation read_gltf_animation(const GltfAccessors& acc, const GltfRig& rig, size_t ai, int& ignored);

}  // namespace spinmotor::detail
