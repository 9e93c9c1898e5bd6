#pragma once
// The deformer contract: one shape shared by every deformer of the project (surface harmonic, spline,
// FFD, cage, ARAP, skin). Read this once; every deformer header only says what differs.
//
//   auto d = SomeDeformer::bind(rest_mesh, handles, options);   // all precomputation, once
//   Eigen::MatrixXd V;                                          // caller-owned output buffer
//   for (each frame) d.pose(motors, V);                         // per-frame work
//
// bind(const Mesh& rest, std::span<const Handle> handles, const Options& options) -> Deformer
//   Does everything that does not depend on the pose: validation of the mesh and the handles
//   (check_handles below), weights (harmonic fields, basis functions), matrix factorizations, and the
//   rest-pose binding of the key motors (CGA paper §III.A: when the rest pose has key motors R_j^0
//   that are not the identity, each vertex is stored as p'_i = ~M_i^0 p_i M_i^0, M_i^0 the rest motor
//   field, so that posing with the rest motors reproduces the rest mesh). Throws spinmotor::Error
//   naming the bad element (handle name, vertex, connected component). The returned object owns
//   copies of everything it needs; the mesh may be destroyed afterwards.
//
// pose(std::span<const ga::Mot> motors, Eigen::MatrixXd& V_out)
//   One unit motor per control (handle, key, lattice point ... in the order the deformer documents),
//   motors relative to the rest pose (all identities reproduce the rest mesh). Writes the n×3
//   deformed positions into V_out, which is resized only if its size is wrong (so from the second
//   frame on pose() allocates nothing). Parallel over vertices (OpenMP, from
//   parallel::kMotorBlend vertices on, core/parallel.hpp). Non-const because a deformer may keep per-frame scratch (prepared motor logarithms, ARAP's
//   warm start): one pose() at a time per object. Throws Error on a wrong motor count or a
//   non-finite motor.
//
// Motor conventions are those of spinmotor::ga: a motor M moves a point by M p ~M, blends are
// exp(Σ w_j log M_j) (Blend::Log) unless stated. Texture coordinates are never touched: the deformed
// mesh is the rest mesh with V replaced.
#include <Eigen/Core>
#include <span>
#include <string>

namespace spinmotor {

/// A named set of vertices that one motor (or one boundary condition) acts on.
struct Handle {
  std::string name;         ///< used in error messages ("handle 'tip'")
  Eigen::VectorXi vertices;  ///< distinct vertex indices in [0, n)
};

/// Checks that every handle is non-empty, has indices in [0, n) without repeats, and that no vertex
/// belongs to two handles. Throws Error naming the handle (and the other handle and the vertex for a
/// shared vertex). `who` prefixes the message (e.g. "SurfaceHarmonicDeformer").
void check_handles(std::span<const Handle> handles, Eigen::Index n, const char* who);

/// Mean of the rows of V (n×3) listed by the handle (its gizmo anchor, an IK tip); zero for an empty handle.
inline Eigen::Vector3d handle_centroid(const Eigen::MatrixXd& V, const Handle& h) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < h.vertices.size(); ++k) c += V.row(h.vertices[k]).transpose();
  return h.vertices.size() > 0 ? Eigen::Vector3d(c / static_cast<double>(h.vertices.size())) : c;
}

}  // namespace spinmotor
