#pragma once
// Explicit, opt-in repairs. Nothing in the project repairs a mesh behind the caller's back: readers
// return the file as it is, operations reject what they cannot handle (validate.hpp), and the caller
// chooses one of these. Both keep the order of the vertices they keep, keep the faces (same count,
// same order, same corners) and leave texture coordinates (UV, FUV) untouched, since those index
// their own list.
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// Drops vertices that no face references.
/// Inputs: mesh (V n×3, F m×3). Output: the mesh with V n'×3 (n' = referenced vertices, in their
/// original order) and F renumbered. If old_to_new is given it receives n entries: the new index of
/// each old vertex, or −1 for a dropped one.
Mesh remove_unreferenced_vertices(const Mesh& mesh, Eigen::VectorXi* old_to_new = nullptr);

/// Merges vertices with exactly equal coordinates (==; 0.0 and −0.0 merge, NaN never does) into the
/// lowest-numbered one, and drops the others.
/// Inputs: mesh (V n×3, F m×3). Output: the mesh with V n'×3 (the first vertex of each position,
/// in original order) and F renumbered. old_to_new (optional) receives n entries: the new index of
/// each old vertex (merged vertices share one). Merging can create faces that repeat a vertex (a
/// face spanning two copies of a point); they are kept — validate() reports them as degenerate.
Mesh merge_duplicate_vertices(const Mesh& mesh, Eigen::VectorXi* old_to_new = nullptr);

}  // namespace spinmotor
