#pragma once
// A grayscale image read from TGA or PNG (via stb_image) and sampled bilinearly, the way the reference
// SpinXForm code samples its curvature images (the reference data of SpinXForm: sphere.obj and bumpy.tga).
//
// Storage: width × height values in [0, 255] (colour images are converted to luminance by stb),
// row 0 is the BOTTOM row, so that pixel (x, y) sits at texture coordinate (x / width, y / height) with
// v pointing up, as in OBJ files. (TGA stores rows bottom-up unless its origin bit says otherwise, PNG
// top-down; stb reports the top row first and the reader flips it.)
#include <Eigen/Core>
#include <filesystem>

namespace spinmotor {

struct GrayscaleImage {
  int width = 0;
  int height = 0;
  Eigen::VectorXf pixels;  ///< width·height values in [0, 255], index x + y·width, y = 0 the bottom row

  float at(int x, int y) const {
    return pixels[static_cast<Eigen::Index>(x) + static_cast<Eigen::Index>(y) * width];
  }

  /// Bilinear sample at pixel coordinates (x, y) with no half-pixel offset: pixel (i, j) is the value
  /// at (i, j); neighbours outside the image are clamped to the edge (SpinXForm's Image::sample).
  /// Throws Error for a coordinate that is not finite.
  double sample(double x, double y) const;
  /// sample(u · width, v · height).
  double sample_uv(double u, double v) const { return sample(u * width, v * height); }
};

/// Reads a TGA or PNG image (any format stb_image decodes) as grayscale. Throws Error naming the file
/// if it cannot be opened or decoded, is empty, announces more pixels than its bytes can hold, or is an
/// TGA (uncompressed or run-length) that ends before the pixels its header announces (truncated).
GrayscaleImage read_grayscale_image(const std::filesystem::path& path);

}  // namespace spinmotor
