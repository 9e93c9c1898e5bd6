// fuzz_image: read_grayscale_image (spin/grayscale_image.hpp, stb_image) on TGA and PNG. The first
// byte selects the extension (even: .tga, odd: .png; stb tells the formats apart by content, the
// extension only names the file), the rest is the file. Then the image's promises and bilinear samples
// inside, on the edges and outside (clamped) of the image.
#include <cmath>

#include "fuzz_support.hpp"
#include "spinmotor/core/error.hpp"
#include "spinmotor/spin/grayscale_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::filesystem::path path =
      spinmotor::fuzz::write_input(data + 1, size - 1, data[0] % 2 ? "input.png" : "input.tga");
  spinmotor::GrayscaleImage image;
  try {
    image = spinmotor::read_grayscale_image(path);
  } catch (const spinmotor::Error& e) {
    return spinmotor::fuzz::refused(e);
  }
  using spinmotor::fuzz::check;
  check(image.width > 0 && image.height > 0, "a read image is not empty");
  check(image.pixels.size() == static_cast<Eigen::Index>(image.width) * image.height,
        "width x height pixels");
  check(image.pixels.minCoeff() >= 0.0f && image.pixels.maxCoeff() <= 255.0f, "pixels in [0, 255]");
  for (const double u : {-1.0, 0.0, 0.37, 1.0, 2.0})
    for (const double v : {-0.5, 0.0, 0.5, 1.0, 1e9}) {
      const double s = image.sample_uv(u, v);
      check(s >= 0.0 && s <= 255.0, "samples in [0, 255]");
    }
  return 0;
}
