// Conversions and the error type of the Python module (common.hpp).
#include "common.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

namespace spinmotor::python {

namespace {

PyObject* g_error = nullptr;  // spinmotor.Error, owned by the module (kept alive by its attribute)

const char* kind_name(Error::Kind k) { return k == Error::Kind::BadInput ? "bad_input" : "numerical"; }

[[noreturn]] void bad(const std::string& what) { throw Error(what); }

std::string shape_of(const py::array& a) {
  std::ostringstream s;
  s << "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s << (d ? ", " : "") << a.shape(d);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

std::string want_shape(Eigen::Index rows, Eigen::Index cols) {
  auto dim = [](Eigen::Index d, const char* sym) { return d < 0 ? std::string(sym) : std::to_string(d); };
  std::string out =
      "(";  // appended, not "(" + std::string&&: GCC 12's -Wrestrict false positive (bug 105329)
  out += dim(rows, "n");
  out += ", ";
  out += dim(cols, "k");
  out += ")";
  return out;
}

/// obj as a numpy array of a real numeric dtype ('f', 'i', 'u'; bool, complex, object, str refused).
py::array as_real_array(py::handle obj, const char* name, bool integer_only) {
  if (obj.is_none()) bad(std::string(name) + ": expected an array, got None");
  py::array a = py::array::ensure(obj);
  if (!a) {
    PyErr_Clear();
    bad(std::string(name) + ": cannot be read as an array (got " +
        std::string(py::str(obj.get_type().attr("__name__"))) + ")");
  }
  const char kind = a.dtype().kind();
  const bool ok = integer_only ? (kind == 'i' || kind == 'u') : (kind == 'f' || kind == 'i' || kind == 'u');
  if (!ok)
    bad(std::string(name) + ": expected " + (integer_only ? "an integer" : "a real (float or integer)") +
        " array, got dtype " + std::string(py::str(a.dtype())));
  return a;
}

}  // namespace

void register_error(py::module_& m) {
  py::dict attrs;
  attrs["__doc__"] = py::str(
      "The one exception type of spinmotor (C++ spinmotor::Error).\n\n"
      "Attributes:\n"
      "  kind: 'bad_input' (malformed file, invalid mesh, bad parameter; the CLI's exit code 2) or\n"
      "        'numerical' (a factorization or iteration failed on valid input; exit code 3).\n"
      "str(e) is the C++ message, which names the bad element (argument, vertex, face, handle...).");
  attrs["kind"] = py::str("bad_input");
  g_error = PyErr_NewException("spinmotor.Error", PyExc_Exception, attrs.ptr());
  if (!g_error) throw py::error_already_set();
  m.add_object("Error", py::handle(g_error));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      py::object type = py::reinterpret_borrow<py::object>(g_error);
      py::object inst = type(py::str(e.what()));
      inst.attr("kind") = py::str(kind_name(e.kind()));
      PyErr_SetObject(g_error, inst.ptr());
    }
  });
}

Eigen::MatrixXd to_matrix(py::handle obj, const char* name, Eigen::Index rows, Eigen::Index cols,
                          bool finite) {
  py::array raw = as_real_array(obj, name, false);
  if (raw.ndim() != 2 || (rows >= 0 && raw.shape(0) != rows) || (cols >= 0 && raw.shape(1) != cols))
    bad(std::string(name) + ": expected shape " + want_shape(rows, cols) + ", got " + shape_of(raw));
  auto a = py::array_t<double, py::array::forcecast>::ensure(raw);
  if (!a) {
    PyErr_Clear();
    bad(std::string(name) + ": cannot be converted to float64");
  }
  const auto u = a.unchecked<2>();  // strided: C and Fortran order alike
  Eigen::MatrixXd M(u.shape(0), u.shape(1));
  for (py::ssize_t i = 0; i < u.shape(0); ++i)
    for (py::ssize_t j = 0; j < u.shape(1); ++j) {
      const double x = u(i, j);
      if (finite && !std::isfinite(x))
        bad(std::string(name) + ": row " + std::to_string(i) + ", column " + std::to_string(j) +
            " is not finite");
      M(i, j) = x;
    }
  return M;
}

Eigen::VectorXd to_vector(py::handle obj, const char* name, Eigen::Index size) {
  py::array raw = as_real_array(obj, name, false);
  if (raw.ndim() != 1 || (size >= 0 && raw.shape(0) != size))
    bad(std::string(name) + ": expected shape (" + (size < 0 ? std::string("n") : std::to_string(size)) +
        ",), got " + shape_of(raw));
  auto a = py::array_t<double, py::array::forcecast>::ensure(raw);
  if (!a) {
    PyErr_Clear();
    bad(std::string(name) + ": cannot be converted to float64");
  }
  const auto u = a.unchecked<1>();
  Eigen::VectorXd v(u.shape(0));
  for (py::ssize_t i = 0; i < u.shape(0); ++i) {
    if (!std::isfinite(u(i))) bad(std::string(name) + ": entry " + std::to_string(i) + " is not finite");
    v[i] = u(i);
  }
  return v;
}

