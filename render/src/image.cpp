#include "spinmotor/render/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "spinmotor/core/atomic_file.hpp"
#include "spinmotor/core/error.hpp"

// stb_image_write and stb_easy_font, private to this translation unit.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb_easy_font.h>
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace spinmotor::render {

Eigen::Vector3f q_colormap(double t) {
  t = std::isnan(t) ? 1.0 : std::clamp(t, 0.0, 1.0);
  const float c[3][3] = {{49, 54, 149}, {255, 255, 191}, {165, 0, 38}};
  const int k = t < 0.5 ? 0 : 1;
  const float s = float(t < 0.5 ? 2 * t : 2 * t - 1);
  Eigen::Vector3f rgb;
  for (int i = 0; i < 3; ++i) rgb[i] = (c[k][i] + s * (c[k + 1][i] - c[k][i])) / 255.0f;
  return rgb;
}

double q_colormap_position(double q, double q_min, double q_max) {
  if (!std::isfinite(q)) return 1.0;
  q_min = std::max(q_min, 1.0);
  q_max = std::max(q_max, q_min * (1 + 1e-9));
  return std::clamp(std::log(std::max(q, q_min) / q_min) / std::log(q_max / q_min), 0.0, 1.0);
}

namespace {
void fill(Image& im, int x0, int y0, int x1, int y1, const Eigen::Vector3f& c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, im.width), y1 = std::min(y1, im.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = &im.rgba[4 * (std::size_t(y) * im.width + x)];
      for (int i = 0; i < 3; ++i) p[i] = std::uint8_t(std::lround(255 * std::clamp(c[i], 0.0f, 1.0f)));
      p[3] = 255;
    }
}

// Text with stb_easy_font's quads (4 vertices of 16 bytes each), scaled by an integer factor.
void text(Image& im, int x, int y, const std::string& s, int scale) {
  static char buffer[64000];
  const int quads = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buffer, sizeof buffer);
  for (int q = 0; q < quads; ++q) {
    const float* v = reinterpret_cast<const float*>(buffer + q * 64);
    const float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];  // vertices 0 and 2 are opposite corners
    fill(im, x + int(qx0 * scale), y + int(qy0 * scale), x + int(qx1 * scale), y + int(qy1 * scale),
         Eigen::Vector3f(0.1f, 0.1f, 0.1f));
  }
}

std::string label(double v) {
  char b[32];
  std::snprintf(b, sizeof b, v < 10 ? "%.2f" : "%.1f", v);
  return b;
}
}  // namespace

void draw_color_bar(Image& image, double q_min, double q_max, const std::string& title) {
  if (image.width < 60 || image.height < 60) return;
  const int scale = std::max(1, image.height / 400);
  const int bar_w = std::max(10, image.width / 50), bar_h = image.height / 2;
  const int x0 = image.width - bar_w - 12 * scale - 40 * scale, y0 = (image.height - bar_h) / 2;
  fill(image, x0 - 1, y0 - 1, x0 + bar_w + 1, y0 + bar_h + 1, Eigen::Vector3f(0.2f, 0.2f, 0.2f));
  for (int y = 0; y < bar_h; ++y)
    fill(image, x0, y0 + y, x0 + bar_w, y0 + y + 1, q_colormap(1.0 - (y + 0.5) / bar_h));
  const int tx = x0 + bar_w + 4 * scale;
  text(image, tx, y0 - 3 * scale, label(q_max), scale);
  text(image, tx, y0 + bar_h / 2 - 3 * scale, label(std::sqrt(q_min * q_max)), scale);  // log scale midpoint
  text(image, tx, y0 + bar_h - 3 * scale, label(q_min), scale);
  text(image, x0, y0 - 16 * scale, title, scale);
}

void write_png(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != std::size_t(image.width) * image.height * 4)
    throw Error("write_png: " + path.string() + ": empty or inconsistent image");
  AtomicFile out(path);
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::ofstream*>(ctx)->write(static_cast<const char*>(data), size);
  };
  if (!stbi_write_png_to_func(sink, &out.stream(), image.width, image.height, 4, image.rgba.data(),
                              image.width * 4))
    throw Error("write_png: " + path.string() + ": PNG encoding failed");
  out.commit();
}

}  // namespace spinmotor::render
