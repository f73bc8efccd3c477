#include "mspline/io/shaded_picture.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "mspline/structure/core/errors.h"

using namespace mspline;

namespace {

// A unit sphere as a latitude-longitude mesh with its exact normals.
void sphere(Eigen::MatrixX3d& positions, std::vector<std::array<int, 3>>& triangles) {
  const int rings = 16, segments = 32;
  const double pi = std::acos(-1.0);
  positions.resize((rings + 1) * segments, 3);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = pi * i / rings, phi = 2 * pi * j / segments;
      positions.row(i * segments + j) << std::sin(theta) * std::cos(phi),
          std::sin(theta) * std::sin(phi), std::cos(theta);
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      triangles.push_back({a, a + segments, b + segments});
      triangles.push_back({a, b + segments, b});
    }
}

}  // namespace

TEST_CASE("shaded_picture: a sphere fills a disk, lit brighter towards the light", "[io]") {
  Eigen::MatrixX3d positions;
  std::vector<std::array<int, 3>> triangles;
  sphere(positions, triangles);
  io::ShadedPictureOptions options;
  options.width = options.height = 200;
  const io::RasterImage image = io::renderShaded(positions, triangles, positions, options);
  int covered = 0;
  for (const io::Rgb& p : image.pixels) covered += p != options.background;
  // The disk fitted inside a 4% margin: pi (0.46)^2 of the image.
  CHECK(double(covered) / double(image.pixels.size()) ==
        Approx(std::acos(-1.0) * 0.46 * 0.46).epsilon(0.03));
  // The light comes from the upper left: that side of the disk is brighter than the lower right.
  CHECK(image.at(70, 70).b > image.at(130, 130).b);
  // Flat shading (no normals) covers the same pixels.
  const io::RasterImage flat = io::renderShaded(positions, triangles, Eigen::MatrixX3d(), options);
  int flatCovered = 0;
  for (const io::Rgb& p : flat.pixels) flatCovered += p != options.background;
  CHECK(flatCovered == covered);
}

TEST_CASE("shaded_picture: bad input is refused", "[io]") {
  Eigen::MatrixX3d positions(3, 3);
  positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  CHECK_THROWS_AS(io::renderShaded(positions, {{0, 1, 3}}, Eigen::MatrixX3d()),
                  structure::InputError);
  CHECK_THROWS_AS(io::renderShaded(positions, {{0, 1, 2}}, Eigen::MatrixX3d(2, 3)),
                  structure::InputError);
}

TEST_CASE("shaded_picture: marked triangles are drawn in the mark color", "[io]") {
  Eigen::MatrixX3d positions;
  std::vector<std::array<int, 3>> triangles;
  sphere(positions, triangles);
  io::ShadedPictureOptions options;
  options.width = options.height = 200;
  options.color = {0, 0, 255};
  options.markColor = {255, 0, 0};
  // The upper half of the sphere (z > 0: the first 8 rings) marked.
  options.marked.assign(triangles.size(), 0);
  std::fill(options.marked.begin(), options.marked.begin() + std::ptrdiff_t(triangles.size() / 2),
            1);
  const io::RasterImage image = io::renderShaded(positions, triangles, positions, options);
  int red = 0, blue = 0;
  for (const io::Rgb& p : image.pixels) {
    red += p.r > 0 && p.b == 0;
    blue += p.b > 0 && p.r == 0;
  }
  CHECK(red > 1000);
  CHECK(blue > 1000);
  options.marked.pop_back();
  CHECK_THROWS_AS(io::renderShaded(positions, triangles, positions, options),
                  structure::InputError);
}
