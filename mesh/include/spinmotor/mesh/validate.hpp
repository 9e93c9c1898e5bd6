#pragma once
// Mesh validation: what a triangle soup is (counts, components, boundary, Euler characteristic,
// genus) and what is wrong with it (defects), each with its first offending element so that error
// messages can name it; and require(), which each operation calls at its entry point to reject
// input it cannot handle.
//
// Definitions (all on the face list F; coordinates matter only for the three geometric checks):
//   proper face            a face with three distinct vertex indices. Topology (edges, boundary,
//                          manifoldness, orientation, Euler characteristic) is computed on proper
//                          faces; a face repeating an index is only counted as degenerate.
//   boundary edge          an edge of one proper face. Boundaries are properties, not defects.
//   boundary loops         connected pieces of the boundary-edge graph, plus one per extra pair of
//                          boundary edges at a pinched vertex (a figure eight is two loops). Counted
//                          without face orientation, so a Möbius band has one loop; on an oriented
//                          manifold this is boundary_loops() of topology.hpp.
//   non-manifold edge      an edge of three or more proper faces.
//   non-manifold vertex    a vertex not on a non-manifold edge whose incident faces form more than
//                          one fan (faces linked across the manifold edges at the vertex): two
//                          cones touching at their apexes, a pinched boundary.
//   inconsistent orient.   a manifold edge (two faces) traversed in the same direction by both.
//   degenerate face        repeats a vertex index, or has area ≤ 1e-10 × the mean face area. The
//                          ratio is relative so the test is scale-invariant; 1e-10 in area is 1e-5
//                          in edge length, far below any modelling resolution yet far above double
//                          rounding (1e-16), so the count barely depends on it (ogre.obj: 4 faces
//                          for every ratio from 1e-16 to 1e-4, see tests). Faces touching a
//                          non-finite vertex are not tested (their vertex is reported instead).
//   duplicate vertex       a vertex whose coordinates equal (==) those of a lower-numbered vertex;
//                          counts every such vertex, so k coincident vertices count k − 1.
//   unreferenced vertex    a vertex in no face.
//   non-finite vertex      a vertex with a NaN or infinite coordinate.
//   components             connected components of the faces (vertices joined by face edges);
//                          unreferenced vertices are not components.
//   Euler characteristic   χ = V − E + F over referenced vertices, edges and proper faces.
//   genus                  Σ over components of (2 − χ_i − b_i) / 2 (b_i = boundary loops of the
//                          component): defined only for an oriented manifold without repeated-index
//                          faces; −1 otherwise (JSON null), with the reason in genus_note.
// Defects: non-manifold edges or vertices, degenerate faces, duplicate, unreferenced or non-finite
// vertices, inconsistent orientation. Boundaries, several components and genus are properties.
#include <array>
#include <string>
#include <string_view>

#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// Relative area threshold for degenerate faces (see the definitions above).
inline constexpr double kDegenerateAreaRatio = 1e-10;

struct MeshReport {
  // Properties.
  Eigen::Index vertices = 0;
  Eigen::Index faces = 0;
  Eigen::Index edges = 0;  ///< unique edges of proper faces
  int components = 0;
  int boundary_loops = 0;
  Eigen::Index boundary_edges = 0;
  long long euler_characteristic = 0;
  int genus = -1;             ///< −1 when not defined; see genus_note
  std::string genus_note;     ///< why genus is −1 (empty when defined)
  double mean_face_area = 0;  ///< over proper faces with finite corners

  // Defects (counts).
  Eigen::Index non_manifold_edges = 0;
  Eigen::Index non_manifold_vertices = 0;
  Eigen::Index degenerate_faces = 0;
  Eigen::Index duplicate_vertices = 0;
  Eigen::Index unreferenced_vertices = 0;
  Eigen::Index nonfinite_vertices = 0;
  Eigen::Index inconsistent_orientation = 0;  ///< number of manifold edges oriented the same way twice

  // First offender of each kind (−1 when none), for messages.
  std::array<int, 2> first_boundary_edge{-1, -1};      ///< (a, b), a < b
  std::array<int, 2> first_non_manifold_edge{-1, -1};  ///< (a, b), a < b
  int non_manifold_edge_faces = 0;                     ///< faces on first_non_manifold_edge
  int first_non_manifold_vertex = -1;
  int non_manifold_vertex_fans = 0;  ///< fans at first_non_manifold_vertex
  int first_degenerate_face = -1;
  double first_degenerate_area = 0;  ///< its area (0 when it repeats an index)
  int first_duplicate_vertex = -1;   ///< duplicates first_duplicate_of (< it)
  int first_duplicate_of = -1;
  int first_unreferenced_vertex = -1;
  int first_nonfinite_vertex = -1;
  std::array<int, 2> first_inconsistent_edge{-1, -1};  ///< (a, b), a < b
  std::array<int, 2> inconsistent_edge_faces{-1, -1};  ///< the two faces that both run a -> b (or b -> a)

  bool is_closed() const { return boundary_edges == 0; }
  bool is_manifold() const { return non_manifold_edges == 0 && non_manifold_vertices == 0; }
  bool is_oriented() const { return inconsistent_orientation == 0; }
  bool has_defects() const {
    return non_manifold_edges + non_manifold_vertices + degenerate_faces + duplicate_vertices +
               unreferenced_vertices + nonfinite_vertices + inconsistent_orientation >
           0;
  }
  /// One sentence per defect kind present, naming the count and the first offender, e.g.
  /// "1 non-manifold edge: edge (0, 1) is shared by 3 faces". Empty when there is no defect.
  std::string defects_summary() const;
};

/// Inputs: a mesh (V n×3, F m×3). Output: its report. Throws Error if the mesh is malformed (F not
/// m×3, an index outside [0, n)), naming the face. O(m log m + n log n).
MeshReport validate(const Mesh& mesh);

/// What an operation needs of its input mesh. Aggregate: use designated initializers, e.g.
/// require(mesh, {.manifold = true, .closed = true, .genus0 = true}, "spin_transform").
struct Requirements {
  bool finite = true;             ///< no NaN/Inf coordinates
  bool manifold = false;          ///< no non-manifold edges or vertices
  bool oriented = false;          ///< consistent orientation
  bool no_degenerate = false;     ///< no degenerate faces
  bool closed = false;            ///< no boundary edges
  bool genus0 = false;            ///< genus defined and 0 (implies manifold and oriented)
  bool single_component = false;  ///< one connected component
  bool no_unreferenced = false;   ///< every vertex in a face
  bool no_duplicates = false;     ///< no two vertices at the same position
  Eigen::Index min_faces = 1;     ///< at least this many faces
};

/// What the Dirac operators and curvature flows need: one closed, oriented, manifold surface without
/// degenerate faces or stray vertices (any genus).
inline constexpr Requirements kClosedSurface{.manifold = true,
                                             .oriented = true,
                                             .no_degenerate = true,
                                             .closed = true,
                                             .single_component = true,
                                             .no_unreferenced = true};

/// Throws Error("<operation> needs <what>: <first offending element>") for the first requirement the
/// mesh fails, e.g. "spin_transform needs a closed mesh: edge (12, 57) is on a boundary (24 boundary
/// edges in 1 loop)". Returns the report so the caller need not validate again.
MeshReport require(const Mesh& mesh, const Requirements& req, std::string_view operation);

/// Same, on a report computed earlier.
void require(const MeshReport& report, const Requirements& req, std::string_view operation);

}  // namespace spinmotor
