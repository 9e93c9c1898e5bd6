#include "spinmotor/spin/grayscale_image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
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
  // A NaN survives std::clamp, and its conversion to int below is undefined behaviour; an infinity
  // would give inf − inf weights.
  if (!std::isfinite(x) || !std::isfinite(y)) {
    std::ostringstream s;
    s << "GrayscaleImage::sample: coordinate (" << x << ", " << y << ") is not finite";
    throw Error(s.str());
  }
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

// stb_image trusts sizes in the file before it reads what they announce, so a few bytes can make it
// allocate gigabytes (found by fuzz_image); both are checked against the file size first:
//   - the image: stb allocates the announced pixels and zero-fills what an uncompressed TGA lacks (an
//     80-byte TGA claimed 16708 × 30804 pixels: 514 MB, 2 GB as floats). No TGA or PNG holds more pixels
//     per byte than kMaxPixelsPerByte: deflate expands at most 1032:1 and PNG packs down to 8 pixels per
//     byte (1-bit grey); an RLE TGA packet of 2 bytes holds at most 128 pixels.
//   - PNG chunks: stb grows its IDAT buffer to a chunk's declared length before reading the chunk (an
//     81-byte PNG declared 1.36 GB); walk_png_chunks refuses a chunk longer than the rest of the file.
constexpr double kMaxPixelsPerByte = 8.0 * 1032.0;

/// For a PNG (by its signature): the first chunk whose declared length runs past the end of the file, as
/// a message, or "" when every chunk fits (or the file is not a PNG; stb reports other defects).
/// Removes empty IDAT chunks from b: valid PNG, but an empty first IDAT makes stb copy 0 bytes to its
/// still-null buffer (memcpy(NULL, ...), undefined behaviour; found by fuzz_image).
std::string png_chunk_overrun(std::string& b) {
  static const char kSignature[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
  if (b.size() < 8 || b.compare(0, 8, kSignature, 8) != 0) return "";
  for (std::size_t at = 8; b.size() - at >= 8;) {
    const auto byte = [&](std::size_t i) {
      return static_cast<std::uint64_t>(static_cast<unsigned char>(b[i]));
    };
    const std::uint64_t length = byte(at) << 24 | byte(at + 1) << 16 | byte(at + 2) << 8 | byte(at + 3);
    const std::uint64_t left = b.size() - at - 8;  // after the length and type fields
    if (length > left)
      return "PNG chunk '" + b.substr(at + 4, 4) + "' at byte " + std::to_string(at) + " declares " +
             std::to_string(length) + " bytes, the file has " + std::to_string(left) + " left";
    if (length == 0 && b.compare(at + 4, 4, "IDAT") == 0) {
      b.erase(at, 8 + std::min<std::size_t>(4, left));  // length, type and CRC
      continue;
    }
    at += 8 + length + std::min<std::uint64_t>(4, left - length);  // data and CRC
  }
  return "";
}

/// For a TGA whose header stb read as w × h: the bytes it lacks, as a message, or "" when its pixels fit
/// in the file (or it is another format). stb zero-fills the pixels a TGA lacks silently, so a cut-off
/// download would otherwise become a black band of ρ. Uncompressed TGAs (types 1–3) need w h (bits/8)
/// bytes of pixels; run-length ones (types 9–11) are walked packet by packet (a header byte, then one
/// pixel for a run of up to 128 or up to 128 literal pixels) until w h pixels are covered.
std::string tga_truncation(const std::string& b, int w, int h) {
  if (b.size() < 18) return "";
  const auto u8 = [&](std::size_t i) { return static_cast<std::uint64_t>(static_cast<unsigned char>(b[i])); };
  const auto u16 = [&](std::size_t i) { return u8(i) | u8(i + 1) << 8; };
  const std::uint64_t type = u8(2), cmap_type = u8(1);
  const bool rle = type >= 9 && type <= 11;
  if (!(rle || (type >= 1 && type <= 3)) || cmap_type > 1) return "";
  if (u16(12) != static_cast<std::uint64_t>(w) || u16(14) != static_cast<std::uint64_t>(h))
    return "";  // not read as TGA
  const std::uint64_t cmap_bytes = cmap_type ? u16(5) * ((u8(7) + 7) / 8) : 0;
  const std::uint64_t pixel_bytes = (u8(16) + 7) / 8, pixels = u16(12) * u16(14);
  const std::uint64_t start = 18 + u8(0) + cmap_bytes;
  const std::string what = "TGA of " + std::to_string(w) + " x " + std::to_string(h) + " pixels at " +
                           std::to_string(u8(16)) + " bits ";
  if (!rle) {
    const std::uint64_t need = start + pixels * pixel_bytes;
    if (need <= b.size()) return "";
    return what + "needs " + std::to_string(need) + " bytes, the file has " + std::to_string(b.size());
  }
  std::uint64_t at = start, covered = 0;
  while (covered < pixels) {
    if (at >= b.size())
      return what + "(run-length) ends after " + std::to_string(covered) + " of its " +
             std::to_string(pixels) + " pixels";
    const std::uint64_t head = u8(at), count = (head & 0x7f) + 1;
    at += 1 + (head & 0x80 ? 1 : count) * pixel_bytes;
    covered += count;
    if (at > b.size())
      return what + "(run-length) ends inside a packet, after " + std::to_string(covered - count) +
             " of its " + std::to_string(pixels) + " pixels";
  }
  return "";
}

}  // namespace

GrayscaleImage read_grayscale_image(const std::filesystem::path& path) {
  const std::string who = "cannot read image '" + path.string() + "': ";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(who + "cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(who + "read error");
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error(who + "larger than 2 GB");
  if (const std::string overrun = png_chunk_overrun(bytes); !overrun.empty())
    throw Error(who + overrun + " (corrupt or truncated)");
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());
  stbi_set_flip_vertically_on_load(1);  // stb reports the top row first; we store the bottom row first
  int w = 0, h = 0, channels = 0;
  if (stbi_info_from_memory(data_in, size, &w, &h, &channels) &&
      static_cast<double>(w) * h > kMaxPixelsPerByte * static_cast<double>(bytes.size()))
    throw Error(who + "its header announces " + std::to_string(w) + " x " + std::to_string(h) +
                " pixels, more than its " + std::to_string(bytes.size()) +
                " bytes can hold (corrupt or truncated)");
  if (const std::string cut = tga_truncation(bytes, w, h); !cut.empty())
    throw Error(who + cut + " (truncated)");
  unsigned char* data = stbi_load_from_memory(data_in, size, &w, &h, &channels, 1);
  if (!data) {
    const char* why = stbi_failure_reason();
    throw Error(who + (why ? why : "unknown error") + " (TGA or PNG expected)");
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
