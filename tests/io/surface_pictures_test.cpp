#include "mspline/io/surface_pictures.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <tuple>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_newton.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "support/test_data.h"
#include "support/test_meshes.h"

using namespace mspline;
using io::Rgb;
using structure::FlatLayout;
using structure::TriMesh;

namespace {

struct Flattened {
  TriMesh mesh;
  FlatLayout layout;
};

// knot1.off (genus 1) flattened without cones: a flat torus, computed once.
const Flattened& knot() {
  static const Flattened flat = [] {
    Flattened f{test::realMesh("knot1.off"), {}};
    const auto result =
        structure::solveVertexScaling(f.mesh, structure::flatTarget(f.mesh, {}), {});
    REQUIRE(result.converged);
    f.layout = structure::layoutFlatMetric(f.mesh, result.edgeLengths);
    REQUIRE(f.layout.hasPeriods);
    return f;
  }();
  return flat;
}

Eigen::Vector3d vec(Rgb c) {
  return {double(c.r), double(c.g), double(c.b)};
}

// Shares of the non-background pixels that are shaded versions of each of the two base colors
// (colors c = s * base, up to rounding) or seams; `unclassified` collects the rest.
struct Shares {
  double surface = 0.0;  // non-background pixels / all pixels
  double first = 0.0;
  double second = 0.0;
  double seam = 0.0;
  double unclassified = 0.0;
};

Shares shadedShares(const io::RasterImage& image, Rgb first, Rgb second) {
  long surface = 0, counts[4] = {0, 0, 0, 0};
  for (Rgb c : image.pixels) {
    if (c == io::kBackground) continue;
    ++surface;
    const Eigen::Vector3d v = vec(c);
    const double a = v.normalized().dot(vec(first).normalized());
    const double b = v.normalized().dot(vec(second).normalized());
    ++counts[c == io::kSeamColor ? 2 : std::max(a, b) < 0.995 ? 3 : a > b ? 0 : 1];
  }
  const double n = std::max(surface, 1L);
  return {surface / double(image.pixels.size()), counts[0] / n, counts[1] / n, counts[2] / n,
          counts[3] / n};
}

}  // namespace

TEST_CASE("surface_pictures: the checkerboard covers the knot with both colors", "[io]") {
  const auto& [mesh, layout] = knot();
  const io::RasterImage image = io::renderSurface(mesh, layout, {}, io::SurfaceTexture::Checker);
  CHECK(image.width == 800);
  CHECK(image.height == 800);
  const Shares shares = shadedShares(image, io::kCheckerColors[0], io::kCheckerColors[1]);
  WARN("checker surface: " << shares.surface << " of the image, colors " << shares.first << " / "
                           << shares.second << ", seams " << shares.seam << ", unclassified "
                           << shares.unclassified);
  CHECK(shares.surface > 0.1);
  CHECK(shares.first > 0.25);
  CHECK(shares.first < 0.75);
  CHECK(shares.second > 0.25);
  CHECK(shares.second < 0.75);
  CHECK(shares.seam > 0.0);
  CHECK(shares.seam < 0.05);
  CHECK(shares.unclassified < 0.01);
}

TEST_CASE("surface_pictures: faces colored by label", "[io]") {
  const auto& [mesh, layout] = knot();
  // Two labels: the faces left and right of the knot's middle.
  std::vector<double> xs;
  for (const auto f : mesh.faces()) xs.push_back(mesh.calc_face_centroid(f)[0]);
  std::vector<double> sorted = xs;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  std::vector<int> labels;
  for (double x : xs) labels.push_back(x < sorted[sorted.size() / 2] ? 0 : 1);
  const io::RasterImage image = io::renderSurfaceLabels(mesh, labels, {});
  const Shares shares = shadedShares(image, io::labelColor(0), io::labelColor(1));
  WARN("labels: colors " << shares.first << " / " << shares.second << ", unclassified "
                         << shares.unclassified);
  CHECK(shares.first > 0.2);
  CHECK(shares.second > 0.2);
  CHECK(shares.unclassified < 0.01);
  for (int a = 0; a < 20; ++a)
    for (int b = 0; b < a; ++b) CHECK(io::labelColor(a) != io::labelColor(b));
  labels.pop_back();
  CHECK_THROWS_AS(io::renderSurfaceLabels(mesh, labels, {}), structure::InputError);
}

