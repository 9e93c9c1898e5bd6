// glTF 2.0 rigs: reader (on Debian's tinygltf, linked as its shared library, which parses the JSON and
// decodes data: URIs, side files and GLB chunks), evaluation of the node hierarchy and animations, and
// the baked morph-target writer. See gltf.hpp for the contract.
#include <tiny_gltf.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>

#include "gltf_builder.hpp"
#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/gltf.hpp"

namespace spinmotor {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// ---- reading accessors ---------------------------------------------------------------------------

struct Reader {
  const tinygltf::Model& m;
  std::string file;

  [[noreturn]] void fail(const std::string& what) const { throw Error(file + ": " + what); }

  static int components(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR:
        return 1;
      case TINYGLTF_TYPE_VEC2:
        return 2;
      case TINYGLTF_TYPE_VEC3:
        return 3;
      case TINYGLTF_TYPE_VEC4:
        return 4;
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
  static const char* type_name(int type) {
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
  static int component_size(int ct) {
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

  // One component at p, converted to double; normalised integers map to [0, 1] (unsigned) or [−1, 1].
  static double component(const unsigned char* p, int ct, bool normalized) {
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

  // The bytes of buffer view `view` (checked to lie in its buffer), for accessor `label`.
  std::pair<const unsigned char*, size_t> view_bytes(int view, const std::string& label) const {
    if (view < 0 || view >= static_cast<int>(m.bufferViews.size()))
      fail(label + ": bufferView " + std::to_string(view) + " does not exist");
    const tinygltf::BufferView& bv = m.bufferViews[view];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m.buffers.size()))
      fail(label + ": bufferView " + std::to_string(view) + " names buffer " + std::to_string(bv.buffer) +
           ", which does not exist");
    const auto& data = m.buffers[bv.buffer].data;
    if (bv.byteOffset + bv.byteLength > data.size())
      fail(label + ": bufferView " + std::to_string(view) + " (bytes " + std::to_string(bv.byteOffset) +
           ".." + std::to_string(bv.byteOffset + bv.byteLength) + ") lies outside buffer " +
           std::to_string(bv.buffer) + " (" + std::to_string(data.size()) + " bytes)");
    return {data.data() + bv.byteOffset, bv.byteLength};
  }

  // count×c strided elements of component type ct starting at byte `offset` of `view` into `out`
  // (rows `rows`, or 0..count−1).
  void read_elements(int view, size_t offset, size_t count, int c, int ct, bool normalized,
                     const std::string& label, RowMatrix& out, const std::vector<size_t>* rows) const {
    const auto [bytes, length] = view_bytes(view, label);
    const size_t elem = static_cast<size_t>(component_size(ct)) * c;
    const size_t stride = m.bufferViews[view].byteStride ? m.bufferViews[view].byteStride : elem;
    if (count > 0 && offset + stride * (count - 1) + elem > length)
      fail(label + ": " + std::to_string(count) + " elements of " + std::to_string(elem) + " bytes (stride " +
           std::to_string(stride) + ", offset " + std::to_string(offset) + ") overrun bufferView " +
           std::to_string(view) + " (" + std::to_string(length) + " bytes)");
    const int cs = component_size(ct);
    for (size_t k = 0; k < count; ++k) {
      const unsigned char* p = bytes + offset + k * stride;
      const size_t r = rows ? (*rows)[k] : k;
      for (int j = 0; j < c; ++j)
        out(static_cast<Eigen::Index>(r), j) = component(p + j * cs, ct, normalized);
    }
  }

  // Accessor `index` as count×components doubles (sparse substitution applied, all finite). `use`
  // names its role ("POSITION of primitive 0 of mesh 'Body'"), `type` the required accessor type and
  // `kind` the component types allowed (glTF 2.0 spec, "Meshes" and "Animations" tables).
  enum class Kind { Float, FloatOrNormalized, Rotation, UnsignedIndex, JointIndex };
  RowMatrix read(int index, int type, Kind kind, const std::string& use) const {
    if (index < 0 || index >= static_cast<int>(m.accessors.size()))
      fail(use + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = m.accessors[index];
    const std::string label = "accessor " + std::to_string(index) + " (" + use + ")";
    if (a.type != type) fail(label + ": type " + type_name(a.type) + ", expected " + type_name(type));
    const int ct = a.componentType;
    const bool is_float = ct == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool is_ubyte = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
               is_ushort = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    bool ok = false;
    switch (kind) {
      case Kind::Float:
        ok = is_float;
        break;
      case Kind::FloatOrNormalized:
        ok = is_float || ((is_ubyte || is_ushort) && a.normalized);
        break;
      case Kind::Rotation:
        ok = is_float || (a.normalized && (is_ubyte || is_ushort || ct == TINYGLTF_COMPONENT_TYPE_BYTE ||
                                           ct == TINYGLTF_COMPONENT_TYPE_SHORT));
        break;
      case Kind::UnsignedIndex:
        ok = (is_ubyte || is_ushort || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) && !a.normalized;
        break;
      case Kind::JointIndex:
        ok = (is_ubyte || is_ushort) && !a.normalized;
        break;
    }
    if (!ok)
      fail(label + ": component type " + std::to_string(ct) + (a.normalized ? " (normalized)" : "") +
           " is not allowed here");
    const int c = components(type);
    RowMatrix out = RowMatrix::Zero(static_cast<Eigen::Index>(a.count), c);
    if (a.bufferView >= 0)
      read_elements(a.bufferView, a.byteOffset, a.count, c, ct, a.normalized, label, out, nullptr);
    if (a.sparse.isSparse) {
      const int sc = a.sparse.count;
      if (sc < 1 || static_cast<size_t>(sc) > a.count)
        fail(label + ": sparse count " + std::to_string(sc) + " outside [1, " + std::to_string(a.count) +
             "]");
      const int ict = a.sparse.indices.componentType;
      if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        fail(label + ": sparse indices have component type " + std::to_string(ict));
      RowMatrix idx(sc, 1);
      const std::string ilabel = label + " sparse indices";
      // Sparse indices and values are tightly packed (the spec forbids a byteStride on their views).
      read_elements(a.sparse.indices.bufferView, static_cast<size_t>(a.sparse.indices.byteOffset), sc, 1, ict,
                    false, ilabel, idx, nullptr);
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
          fail(label + ": element " + std::to_string(r) + " component " + std::to_string(j) +
               " is not finite");
    return out;
  }
};

// ---- transforms ----------------------------------------------------------------------------------

Eigen::Matrix4d trs_matrix(const Eigen::Vector3d& t, const Eigen::Quaterniond& r, const Eigen::Vector3d& s) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r.toRotationMatrix() * s.asDiagonal();
  m.topRightCorner<3, 1>() = t;
  return m;
}

// Inverse of an affine 4×4 matrix (last row 0 0 0 1).
Eigen::Matrix4d affine_inverse(const Eigen::Matrix4d& m) {
  Eigen::Matrix4d r = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d li = m.topLeftCorner<3, 3>().inverse();
  r.topLeftCorner<3, 3>() = li;
  r.topRightCorner<3, 1>() = -li * m.topRightCorner<3, 1>();
  return r;
}

// Checks that a scale vector is uniform within kGltfScaleTolerance and positive.
bool uniform_positive(const Eigen::Vector3d& s) {
  return s.minCoeff() > 0.0 && (s.maxCoeff() - s.minCoeff()) <= kGltfScaleTolerance * s.maxCoeff();
}
// Tangents of a cubic spline: only uniformity (they may be zero or negative).
bool uniform_tangent(const Eigen::Vector3d& s) {
  return (s.maxCoeff() - s.minCoeff()) <= kGltfScaleTolerance * std::max(1.0, s.cwiseAbs().maxCoeff());
}

Eigen::Quaterniond quat_xyzw(const Eigen::Vector4d& v) { return Eigen::Quaterniond(v[3], v[0], v[1], v[2]); }

// Spherical linear interpolation along the shorter arc (glTF spec, Appendix C), normalised.
Eigen::VectorXd slerp_xyzw(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double u) {
  double d = a.dot(b);
  const double s = d < 0.0 ? -1.0 : 1.0;
  d = std::min(std::abs(d), 1.0);
  Eigen::VectorXd r;
  if (d > 1.0 - 1e-12) {
    r = (1.0 - u) * a + s * u * b;  // nearly equal: the lerp is exact to rounding
  } else {
    const double th = std::acos(d), sn = std::sin(th);
    r = std::sin((1.0 - u) * th) / sn * a + s * std::sin(u * th) / sn * b;
  }
  return r.normalized();
}

}  // namespace

// ---- similarities -------------------------------------------------------------------------------

ScaledMotor scaled_motor(const Eigen::Matrix4d& m, const std::string& what, double tolerance) {
  if (!m.allFinite()) throw Error(what + ": a matrix entry is not finite");
  const double scale_ref = std::max(1.0, m.cwiseAbs().maxCoeff());
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6 * scale_ref)
    throw Error(what + ": the last matrix row is not (0 0 0 1)");
  const Eigen::Matrix3d l = m.topLeftCorner<3, 3>();
  const double det = l.determinant();
  if (!(det > 0.0))
    throw Error(what + ": the linear part has determinant " + std::to_string(det) +
                " (a reflection or a collapse), not a similarity");
  const double s = std::cbrt(det);
  const Eigen::Matrix3d r0 = l / s;
  const double defect = (r0.transpose() * r0 - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (defect > tolerance) {
    std::ostringstream os;
    os << what << ": not a rigid motion with uniform scale (|LᵀL/s² − I| = " << defect << " > " << tolerance
       << "): non-uniform scale or shear is not supported";
    throw Error(os.str());
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r0, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();  // det > 0 since det r0 > 0
  ScaledMotor out;
  out.scale = s;
  out.motor = ga::motor(ga::from_quaterniond(Eigen::Quaterniond(r).normalized()),
                        ga::translator(Eigen::Vector3d(m.topRightCorner<3, 1>())));
  return out;
}

Eigen::Matrix4d to_matrix(const ScaledMotor& s) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  const Eigen::Isometry3d iso = ga::to_isometry(s.motor);
  m.topLeftCorner<3, 3>() = s.scale * iso.linear();
  m.topRightCorner<3, 1>() = iso.translation();
  return m;
}

// ---- animation sampling ---------------------------------------------------------------------------

Eigen::VectorXd GltfChannel::sample(double t) const {
  const Eigen::Index k = times.size();
  const bool rot = path == GltfPath::Rotation;
  const bool cubic = interpolation == GltfInterpolation::CubicSpline;
  auto value = [&](Eigen::Index i) -> Eigen::VectorXd {
    return values.row(cubic ? 3 * i + 1 : i).transpose();
  };
  auto finish = [&](Eigen::VectorXd v) {
    if (rot) v.normalize();
    return v;
  };
  if (k == 1 || t <= times[0]) return finish(value(0));
  if (t >= times[k - 1]) return finish(value(k - 1));
  // The key interval [t_i, t_{i+1}) holding t.
  const Eigen::Index i = std::upper_bound(times.data(), times.data() + k, t) - times.data() - 1;
  const double td = times[i + 1] - times[i], u = (t - times[i]) / td;
  switch (interpolation) {
    case GltfInterpolation::Step:
      return finish(value(i));
    case GltfInterpolation::Linear:
      if (rot) return slerp_xyzw(value(i), value(i + 1), u);
      return (1.0 - u) * value(i) + u * value(i + 1);
    case GltfInterpolation::CubicSpline: {
      // Hermite spline, glTF spec Appendix C: p(u) = (2u³−3u²+1) v_i + td (u³−2u²+u) b_i
      //                                              + (−2u³+3u²) v_{i+1} + td (u³−u²) a_{i+1}
      const double u2 = u * u, u3 = u2 * u;
      const Eigen::VectorXd b_i = values.row(3 * i + 2).transpose(),
                            a_n = values.row(3 * (i + 1)).transpose();
      return finish((2 * u3 - 3 * u2 + 1) * value(i) + td * (u3 - 2 * u2 + u) * b_i +
                    (-2 * u3 + 3 * u2) * value(i + 1) + td * (u3 - u2) * a_n);
    }
  }
  return finish(value(i));
}

double gltf_frame_time(const GltfAnimation& anim, int f, int n) {
  if (n <= 1) return anim.start;
  return anim.start + (anim.end - anim.start) * static_cast<double>(f) / static_cast<double>(n - 1);
}

// ---- the reader -------------------------------------------------------------------------------------

namespace {

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                  int, void*) {
  return true;  // textures are not used: do not decode them
}

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

/// The parsed file (.gltf with data: URIs or side files, or .glb; images are not decoded). Throws Error
/// "<file>: ..." for a missing file, another extension, a side file outside the file's folder, or
/// tinygltf's parse error.
tinygltf::Model load_model(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::exists(path)) throw Error(file + ": no such file");
  const std::string ext = lower_ext(path);
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
  return model;
}

}  // namespace

GltfRig read_gltf(const std::filesystem::path& path) {
  const std::string file = path.string();
  const tinygltf::Model model = load_model(path);
  const Reader rd{model, file};
  if (!model.extensionsRequired.empty())
    rd.fail("requires extension '" + model.extensionsRequired.front() + "' (unsupported)");

  GltfRig rig;
  rig.file = path;

  // ---- nodes and hierarchy
  const int N = static_cast<int>(model.nodes.size());
  rig.nodes.resize(N);
  for (int i = 0; i < N; ++i) {
    const tinygltf::Node& n = model.nodes[i];
    GltfNode& g = rig.nodes[i];
    g.name = n.name.empty() ? "node " + std::to_string(i) : n.name;
    const std::string label = "node " + std::to_string(i) + (n.name.empty() ? "" : " '" + n.name + "'");
    auto vec = [&](const std::vector<double>& v, size_t size, const char* what) {
      if (v.size() != size)
        rd.fail(label + ": " + what + " has " + std::to_string(v.size()) + " numbers, expected " +
                std::to_string(size));
      for (double x : v)
        if (!std::isfinite(x)) rd.fail(label + ": " + what + " is not finite");
    };
    if (!n.matrix.empty()) {
      vec(n.matrix, 16, "matrix");
      g.has_matrix = true;
      g.matrix = Eigen::Map<const Eigen::Matrix4d>(n.matrix.data());  // column-major, as Eigen
      if ((g.matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
        rd.fail(label + ": matrix last row is not (0 0 0 1)");
    }
    if (!n.translation.empty()) {
      vec(n.translation, 3, "translation");
      g.translation = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
    }
    if (!n.rotation.empty()) {
      vec(n.rotation, 4, "rotation");
      const Eigen::Vector4d q(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]);
      if (q.norm() < 1e-6) rd.fail(label + ": rotation is the zero quaternion");
      g.rotation = quat_xyzw(q.normalized());
    }
    if (!n.scale.empty()) {
      vec(n.scale, 3, "scale");
      g.scale = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
    }
  }
  for (int i = 0; i < N; ++i)
    for (int c : model.nodes[i].children) {
      if (c < 0 || c >= N) rd.fail(rig.nodes[i].name + ": child " + std::to_string(c) + " does not exist");
      if (rig.nodes[c].parent >= 0)
        rd.fail("node " + std::to_string(c) + " '" + rig.nodes[c].name + "' has two parents (" +
                rig.nodes[rig.nodes[c].parent].name + ", " + rig.nodes[i].name + ")");
      rig.nodes[c].parent = i;
    }
  for (int i = 0; i < N; ++i) {  // cycles: walking up from any node must reach a root in < N steps
    int p = i, steps = 0;
    while (p >= 0 && steps <= N) p = rig.nodes[p].parent, ++steps;
    if (p >= 0)
      rd.fail("node " + std::to_string(i) + " '" + rig.nodes[i].name + "' lies on a cycle of children");
  }

  // ---- the skinned mesh node
  for (int i = 0; i < N && rig.mesh_node < 0; ++i)
    if (model.nodes[i].mesh >= 0 && model.nodes[i].skin >= 0) rig.mesh_node = i;
  if (rig.mesh_node < 0) rd.fail("no skinned mesh (no node has both 'mesh' and 'skin')");
  const tinygltf::Node& mnode = model.nodes[rig.mesh_node];
  if (mnode.mesh >= static_cast<int>(model.meshes.size()))
    rd.fail(rig.nodes[rig.mesh_node].name + ": mesh " + std::to_string(mnode.mesh) + " does not exist");
  if (mnode.skin >= static_cast<int>(model.skins.size()))
    rd.fail(rig.nodes[rig.mesh_node].name + ": skin " + std::to_string(mnode.skin) + " does not exist");
  const tinygltf::Mesh& gmesh = model.meshes[mnode.mesh];
  const tinygltf::Skin& skin = model.skins[mnode.skin];
  rig.mesh_name = gmesh.name.empty() ? "mesh " + std::to_string(mnode.mesh) : gmesh.name;
  const std::string skin_label =
      "skin " + std::to_string(mnode.skin) + (skin.name.empty() ? "" : " '" + skin.name + "'");

  // ---- skin: joints and inverse bind matrices
  const int J = static_cast<int>(skin.joints.size());
  if (J == 0) rd.fail(skin_label + ": no joints");
  std::vector<int> joint_of_node(N, -1);
  for (int j = 0; j < J; ++j) {
    const int n = skin.joints[j];
    if (n < 0 || n >= N)
      rd.fail(skin_label + ": joint " + std::to_string(j) + " is node " + std::to_string(n) +
              ", which does not exist");
    if (joint_of_node[n] >= 0)
      rd.fail(skin_label + ": node " + std::to_string(n) + " '" + rig.nodes[n].name +
              "' is listed twice (joints " + std::to_string(joint_of_node[n]) + " and " + std::to_string(j) +
              ")");
    joint_of_node[n] = j;
    rig.joint_nodes.push_back(n);
    rig.joint_names.push_back(rig.nodes[n].name);
  }
  rig.joint_parents.assign(J, -1);
  for (int j = 0; j < J; ++j)
    for (int p = rig.nodes[rig.joint_nodes[j]].parent; p >= 0; p = rig.nodes[p].parent)
      if (joint_of_node[p] >= 0) {
        rig.joint_parents[j] = joint_of_node[p];
        break;
      }
  rig.inverse_bind.assign(J, Eigen::Matrix4d::Identity());
  if (skin.inverseBindMatrices >= 0) {
    const RowMatrix ibm = rd.read(skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4, Reader::Kind::Float,
                                  "inverseBindMatrices of " + skin_label);
    if (ibm.rows() < J)
      rd.fail("accessor " + std::to_string(skin.inverseBindMatrices) + " (inverseBindMatrices of " +
              skin_label + "): " + std::to_string(ibm.rows()) + " matrices for " + std::to_string(J) +
              " joints");
    for (int j = 0; j < J; ++j) {
      rig.inverse_bind[j] = Eigen::Map<const Eigen::Matrix4d>(ibm.row(j).data());  // column-major
      if ((rig.inverse_bind[j].row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
        rd.fail("accessor " + std::to_string(skin.inverseBindMatrices) + " (inverseBindMatrices of " +
                skin_label + "): matrix " + std::to_string(j) + " (joint '" + rig.joint_names[j] +
                "') has last row not (0 0 0 1)");
    }
  }

  // ---- primitives: positions, UVs, weights, triangles (file vertices)
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> UV;
  std::vector<std::vector<std::pair<int, double>>> W;  // file vertex -> (joint, weight), merged
  std::vector<std::array<int, 3>> T;
  bool any_uv = false, all_uv = true;
  for (size_t pi = 0; pi < gmesh.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = gmesh.primitives[pi];
    const std::string plabel = "primitive " + std::to_string(pi) + " of mesh '" + rig.mesh_name + "'";
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
      rd.fail(plabel + ": mode " + std::to_string(prim.mode) + " is not supported (only TRIANGLES, mode 4)");
    if (!prim.targets.empty()) rd.fail(plabel + ": morph targets are not supported on a skinned mesh");
    auto attr = [&](const std::string& name) {
      const auto it = prim.attributes.find(name);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    const int pos = attr("POSITION");
    if (pos < 0) rd.fail(plabel + ": no POSITION attribute");
    const RowMatrix pv = rd.read(pos, TINYGLTF_TYPE_VEC3, Reader::Kind::Float, "POSITION of " + plabel);
    const int base = static_cast<int>(P.size());
    const Eigen::Index nv = pv.rows();
    for (Eigen::Index i = 0; i < nv; ++i) P.emplace_back(pv(i, 0), pv(i, 1), pv(i, 2));
    const int tc = attr("TEXCOORD_0");
    if (tc >= 0) {
      any_uv = true;
      const RowMatrix uv =
          rd.read(tc, TINYGLTF_TYPE_VEC2, Reader::Kind::FloatOrNormalized, "TEXCOORD_0 of " + plabel);
      if (uv.rows() != nv)
        rd.fail("accessor " + std::to_string(tc) + " (TEXCOORD_0 of " + plabel +
                "): " + std::to_string(uv.rows()) + " elements for " + std::to_string(nv) + " vertices");
      for (Eigen::Index i = 0; i < nv; ++i) UV.emplace_back(uv(i, 0), 1.0 - uv(i, 1));
    } else {
      all_uv = false;
      for (Eigen::Index i = 0; i < nv; ++i) UV.emplace_back(0.0, 0.0);
    }
    // Weights: every set n with JOINTS_n and WEIGHTS_n.
    W.resize(P.size());
    if (attr("JOINTS_0") < 0 || attr("WEIGHTS_0") < 0)
      rd.fail(plabel + ": a skinned primitive needs JOINTS_0 and WEIGHTS_0");
    for (int set = 0;; ++set) {
      const int ja = attr("JOINTS_" + std::to_string(set)), wa = attr("WEIGHTS_" + std::to_string(set));
      if (ja < 0 && wa < 0) break;
      if (ja < 0 || wa < 0)
        rd.fail(plabel + ": JOINTS_" + std::to_string(set) + " and WEIGHTS_" + std::to_string(set) +
                " must come together");
      const std::string jl = "JOINTS_" + std::to_string(set) + " of " + plabel,
                        wl = "WEIGHTS_" + std::to_string(set) + " of " + plabel;
      const RowMatrix jv = rd.read(ja, TINYGLTF_TYPE_VEC4, Reader::Kind::JointIndex, jl);
      const RowMatrix wv = rd.read(wa, TINYGLTF_TYPE_VEC4, Reader::Kind::FloatOrNormalized, wl);
      if (jv.rows() != nv || wv.rows() != nv)
        rd.fail(plabel + ": " + jl + " / " + wl + " have " + std::to_string(jv.rows()) + " / " +
                std::to_string(wv.rows()) + " elements for " + std::to_string(nv) + " vertices");
      for (Eigen::Index i = 0; i < nv; ++i)
        for (int k = 0; k < 4; ++k) {
          const int j = static_cast<int>(jv(i, k));
          const double w = wv(i, k);
          if (j >= J)
            rd.fail("accessor " + std::to_string(ja) + " (" + jl + "): vertex " + std::to_string(i) +
                    " names joint " + std::to_string(j) + ", but " + skin_label + " has " +
                    std::to_string(J) + " joints");
          if (w < 0.0)
            rd.fail("accessor " + std::to_string(wa) + " (" + wl + "): vertex " + std::to_string(i) +
                    " has a negative weight");
          if (w == 0.0) continue;
          auto& row = W[base + i];
          const auto it = std::find_if(row.begin(), row.end(), [&](const auto& e) { return e.first == j; });
          if (it == row.end())
            row.emplace_back(j, w);
          else
            it->second += w;  // a joint named twice: the spec sums the influences
        }
    }
    // Triangles.
    std::vector<int> idx;
    if (prim.indices >= 0) {
      const RowMatrix iv =
          rd.read(prim.indices, TINYGLTF_TYPE_SCALAR, Reader::Kind::UnsignedIndex, "indices of " + plabel);
      idx.resize(iv.rows());
      for (Eigen::Index k = 0; k < iv.rows(); ++k) {
        if (iv(k, 0) >= static_cast<double>(nv))
          rd.fail("accessor " + std::to_string(prim.indices) + " (indices of " + plabel + "): index " +
                  std::to_string(k) + " = " + std::to_string(static_cast<long long>(iv(k, 0))) +
                  " is out of range (" + std::to_string(nv) + " vertices)");
        idx[k] = static_cast<int>(iv(k, 0));
      }
    } else {
      idx.resize(nv);
      for (Eigen::Index k = 0; k < nv; ++k) idx[k] = static_cast<int>(k);
    }
    if (idx.size() % 3 != 0)
      rd.fail(plabel + ": " + std::to_string(idx.size()) + " indices, not a multiple of 3 (TRIANGLES)");
    for (size_t k = 0; k < idx.size(); k += 3)
      T.push_back({base + idx[k], base + idx[k + 1], base + idx[k + 2]});
  }
  if (T.empty()) rd.fail("mesh '" + rig.mesh_name + "' has no triangles");
  if (any_uv && !all_uv)
    rig.warnings.push_back("some primitives have no TEXCOORD_0: their UVs are set to (0, 0)");

  // ---- weights: renormalise rows (file vertices)
  const Eigen::Index nf = static_cast<Eigen::Index>(P.size());
  rig.file_vertices = nf;
  rig.min_weight_sum = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < nf; ++i) {
    double s = 0.0;
    for (const auto& e : W[i]) s += e.second;
    if (!(s > 0.0))
      rd.fail("mesh '" + rig.mesh_name + "': file vertex " + std::to_string(i) +
              " has all skin weights zero");
    rig.min_weight_sum = std::min(rig.min_weight_sum, s);
    if (std::abs(s - 1.0) > 1e-5) ++rig.renormalised_rows;
    for (auto& e : W[i]) e.second /= s;
    std::sort(W[i].begin(), W[i].end());
  }
  if (rig.renormalised_rows > 0) {
    std::ostringstream os;
    os << rig.renormalised_rows << " of " << nf << " vertices had skin weights summing to "
       << rig.min_weight_sum << " .. 1 (not 1): renormalised";
    rig.warnings.push_back(os.str());
  }

  // ---- weld equal positions
  std::unordered_map<PositionKey, int, PositionHash> first;
  first.reserve(static_cast<size_t>(nf));
  rig.file_to_surface.resize(nf);
  std::vector<int> representative;
  for (Eigen::Index i = 0; i < nf; ++i) {
    PositionKey key{{P[i].x() + 0.0, P[i].y() + 0.0, P[i].z() + 0.0}};  // + 0.0 turns −0 into +0
    const auto [it, inserted] = first.emplace(key, static_cast<int>(representative.size()));
    if (inserted) representative.push_back(static_cast<int>(i));
    rig.file_to_surface[i] = it->second;
  }
  const Eigen::Index n = static_cast<Eigen::Index>(representative.size());
  rig.mesh.V.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) rig.mesh.V.row(v) = P[representative[v]].transpose();
  for (Eigen::Index i = 0; i < nf; ++i) {
    const auto& a = W[representative[rig.file_to_surface[i]]];
    if (representative[rig.file_to_surface[i]] == i) continue;
    const auto& b = W[i];
    double diff = 0.0;  // max |w_a − w_b| over the union of joints (rows are sorted by joint)
    size_t p = 0, q = 0;
    while (p < a.size() || q < b.size()) {
      if (q == b.size() || (p < a.size() && a[p].first < b[q].first))
        diff = std::max(diff, a[p++].second);
      else if (p == a.size() || b[q].first < a[p].first)
        diff = std::max(diff, b[q++].second);
      else
        diff = std::max(diff, std::abs(a[p++].second - b[q++].second));
    }
    if (diff > 1e-6) ++rig.weld_weight_mismatches;
    rig.weld_weight_max_difference = std::max(rig.weld_weight_max_difference, diff);
  }
  if (rig.weld_weight_mismatches > 0)
    rig.warnings.push_back(
        std::to_string(rig.weld_weight_mismatches) +
        " welded vertices had skin weights different from the vertex they were welded to (max "
        "difference " +
        std::to_string(rig.weld_weight_max_difference) + "): the first one's weights are used");
  std::vector<Eigen::Triplet<double>> trip;
  for (Eigen::Index v = 0; v < n; ++v)
    for (const auto& e : W[representative[v]]) trip.emplace_back(static_cast<int>(v), e.first, e.second);
  rig.weights.resize(n, J);
  rig.weights.setFromTriplets(trip.begin(), trip.end());

  std::vector<std::array<int, 3>> kept;
  kept.reserve(T.size());
  for (const auto& t : T) {
    const int a = rig.file_to_surface[t[0]], b = rig.file_to_surface[t[1]], c = rig.file_to_surface[t[2]];
    if (a == b || b == c || a == c)
      ++rig.dropped_faces;
    else
      kept.push_back(t);
  }
  if (kept.empty()) rd.fail("mesh '" + rig.mesh_name + "': every triangle is degenerate");
  if (rig.dropped_faces > 0)
    rig.warnings.push_back(std::to_string(rig.dropped_faces) +
                           " triangles with two equal corner positions were dropped");
  const Eigen::Index m = static_cast<Eigen::Index>(kept.size());
  rig.mesh.F.resize(m, 3);
  if (any_uv) rig.mesh.FUV.resize(m, 3);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      rig.mesh.F(f, k) = rig.file_to_surface[kept[f][k]];
      if (any_uv) rig.mesh.FUV(f, k) = kept[f][k];
    }
  if (any_uv) {
    rig.mesh.UV.resize(nf, 2);
    for (Eigen::Index i = 0; i < nf; ++i) rig.mesh.UV.row(i) = UV[i].transpose();
  }

  // ---- animations
  for (size_t ai = 0; ai < model.animations.size(); ++ai) {
    const tinygltf::Animation& a = model.animations[ai];
    GltfAnimation anim;
    anim.name = a.name.empty() ? "animation " + std::to_string(ai) : a.name;
    anim.start = std::numeric_limits<double>::infinity();
    anim.end = -std::numeric_limits<double>::infinity();
    int skipped = 0;
    for (size_t ci = 0; ci < a.channels.size(); ++ci) {
      const tinygltf::AnimationChannel& ch = a.channels[ci];
      const std::string clabel = "channel " + std::to_string(ci) + " of " + anim.name;
      if (ch.target_node < 0) {
        ++skipped;  // no target node: the spec allows extensions to define one; nothing to animate here
        continue;
      }
      if (ch.target_node >= N)
        rd.fail(clabel + ": target node " + std::to_string(ch.target_node) + " does not exist");
      GltfChannel g;
      g.node = ch.target_node;
      if (ch.target_path == "translation")
        g.path = GltfPath::Translation;
      else if (ch.target_path == "rotation")
        g.path = GltfPath::Rotation;
      else if (ch.target_path == "scale")
        g.path = GltfPath::Scale;
      else if (ch.target_path == "weights") {
        ++skipped;
        continue;
      } else
        rd.fail(clabel + ": target path '" + ch.target_path + "' is not supported");
      if (rig.nodes[g.node].has_matrix)
        rd.fail(clabel + ": animates node '" + rig.nodes[g.node].name +
                "', which is given by a matrix (not allowed)");
      if (ch.sampler < 0 || ch.sampler >= static_cast<int>(a.samplers.size()))
        rd.fail(clabel + ": sampler " + std::to_string(ch.sampler) + " does not exist");
      const tinygltf::AnimationSampler& s = a.samplers[ch.sampler];
      const std::string slabel = "sampler " + std::to_string(ch.sampler) + " of " + anim.name;
      if (s.interpolation == "LINEAR" || s.interpolation.empty())
        g.interpolation = GltfInterpolation::Linear;
      else if (s.interpolation == "STEP")
        g.interpolation = GltfInterpolation::Step;
      else if (s.interpolation == "CUBICSPLINE")
        g.interpolation = GltfInterpolation::CubicSpline;
      else
        rd.fail(slabel + ": interpolation '" + s.interpolation + "' is not supported");
      const RowMatrix in = rd.read(s.input, TINYGLTF_TYPE_SCALAR, Reader::Kind::Float, "input of " + slabel);
      if (in.rows() < 1)
        rd.fail("accessor " + std::to_string(s.input) + " (input of " + slabel + "): no key times");
      for (Eigen::Index k = 1; k < in.rows(); ++k)
        if (!(in(k, 0) > in(k - 1, 0)))
          rd.fail("accessor " + std::to_string(s.input) + " (input of " + slabel + "): key time " +
                  std::to_string(k) + " is not after key time " + std::to_string(k - 1));
      g.times = in.col(0);
      const bool rot = g.path == GltfPath::Rotation;
      g.values = rd.read(s.output, rot ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3,
                         rot ? Reader::Kind::Rotation : Reader::Kind::Float, "output of " + slabel);
      const Eigen::Index expect = in.rows() * (g.interpolation == GltfInterpolation::CubicSpline ? 3 : 1);
      if (g.values.rows() != expect)
        rd.fail("accessor " + std::to_string(s.output) + " (output of " + slabel +
                "): " + std::to_string(g.values.rows()) + " values for " + std::to_string(in.rows()) +
                " key times (expected " + std::to_string(expect) + ")");
      if (rot)
        for (Eigen::Index k = 0; k < g.values.rows(); ++k)
          if ((g.interpolation != GltfInterpolation::CubicSpline || k % 3 == 1) &&
              g.values.row(k).norm() < 1e-6)
            rd.fail("accessor " + std::to_string(s.output) + " (output of " + slabel + "): key " +
                    std::to_string(k) + " is the zero quaternion");
      // LINEAR and STEP rotation keys are unit quaternions by the spec: normalise the float32 values so
      // that slerp measures the true angle (a CUBICSPLINE's values and tangents stay as stored).
      if (rot && g.interpolation != GltfInterpolation::CubicSpline) g.values.rowwise().normalize();
      anim.start = std::min(anim.start, g.times[0]);
      anim.end = std::max(anim.end, g.times[g.times.size() - 1]);
      anim.channels.push_back(std::move(g));
    }
    if (anim.channels.empty()) anim.start = anim.end = 0.0;
    if (skipped > 0)
      rig.warnings.push_back(anim.name + ": " + std::to_string(skipped) +
                             " channels on morph weights (or without a target) skipped");
    rig.animations.push_back(std::move(anim));
  }

  // ---- scale: the joints and the mesh node must be similarities (rest and animated). Other nodes are
  // free: a transform common to the mesh node and the joints (a scene root's axis change or scale)
  // cancels in W_mesh⁻¹ W_j; one between them shows up in the joint rest transforms below (Error naming
  // the joint) or, if animated, in skinning_motors / rig_pose_motors (Error naming the joint and time).
  std::vector<bool> relevant(N, false);
  relevant[rig.mesh_node] = true;
  for (int j : rig.joint_nodes) relevant[j] = true;
  for (int i = 0; i < N; ++i) {
    if (!relevant[i]) continue;
    const GltfNode& g = rig.nodes[i];
    const std::string label = "node " + std::to_string(i) + " '" + g.name + "'";
    if (g.has_matrix)
      scaled_motor(g.matrix, file + ": " + label + " matrix");  // throws for shear / non-uniform scale
    else if (!uniform_positive(g.scale)) {
      std::ostringstream os;
      os << label << ": scale (" << g.scale.x() << ", " << g.scale.y() << ", " << g.scale.z()
         << ") is not uniform and positive (a joint, the mesh node or their ancestors must scale uniformly)";
      rd.fail(os.str());
    }
  }
  for (const GltfAnimation& a : rig.animations)
    for (const GltfChannel& c : a.channels) {
      if (!relevant[c.node] || c.path != GltfPath::Scale) continue;
      for (Eigen::Index k = 0; k < c.values.rows(); ++k) {
        const Eigen::Vector3d s = c.values.row(k).transpose();
        const bool tangent = c.interpolation == GltfInterpolation::CubicSpline && k % 3 != 1;
        if (tangent ? !uniform_tangent(s) : !uniform_positive(s)) {
          std::ostringstream os;
          os << a.name << ": animated scale of node " << c.node << " '" << rig.nodes[c.node].name << "' (key "
             << k << ": " << s.x() << ", " << s.y() << ", " << s.z() << ") is not uniform and positive";
          rd.fail(os.str());
        }
      }
    }

  // ---- joint rest transforms (mesh space), as similarities relative to the parent joint
  const std::vector<Eigen::Matrix4d> world = node_world_matrices(rig, -1, 0.0);
  const Eigen::Matrix4d mesh_inv = affine_inverse(world[rig.mesh_node]);
  rig.joint_rest_local.resize(J);
  for (int j = 0; j < J; ++j) {
    const Eigen::Matrix4d rel_j = mesh_inv * world[rig.joint_nodes[j]];
    const int p = rig.joint_parents[j];
    const Eigen::Matrix4d local =
        p < 0 ? rel_j : affine_inverse(mesh_inv * world[rig.joint_nodes[p]]) * rel_j;
    rig.joint_rest_local[j] =
        scaled_motor(local, file + ": joint '" + rig.joint_names[j] + "' rest transform");
  }
  return rig;
}

// ---- evaluation ---------------------------------------------------------------------------------------

std::vector<Eigen::Matrix4d> node_local_matrices(const GltfRig& rig, int anim, double t) {
  if (anim < -1 || anim >= static_cast<int>(rig.animations.size()))
    throw Error(rig.file.string() + ": animation " + std::to_string(anim) + " does not exist (the file has " +
                std::to_string(rig.animations.size()) + ")");
  if (!std::isfinite(t)) throw Error(rig.file.string() + ": animation time is not finite");
  const size_t N = rig.nodes.size();
  std::vector<Eigen::Vector3d> T(N), S(N);
  std::vector<Eigen::Quaterniond> R(N);
  for (size_t i = 0; i < N; ++i)
    T[i] = rig.nodes[i].translation, R[i] = rig.nodes[i].rotation, S[i] = rig.nodes[i].scale;
  if (anim >= 0)
    for (const GltfChannel& c : rig.animations[anim].channels) {
      const Eigen::VectorXd v = c.sample(t);
      switch (c.path) {
        case GltfPath::Translation:
          T[c.node] = v.head<3>();
          break;
        case GltfPath::Rotation:
          R[c.node] = quat_xyzw(v.head<4>());
          break;
        case GltfPath::Scale:
          S[c.node] = v.head<3>();
          break;
      }
    }
  std::vector<Eigen::Matrix4d> out(N);
  for (size_t i = 0; i < N; ++i)
    out[i] = rig.nodes[i].has_matrix ? rig.nodes[i].matrix : trs_matrix(T[i], R[i], S[i]);
  return out;
}

std::vector<Eigen::Matrix4d> node_world_matrices(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> local = node_local_matrices(rig, anim, t);
  const size_t N = rig.nodes.size();
  std::vector<Eigen::Matrix4d> world(N);
  std::vector<char> done(N, 0);
  std::vector<int> chain;
  for (size_t i = 0; i < N; ++i) {
    chain.clear();
    for (int p = static_cast<int>(i); p >= 0 && !done[p]; p = rig.nodes[p].parent) chain.push_back(p);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const int p = rig.nodes[*it].parent;
      world[*it] = p < 0 ? local[*it] : Eigen::Matrix4d(world[p] * local[*it]);
      done[*it] = 1;
    }
  }
  return world;
}

std::vector<Eigen::Matrix4d> joint_world_matrices(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> world = node_world_matrices(rig, anim, t);
  std::vector<Eigen::Matrix4d> out;
  out.reserve(rig.joint_nodes.size());
  for (int n : rig.joint_nodes) out.push_back(world[n]);
  return out;
}

std::vector<Eigen::Matrix4d> skinning_matrices(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> world = node_world_matrices(rig, anim, t);
  const Eigen::Matrix4d mesh_inv = affine_inverse(world[rig.mesh_node]);
  std::vector<Eigen::Matrix4d> out;
  out.reserve(rig.joint_nodes.size());
  for (size_t j = 0; j < rig.joint_nodes.size(); ++j)
    out.push_back(mesh_inv * world[rig.joint_nodes[j]] * rig.inverse_bind[j]);
  return out;
}

std::vector<ScaledMotor> skinning_motors(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> s = skinning_matrices(rig, anim, t);
  std::vector<ScaledMotor> out;
  out.reserve(s.size());
  for (size_t j = 0; j < s.size(); ++j)
    out.push_back(scaled_motor(s[j], rig.file.string() + ": joint '" + rig.joint_names[j] +
                                         "' skinning transform at t = " + std::to_string(t)));
  return out;
}

std::vector<ScaledMotor> joint_rest_frames(const GltfRig& rig) {
  const std::vector<Eigen::Matrix4d> world = node_world_matrices(rig, -1, 0.0);
  const Eigen::Matrix4d mesh_inv = affine_inverse(world[rig.mesh_node]);
  std::vector<ScaledMotor> out;
  for (size_t j = 0; j < rig.joint_nodes.size(); ++j)
    out.push_back(scaled_motor(mesh_inv * world[rig.joint_nodes[j]],
                               rig.file.string() + ": joint '" + rig.joint_names[j] + "' rest frame"));
  return out;
}

Eigen::MatrixXd skin_positions(const GltfRig& rig, int anim, double t) {
  const std::vector<Eigen::Matrix4d> s = skinning_matrices(rig, anim, t);
  const Eigen::MatrixXd& V = rig.mesh.V;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (int j = 0; j < rig.weights.outerSize(); ++j) {
    const Eigen::Matrix3d l = s[j].topLeftCorner<3, 3>();
    const Eigen::Vector3d tr = s[j].topRightCorner<3, 1>();
    for (Eigen::SparseMatrix<double>::InnerIterator it(rig.weights, j); it; ++it)
      out.row(it.row()) += it.value() * (l * V.row(it.row()).transpose() + tr).transpose();
  }
  return out;
}

// ---- baked output -----------------------------------------------------------------------------------

void write_gltf_morph_animation(const std::filesystem::path& path, const Mesh& rest,
                                const std::vector<Eigen::MatrixXd>& frames, const std::vector<double>& times,
                                const std::string& name, const Eigen::Matrix4d& node_matrix) {
  const std::string file = path.string();
  const std::string ext = lower_ext(path);
  if (ext != ".gltf" && ext != ".glb") throw Error(file + ": not a glTF file name (expected .gltf or .glb)");
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
  const bool uv = rest.has_uv();

  // glTF vertices: one per distinct (vertex, uv index) corner pair (UVs split vertices at seams),
  // ordered by vertex, so that welding equal positions back (read_gltf_morph_animation) returns the
  // vertices in `rest`'s order.
  const detail::CornerSplit split = detail::split_corners(rest, file, true);
  const std::vector<int>&vert_of = split.vertex, &uv_of = split.uv;
  const size_t nv = vert_of.size(), nframes = frames.size();

  detail::GltfBuilder b;
  tinygltf::Model& model = b.model;
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<float> pos(3 * nv);
  for (size_t i = 0; i < nv; ++i)
    for (int c = 0; c < 3; ++c) pos[3 * i + c] = static_cast<float>(rest.V(vert_of[i], c));
  prim.attributes["POSITION"] = b.vec3_accessor(pos);
  if (uv) {
    std::vector<float> tex(2 * nv);
    for (size_t i = 0; i < nv; ++i) {
      tex[2 * i] = static_cast<float>(rest.UV(uv_of[i], 0));
      tex[2 * i + 1] = static_cast<float>(1.0 - rest.UV(uv_of[i], 1));  // back to glTF's top-left origin
    }
    prim.attributes["TEXCOORD_0"] =
        b.float_accessor(tex, TINYGLTF_TYPE_VEC2, 2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }
  {
    const int view = b.add_view(split.indices.data(), split.indices.size() * sizeof(uint32_t),
                                TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.indices = b.add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, split.indices.size(),
                                  TINYGLTF_TYPE_SCALAR);
  }
  // Morph targets: POSITION displacements (float32: the positions read back as rest + displacement).
  for (size_t f = 0; f < nframes; ++f) {
    std::vector<float> d(3 * nv);
    for (size_t i = 0; i < nv; ++i)
      for (int c = 0; c < 3; ++c)
        d[3 * i + c] = static_cast<float>(frames[f](vert_of[i], c) - static_cast<double>(pos[3 * i + c]));
    prim.targets.push_back({{"POSITION", b.vec3_accessor(d)}});
  }
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(prim);
  mesh.weights.assign(nframes, 0.0);
  mesh.weights[0] = 1.0;
  {
    tinygltf::Value::Array names;
    for (size_t f = 0; f < nframes; ++f) {
      char label[32];
      std::snprintf(label, sizeof label, "frame %04zu", f);
      names.emplace_back(std::string(label));
    }
    tinygltf::Value::Object extras;
    extras["targetNames"] = tinygltf::Value(std::move(names));
    mesh.extras = tinygltf::Value(std::move(extras));
  }
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = name;
  node.mesh = 0;
  if (!node_matrix.isIdentity(0.0))
    node.matrix.assign(node_matrix.data(), node_matrix.data() + 16);  // column-major
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  // The weights animation: STEP, key f at times[f], output one-hot on target f (nframes² floats).
  {
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
    model.animations.push_back(a);
  }
  b.write(path, ext == ".glb");
}

// ---- baked output read back ---------------------------------------------------------------------------

GltfMorphAnimation read_gltf_morph_animation(const std::filesystem::path& path) {
  const std::string file = path.string();
  const tinygltf::Model model = load_model(path);
  const Reader rd{model, file};
  if (!model.extensionsRequired.empty())
    rd.fail("requires extension '" + model.extensionsRequired.front() + "' (unsupported)");

  // The node: the first one whose mesh has morph targets.
  const int N = static_cast<int>(model.nodes.size());
  int node = -1;
  for (int i = 0; i < N && node < 0; ++i) {
    const int mi = model.nodes[i].mesh;
    if (mi < 0 || mi >= static_cast<int>(model.meshes.size())) continue;
    for (const auto& prim : model.meshes[mi].primitives)
      if (!prim.targets.empty()) node = i;
  }
  if (node < 0) rd.fail("no mesh with morph targets (not a baked animation)");
  const tinygltf::Mesh& gmesh = model.meshes[model.nodes[node].mesh];
  GltfMorphAnimation out;
  out.name = gmesh.name;

  // Global matrix: the chain of parents' rest matrices (a node with two parents or a cycle is an error).
  {
    std::vector<int> parent(N, -1);
    for (int i = 0; i < N; ++i)
      for (int c : model.nodes[i].children) {
        if (c < 0 || c >= N)
          rd.fail("node " + std::to_string(i) + ": child " + std::to_string(c) + " does not exist");
        if (parent[c] >= 0) rd.fail("node " + std::to_string(c) + " has two parents");
        parent[c] = i;
      }
    auto local = [&](int i) {
      const tinygltf::Node& nd = model.nodes[i];
      const std::string label = "node " + std::to_string(i);
      auto check = [&](const std::vector<double>& v, size_t size, const char* what) {
        if (v.size() != size) rd.fail(label + ": " + what + " has " + std::to_string(v.size()) + " numbers");
        for (double x : v)
          if (!std::isfinite(x)) rd.fail(label + ": " + what + " is not finite");
      };
      if (!nd.matrix.empty()) {
        check(nd.matrix, 16, "matrix");
        return Eigen::Matrix4d(Eigen::Map<const Eigen::Matrix4d>(nd.matrix.data()));
      }
      Eigen::Vector3d t = Eigen::Vector3d::Zero(), sc = Eigen::Vector3d::Ones();
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      if (!nd.translation.empty())
        check(nd.translation, 3, "translation"), t = Eigen::Vector3d(nd.translation.data());
      if (!nd.scale.empty()) check(nd.scale, 3, "scale"), sc = Eigen::Vector3d(nd.scale.data());
      if (!nd.rotation.empty()) {
        check(nd.rotation, 4, "rotation");
        const Eigen::Vector4d r(nd.rotation.data());
        if (r.norm() < 1e-6) rd.fail(label + ": rotation is the zero quaternion");
        q = quat_xyzw(r.normalized());
      }
      return trs_matrix(t, q, sc);
    };
    int steps = 0;
    for (int i = node; i >= 0; i = parent[i]) {
      if (++steps > N) rd.fail("node " + std::to_string(node) + " lies on a cycle of children");
      out.node_matrix = local(i) * out.node_matrix;
    }
  }

  // Primitives: base positions, UVs, triangles, and the targets' displacements (file vertices).
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> UV;
  std::vector<std::array<int, 3>> T;
  std::vector<std::vector<Eigen::Vector3d>> D;  // per target, per file vertex
  bool any_uv = false;
  const std::string mlabel =
      "mesh '" + (gmesh.name.empty() ? std::to_string(model.nodes[node].mesh) : gmesh.name) + "'";
  for (size_t pi = 0; pi < gmesh.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = gmesh.primitives[pi];
    const std::string plabel = "primitive " + std::to_string(pi) + " of " + mlabel;
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
      rd.fail(plabel + ": mode " + std::to_string(prim.mode) + " is not supported (only TRIANGLES, mode 4)");
    if (pi == 0) D.resize(prim.targets.size());
    if (prim.targets.size() != D.size())
      rd.fail(plabel + ": " + std::to_string(prim.targets.size()) + " morph targets, primitive 0 has " +
              std::to_string(D.size()));
    auto attr = [&](const std::map<std::string, int>& attrs, const std::string& name) {
      const auto it = attrs.find(name);
      return it == attrs.end() ? -1 : it->second;
    };
    const int pos = attr(prim.attributes, "POSITION");
    if (pos < 0) rd.fail(plabel + ": no POSITION attribute");
    const RowMatrix pv = rd.read(pos, TINYGLTF_TYPE_VEC3, Reader::Kind::Float, "POSITION of " + plabel);
    const int base = static_cast<int>(P.size());
    const Eigen::Index nv = pv.rows();
    for (Eigen::Index i = 0; i < nv; ++i) P.emplace_back(pv(i, 0), pv(i, 1), pv(i, 2));
    const int tc = attr(prim.attributes, "TEXCOORD_0");
    if (tc >= 0) {
      any_uv = true;
      const RowMatrix uv =
          rd.read(tc, TINYGLTF_TYPE_VEC2, Reader::Kind::FloatOrNormalized, "TEXCOORD_0 of " + plabel);
      if (uv.rows() != nv)
        rd.fail("TEXCOORD_0 of " + plabel + ": " + std::to_string(uv.rows()) + " elements for " +
                std::to_string(nv) + " vertices");
      for (Eigen::Index i = 0; i < nv; ++i) UV.emplace_back(uv(i, 0), 1.0 - uv(i, 1));
    } else {
      for (Eigen::Index i = 0; i < nv; ++i) UV.emplace_back(0.0, 0.0);
    }
    for (size_t f = 0; f < D.size(); ++f) {
      const std::string tlabel = "POSITION of morph target " + std::to_string(f) + " of " + plabel;
      const int ta = attr(prim.targets[f], "POSITION");
      if (ta < 0) rd.fail(tlabel + ": missing");
      const RowMatrix dv = rd.read(ta, TINYGLTF_TYPE_VEC3, Reader::Kind::Float, tlabel);
      if (dv.rows() != nv)
        rd.fail(tlabel + ": " + std::to_string(dv.rows()) + " elements for " + std::to_string(nv) +
                " vertices");
      for (Eigen::Index i = 0; i < nv; ++i) D[f].emplace_back(dv(i, 0), dv(i, 1), dv(i, 2));
    }
    std::vector<int> idx;
    if (prim.indices >= 0) {
      const RowMatrix iv =
          rd.read(prim.indices, TINYGLTF_TYPE_SCALAR, Reader::Kind::UnsignedIndex, "indices of " + plabel);
      for (Eigen::Index k = 0; k < iv.rows(); ++k) {
        if (iv(k, 0) >= static_cast<double>(nv))
          rd.fail("indices of " + plabel + ": index " + std::to_string(k) + " is out of range (" +
                  std::to_string(nv) + " vertices)");
        idx.push_back(static_cast<int>(iv(k, 0)));
      }
    } else {
      for (Eigen::Index k = 0; k < nv; ++k) idx.push_back(static_cast<int>(k));
    }
    if (idx.size() % 3 != 0)
      rd.fail(plabel + ": " + std::to_string(idx.size()) + " indices, not a multiple of 3 (TRIANGLES)");
    for (size_t k = 0; k < idx.size(); k += 3)
      T.push_back({base + idx[k], base + idx[k + 1], base + idx[k + 2]});
  }
  if (T.empty()) rd.fail(mlabel + " has no triangles");

  // Weld equal base positions (as read_gltf); a welded vertex takes its first file vertex's frames.
  const Eigen::Index nf = static_cast<Eigen::Index>(P.size());
  std::unordered_map<PositionKey, int, PositionHash> first;
  std::vector<int> surface(static_cast<size_t>(nf)), representative;
  for (Eigen::Index i = 0; i < nf; ++i) {
    PositionKey key{{P[i].x() + 0.0, P[i].y() + 0.0, P[i].z() + 0.0}};
    const auto [it, inserted] = first.emplace(key, static_cast<int>(representative.size()));
    if (inserted) representative.push_back(static_cast<int>(i));
    surface[static_cast<size_t>(i)] = it->second;
  }
  const Eigen::Index n = static_cast<Eigen::Index>(representative.size());
  out.mesh.V.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) out.mesh.V.row(v) = P[representative[v]].transpose();
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : T) {
    const int a = surface[t[0]], b = surface[t[1]], c = surface[t[2]];
    if (a != b && b != c && a != c) kept.push_back(t);
  }
  if (kept.empty()) rd.fail(mlabel + ": every triangle is degenerate");
  out.mesh.F.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (size_t f = 0; f < kept.size(); ++f)
    for (int k = 0; k < 3; ++k) out.mesh.F(static_cast<Eigen::Index>(f), k) = surface[kept[f][k]];
  if (any_uv) {
    out.mesh.UV.resize(nf, 2);
    for (Eigen::Index i = 0; i < nf; ++i) out.mesh.UV.row(i) = UV[i].transpose();
    out.mesh.FUV.resize(out.mesh.F.rows(), 3);
    for (size_t f = 0; f < kept.size(); ++f)
      for (int k = 0; k < 3; ++k) out.mesh.FUV(static_cast<Eigen::Index>(f), k) = kept[f][k];
  }
  out.frames.resize(D.size());
  for (size_t f = 0; f < D.size(); ++f) {
    out.frames[f].resize(n, 3);
    for (Eigen::Index v = 0; v < n; ++v)
      out.frames[f].row(v) = (P[representative[v]] + D[f][representative[v]]).transpose();
  }

