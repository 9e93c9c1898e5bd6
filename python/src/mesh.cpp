// Python bindings of the mesh module: Mesh, read_mesh / write_mesh, check (validation report),
// metrics (deformation metrics), generators.
#include <filesystem>

#include "common.hpp"
#include "spinmotor/mesh/generators.hpp"
#include "spinmotor/mesh/io.hpp"
#include "spinmotor/mesh/metrics/deformation_metrics.hpp"
#include "spinmotor/mesh/metrics/json.hpp"
#include "spinmotor/mesh/validate.hpp"
#include "spinmotor/mesh/validate_json.hpp"

namespace spinmotor::python {

namespace {

/// The Python-side mesh: numpy arrays; unpacks as (V, F).
struct PyMesh {
  py::object V, F, UV, FUV;
};

PyMesh wrap(const Mesh& m) {
  PyMesh p;
  p.V = to_numpy(m.V);
  p.F = to_numpy(m.F);
  p.UV = m.has_uv() ? py::object(to_numpy(m.UV)) : py::object(py::none());
  p.FUV = m.has_uv() ? py::object(to_numpy(m.FUV)) : py::object(py::none());
  return p;
}

/// Runs a generator with the GIL released and wraps its mesh.
template <class G>
PyMesh generate(G g) {
  Mesh mesh;
  {
    py::gil_scoped_release release;
    mesh = g();
  }
  return wrap(mesh);
}

}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<PyMesh>(m, "Mesh", R"doc(
A triangle mesh as numpy arrays (returned by read_mesh and the generators).

Attributes:
  V:   (n, 3) float64 vertex positions
  F:   (m, 3) int32 triangles (counter-clockwise seen from outside)
  UV:  (t, 2) float64 per-corner texture coordinates, or None
  FUV: (m, 3) int32 indices into UV per face corner, or None

A Mesh unpacks as (V, F):  V, F = spinmotor.icosphere(3)
)doc")
      .def(py::init([](py::object V, py::object F, py::object UV, py::object FUV) {
             Mesh mm = to_mesh(V, F, false);
             PyMesh p;
             p.V = to_numpy(mm.V);
             p.F = to_numpy(mm.F);
             if (!UV.is_none() || !FUV.is_none()) {
               Eigen::MatrixXd uv = to_matrix(UV, "UV", -1, 2);
               Eigen::MatrixXi fuv = to_int_matrix(FUV, "FUV", mm.F.rows(), 3);
               if (fuv.size() && (fuv.minCoeff() < 0 || fuv.maxCoeff() >= uv.rows()))
                 throw Error("FUV: an index is outside [0, " + std::to_string(uv.rows()) + ")");
               p.UV = to_numpy(uv);
               p.FUV = to_numpy(fuv);
             } else {
               p.UV = py::none();
               p.FUV = py::none();
             }
             return p;
           }),
           py::arg("V"), py::arg("F"), py::arg("UV") = py::none(), py::arg("FUV") = py::none(),
           "Mesh(V, F, UV=None, FUV=None). Validates shapes, dtypes and index ranges (spinmotor.Error).")
      .def_readwrite("V", &PyMesh::V, "V: (n, 3) float64 vertex positions.")
      .def_readwrite("F", &PyMesh::F, "F: (m, 3) int32 triangles (vertex indices, counter-clockwise).")
      .def_readwrite("UV", &PyMesh::UV, "UV: (t, 2) texture coordinates, or None.")
      .def_readwrite("FUV", &PyMesh::FUV, "FUV: (m, 3) texture coordinate index per corner, or None.")
      .def("__iter__", [](const PyMesh& p) { return py::iter(py::make_tuple(p.V, p.F)); })
      .def("__len__", [](const PyMesh&) { return 2; })
      .def("__getitem__",
           [](const PyMesh& p, int i) {
             if (i == 0 || i == -2) return p.V;
             if (i == 1 || i == -1) return p.F;
             throw py::index_error("Mesh unpacks as (V, F)");
           })
      .def("__repr__", [](const PyMesh& p) {
        return "<spinmotor.Mesh " + std::to_string(py::len(p.V)) + " vertices, " +
               std::to_string(py::len(p.F)) + " faces" + (p.UV.is_none() ? "" : ", with UV") + ">";
      });

