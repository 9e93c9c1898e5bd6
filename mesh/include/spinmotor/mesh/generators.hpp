#pragma once
// Procedural meshes: the embedded defaults of the CLI and the source of the 10k / 100k / 1M-vertex
// benchmark meshes.
//
// Every generator returns a spinmotor::Mesh with
//   - faces counter-clockwise seen from outside (outward normals; closed meshes have positive signed
//     volume), and
//   - texture coordinates per corner (UV t×2, FUV m×3) whose triangles are counter-clockwise in the
//     (u, v) plane, i.e. the parameterisation preserves orientation. Periodic directions are cut along
//     a seam whose UVs are duplicated (u = 0 and u = 1 are different UV rows of the same vertex, so
//     FUV differs from F there and no face wraps across u = 1 → 0). A pole vertex gets one UV per
//     incident face (u at the middle of that face's sector), so pole triangles are not degenerate in UV.
// Bad parameters throw spinmotor::Error naming the parameter. All sizes are in the caller's units.
// Generation is O(output size); a 1M-vertex mesh takes a few tens of milliseconds.
#include "spinmotor/mesh/mesh.hpp"

namespace spinmotor {

/// Icosphere: the icosahedron (level 0) subdivided `level` times by edge midpoints, every new vertex
/// projected onto the sphere. Vertices: 10·4^level + 2, faces: 20·4^level (level 5: 10,242;
/// level 7: 163,842; level 8: 655,362). All vertices lie on the sphere of `radius` centred at the
/// origin; vertex 0 is the north pole (0, 0, radius) and vertex 11 the south pole.
/// UV: u = longitude / 2π (from +x towards +y), v = 1 − polar angle / π (v = 1 at the north pole).
/// The seam meridian u = 0 is not a path of edges (it bisects triangles of the icosahedron), so faces
/// it cuts keep their shape and extend past u = 1 (into [1, 1.1], a texture wraps there), duplicating
/// the UVs of their corners with u < ½. Requires 0 ≤ level ≤ 10 and radius > 0.
Mesh icosphere(int level, double radius = 1.0);

/// Latitude–longitude sphere of `radius` centred at the origin: `rings` circles of latitude, ring k
/// (k = 0..rings−1, from south to north) at polar angle θ_k = π (rings − k) / (rings + 1) from +z, each
/// with `sectors` vertices at longitudes φ_j = 2π j / sectors, plus the two poles.
/// Vertices: rings·sectors + 2 (ring k, sector j is vertex k·sectors + j; the south pole is
/// rings·sectors, the north pole rings·sectors + 1). Faces: 2·rings·sectors.
/// Near-square quads at the equator need sectors ≈ 2·(rings + 1): e.g. 70×142 → 9,942 vertices,
/// 223×446 → 99,460, 707×1414 → 999,700.
/// UV: u = j / sectors (seam column duplicated at u = 1), v = 1 − θ/π. Requires rings ≥ 1,
/// sectors ≥ 3, radius > 0.
Mesh uv_sphere(int rings, int sectors, double radius = 1.0);

/// Planar grid in the z = 0 plane, centred at the origin, of extent size.x() × size.y(), with
/// n.x() × n.y() vertices (vertex (i, j) is index i + j·n.x(), at x = −size.x()/2 + i·size.x()/(n.x()−1)).
/// Each cell is split along its (i, j)–(i+1, j+1) diagonal; faces are CCW seen from +z.
/// Faces: 2 (n.x() − 1)(n.y() − 1). UV = (x / size.x() + ½, y / size.y() + ½) per vertex, FUV = F.
/// Requires size > 0 and n ≥ 2 in both directions.
Mesh grid(const Eigen::Vector2d& size, const Eigen::Vector2i& n);

/// Torus around the z axis with major radius R and minor radius r (0 < r < R): u vertices around the
/// big circle (angle φ) times v vertices around the tube (angle ψ), vertex (i, j) = index i·v + j at
/// ((R + r cos ψ) cos φ, (R + r cos ψ) sin φ, r sin ψ), φ = 2π i/u, ψ = 2π j/v.
/// Vertices: u·v, faces: 2·u·v, genus 1. UV = (i/u, j/v) with both seams duplicated.
/// Requires u ≥ 3, v ≥ 3.
Mesh torus(double R, double r, int u, int v);

/// Cylindrical tube of `radius` around the z axis from z = 0 to z = length: `rings` vertex rings
/// (ring k at z = length·k/(rings−1)) of `sides` vertices each (vertex k·sides + j at angle 2π j/sides).
/// Open: rings·sides vertices, 2·(rings−1)·sides faces, two boundary loops (χ = 0).
/// Capped: each end is closed by a fan around a centre vertex (bottom centre rings·sides, top centre
/// rings·sides + 1), adding 2 vertices and 2·sides faces (a closed sphere, χ = 2).
/// An "80k-vertex tube" is rings = 400, sides = 200.
/// UV: u = j / sides (seam duplicated); v = arc length along the profile / total profile length (open:
/// z / length; capped: the profile runs centre → rim → up the side → rim → centre).
/// Requires radius > 0, length > 0, rings ≥ 2, sides ≥ 3.
Mesh tube(double radius, double length, int rings, int sides, bool capped = false);

/// Capsule: the cylinder of `radius` from z = 0 to z = length closed by hemispheres (centred at z = 0
/// and z = length), so it spans z ∈ [−radius, length + radius]. The profile curve from the south pole
/// to the north pole (arc length L = π·radius + length) is sampled at `rings` equally spaced interior
/// points, each a ring of `sides` vertices; the poles are vertices rings·sides (south) and
/// rings·sides + 1 (north). Vertices: rings·sides + 2, faces: 2·rings·sides. The surface is C¹
/// (tangent-continuous); with length = 0 it is uv_sphere(rings, sides, radius), vertex for vertex.
/// UV: u = j / sides (seam duplicated), v = arc length from the south pole / L.
/// Requires radius > 0, length ≥ 0, rings ≥ 1, sides ≥ 3.
Mesh capsule(double radius, double length, int rings, int sides);

/// Bar with a "+"-shaped cross section extruded along z from 0 to `length`: the section is the union
/// of two arms of `width` crossing at the origin, each reaching ±half_span along x resp. y. The side
/// walls are `segments` bands along z (so the bar can bend smoothly), the ends are flat caps meshed
/// by a structured grid of the section, and the mesh is closed (χ = 2). The section resolution is
/// chosen so that side quads are close to square: each arm tip is split into
/// max(1, round(width/h)) edges and each arm side into max(1, round((half_span − width/2)/h)) edges,
/// h = length / segments.
/// UV: an isometric atlas in [0, 1]²: the unrolled side walls (u along the section outline, v along z)
/// and, to their right, the two caps (the bottom one mirrored so that every chart keeps orientation).
/// Requires length > 0, 0 < width < 2·half_span, segments ≥ 1.
Mesh cross_bar(double length = 4.0, double half_span = 0.5, double width = 0.25, int segments = 64);

}  // namespace spinmotor
