// Parsing a glTF file and decoding its accessors (gltf_model.hpp).
#include "gltf_model.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <vector>

#include "spinmotor/core/error.hpp"

namespace spinmotor::detail {

namespace {

int components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "unknown type";
  }
}

int component_size(int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not valid glTF 2.0 component types
  }
}

// One component at p, converted to double; normalised integers map to [0, 1] (unsigned) or [−1, 1]
// (glTF 2.0 §3.11, "Animation samplers" and §3.7.2.1: c / (2^(b−1) − 1) clamped at −1).
double component(const unsigned char* p, int ct, bool normalized) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

bool allowed(GltfKind kind, int ct, bool normalized, bool quantized) {
  const bool is_float = ct == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool ubyte = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
             ushort = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const bool sbyte = ct == TINYGLTF_COMPONENT_TYPE_BYTE, sshort = ct == TINYGLTF_COMPONENT_TYPE_SHORT;
  switch (kind) {
    case GltfKind::Float:
      return is_float;
    case GltfKind::Position:
      return is_float || (quantized && (ubyte || ushort || sbyte || sshort));
    case GltfKind::FloatOrNormalized:
      return is_float || ((ubyte || ushort || (quantized && (sbyte || sshort))) && normalized);
    case GltfKind::Rotation:
      return is_float || (normalized && (ubyte || ushort || sbyte || sshort));
    case GltfKind::UnsignedIndex:
      return (ubyte || ushort || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) && !normalized;
    case GltfKind::JointIndex:
      return (ubyte || ushort) && !normalized;
  }
  return false;
}

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                  int, void*) {
  return true;  // textures are not used: do not decode them
}

/// The folders a glTF file may read side files from: its own (as named, and with symbolic links
/// resolved), and what is below them.
struct SideFileFolders {
  std::vector<std::filesystem::path> roots;
};

/// tinygltf's file reader, restricted: a buffer URI ("../../x.bin", or a link out of the folder) must
/// name a regular file in the glTF file's folder or below it. Without this a downloaded asset could
/// read any file the user can (its bytes then surface in positions or error messages), or a device
/// such as /dev/zero that never ends.
bool read_side_file(std::vector<unsigned char>* out, std::string* err, const std::string& file, void* user) {
  namespace fs = std::filesystem;
  const auto& folders = *static_cast<const SideFileFolders*>(user);
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::path(file), ec);
  const bool inside = !ec && std::any_of(folders.roots.begin(), folders.roots.end(), [&](const fs::path& r) {
    const fs::path rel = p.lexically_relative(r);
    return !rel.empty() && *rel.begin() != "..";
  });
  if (!inside) {
    if (err) *err += "'" + file + "' is outside the glTF file's folder (side files must be in it or below)\n";
    return false;
  }
  if (!fs::is_regular_file(p, ec)) {
    if (err) *err += "'" + file + "' is not a regular file\n";
    return false;
  }
  return tinygltf::ReadWholeFile(out, err, file, nullptr);
}

}  // namespace

std::string gltf_extension(const std::filesystem::path& path) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

tinygltf::Model load_gltf_model(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw Error(file + ": no such file");
  const std::string ext = gltf_extension(path);
  if (ext != ".gltf" && ext != ".glb")
    throw Error(file + ": not a glTF file (expected extension .gltf or .glb)");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignore_image, nullptr);
  SideFileFolders folders;
  std::error_code ec;
  for (const auto& dir : {std::filesystem::absolute(path, ec).parent_path(),
                          std::filesystem::weakly_canonical(path, ec).parent_path()})
    if (!dir.empty()) folders.roots.push_back(std::filesystem::weakly_canonical(dir, ec));
  loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_side_file,
                         &tinygltf::WriteWholeFile, &folders});
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, file)
                                : loader.LoadASCIIFromFile(&model, &err, &warn, file);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw Error(file + ": " + (err.empty() ? std::string("tinygltf could not parse the file") : err));
  }
  // Extensions that store geometry another way: the accessors alone would give the wrong surface.
  for (const std::string& x : model.extensionsRequired)
    if (x == "KHR_draco_mesh_compression" || x == "EXT_meshopt_compression" || x == "KHR_meshopt_compression")
      throw Error(file + ": requires extension '" + x +
                  "' (compressed geometry is not supported: export without compression)");
  return model;
}

void GltfAccessors::fail(const std::string& what) const { throw Error(file + ": " + what); }

