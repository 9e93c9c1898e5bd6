#pragma once
// RGBA8 images (top row first), the Q colour map, a colour bar overlay and atomic PNG output.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace spinmotor::render {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  ///< width·height·4 bytes, row 0 at the top

  std::array<std::uint8_t, 4> pixel(int x, int y) const {
    const std::size_t i = 4 * (std::size_t(y) * width + x);
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
  }
};

/// Colour of t ∈ [0, 1] (clamped): blue (t = 0) → pale yellow (½) → red (1); the map of the CLI's
/// Q colour PLY (scene/src/run.cpp). Components in [0, 1].
Eigen::Vector3f q_colormap(double t);

/// Position of Q on the colour map of a range [q_min, q_max] (1 ≤ q_min < q_max), log scale:
/// t = log(Q / q_min) / log(q_max / q_min), clamped to [0, 1]; +inf (collapsed face) → 1.
double q_colormap_position(double q, double q_min, double q_max);

/// Draws a vertical colour bar for [q_min, q_max] at the right edge of `image`, with labels (stb_easy_font).
void draw_color_bar(Image& image, double q_min, double q_max, const std::string& title = "Q");

/// Writes `image` as PNG (stb_image_write) atomically: the target is complete or untouched.
/// Throws Error naming the path on failure.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace spinmotor::render
