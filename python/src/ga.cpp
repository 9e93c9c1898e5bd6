// Python bindings of the ga module: spinmotor.Motor (a unit CGA motor) and blend().
#include <cmath>
#include <sstream>

#include "common.hpp"

namespace spinmotor::python {

namespace {

/// A 3-vector as a dynamic one, element by element (GCC 12 reports the vectorised fixed → dynamic copy
/// as reading past the 3 doubles, -Warray-bounds; it does not).
Eigen::VectorXd to_dynamic(const Eigen::Vector3d& v) {
  Eigen::VectorXd out(3);
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
  return out;
}

Eigen::Vector3d to_vec3(py::handle obj, const char* name) { return to_vector(obj, name, 3); }

ga::Mot from_matrix(py::handle obj) {
  const Eigen::MatrixXd M = to_matrix(obj, "matrix", 4, 4);
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw Error("matrix: the last row must be (0, 0, 0, 1) (a rigid motion)");
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = M.topLeftCorner<3, 3>();
  iso.translation() = M.topRightCorner<3, 1>();
  return ga::from_isometry(iso);  // Error unless the 3×3 block is a rotation
}

void check_unit(const ga::Mot& m, const char* who) {
  for (std::size_t j = 0; j < 8; ++j)
    if (!std::isfinite(m[j])) throw Error(std::string(who) + ": the motor is not finite");
}

}  // namespace

void bind_ga(py::module_& m) {
  py::class_<ga::Mot>(m, "Motor", R"doc(
A unit CGA motor (rigid motion). A motor M moves a point by M p ~M.

Construction:
  Motor()                          the identity
  Motor(matrix)                    from a 4x4 rigid matrix [[R, t], [0, 1]] (R a rotation)
  Motor.from_rotation(axis, degrees, about=(0,0,0), translate=(0,0,0))
  Motor.from_translation(t)
  Motor.exp(b)                     from a 6-vector generator (see log)
  Motor.from_coefficients(c)       from the 8 coefficients (normalised)
Composition: a * b applies b first, then a (as matrices).
)doc")
      .def(py::init([] { return ga::Mot(1, 0, 0, 0, 0, 0, 0, 0); }), "The identity motor.")
      .def(py::init([](py::object matrix) { return from_matrix(matrix); }), py::arg("matrix"),
           "Motor(matrix): from a 4x4 rigid matrix (float array). Errors: spinmotor.Error unless the "
           "upper-left "
           "3x3 block is a rotation (|R^T R - I| <= 1e-6, det > 0), the last row is (0, 0, 0, 1) and all "
           "entries "
           "are finite.")
      .def_static(
          "from_rotation",
          [](py::object axis, double degrees, py::object about, py::object translate) {
            const Eigen::Vector3d ax = to_vec3(axis, "axis"), a = to_vec3(about, "about"),
                                  t = to_vec3(translate, "translate");
            if (!std::isfinite(degrees)) throw Error("degrees: not finite");
            const ga::Rot r = ga::rotor(ax, degrees * M_PI / 180.0);  // Error for a zero axis
            // rotate about `about`, then translate: x -> R (x - a) + a + t (as scene files do)
            return ga::motor(r, ga::translator(a + t - ga::rotate(r, a)));
          },
          py::arg("axis"), py::arg("degrees"), py::arg("about") = std::array<double, 3>{0, 0, 0},
          py::arg("translate") = std::array<double, 3>{0, 0, 0},
          "Motor.from_rotation(axis, degrees, about=(0,0,0), translate=(0,0,0)): rotation by `degrees` about "
          "the "
          "line through `about` along `axis` (any non-zero length), then translation by `translate`: "
          "x -> R (x - about) + about + translate. Errors: spinmotor.Error for a zero or non-finite axis.")
      .def_static(
          "from_translation",
          [](py::object t) { return ga::motor(ga::Rot(1, 0, 0, 0), ga::translator(to_vec3(t, "t"))); },
          py::arg("t"),
          "Motor.from_translation(t) -> Motor: translation by the 3-vector t. Errors: spinmotor.Error for a "
          "wrong length or a non-finite entry.")
      .def_static(
          "exp",
          [](py::object b) {
            const Eigen::VectorXd v = to_vector(b, "b", 6);
            return ga::exp(ga::Dll(v[0], v[1], v[2], v[3], v[4], v[5]));
          },
          py::arg("b"),
          "Motor.exp(b) -> Motor: the motor exp(B) of a generator given as 6 coefficients in the order of "
          "log() "
          "(e12, e31, e23, e1inf, e2inf, e3inf). Errors: spinmotor.Error for a wrong length or a non-finite "
          "entry.")
      .def_static(
          "from_coefficients",
          [](py::object c) {
            const Eigen::VectorXd v = to_vector(c, "c", 8);
            return ga::normalize(ga::Mot(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]));
          },
          py::arg("c"),
          "Motor.from_coefficients(c) -> Motor: the 8 coefficients (s, e12, e31, e23, e1inf, e2inf, e3inf, "
          "e123inf), "
          "normalised to a unit motor. Errors: spinmotor.Error for a zero rotor part.")
      .def(
          "to_matrix",
          [](const ga::Mot& self) {
            check_unit(self, "Motor.to_matrix");
            return to_numpy(Eigen::MatrixXd(ga::to_isometry(self).matrix()));
          },
          "to_matrix() -> (4, 4) float64 rigid matrix [[R, t], [0, 1]].")
      .def(
          "log",
          [](const ga::Mot& self) {
            const ga::Dll b = ga::log(self);
            Eigen::VectorXd v(6);
            for (int j = 0; j < 6; ++j) v[j] = b[j];
            return to_numpy(v);
          },
          "log() -> (6,) float64: the generator B with exp(B) = +-M, rotation angle <= pi (the short way), "
          "coefficients (e12, e31, e23, e1inf, e2inf, e3inf). Motor.exp(M.log()) is M (up to sign).")
      .def(
          "coefficients",
          [](const ga::Mot& self) {
            Eigen::VectorXd v(8);
            for (int j = 0; j < 8; ++j) v[j] = self[j];
            return to_numpy(v);
          },
          "coefficients() -> (8,) float64 (s, e12, e31, e23, e1inf, e2inf, e3inf, e123inf).")
      .def(
          "translation", [](const ga::Mot& self) { return to_numpy(to_dynamic(ga::translation(self))); },
          "translation() -> (3,) the translation part t of x -> R x + t.")
      .def(
          "inverse", [](const ga::Mot& self) { return ga::Mot(ga::reverse(self)); },
          "inverse() -> Motor: the reverse ~M (the inverse motion of a unit motor).")
      .def(
          "__mul__", [](const ga::Mot& a, const ga::Mot& b) { return ga::Mot(a * b); }, py::is_operator(),
          "a * b: the composition (b first, then a).")
      .def(
          "apply",
          [](const ga::Mot& self, py::object points) {
            check_unit(self, "Motor.apply");
            py::array raw = py::array::ensure(points);
            if (raw && raw.ndim() == 1) {  // one point
              const Eigen::Vector3d p = to_vec3(points, "points");
              return to_numpy(to_dynamic(ga::transform(self, p)));
            }
            const Eigen::MatrixXd P = to_points(points, "points");
            Eigen::MatrixXd out(P.rows(), 3);
            for (Eigen::Index i = 0; i < P.rows(); ++i)
              out.row(i) = ga::transform(self, P.row(i).transpose()).transpose();
            return to_numpy(out);
          },
          py::arg("points"),
          "apply(points) -> moved points: (n, 3) -> (n, 3), or one (3,) point -> (3,). Errors: "
          "spinmotor.Error "
          "for a bad shape or a non-finite coordinate.")
      .def("__repr__",
           [](const ga::Mot& self) {
             std::ostringstream s;
             s.precision(6);
             s << "Motor(";
             for (int j = 0; j < 8; ++j) s << (j ? ", " : "") << self[j];
             s << ")";
             return s.str();
           })
      .def(py::pickle(
          [](const ga::Mot& self) {
            py::tuple t(8);
            for (int j = 0; j < 8; ++j) t[j] = self[j];
            return t;
          },
          [](py::tuple t) {
            if (t.size() != 8) throw Error("Motor: bad pickle state");
            return ga::Mot(t[0].cast<double>(), t[1].cast<double>(), t[2].cast<double>(), t[3].cast<double>(),
                           t[4].cast<double>(), t[5].cast<double>(), t[6].cast<double>(),
                           t[7].cast<double>());
          }));

  m.def(
      "blend",
      [](py::object motors, py::object weights, const std::string& mode) {
        const std::vector<ga::Mot> ms = to_motors(motors, "motors");
        const Eigen::VectorXd w = to_vector(weights, "weights", static_cast<Eigen::Index>(ms.size()));
        const ga::Blend b = parse_option<ga::Blend>(mode, "mode: ");
        return ga::blend(ms, std::span<const double>(w.data(), static_cast<std::size_t>(w.size())), b);
      },
      py::arg("motors"), py::arg("weights"), py::arg("mode") = std::string(option_name(ga::Blend::Log)),
      R"doc(
Weighted blend of motors (CGA paper II.B.2).

Inputs:  motors: list of k >= 1 Motor; weights: k finite weights (normally summing to 1);
         mode: "log" (exp of the weighted sum of logs), "pivot-log" (in the frame of the heaviest
         motor) or "dlb" (dual-quaternion linear blending).
Output:  a unit Motor.
Errors:  spinmotor.Error for mismatched lengths, an empty list, a non-finite weight, an unknown mode
         (the message lists the choices).
)doc");
}

}  // namespace spinmotor::python
