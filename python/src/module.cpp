// The extension module spinmotor._spinmotor (imported by the package spinmotor/__init__.py).
#include "common.hpp"
#include "spinmotor/deform/harmonic_field.hpp"
#include "spinmotor/deform/skinning.hpp"
#include "spinmotor/mesh/metrics/distances.hpp"

PYBIND11_MODULE(_spinmotor, m) {
  namespace sp = spinmotor::python;
  m.doc() =
      "spinmotor: mesh deformation with CGA motors and conformal cleanup by spin transformations.\n"
      "Meshes are numpy arrays V (n, 3) float64 and F (m, 3) integers; every error is spinmotor.Error.";
  sp::register_error(m);
  sp::bind_ga(m);  // Motor first: the deformers' and blend's signatures name it
  sp::bind_mesh(m);
  sp::bind_deform(m);
  sp::bind_spin(m);
  sp::bind_rig(m);
  m.def(
      "option_values",
      [](const std::string& option) -> std::vector<std::string> {
        using namespace spinmotor;
        if (option == "blend") return option_values<ga::Blend>();
        if (option == "skin-blend") return option_values<SkinBlend>();
        if (option == "weights") return option_values<HarmonicWeights>();
        if (option == "mode") return option_values<ControlMode>();
        if (option == "alignment") return option_values<Alignment>();
        throw Error("unknown option '" + option + "' (one of: blend, skin-blend, weights, mode, alignment)");
      },
      pybind11::arg("option"),
      "option_values(option) -> list of the names an option accepts (from the C++ option tables): "
      "'blend', 'skin-blend', 'weights', 'mode', 'alignment'.");
}
