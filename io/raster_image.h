#pragma once
// A small RGB picture in memory and its PNG encoding (stb_image_write): enough for the software
// rasterizer of io/surface_pictures.h, with no GPU.
#include <cstdint>
#include <string>
#include <vector>

namespace mspline::io {

struct Rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend bool operator==(const Rgb& x, const Rgb& y) {
    return x.r == y.r && x.g == y.g && x.b == y.b;
  }
  friend bool operator!=(const Rgb& x, const Rgb& y) { return !(x == y); }
};
static_assert(sizeof(Rgb) == 3, "pixels are handed to the PNG encoder as packed RGB bytes");

struct RasterImage {
  RasterImage(int width, int height, Rgb fill);
  int width = 0;
  int height = 0;
  /// Row-major, top row first: pixel (x, y) is pixels[y * width + x].
  std::vector<Rgb> pixels;
  Rgb& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const Rgb& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Encodes `image` as an 8-bit RGB PNG and writes it atomically (no partial file is ever left).
/// Throws IoError naming `path` when the image cannot be encoded or written.
void writePng(const std::string& path, const RasterImage& image);

}  // namespace mspline::io
