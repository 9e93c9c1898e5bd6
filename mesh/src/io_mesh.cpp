// read_mesh / write_mesh: dispatch by extension, plus the helpers of io_detail.hpp.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "io_detail.hpp"
#include "spinmotor/mesh/io.hpp"

namespace spinmotor {
namespace fs = std::filesystem;

namespace io_detail {

std::string read_file_bytes(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path.string() + "': it is a directory");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error("cannot open '" + path.string() + "': " + (errno ? std::strerror(errno) : "unknown error"));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error("cannot read '" + path.string() + "'");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  in.read(bytes.data(), size);
  if (in.gcount() != size) throw Error("cannot read '" + path.string() + "': short read");
  return bytes;
}

void fail(const fs::path& path, std::size_t line, const std::string& msg) {
  if (line > 0) throw Error(path.string() + ":" + std::to_string(line) + ": " + msg);
  throw Error(path.string() + ": " + msg);
}

Mesh Soup::to_mesh() const {
  using RowMat3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMat3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMat2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
  Mesh m;
  m.V = Eigen::Map<const RowMat3d>(V.data(), static_cast<Eigen::Index>(V.size() / 3), 3);
  m.F = Eigen::Map<const RowMat3i>(F.data(), static_cast<Eigen::Index>(F.size() / 3), 3);
  m.UV = Eigen::Map<const RowMat2d>(UV.data(), static_cast<Eigen::Index>(UV.size() / 2), 2);
  m.FUV = Eigen::Map<const RowMat3i>(FUV.data(), static_cast<Eigen::Index>(FUV.size() / 3), 3);
  return m;
}

void check_writable(const fs::path& path, const Mesh& mesh) {
  const std::string where = "cannot write '" + path.string() + "': ";
  if (mesh.V.cols() != 3 && mesh.V.size() > 0)
    throw Error(where + "V has " + std::to_string(mesh.V.cols()) + " columns, expected 3");
  if (mesh.F.cols() != 3 && mesh.F.size() > 0)
    throw Error(where + "F has " + std::to_string(mesh.F.cols()) + " columns, expected 3");
  if (mesh.F.rows() == 0) throw Error(where + "the mesh has no faces");
  const Eigen::Index n = mesh.V.rows();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= n)
        throw Error(where + "face " + std::to_string(f) + " references vertex " +
                    std::to_string(mesh.F(f, c)) + ", but the mesh has " + std::to_string(n) + " vertices");
  if (mesh.UV.size() > 0 && mesh.UV.cols() != 2)
    throw Error(where + "UV has " + std::to_string(mesh.UV.cols()) + " columns, expected 2");
  if (mesh.FUV.size() > 0) {
    if (mesh.FUV.rows() != mesh.F.rows() || mesh.FUV.cols() != 3)
      throw Error(where + "FUV is " + std::to_string(mesh.FUV.rows()) + "x" +
                  std::to_string(mesh.FUV.cols()) + ", expected " + std::to_string(mesh.F.rows()) +
                  "x3 (one texture index per corner)");
    const Eigen::Index t = mesh.UV.rows();
    for (Eigen::Index f = 0; f < mesh.FUV.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        if (mesh.FUV(f, c) < 0 || mesh.FUV(f, c) >= t)
          throw Error(where + "face " + std::to_string(f) + " references texture coordinate " +
                      std::to_string(mesh.FUV(f, c)) + ", but the mesh has " + std::to_string(t));
  }
}

}  // namespace io_detail

MeshFormat mesh_format(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".stl") return MeshFormat::Stl;
  throw Error("unsupported mesh format '" + path.extension().string() + "' (file " + path.string() +
              "); expected .obj, .off, .ply or .stl");
}

Mesh read_mesh(const fs::path& path) {
  switch (mesh_format(path)) {
    case MeshFormat::Obj:
      return read_obj(path);
    case MeshFormat::Off:
      return read_off(path);
    case MeshFormat::Ply:
      return read_ply(path);
    case MeshFormat::Stl:
      return read_stl(path);
  }
  throw Error("unreachable");
}

void write_mesh(const fs::path& path, const Mesh& mesh, const WriteOptions& options) {
  switch (mesh_format(path)) {
    case MeshFormat::Obj:
      return write_obj(path, mesh, options.objects);
    case MeshFormat::Off:
      return write_off(path, mesh);
    case MeshFormat::Ply:
      return write_ply(path, mesh, options.binary);
    case MeshFormat::Stl:
      return write_stl(path, mesh, options.binary);
  }
}

}  // namespace spinmotor