std::pair<const unsigned char*, size_t> GltfAccessors::view_bytes(int view, const std::string& label) const {
  if (view < 0 || view >= static_cast<int>(model.bufferViews.size()))
    fail(label + ": bufferView " + std::to_string(view) + " does not exist");
  const tinygltf::BufferView& bv = model.bufferViews[view];
  if (bv.buffer < 0 || bv.buffer >= static_cast<int>(model.buffers.size()))
    fail(label + ": bufferView " + std::to_string(view) + " names buffer " + std::to_string(bv.buffer) +
         ", which does not exist");
  const auto& data = model.buffers[bv.buffer].data;
  if (bv.byteOffset + bv.byteLength > data.size())
    fail(label + ": bufferView " + std::to_string(view) + " (bytes " + std::to_string(bv.byteOffset) + ".." +
         std::to_string(bv.byteOffset + bv.byteLength) + ") lies outside buffer " +
         std::to_string(bv.buffer) + " (" + std::to_string(data.size()) + " bytes)");
  return {data.data() + bv.byteOffset, bv.byteLength};
}

void GltfAccessors::read_elements(int view, size_t offset, size_t count, int c, int ct, bool normalized,
                                  const std::string& label, GltfRows& out,
                                  const std::vector<size_t>* rows) const {
  const auto [bytes, length] = view_bytes(view, label);
  const size_t elem = static_cast<size_t>(component_size(ct)) * c;
  // Vertex attributes align each element to 4 bytes (§3.6.2.4); the stride is the view's or the element's.
  const size_t stride = model.bufferViews[view].byteStride ? model.bufferViews[view].byteStride : elem;
  if (count > 0 && offset + stride * (count - 1) + elem > length)
    fail(label + ": " + std::to_string(count) + " elements of " + std::to_string(elem) + " bytes (stride " +
         std::to_string(stride) + ", offset " + std::to_string(offset) + ") overrun bufferView " +
         std::to_string(view) + " (" + std::to_string(length) + " bytes)");
  const int cs = component_size(ct);
  for (size_t k = 0; k < count; ++k) {
    const unsigned char* p = bytes + offset + k * stride;
    const size_t r = rows ? (*rows)[k] : k;
    for (int j = 0; j < c; ++j) out(static_cast<Eigen::Index>(r), j) = component(p + j * cs, ct, normalized);
  }
}

GltfRows GltfAccessors::read(int index, int type, GltfKind kind, const std::string& use) const {
  if (index < 0 || index >= static_cast<int>(model.accessors.size()))
    fail(use + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = model.accessors[index];
  const std::string label = "accessor " + std::to_string(index) + " (" + use + ")";
  if (a.type != type) fail(label + ": type " + type_name(a.type) + ", expected " + type_name(type));
  const int ct = a.componentType;
  if (!allowed(kind, ct, a.normalized, quantized))
    fail(label + ": component type " + std::to_string(ct) + (a.normalized ? " (normalized)" : "") +
         " is not allowed here");
  const int c = components(type);
  GltfRows out = GltfRows::Zero(static_cast<Eigen::Index>(a.count), c);
  if (a.bufferView >= 0)
    read_elements(a.bufferView, a.byteOffset, a.count, c, ct, a.normalized, label, out, nullptr);
  if (a.sparse.isSparse) {
    const int sc = a.sparse.count;
    if (sc < 1 || static_cast<size_t>(sc) > a.count)
      fail(label + ": sparse count " + std::to_string(sc) + " outside [1, " + std::to_string(a.count) + "]");
    const int ict = a.sparse.indices.componentType;
    if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(label + ": sparse indices have component type " + std::to_string(ict));
    GltfRows idx(sc, 1);
    // Sparse indices and values are tightly packed (the spec forbids a byteStride on their views).
    read_elements(a.sparse.indices.bufferView, static_cast<size_t>(a.sparse.indices.byteOffset), sc, 1, ict,
                  false, label + " sparse indices", idx, nullptr);
    std::vector<size_t> rows(sc);
    for (int k = 0; k < sc; ++k) {
      if (idx(k, 0) >= static_cast<double>(a.count) || (k > 0 && idx(k, 0) <= idx(k - 1, 0)))
        fail(label + ": sparse index " + std::to_string(k) + " = " +
             std::to_string(static_cast<long long>(idx(k, 0))) + " is out of range or not increasing");
      rows[k] = static_cast<size_t>(idx(k, 0));
    }
    read_elements(a.sparse.values.bufferView, static_cast<size_t>(a.sparse.values.byteOffset), sc, c, ct,
                  a.normalized, label + " sparse values", out, &rows);
  }
  for (Eigen::Index r = 0; r < out.rows(); ++r)
    for (Eigen::Index j = 0; j < c; ++j)
      if (!std::isfinite(out(r, j)))
        fail(label + ": element " + std::to_string(r) + " component " + std::to_string(j) + " is not finite");
  return out;
}

double GltfAccessors::half_step(int index) const {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) return 0.0;
  const tinygltf::Accessor& a = model.accessors[index];
  if (!a.normalized) return 0.0;
  switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 0.5 / 255.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 0.5 / 65535.0;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return 0.5 / 127.0;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return 0.5 / 32767.0;
    default:
      return 0.0;
  }
}

}  // namespace spinmotor::detail
