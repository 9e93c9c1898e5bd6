#pragma once
// Conversion between spinmotor::Mesh (Eigen arrays, the form all numerics use) and an OpenMesh
// halfedge mesh (for code that wants halfedge traversal). Header-only; include it only where
// OpenMesh is available (link OpenMeshCore).
//
// OpenMesh cannot hold a non-manifold face list: to_openmesh() rejects such input with Error naming
// the first face OpenMesh refuses (call validate()/require() first for a full report). Texture
// coordinates travel as OpenMesh halfedge texcoords (the texcoord of a corner is stored on the
// halfedge pointing *to* that corner's vertex, as OpenMesh's own OBJ reader does).
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// OpenMesh traits with double-precision points (OpenMesh's default is float).
struct OpenMeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
};
using OpenMeshTriMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMeshTraits>;

/// Inputs: mesh (V n×3, F m×3, optional UV/FUV). Output: an OpenMesh triangle mesh with the same
/// vertex and face numbering and, if the mesh has UVs, halfedge texcoords. Throws Error naming the
/// first face OpenMesh cannot add (a non-manifold edge or vertex, or a repeated index).
inline OpenMeshTriMesh to_openmesh(const Mesh& mesh) {
  OpenMeshTriMesh om;
  const bool uv = mesh.has_uv();
  if (uv) om.request_halfedge_texcoords2D();
  om.reserve(static_cast<size_t>(mesh.V.rows()), static_cast<size_t>(3 * mesh.F.rows() / 2),
             static_cast<size_t>(mesh.F.rows()));
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
    om.add_vertex(OpenMesh::Vec3d(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2)));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= mesh.V.rows())
        throw Error("to_openmesh: face " + std::to_string(f) + " references vertex " +
                    std::to_string(mesh.F(f, c)) + ", but the mesh has " + std::to_string(mesh.V.rows()) +
                    " vertices");
    // OpenMesh prints its own complaint to std::cerr before returning an invalid handle.
    const auto fh = om.add_face(OpenMesh::VertexHandle(mesh.F(f, 0)), OpenMesh::VertexHandle(mesh.F(f, 1)),
                                OpenMesh::VertexHandle(mesh.F(f, 2)));
    if (!fh.is_valid())
      throw Error("to_openmesh: OpenMesh cannot add face " + std::to_string(f) + " (" +
                  std::to_string(mesh.F(f, 0)) + ", " + std::to_string(mesh.F(f, 1)) + ", " +
                  std::to_string(mesh.F(f, 2)) +
                  "): it makes an edge or a vertex non-manifold, or repeats a vertex");
    if (uv)
      for (const auto heh : om.fh_range(fh))
        for (int c = 0; c < 3; ++c)
          if (om.to_vertex_handle(heh).idx() == mesh.F(f, c))
            om.set_texcoord2D(heh, OpenMesh::Vec2d(mesh.UV(mesh.FUV(f, c), 0), mesh.UV(mesh.FUV(f, c), 1)));
  }
  return om;
}

/// Inputs: an OpenMesh triangle mesh (any traits). Output: V n×3 and F m×3 with the same vertex
/// and face numbering (deleted elements must have been garbage-collected); each face's corners in
/// OpenMesh's halfedge order, which keeps the orientation but may rotate the corners of a face
/// given to to_openmesh(). If the mesh has halfedge texcoords: UV with one row per distinct (u, v)
/// value and FUV indexing it. Throws Error on a non-triangle face.
template <class OMMesh>
Mesh from_openmesh(const OMMesh& om) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
  for (const auto vh : om.vertices())
    for (int k = 0; k < 3; ++k) m.V(vh.idx(), k) = static_cast<double>(om.point(vh)[k]);
  m.F.resize(static_cast<Eigen::Index>(om.n_faces()), 3);
  const bool uv = om.has_halfedge_texcoords2D();
  if (uv) m.FUV.resize(m.F.rows(), 3);
  std::map<std::pair<double, double>, int> uv_index;
  std::vector<std::pair<double, double>> uvs;
  for (const auto fh : om.faces()) {
    int c = 0;
    for (const auto heh : om.fh_ccw_range(fh)) {
      if (c == 3) throw Error("from_openmesh: face " + std::to_string(fh.idx()) + " is not a triangle");
      m.F(fh.idx(), c) = om.to_vertex_handle(heh).idx();
      if (uv) {
        const auto t = om.texcoord2D(heh);
        const std::pair<double, double> key(t[0], t[1]);
        auto [it, added] = uv_index.emplace(key, static_cast<int>(uvs.size()));
        if (added) uvs.push_back(key);
        m.FUV(fh.idx(), c) = it->second;
      }
      ++c;
    }
    if (c != 3) throw Error("from_openmesh: face " + std::to_string(fh.idx()) + " is not a triangle");
  }
  if (uv) {
    m.UV.resize(static_cast<Eigen::Index>(uvs.size()), 2);
    for (std::size_t i = 0; i < uvs.size(); ++i)
      m.UV.row(static_cast<Eigen::Index>(i)) << uvs[i].first, uvs[i].second;
  }
  return m;
}

}  // namespace spinmotor
