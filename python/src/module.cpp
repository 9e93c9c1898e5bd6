// The extension module spinmotor._spinmotor (imported by the package spinmotor/__init__.py).
#include <functional>
#include <utility>

#include "common.hpp"
#include "spinmotor/core/memory_budget.hpp"
#include "spinmotor/deform/arap.hpp"
#include "spinmotor/deform/cage_deformer.hpp"
#include "spinmotor/deform/ffd.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/deform/spline_basis.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"
#include "spinmotor/scene/rig_pose.hpp"
#include "spinmotor/spin/conformal_snap.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"
#include "spinmotor/spin/spin_transform.hpp"

namespace {

using Values = std::function<std::vector<std::string>()>;

/// Every option table the module's string arguments go through (core/option_names.hpp), by the key
/// option_values() takes, with the arguments that use it.
const std::vector<std::pair<const char*, Values>>& option_tables() {
  using namespace spinmotor;
  static const std::vector<std::pair<const char*, Values>> t{
      {"blend", option_values<ga::Blend>},       // blend(mode=), deformers' blend=
      {"skin-blend", option_values<SkinBlend>},  // SkinDeformer, DeltaMush, Rig.pose blend=
      {"weights", option_values<HarmonicWeights>},
      {"mode", option_values<ControlMode>},     // FFD and cage mode=
      {"alignment", option_values<Alignment>},  // metrics(alignment=)
      {"ffd-basis", option_values<FfdDeformer::Basis>},
      {"spline-basis", option_values<SplineBasis>},
      {"coordinates", option_values<CageDeformer::Coordinates>},
      {"energy", option_values<ArapEnergy>},
      {"initial", option_values<ArapInitial>},
      {"snap-mode", option_values<SnapMode>},             // ConformalSnap.snap(mode=)
      {"snap-alignment", option_values<SnapAlignment>},   // ConformalSnap(alignment=)
      {"problem", option_values<SpinEigenProblem>},       // ConformalSnap / SpinTransform problem=
      {"scale", option_values<SpinScale>},                // SpinTransform(scale=)
      {"ordering", vertex_ordering_values},               // SpinTransform(ordering=)
      {"keep", option_values<CleanupKeep>},               // PinnedCleanup, ConformalSnap.snap(keep=)
      {"cleanup", option_values<scene::RigCleanupMode>},  // Rig.poser / Rig.bake cleanup=
      {"space", option_values<scene::RigSpace>},          // Rig.poser / Rig.bake space=
  };
  return t;
}

}  // namespace

PYBIND11_MODULE(_spinmotor, m) {
  namespace sp = spinmotor::python;
  namespace py = pybind11;
  m.doc() =
      "spinmotor: mesh deformation with CGA motors and conformal cleanup by spin transformations.\n"
      "Meshes are numpy arrays V (n, 3) float64 and F (m, 3) integers; every error is spinmotor.Error.";
  sp::register_error(m);
  sp::bind_ga(m);  // Motor first: the deformers' and blend's signatures name it
  sp::bind_mesh(m);
  sp::bind_deform(m);
  sp::bind_spin(m);
  sp::bind_rig(m);
  std::string keys;
  for (const auto& [k, v] : option_tables()) keys += (keys.empty() ? "" : ", ") + std::string(k);
  m.def(
      "option_values",
      [keys](const py::object& option) -> py::object {
        if (option.is_none()) {
          py::dict d;
          for (const auto& [k, v] : option_tables()) d[py::str(k)] = v();
          return d;
        }
        if (!py::isinstance<py::str>(option)) throw spinmotor::Error("option: expected a str or None");
        const std::string name = option.cast<std::string>();
        for (const auto& [k, v] : option_tables())
          if (name == k) return py::cast(v());
        throw spinmotor::Error("unknown option '" + name + "' (one of: " + keys + ")");
      },
      py::arg("option") = py::none(),
      ("option_values(option=None) -> the names a string option accepts, from the C++ option tables "
       "(core/option_names.hpp; the same names as the CLI and scene files). Input: option, one of " +
       keys +
       "; None: all of them. Output: a list of str (a dict {option: list} for None). Errors: "
       "spinmotor.Error for an unknown option, naming the valid ones. A string argument outside its "
       "table raises spinmotor.Error listing the valid names.")
          .c_str());
  m.def(
      "set_memory_limit",
      [](const py::object& size) {
        if (size.is_none()) return spinmotor::set_memory_limit(0);
        if (py::isinstance<py::str>(size))
          return spinmotor::set_memory_limit(spinmotor::parse_memory_size(size.cast<std::string>()));
        const long long bytes = size.cast<long long>();
        if (bytes <= 0)
          throw spinmotor::Error("set_memory_limit: the size must be positive, got " + std::to_string(bytes));
        spinmotor::set_memory_limit(static_cast<std::uint64_t>(bytes));
      },
      py::arg("size"),
      "set_memory_limit(size) -> None. Work whose memory can be estimated before it starts (a Cholesky "
      "factor after its symbolic analysis, a harmonic cage grid, dense cage weights) raises spinmotor.Error "
      "at once, naming the estimate and the limit, when the estimate exceeds it; the CLI's --max-memory. "
      "Input: size, bytes (int > 0) or a str such as '512M' or '8G' (powers of 1024); None: back to the "
      "default, the memory available when first needed. Errors: spinmotor.Error for a malformed size.");
  m.def(
      "memory_limit", [] { return spinmotor::memory_limit(); },
      "memory_limit() -> int: the current limit in bytes (set_memory_limit's, else the available memory). "
      "Errors: none.");
}
