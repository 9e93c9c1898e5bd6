// fuzz_scalars: the two plain-text number readers of spin/, on the same bytes. The first byte is the
// count (0..255): read_scalar_values (curvature_change.hpp: ρ per face or vertex) expects that many
// values, read_pin_file (pinned_cleanup.hpp) indices below it. The rest is the file.
#include <cmath>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/spin/curvature_change.hpp"
#include "spinmotor/spin/pinned_cleanup.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using spinmotor::fuzz::check;
  if (size < 1) return 0;
  const Eigen::Index count = data[0];
  const std::filesystem::path path = spinmotor::fuzz::write_input(data + 1, size - 1, "input.txt");
  try {
    const Eigen::VectorXd rho = spinmotor::read_scalar_values(path, count, "faces");
    check(rho.size() == count && rho.allFinite(), "count finite values");
  } catch (const spinmotor::Error& e) {
    spinmotor::fuzz::refused(e);
  }
  try {
    const Eigen::VectorXi pins = spinmotor::read_pin_file(path, count);
    check(pins.size() > 0 && pins.minCoeff() >= 0 && pins.maxCoeff() < count, "indices in [0, n)");
  } catch (const spinmotor::Error& e) {
    spinmotor::fuzz::refused(e);
  }
  return 0;
}
