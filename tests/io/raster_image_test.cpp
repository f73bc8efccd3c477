#include "mspline/io/raster_image.h"

#include <catch2/catch.hpp>
#include <filesystem>

#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

using mspline::io::RasterImage;
using mspline::io::Rgb;

TEST_CASE("raster_image: a PNG reads back pixel for pixel", "[io]") {
  const std::string path = mspline::test::scratchDirectory("raster_image_png") + "/small.png";
  RasterImage image(5, 3, {10, 20, 30});
  image.at(0, 0) = {255, 0, 0};
  image.at(4, 0) = {0, 255, 0};
  image.at(4, 2) = {1, 2, 3};
  mspline::io::writePng(path, image);

  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  REQUIRE(data != nullptr);
  CHECK(width == 5);
  CHECK(height == 3);
  CHECK(channels == 3);
  int mismatches = 0;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const unsigned char* p = data + 3 * (y * 5 + x);
      mismatches += Rgb{p[0], p[1], p[2]} != image.at(x, y);
    }
  stbi_image_free(data);
  CHECK(mismatches == 0);
}

TEST_CASE("raster_image: bad sizes and unwritable paths are reported", "[io]") {
  CHECK_THROWS_AS(RasterImage(0, 4, {}), mspline::structure::InputError);
  const std::string missing =
      mspline::test::scratchDirectory("raster_image_missing") + "/no/such/dir/out.png";
  CHECK_THROWS_AS(mspline::io::writePng(missing, RasterImage(2, 2, {})),
                  mspline::structure::IoError);
  CHECK_THROWS_WITH(mspline::io::writePng(missing, RasterImage(2, 2, {})),
                    Catch::Contains(missing));
  CHECK(!std::filesystem::exists(missing));
}
