#pragma once
// Mesh files: read and write OBJ, OFF, PLY and STL.
//
// Reading returns the file's face *soup* faithfully: vertices in file order, faces in file order,
// no vertex merging (except STL, below), no face dropping, no reorientation — a defective mesh is
// read as it is so that validate() can report the defects. Polygons with more than three corners
// are fan-triangulated (c0, c_i, c_i+1) in file order. A file with no face at all is an error.
// Every syntax error throws spinmotor::Error naming `file:line` (text formats) or the element and
// byte offset (binary formats); an index out of range names the face's line. NaN/Inf coordinates
// are read as they are (validation reports them).
//
// Formats (chosen by the extension, case-insensitive):
//   .obj  `v x y z [w|r g b]`, `vt u [v [w]]`, `f` with corners `v`, `v/vt`, `v//vn`, `v/vt/vn`,
//         1-based or negative (relative) indices; other statements (vn, o, g, s, usemtl, mtllib,
//         l, p, ...) are ignored. Texture coordinates are kept per corner exactly as in the file
//         (UV = the `vt` list in file order, FUV = each corner's vt index), so writing back
//         reproduces every `vt` line and every face's vt index. A face with vt on some corners and
//         not on others, or a file mixing faces with and without vt, is an error naming the line.
//   .off  OFF / COFF / NOFF / CNOFF / STOFF headers (ASCII); per-vertex and per-face extras
//         (colours, normals) are skipped to the end of their line.
//   .ply  ASCII, binary_little_endian and binary_big_endian; `vertex` x, y, z of any scalar type
//         (read as double, no rounding to float), `face` `vertex_indices` (or `vertex_index`) list
//         of any integer type; other properties and elements are skipped.
//   .stl  ASCII or binary (told apart by size: a binary file is 84 + 50·n bytes). STL stores
//         every triangle with its own three corners, so positions that are exactly equal (==) are
//         merged into one vertex on read — the only merging any reader does. Degenerate triangles
//         are kept.
//
// Writing (atomic, see atomic_file.hpp; parent directories are created):
//   ASCII numbers are written in the shortest form that reads back to the same double, so an
//   OBJ/OFF/ASCII-PLY round trip is bit-exact. Binary PLY stores doubles (exact); binary STL
//   stores float32 by definition of the format (positions round to float). Texture coordinates
//   are written to OBJ only (OFF, PLY and STL do not carry per-corner texture coordinates).
//
// Why not OpenMesh::IO (which the design first named): OpenMesh's OBJ/OFF readers build a halfedge
// mesh and drop or split non-manifold faces (which validation must report), do not keep `vt`
// indexing and give no line numbers; its PLY reader and writer round positions to float32 (1/3
// comes back as 0.3333333432674408) and accept a truncated ASCII PLY silently; its STL reader drops
// degenerate triangles. The hand-written readers here keep everything and name the bad line.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

enum class MeshFormat { Obj, Off, Ply, Stl };

/// The format of `path` from its extension (case-insensitive). Throws Error
/// "unsupported mesh format '.xyz' (file ...)" for any other extension.
MeshFormat mesh_format(const std::filesystem::path& path);

/// Options for write_mesh.
struct WriteOptions {
  bool binary = true;  ///< PLY and STL: binary (little-endian) or ASCII; OBJ and OFF are always ASCII
  /// OBJ: named objects, each (name, first face) in increasing first-face order: an `o name` line before
  /// that face (importers make one object of each). Other formats have no objects and ignore it.
  std::vector<std::pair<std::string, Eigen::Index>> objects{};
};

/// Reads a mesh, format by extension. Output: V (n×3), F (m×3, file order), and for OBJ with vt
/// UV (t×2) and FUV (m×3). Throws Error naming the file and line on any problem.
Mesh read_mesh(const std::filesystem::path& path);

/// Writes a mesh atomically, format by extension. Throws Error if the mesh is malformed (F or FUV
/// index out of range, wrong column counts, no faces) or the file cannot be written; on error no
/// file (partial or temporary) is left behind and an existing file is untouched.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const WriteOptions& options = {});

// Per-format entry points (same contracts as read_mesh / write_mesh, any extension accepted).
Mesh read_obj(const std::filesystem::path& path);
Mesh read_off(const std::filesystem::path& path);
Mesh read_ply(const std::filesystem::path& path);
Mesh read_stl(const std::filesystem::path& path);
void write_obj(const std::filesystem::path& path, const Mesh& mesh,
               const std::vector<std::pair<std::string, Eigen::Index>>& objects = {});
void write_off(const std::filesystem::path& path, const Mesh& mesh);
void write_ply(const std::filesystem::path& path, const Mesh& mesh, bool binary = true);
void write_stl(const std::filesystem::path& path, const Mesh& mesh, bool binary = true);

}  // namespace spinmotor