  m.def(
      "read_mesh",
      [](const std::filesystem::path& path) {
        Mesh mesh;
        {
          py::gil_scoped_release release;
          mesh = read_mesh(path);
        }
        return wrap(mesh);
      },
      py::arg("path"), R"doc(
Reads an OBJ, OFF, PLY or STL file (format by extension).

Input:  path (str or os.PathLike).
Output: a spinmotor.Mesh (V, F and, for an OBJ with texture coordinates, UV and FUV); it unpacks as
        (V, F). The face soup is read as it is (no merging, no reorientation) so check() can report
        its defects.
Errors: spinmotor.Error naming the file and line (unsupported extension, syntax, index out of range).
)doc");

  m.def(
      "write_mesh",
      [](const std::filesystem::path& path, py::object V, py::object F, py::object UV, py::object FUV,
         bool binary) {
        Mesh mesh = to_mesh(V, F, false);
        if (!UV.is_none() || !FUV.is_none()) {
          mesh.UV = to_matrix(UV, "UV", -1, 2);
          mesh.FUV = to_int_matrix(FUV, "FUV", mesh.F.rows(), 3);
        }
        WriteOptions wo;
        wo.binary = binary;
        py::gil_scoped_release release;
        write_mesh(path, mesh, wo);
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("UV") = py::none(), py::arg("FUV") = py::none(),
      py::arg("binary") = WriteOptions{}.binary, R"doc(
Writes a mesh atomically (format by extension: .obj, .off, .ply, .stl).

Inputs: path; V (n, 3) real array; F (m, 3) integer array with indices in [0, n); optional UV (t, 2)
        and FUV (m, 3) (written to OBJ only); binary: PLY/STL binary or ASCII.
Output: None. On error no file (partial or temporary) is left and an existing file is untouched.
Errors: spinmotor.Error for a bad shape, dtype or index (naming the face) or an unwritable path.
)doc");

  m.def(
      "check",
      [](py::object V, py::object F) {
        const Mesh mesh = to_mesh(V, F, /*finite=*/false);
        MeshReport r;
        {
          py::gil_scoped_release release;
          r = validate(mesh);
        }
        return to_python(report_json(r));
      },
      py::arg("V"), py::arg("F"), R"doc(
Validates a mesh: what it is and what is wrong with it.

Inputs:  V (n, 3) real array (NaN/inf allowed: they are reported), F (m, 3) integer array.
Output:  dict with the keys of `spinmotor check --json` except "file": vertices, faces, edges,
         components, boundary_loops, boundary_edges, euler_characteristic, genus (None when undefined,
         then genus_note), non_manifold_edges, non_manifold_vertices, degenerate_faces,
         duplicate_vertices, unreferenced_vertices, nonfinite_vertices, inconsistent_orientation,
         closed, manifold, ok, first (first offender of each kind, 0-based), defects (when any).
Errors:  spinmotor.Error for a bad shape or dtype, or a face index outside [0, n) (naming the face).
)doc");

  m.def(
      "metrics",
      [](py::object V0, py::object V1, py::object F, const std::string& alignment, bool willmore) {
        const Eigen::MatrixXd Vr = to_points(V0, "V0");
        const Eigen::MatrixXd Vd = to_points(V1, "V1");
        if (Vd.rows() != Vr.rows())
          throw Error("V1: has " + std::to_string(Vd.rows()) + " vertices, V0 " + std::to_string(Vr.rows()) +
                      " (same connectivity required)");
        const Eigen::MatrixXi Fi = to_faces(F, "F", Vr.rows());
        const MetricsOptions o{.alignment = parse_option<Alignment>(alignment, "alignment: "),
                               .willmore = willmore};
        DeformationMetrics r;
        {
          py::gil_scoped_release release;
          r = compute_metrics(Vr, Fi, Vd, o);
        }
        return to_python(to_json(r));
      },
      py::arg("V0"), py::arg("V1"), py::arg("F"),
      py::arg("alignment") = std::string(option_name(MetricsOptions{}.alignment)),
      py::arg("willmore") = MetricsOptions{}.willmore, R"doc(
Deformation metrics of V1 against the rest mesh (V0, F).

Inputs:  V0, V1 (n, 3) finite real arrays (same vertex order), F (m, 3) integer array;
         alignment: "none" | "translation" | "rigid" | "similarity" (factored out before rms/max);
         willmore: also compute the Willmore energies.
Output:  dict with the keys of `spinmotor metrics --json`: vertices, faces, q_mean, q_max,
         collapsed_faces, area_distortion, area_distortion_max, area_scale, edge_distortion,
         edge_distortion_max, rms, max, diagonal, alignment, alignment_scale, willmore_rest and
         willmore_deformed (when computed). Non-finite values (q_max with a collapsed face) are None.
         Q = 1 is conformal: metrics(V, V, F)["q_mean"] == 1.
Errors:  spinmotor.Error for bad shapes, NaN/inf, bad indices, an unknown alignment name.
)doc");

  // ---- generators (mesh/generators.hpp; Error names the bad parameter) ----
  m.def(
      "icosphere",
      [](int level, double radius) { return generate([&] { return icosphere(level, radius); }); },
      py::arg("level"), py::arg("radius") = 1.0,
      "icosphere(level, radius=1.0) -> Mesh. Subdivided icosahedron: 10*4^level + 2 vertices on the sphere; "
      "vertex 0 is the north pole. Requires 0 <= level <= 10, radius > 0 (spinmotor.Error otherwise).");
  m.def(
      "uv_sphere",
      [](int rings, int sectors, double radius) {
        return generate([&] { return uv_sphere(rings, sectors, radius); });
      },
      py::arg("rings"), py::arg("sectors"), py::arg("radius") = 1.0,
      "uv_sphere(rings, sectors, radius=1.0) -> Mesh. Latitude-longitude sphere, rings*sectors + 2 vertices. "
      "Requires rings >= 1, sectors >= 3, radius > 0 (spinmotor.Error otherwise).");
  m.def(
      "grid",
      [](std::array<double, 2> size, std::array<int, 2> n) {
        return generate([&] { return grid(Eigen::Vector2d(size[0], size[1]), Eigen::Vector2i(n[0], n[1])); });
      },
      py::arg("size"), py::arg("n"),
      "grid(size=(sx, sy), n=(nx, ny)) -> Mesh. Planar grid in z = 0 centred at the origin, nx*ny vertices "
      "(vertex (i, j) is i + j*nx). Requires size > 0 and n >= 2 (spinmotor.Error otherwise).");
  m.def(
      "torus", [](double R, double r, int u, int v) { return generate([&] { return torus(R, r, u, v); }); },
      py::arg("R"), py::arg("r"), py::arg("u"), py::arg("v"),
      "torus(R, r, u, v) -> Mesh. Torus around z, u*v vertices (genus 1). Requires 0 < r < R, u, v >= 3 "
      "(spinmotor.Error "
      "otherwise).");
  m.def(
      "tube",
      [](double radius, double length, int rings, int sides, bool capped) {
        return generate([&] { return tube(radius, length, rings, sides, capped); });
      },
      py::arg("radius"), py::arg("length"), py::arg("rings"), py::arg("sides"), py::arg("capped") = false,
      "tube(radius, length, rings, sides, capped=False) -> Mesh. Cylinder around z from 0 to length; ring k "
      "is vertices k*sides .. k*sides + sides - 1. Capped: two fan centres (rings*sides, rings*sides + 1). "
      "Requires radius, length > 0, rings >= 2, sides >= 3 (spinmotor.Error otherwise).");
  m.def(
      "capsule",
      [](double radius, double length, int rings, int sides) {
        return generate([&] { return capsule(radius, length, rings, sides); });
      },
      py::arg("radius"), py::arg("length"), py::arg("rings"), py::arg("sides"),
      "capsule(radius, length, rings, sides) -> Mesh. Cylinder from z = 0 to length closed by hemispheres; "
      "rings*sides + 2 vertices, poles rings*sides (south) and rings*sides + 1 (north). Requires radius, "
      "length >= 0, rings >= 1, sides >= 3 (spinmotor.Error otherwise).");
  m.def(
      "cross_bar",
      [](double length, double half_span, double width, int segments) {
        return generate([&] { return cross_bar(length, half_span, width, segments); });
      },
      py::arg("length") = 4.0, py::arg("half_span") = 0.5, py::arg("width") = 0.25, py::arg("segments") = 64,
      "cross_bar(length=4.0, half_span=0.5, width=0.25, segments=64) -> Mesh. Closed bar with a '+' section "
      "along z from 0 to length. Requires length > 0, 0 < width < 2*half_span and segments >= 1 "
      "(spinmotor.Error otherwise).");
}

}  // namespace spinmotor::python