  // Times: the first animation channel on this node's weights.
  out.times.resize(D.size());
  for (size_t f = 0; f < D.size(); ++f) out.times[f] = static_cast<double>(f);
  for (size_t ai = 0; ai < model.animations.size(); ++ai) {
    const tinygltf::Animation& an = model.animations[ai];
    for (const auto& ch : an.channels) {
      if (ch.target_node != node || ch.target_path != "weights") continue;
      const std::string label =
          "animation " + std::to_string(ai) + " (weights of node " + std::to_string(node) + ")";
      if (ch.sampler < 0 || ch.sampler >= static_cast<int>(an.samplers.size()))
        rd.fail(label + ": sampler does not exist");
      const tinygltf::AnimationSampler& sm = an.samplers[ch.sampler];
      const RowMatrix tin = rd.read(sm.input, TINYGLTF_TYPE_SCALAR, Reader::Kind::Float, "input of " + label);
      const RowMatrix wout =
          rd.read(sm.output, TINYGLTF_TYPE_SCALAR, Reader::Kind::FloatOrNormalized, "output of " + label);
      const Eigen::Index keys = tin.rows(), nt = static_cast<Eigen::Index>(D.size());
      const Eigen::Index per = sm.interpolation == "CUBICSPLINE" ? 3 : 1;
      if (wout.rows() != keys * nt * per)
        rd.fail(label + ": " + std::to_string(wout.rows()) + " weights for " + std::to_string(keys) +
                " keys and " + std::to_string(nt) + " targets");
      std::vector<bool> seen(D.size(), false);
      for (Eigen::Index k = 0; k < keys; ++k) {
        const Eigen::Index row0 = (k * per + (per == 3 ? 1 : 0)) * nt;
        Eigen::Index best = 0;
        for (Eigen::Index f = 1; f < nt; ++f)
          if (wout(row0 + f, 0) > wout(row0 + best, 0)) best = f;
        if (!seen[best]) seen[best] = true, out.times[best] = tin(k, 0);
      }
      for (size_t f = 0; f < D.size(); ++f)
        if (!seen[f])
          rd.fail(label + ": morph target " + std::to_string(f) +
                  " is never the largest weight (not a baked frame sequence)");
      return out;
    }
  }
  return out;
}

}  // namespace spinmotor
