#include "mspline/io/raster_image.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "mspline/io/atomic_file.h"
#include "mspline/structure/core/errors.h"

namespace mspline::io {

RasterImage::RasterImage(int width_, int height_, Rgb fill)
    : width(width_), height(height_), pixels(static_cast<std::size_t>(width_) * height_, fill) {
  if (width_ <= 0 || height_ <= 0)
    throw structure::InputError("image size " + std::to_string(width_) + " x " +
                                std::to_string(height_) + " is not positive");
}

void writePng(const std::string& path, const RasterImage& image) {
  // Encode into memory first so that the file is written in one atomic step.
  std::string png;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
  };
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, image.pixels.data(),
                              3 * image.width))
    throw structure::IoError("cannot write '" + path + "': PNG encoding failed");
  writeFileAtomically(path, [&](std::ostream& out) { out.write(png.data(), png.size()); });
}

}  // namespace mspline::io
