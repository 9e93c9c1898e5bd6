#include "spinmotor/spin/grayscale_image.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "spinmotor/core/error.hpp"

// stb_image, private to this translation unit (static functions: no clash with other users of stb).
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_TGA
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace spinmotor {

double GrayscaleImage::sample(double x, double y) const {
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy, bx = 1.0 - ax, by = 1.0 - ay;
  auto clampi = [](double v, int hi) {
    return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi)));
  };
  const int x0 = clampi(fx, width - 1), x1 = clampi(fx + 1, width - 1);
  const int y0 = clampi(fy, height - 1), y1 = clampi(fy + 1, height - 1);
  return by * (bx * at(x0, y0) + ax * at(x1, y0)) + ay * (bx * at(x0, y1) + ax * at(x1, y1));
}

namespace {

// stb_image allocates the pixels its header announces before it reads them, and fills what an
// uncompressed TGA lacks: an 80-byte file can claim 16708 × 30804 pixels (514 MB, 2 GB as floats). No TGA
// or PNG holds more pixels per byte than this: deflate expands at most 1032:1 and PNG packs down to 8
// pixels per byte (1-bit grey); an RLE TGA packet of 2 bytes holds at most 128 pixels.
constexpr double kMaxPixelsPerByte = 8.0 * 1032.0;

}  // namespace

GrayscaleImage read_grayscale_image(const std::filesystem::path& path) {
  stbi_set_flip_vertically_on_load(1);  // stb reports the top row first; we store the bottom row first
  int w = 0, h = 0, channels = 0;
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec && stbi_info(path.string().c_str(), &w, &h, &channels) &&
      static_cast<double>(w) * h > kMaxPixelsPerByte * static_cast<double>(bytes))
    throw Error("cannot read image '" + path.string() + "': its header announces " + std::to_string(w) +
                " x " + std::to_string(h) + " pixels, more than its " + std::to_string(bytes) +
                " bytes can hold (corrupt or truncated)");
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &channels, 1);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw Error("cannot read image '" + path.string() + "': " + (why ? why : "unknown error") +
                " (TGA or PNG expected)");
  }
  GrayscaleImage img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<Eigen::Index>(w) * h);
  for (Eigen::Index i = 0; i < img.pixels.size(); ++i) img.pixels[i] = static_cast<float>(data[i]);
  stbi_image_free(data);
  if (w <= 0 || h <= 0) throw Error("image '" + path.string() + "' is empty");
  return img;
}

}  // namespace spinmotor
