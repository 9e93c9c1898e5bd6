#pragma once
// Boundary prescription (Crane, Pinkall & Schröder 2011, §7.4, Figs 7, 15, 16 bottom): edit a surface
// with boundary by giving new tangent directions T̃ of its boundary curve (§5.7) and keeping the mean
// curvature half-density (ρ = 0), or changing it too (any ρ, e.g. the §7.2 fit of an edit).
// As in the paper, the target tangent of a boundary vertex is the unit outgoing boundary edge of the
// target curve (boundary_tangents below), the same convention SpinTransform uses for the source.
#include <Eigen/Core>
#include <sstream>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/mesh/topology.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace spinmotor {

/// Inputs: V (n×3), F (m×3, counter-clockwise). Output: SpinBoundaryTangents listing every boundary
/// vertex (loop order, loops as boundary_loops returns them) with its unit outgoing boundary edge
/// V[next] − V[i] (surface on the left). Pass another V of the same connectivity (a target shape) to
/// get target tangents. Throws Error if the mesh has no boundary or a boundary edge has zero length
/// (naming the vertex).
inline SpinBoundaryTangents boundary_tangents(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const std::vector<std::vector<int>> loops = boundary_loops(F);
  Eigen::Index k = 0;
  for (const auto& loop : loops) k += static_cast<Eigen::Index>(loop.size());
  if (k == 0) throw Error("boundary_tangents: the mesh has no boundary");
  SpinBoundaryTangents bt;
  bt.vertices.resize(k);
  bt.targets.resize(k, 3);
  Eigen::Index r = 0;
  for (const auto& loop : loops)
    for (std::size_t j = 0; j < loop.size(); ++j, ++r) {
      const int i = loop[j], next = loop[(j + 1) % loop.size()];
      if (i < 0 || i >= V.rows() || next < 0 || next >= V.rows()) {
        std::ostringstream m;
        m << "boundary_tangents: boundary vertex " << (i < 0 || i >= V.rows() ? i : next)
          << " is outside [0, " << V.rows() << ")";
        throw Error(m.str());
      }
      const Eigen::RowVector3d e = V.row(next) - V.row(i);
      if (!e.allFinite() || !(e.norm() > 0)) {
        std::ostringstream m;
        m << "boundary_tangents: boundary edge from vertex " << i << " to " << next
          << " has zero length or is not finite";
        throw Error(m.str());
      }
      bt.vertices[r] = i;
      bt.targets.row(r) = e / e.norm();
    }
  return bt;
}

/// §7.4: the spin transformation of `mesh` whose boundary tangents are `targets` (vertices not listed
/// stay free) and whose curvature change is ρ (empty: ρ = 0, keep the half-density). Inputs: mesh,
/// targets (distinct boundary vertices, nonzero k×3 directions), rho (empty or m values), spin options
/// (their `boundary` is replaced by `targets`; the problem must be Standard or Unweighted). Output:
/// the spin result (V n×3). Throws Error on bad input (naming the vertex or face), numerical_error if
/// the solve fails.
inline SpinTransformResult prescribe_boundary(const Mesh& mesh, const SpinBoundaryTangents& targets,
                                              const Eigen::VectorXd& rho = Eigen::VectorXd(),
                                              SpinTransformOptions options = {}) {
  if (targets.vertices.size() == 0) throw Error("prescribe_boundary: no boundary tangents given");
  options.boundary = targets;
  SpinTransform st(mesh, options);
  return st.solve(rho.size() == 0 ? Eigen::VectorXd::Zero(mesh.F.rows()).eval() : rho);
}

}  // namespace spinmotor
