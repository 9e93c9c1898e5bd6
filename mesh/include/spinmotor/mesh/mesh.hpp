#pragma once
// spinmotor::Mesh — the triangle mesh every module passes around.
//
// Numerics run on Eigen arrays: V (n×3 positions, double) and F (m×3 vertex indices, faces
// counter-clockwise seen from outside). Texture coordinates are per corner, not per vertex: UV is a
// t×2 list and FUV an m×3 index into it, exactly as OBJ `vt`/`f v/vt` stores them, so seams survive a
// read/write round trip. Deformations replace V and never touch UV/FUV.
#include <Eigen/Core>

namespace spinmotor {

struct Mesh {
  Eigen::MatrixXd V;    ///< n×3 vertex positions
  Eigen::MatrixXi F;    ///< m×3 triangles (counter-clockwise)
  Eigen::MatrixXd UV;   ///< t×2 texture coordinates, empty if the mesh has none
  Eigen::MatrixXi FUV;  ///< m×3 per-corner indices into UV, empty if the mesh has none

  Eigen::Index num_vertices() const { return V.rows(); }
  Eigen::Index num_faces() const { return F.rows(); }
  bool has_uv() const { return UV.rows() > 0 && FUV.rows() == F.rows(); }
};

}  // namespace spinmotor
