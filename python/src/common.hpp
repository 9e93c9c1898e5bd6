#pragma once
// Shared helpers of the Python module: numpy <-> Eigen conversion with validation, the exception
// translation, JSON -> dict. Every conversion runs with the GIL held and throws spinmotor::Error
// (-> spinmotor.Error, kind "bad_input") naming the argument and the bad element, before any work.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "spinmotor/core/error.hpp"
#include "spinmotor/ga.hpp"
#include "spinmotor/mesh/mesh.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

namespace spinmotor::python {

namespace py = pybind11;

/// spinmotor.PinnedCleanup (bound in spin.cpp; also returned by Rig.bind_cleanup in rig.cpp).
struct PyCleanup {
  std::unique_ptr<PinnedCleanup> cleanup;
  std::unique_ptr<std::mutex> lock = std::make_unique<std::mutex>();
};

/// Registers spinmotor.Error (subclass of Exception, attribute .kind) and the translator of
/// spinmotor::Error into it. Call first in the module init.
void register_error(py::module_& m);

/// A real (float or integer) array of shape (rows, cols) as an Eigen matrix, any memory order.
/// rows = -1: any row count; cols = -1: any column count. finite = true rejects NaN/inf, naming the
/// row and column. `name` is the argument name used in messages.
Eigen::MatrixXd to_matrix(py::handle obj, const char* name, Eigen::Index rows, Eigen::Index cols,
                          bool finite = true);

/// A real vector of `size` entries (-1: any size), finite.
Eigen::VectorXd to_vector(py::handle obj, const char* name, Eigen::Index size = -1);

/// n×3 finite positions.
inline Eigen::MatrixXd to_points(py::handle obj, const char* name, bool finite = true) {
  return to_matrix(obj, name, -1, 3, finite);
}

/// An integer array of shape (rows, cols) (cols = -1: any); values must fit int. A float array whose
/// entries are all integers is refused (the dtype says what the array is).
Eigen::MatrixXi to_int_matrix(py::handle obj, const char* name, Eigen::Index rows, Eigen::Index cols);

/// A 1-D integer array (or list of ints).
Eigen::VectorXi to_int_vector(py::handle obj, const char* name);

/// m×3 faces with every index in [0, n) (Error naming the face otherwise).
Eigen::MatrixXi to_faces(py::handle obj, const char* name, Eigen::Index n);

/// (V, F) as a Mesh, validated as above (finite V unless finite = false).
Mesh to_mesh(py::handle V, py::handle F, bool finite = true, const char* vname = "V",
             const char* fname = "F");

/// A C-ordered float64 / int32 numpy copy.
py::array_t<double> to_numpy(const Eigen::MatrixXd& M);
py::array_t<double> to_numpy(const Eigen::VectorXd& v);
py::array_t<int> to_numpy(const Eigen::MatrixXi& M);

/// The matrix moved into a new numpy array without a copy: column-major (Fortran order, Eigen's
/// layout), owning the memory through a capsule (freed with the array). For per-frame outputs, where
/// the copy into C order cost as much as an LBS pose (1M vertices: 6-15 ms).
py::array_t<double> to_numpy_owned(Eigen::MatrixXd&& M);

/// A list of spinmotor.Motor (or anything convertible) as motors.
std::vector<ga::Mot> to_motors(py::handle obj, const char* name);

/// JSON value -> Python object (dict/list/float/int/bool/str/None).
py::object to_python(const nlohmann::ordered_json& j);
py::object to_python(const nlohmann::json& j);

/// Wall-clock milliseconds of `repeats` calls of f() (GIL released by the caller), one entry per call:
/// the private _time_* hooks that bench/python_overhead.py compares the Python calls with.
template <class Fn>
std::vector<double> time_calls(int repeats, Fn&& f) {
  if (repeats < 1) throw Error("repeats: must be >= 1");
  std::vector<double> ms;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return ms;
}

/// Module parts (one source file each).
void bind_mesh(py::module_& m);
void bind_ga(py::module_& m);
void bind_deform(py::module_& m);
void bind_spin(py::module_& m);
void bind_rig(py::module_& m);

}  // namespace spinmotor::python