Eigen::MatrixXi to_int_matrix(py::handle obj, const char* name, Eigen::Index rows, Eigen::Index cols) {
  py::array raw = as_real_array(obj, name, true);
  if (raw.ndim() != 2 || (rows >= 0 && raw.shape(0) != rows) || (cols >= 0 && raw.shape(1) != cols))
    bad(std::string(name) + ": expected shape " + want_shape(rows, cols) + ", got " + shape_of(raw));
  // through int64 (uint64 above 2^63 wraps negative and is refused as out of range below)
  auto a = py::array_t<long long, py::array::forcecast>::ensure(raw);
  if (!a) {
    PyErr_Clear();
    bad(std::string(name) + ": cannot be converted to int64");
  }
  const auto u = a.unchecked<2>();
  Eigen::MatrixXi M(u.shape(0), u.shape(1));
  for (py::ssize_t i = 0; i < u.shape(0); ++i)
    for (py::ssize_t j = 0; j < u.shape(1); ++j) {
      const long long x = u(i, j);
      if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
        bad(std::string(name) + ": row " + std::to_string(i) + ", column " + std::to_string(j) + " = " +
            std::to_string(x) + " does not fit a 32-bit index");
      M(i, j) = static_cast<int>(x);
    }
  return M;
}

Eigen::VectorXi to_int_vector(py::handle obj, const char* name) {
  py::array raw = as_real_array(obj, name, true);
  if (raw.ndim() != 1) bad(std::string(name) + ": expected a 1-D integer array, got shape " + shape_of(raw));
  auto a = py::array_t<long long, py::array::forcecast>::ensure(raw);
  if (!a) {
    PyErr_Clear();
    bad(std::string(name) + ": cannot be converted to int64");
  }
  const auto u = a.unchecked<1>();
  Eigen::VectorXi v(u.shape(0));
  for (py::ssize_t i = 0; i < u.shape(0); ++i) {
    if (u(i) < std::numeric_limits<int>::min() || u(i) > std::numeric_limits<int>::max())
      bad(std::string(name) + ": entry " + std::to_string(i) + " = " + std::to_string(u(i)) +
          " does not fit a 32-bit index");
    v[i] = static_cast<int>(u(i));
  }
  return v;
}

Eigen::MatrixXi to_faces(py::handle obj, const char* name, Eigen::Index n) {
  Eigen::MatrixXi F = to_int_matrix(obj, name, -1, 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (F(f, c) < 0 || F(f, c) >= n)
        bad(std::string(name) + ": face " + std::to_string(f) + " has vertex index " +
            std::to_string(F(f, c)) + " outside [0, " + std::to_string(n) + ")");
  return F;
}

Mesh to_mesh(py::handle V, py::handle F, bool finite, const char* vname, const char* fname) {
  Mesh m;
  m.V = to_points(V, vname, finite);
  m.F = to_faces(F, fname, m.V.rows());
  return m;
}

// Copies through Eigen maps (a vectorised, cache-friendly transposing copy; the element-wise unchecked
// loop it replaced took 15 ms for 1M×3, more than half of an LBS pose of that size).
py::array_t<double> to_numpy(const Eigen::MatrixXd& M) {
  py::array_t<double> a({static_cast<py::ssize_t>(M.rows()), static_cast<py::ssize_t>(M.cols())});
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(a.mutable_data(),
                                                                                     M.rows(), M.cols()) = M;
  return a;
}

py::array_t<double> to_numpy(const Eigen::VectorXd& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  Eigen::Map<Eigen::VectorXd>(a.mutable_data(), v.size()) = v;
  return a;
}

py::array_t<int> to_numpy(const Eigen::MatrixXi& M) {
  py::array_t<int> a({static_cast<py::ssize_t>(M.rows()), static_cast<py::ssize_t>(M.cols())});
  Eigen::Map<Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(a.mutable_data(), M.rows(),
                                                                                  M.cols()) = M;
  return a;
}

py::array_t<double> to_numpy_owned(Eigen::MatrixXd&& M) {
  auto owned = std::make_unique<Eigen::MatrixXd>(std::move(M));
  py::capsule free_when_done(owned.get(), [](void* p) { delete static_cast<Eigen::MatrixXd*>(p); });
  Eigen::MatrixXd* m = owned.release();  // the capsule owns it now
  const auto r = static_cast<py::ssize_t>(m->rows()), c = static_cast<py::ssize_t>(m->cols());
  const auto d = static_cast<py::ssize_t>(sizeof(double));
  return py::array_t<double>({r, c}, {d, d * r}, m->data(), free_when_done);
}

std::vector<ga::Mot> to_motors(py::handle obj, const char* name) {
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    bad(std::string(name) + ": expected a list of spinmotor.Motor");
  std::vector<ga::Mot> out;
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
  out.reserve(seq.size());
  for (std::size_t i = 0; i < seq.size(); ++i) {
    py::object item = seq[i];
    if (!py::isinstance<ga::Mot>(item))
      bad(std::string(name) + "[" + std::to_string(i) + "]: expected a spinmotor.Motor, got " +
          std::string(py::str(item.get_type().attr("__name__"))));
    out.push_back(item.cast<ga::Mot>());
  }
  return out;
}

template <class J>
py::object json_to_python(const J& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(j.template get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(j.template get<long long>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(j.template get<unsigned long long>());
    case nlohmann::json::value_t::number_float:
      return py::float_(j.template get<double>());
    case nlohmann::json::value_t::string:
      return py::str(j.template get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(json_to_python(e));
      return l;
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = json_to_python(it.value());
      return d;
    }
    default:
      return py::none();
  }
}

py::object to_python(const nlohmann::ordered_json& j) { return json_to_python(j); }
py::object to_python(const nlohmann::json& j) { return json_to_python(j); }

}  // namespace spinmotor::python
