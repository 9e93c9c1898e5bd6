#pragma once
// Combinatorial topology of a triangle list: unique edges, edge–face incidence, connected
// components, boundary loops and the boundary / interior vertex sets.
//
// These work on any face list, including non-manifold ones (validation needs them to find the
// defects), so they never build a halfedge structure.
#include <Eigen/Core>
#include <vector>

namespace spinmotor {

/// Unique undirected edges of F and their incidence.
struct EdgeTopology {
  Eigen::MatrixXi E;          ///< k×2 unique edges, E(e,0) < E(e,1), sorted lexicographically
  Eigen::MatrixXi FE;         ///< m×3: FE(f,c) is the edge opposite corner c, i.e. {F(f,c+1), F(f,c+2)}
  Eigen::VectorXi EF_offset;  ///< k+1 offsets into EF_face (CSR)
  Eigen::VectorXi EF_face;    ///< faces incident to each edge, EF_face[EF_offset[e] .. EF_offset[e+1])

  Eigen::Index num_edges() const { return E.rows(); }
  /// Number of faces that share edge e: 1 on the boundary, 2 inside a manifold, > 2 non-manifold.
  int valence(Eigen::Index e) const { return EF_offset[e + 1] - EF_offset[e]; }
};

/// Inputs: F (m×3). Output: the unique edges with FE and edge→face incidence. O(m log m).
EdgeTopology edge_topology(const Eigen::MatrixXi& F);

/// Connected components of the graph whose nodes are the n vertices and whose edges are the face
/// edges. A vertex referenced by no face is a component of its own. Labels are 0..count-1, numbered
/// in order of the smallest vertex index in each component.
Eigen::VectorXi vertex_components(const Eigen::MatrixXi& F, Eigen::Index n, int* count = nullptr);

/// Component label of each face (the label of its vertices under vertex_components), 0..count-1
/// numbered in order of the first face of each component.
Eigen::VectorXi face_components(const Eigen::MatrixXi& F, int* count = nullptr);

/// Boundary loops: each is the cycle of vertices along boundary edges (edges of valence 1), ordered
/// so that the surface lies to the left (same direction as the faces' halfedges). On a pinched
/// boundary (a vertex with several outgoing boundary edges) each closed walk is one loop.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F);

/// Sorted indices of vertices on a boundary edge.
Eigen::VectorXi boundary_vertices(const Eigen::MatrixXi& F, Eigen::Index n);

/// Sorted indices of vertices referenced by F and not on a boundary edge.
Eigen::VectorXi interior_vertices(const Eigen::MatrixXi& F, Eigen::Index n);

}  // namespace spinmotor
