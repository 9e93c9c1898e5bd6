#pragma once
// Shared by DeltaMushDeformer and DirectDeltaMushDeformer (private to deform/): the mesh checks both
// make at bind, the one-ring adjacency of the uniform Laplacian, and the bone matrices of a pose.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/deform/motor_blend_field.hpp"  // checked_unit_motor
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/mesh/validate.hpp"

namespace spinmotor::detail {

/// Vertex one-rings in CSR form: the neighbours of vertex i are index[offset[i] .. offset[i+1]),
/// ascending.
struct Rings {
  std::vector<int> offset;
  std::vector<int> index;
  int valence(Eigen::Index i) const { return offset[i + 1] - offset[i]; }
};

/// What the mush deformers need of the rest mesh: at least one face, finite coordinates, a manifold
/// (and, with `oriented`, consistently oriented) surface and no vertex outside every face (it would
/// have no neighbour to be smoothed towards). Throws Error naming the first offending element.
inline void require_mush_mesh(const Mesh& rest, bool oriented, const char* who) {
  require(rest,
          {.finite = true, .manifold = true, .oriented = oriented, .no_unreferenced = true, .min_faces = 1},
          who);
}

/// One-rings from the unique edges E (k×2) of a mesh with n vertices.
inline Rings vertex_rings(const Eigen::MatrixXi& E, Eigen::Index n) {
  Rings r;
  r.offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index e = 0; e < E.rows(); ++e) ++r.offset[E(e, 0) + 1], ++r.offset[E(e, 1) + 1];
  for (Eigen::Index i = 0; i < n; ++i) r.offset[i + 1] += r.offset[i];
  r.index.resize(r.offset[n]);
  std::vector<int> fill(r.offset.begin(), r.offset.end() - 1);
  // E is sorted lexicographically with E(e,0) < E(e,1): appending in edge order keeps each ring sorted
  // for the smaller endpoint; the other endpoint's entries arrive in increasing E(e,0) order too,
  // but interleaved with its own larger neighbours, so sort each ring once.
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    r.index[fill[E(e, 0)]++] = E(e, 1);
    r.index[fill[E(e, 1)]++] = E(e, 0);
  }
  for (Eigen::Index i = 0; i < n; ++i)
    std::sort(r.index.begin() + r.offset[i], r.index.begin() + r.offset[i + 1]);
  return r;
}

/// The 3×4 matrices [R_j | t_j] of the bone motions K_j = F_j ~F_j^0 (as SkinDeformer computes them),
/// written into T (size B). Throws Error naming the bone for a wrong count or a frame that is not a
/// finite unit motor.
inline void bone_matrices(std::span<const Bone> bones, std::span<const ga::Mot> frames,
                          std::vector<Eigen::Matrix<double, 3, 4>>& T, const char* who) {
  if (frames.size() != bones.size())
    throw Error(std::string(who) + ": " + std::to_string(frames.size()) + " bone frames for " +
                std::to_string(bones.size()) + " bones");
  T.resize(bones.size());
  for (std::size_t j = 0; j < bones.size(); ++j) {
    // the same test as checked_unit_motor, whose message (a string built per call) is made only on failure
    const ga::Mot& m = frames[j];
    bool ok = true;
    for (double c : m.c) ok = ok && std::isfinite(c);
    if (ok) {
      const auto nn = m * ga::reverse(m);
      ok = std::abs(nn.get<ga::blade::s>() - 1.0) <= 1e-6 && std::abs(nn.get<ga::blade::e123ni>()) <= 1e-6;
    }
    if (!ok) checked_unit_motor(m, std::string(who) + ": frame of bone '" + bones[j].name + "'");  // throws
    const ga::Mot K = ga::normalize(ga::normalize(m) * ga::reverse(bones[j].rest));
    T[j] = ga::to_isometry(K).matrix().topRows<3>();
  }
}

}  // namespace spinmotor::detail