TEST_CASE("surface_pictures: the layout is filled with the checkerboard", "[io]") {
  const auto& [mesh, layout] = knot();
  io::PictureOptions options;
  options.width = 600;
  options.height = 400;
  const io::RasterImage image = io::renderLayout(mesh, layout, options);
  CHECK(image.width == 600);
  CHECK(image.height == 400);
  // Unshaded: every pixel is exactly the background or one of the two colors.
  long counts[3] = {0, 0, 0};
  for (Rgb c : image.pixels)
    ++counts[c == io::kCheckerColors[0] ? 0 : c == io::kCheckerColors[1] ? 1 : 2];
  const double surface = counts[0] + counts[1];
  WARN("checker layout: " << surface / image.pixels.size() << " of the image, colors "
                          << counts[0] / surface << " / " << counts[1] / surface);
  CHECK(counts[0] + counts[1] +
            std::count(image.pixels.begin(), image.pixels.end(), io::kBackground) ==
        static_cast<long>(image.pixels.size()));
  CHECK(surface / image.pixels.size() > 0.05);  // knot1's layout is a long thin strip
  CHECK(counts[0] / surface > 0.25);
  CHECK(counts[1] / surface > 0.25);
}

TEST_CASE("surface_pictures: lines cover the share of the surface their width says", "[io]") {
  const auto& [mesh, layout] = knot();
  for (double width : {0.2, 0.4}) {
    io::PictureOptions options;
    options.lineWidth = width;
    const io::RasterImage image =
        io::renderSurface(mesh, layout, options, io::SurfaceTexture::Lines);
    const Shares shares = shadedShares(image, io::kLinesInk, io::kLinesPaper);
    const double ink = shares.first / (shares.first + shares.second);
    WARN("lines of width " << width << ": " << shares.surface << " of the image, ink " << ink
                           << " of the textured pixels, unclassified " << shares.unclassified);
    CHECK(shares.surface > 0.1);
    CHECK(ink == Approx(width).margin(0.03));
    CHECK(shares.unclassified < 0.01);
  }
}

TEST_CASE("surface_pictures: the cover of the knot shows 3 x 3 copies", "[io]") {
  const auto& [mesh, layout] = knot();
  io::PictureOptions options;
  options.outlineWidth = 0.0;  // the outline would hide part of the copies
  const io::RasterImage image = io::renderCover(mesh, layout, options);
  std::map<std::tuple<int, int, int>, long> histogram;
  for (Rgb c : image.pixels)
    if (c != io::kBackground) ++histogram[{c.r, c.g, c.b}];
  long copies = 0, home = 0, smallest = image.pixels.size();
  for (const auto& [color, count] : histogram) {
    copies += count;
    smallest = std::min(smallest, count);
  }
  for (Rgb c : io::kCheckerColors) home += histogram[{c.r, c.g, c.b}];
  // Nine copies in two colors each, all visible; they are congruent, so the home copy (the only
  // one in pure checker colors) covers a ninth of them.
  WARN("cover: " << double(copies) / image.pixels.size() << " of the image, " << histogram.size()
                 << " colors (the rarest on " << smallest << " pixels), home copy "
                 << double(home) / copies << " of the copies");
  CHECK(histogram.size() == 18);
  CHECK(double(smallest) / copies > 0.02);
  CHECK(double(copies) / image.pixels.size() > 0.05);
  CHECK(double(home) / copies == Approx(1.0 / 9.0).margin(0.002));

  // The default draws the fundamental parallelogram; radius 0 is the layout alone.
  options = {};
  options.coverRadius = 0;
  const io::RasterImage single = io::renderCover(mesh, layout, options);
  long other = 0;
  for (Rgb c : single.pixels)
    other += c != io::kBackground && c != io::kOutlineColor && c != io::kCheckerColors[0] &&
             c != io::kCheckerColors[1];
  CHECK(other == 0);
  CHECK(std::count(single.pixels.begin(), single.pixels.end(), io::kOutlineColor) > 0);
}

TEST_CASE("surface_pictures: the cover needs a flat torus", "[io]") {
  const TriMesh sphere = test::icosphere(2);
  const FlatLayout layout = structure::layoutFlatMetric(sphere, structure::edgeLengths(sphere));
  CHECK_NOTHROW(io::renderLayout(sphere, layout));
  CHECK_THROWS_AS(io::renderCover(sphere, layout), structure::InputError);
  io::PictureOptions bad;
  bad.lineWidth = 1.5;
  CHECK_THROWS_AS(io::renderSurface(knot().mesh, knot().layout, bad, io::SurfaceTexture::Lines),
                  structure::InputError);
}
