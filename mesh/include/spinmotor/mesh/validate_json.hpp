#pragma once
// JSON form of MeshReport (nlohmann-json, header-only like metrics/json.hpp, so the mesh library does
// not depend on nlohmann): the object `spinmotor check --json` prints (without its "file" key) and the
// dict the Python module's check() returns.
//
// Keys, in the order of the CLI's table: vertices, faces, edges, components, boundary_loops,
// boundary_edges, euler_characteristic, genus (null when undefined, then genus_note), the defect
// counts non_manifold_edges, non_manifold_vertices, degenerate_faces, duplicate_vertices,
// unreferenced_vertices, nonfinite_vertices, inconsistent_orientation, then closed, manifold, ok,
// first (the first offender of each kind present: boundary_edge [a, b], non_manifold_edge [a, b],
// non_manifold_vertex, degenerate_face, duplicate_vertex [v, of], unreferenced_vertex,
// nonfinite_vertex, inconsistent_edge [a, b]; 0-based) and defects (the summary, when any).
#include <nlohmann/json.hpp>

#include "spinmotor/mesh/validate.hpp"

namespace spinmotor {

/// The report as an ordered JSON object (keys above).
inline nlohmann::ordered_json report_json(const MeshReport& r) {
  nlohmann::ordered_json j;
  j["vertices"] = r.vertices;
  j["faces"] = r.faces;
  j["edges"] = r.edges;
  j["components"] = r.components;
  j["boundary_loops"] = r.boundary_loops;
  j["boundary_edges"] = r.boundary_edges;
  j["euler_characteristic"] = r.euler_characteristic;
  j["genus"] = r.genus >= 0 ? nlohmann::ordered_json(r.genus) : nlohmann::ordered_json(nullptr);
  if (r.genus < 0) j["genus_note"] = r.genus_note;
  j["non_manifold_edges"] = r.non_manifold_edges;
  j["non_manifold_vertices"] = r.non_manifold_vertices;
  j["degenerate_faces"] = r.degenerate_faces;
  j["duplicate_vertices"] = r.duplicate_vertices;
  j["unreferenced_vertices"] = r.unreferenced_vertices;
  j["nonfinite_vertices"] = r.nonfinite_vertices;
  j["inconsistent_orientation"] = r.inconsistent_orientation;
  j["closed"] = r.is_closed();
  j["manifold"] = r.is_manifold();
  j["ok"] = !r.has_defects();
  nlohmann::ordered_json first = nlohmann::ordered_json::object();  // first offender of each kind present
  if (r.first_boundary_edge[0] >= 0) first["boundary_edge"] = r.first_boundary_edge;
  if (r.first_non_manifold_edge[0] >= 0) first["non_manifold_edge"] = r.first_non_manifold_edge;
  if (r.first_non_manifold_vertex >= 0) first["non_manifold_vertex"] = r.first_non_manifold_vertex;
  if (r.first_degenerate_face >= 0) first["degenerate_face"] = r.first_degenerate_face;
  if (r.first_duplicate_vertex >= 0)
    first["duplicate_vertex"] = {r.first_duplicate_vertex, r.first_duplicate_of};
  if (r.first_unreferenced_vertex >= 0) first["unreferenced_vertex"] = r.first_unreferenced_vertex;
  if (r.first_nonfinite_vertex >= 0) first["nonfinite_vertex"] = r.first_nonfinite_vertex;
  if (r.first_inconsistent_edge[0] >= 0) first["inconsistent_edge"] = r.first_inconsistent_edge;
  j["first"] = first;
  if (r.has_defects()) j["defects"] = r.defects_summary();
  return j;
}

}  // namespace spinmotor
