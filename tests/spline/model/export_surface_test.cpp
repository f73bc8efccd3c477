#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include <Eigen/Geometry>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/export_surface.h"
#include "mspline/spline/model/filled_faces.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "support/test_data.h"

using namespace mspline;

namespace {

double triangleArea(const structure::PolygonSoup& soup, std::size_t f) {
  const auto at = [&](int k) {
    const auto& p = soup.positions[std::size_t(soup.faces[f][std::size_t(k)])];
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  return 0.5 * (at(1) - at(0)).cross(at(2) - at(0)).norm();
}

}  // namespace

TEST_CASE("export_surface: trimming removes the faces over the filled holes of a head.off fit",
          "[spline]") {
  const spline::SplineModel& model = test::headModel("tribspline");
  REQUIRE(std::count(model.surfaceFaceFilled.begin(), model.surfaceFaceFilled.end(), char(1)) > 0);
  spline::ExportOptions options;
  options.resolution = 4;
  options.trimFills = false;
  const spline::ExportResult whole = spline::exportSurface(model, "head", options);
  options.trimFills = true;
  const spline::ExportResult trimmed = spline::exportSurface(model, "head", options);
  CHECK(whole.trimmedFaces == 0);
  REQUIRE(trimmed.trimmedFaces > 0);
  CHECK(trimmed.surface.mesh.faces.size() + trimmed.trimmedFaces ==
        whole.surface.mesh.faces.size());

  // The kept faces are the untrimmed surface's over the scan, in order, with their vertices'
  // normals and chart coordinates.
  const std::vector<char> keep = spline::facesToKeep(whole.surface.mesh, model);
  const auto& before = whole.surface;
  const auto& after = trimmed.surface;
  CHECK(after.normals.size() == after.mesh.positions.size());
  CHECK(after.uvs.size() == after.mesh.positions.size());
  std::size_t k = 0;
  double removedArea = 0.0;
  for (std::size_t f = 0; f < before.mesh.faces.size(); ++f) {
    if (!keep[f]) {
      removedArea += triangleArea(before.mesh, f);
      continue;
    }
    REQUIRE(k < after.mesh.faces.size());
    for (std::size_t c = 0; c < 3; ++c) {
      const auto v = std::size_t(before.mesh.faces[f][c]), w = std::size_t(after.mesh.faces[k][c]);
      CHECK(after.mesh.positions[w] == before.mesh.positions[v]);
      CHECK(after.normals[w] == before.normals[v]);
      CHECK(after.uvs[w] == before.uvs[v]);
    }
    ++k;
  }
  CHECK(k == after.mesh.faces.size());

  // The area taken away is the fills' area on the spline (the filled faces of the model's mesh
  // moved onto the spline), up to the jagged trim line.
  const Eigen::MatrixX3d images = spline::surfaceVertexImages(model);
  double fillArea = 0.0;
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f) {
    if (!model.surfaceFaceFilled[f]) continue;
    const auto& t = model.surfaceFaces[f];
    fillArea +=
        0.5 *
        (images.row(t[1]) - images.row(t[0])).cross(images.row(t[2]) - images.row(t[0])).norm();
  }
  INFO("removed " << removedArea << ", fills " << fillArea);
  CHECK(removedArea == Approx(fillArea).epsilon(0.1));

  // Without filled faces nothing is trimmed.
  spline::SplineModel unfilled = model;
  unfilled.surfaceFaceFilled.clear();
  CHECK(spline::exportSurface(unfilled, "head", options).trimmedFaces == 0);
}

TEST_CASE("export_surface: a fill lying on its scan is told apart by the way it faces",
          "[spline]") {
  // plane.off is a flat square: the patch that closes its boundary lies on the scan itself, so
  // the closed surface is a flat pillow and both sides are at distance 0 from scan and fill.
  // Valence 2: the pillow's corners are cones of angle pi (with valence 3 each is two cones, and
  // the rim stands 2 % of the diagonal beyond the square).
  const spline::SplineModel& model =
      test::fittedModel("plane.off", "tspline", test::kSmallFit + " --min-corner-valence 2");
  REQUIRE(std::count(model.surfaceFaceFilled.begin(), model.surfaceFaceFilled.end(), char(1)) > 0);
  spline::ExportOptions options;
  options.resolution = 4;
  const spline::ExportResult trimmed = spline::exportSurface(model, "plane", options);
  options.trimFills = false;
  const spline::ExportResult whole = spline::exportSurface(model, "plane", options);
  // The scan faces +y. What is kept faces it, what is trimmed faces away: the rim where the
  // pillow turns over is the only place either way.
  const auto facing = [](const structure::PolygonSoup& soup, double& up, double& down) {
    up = down = 0.0;
    for (std::size_t f = 0; f < soup.faces.size(); ++f) {
      const auto at = [&](int k) {
        const auto& p = soup.positions[std::size_t(soup.faces[f][std::size_t(k)])];
        return Eigen::Vector3d(p[0], p[1], p[2]);
      };
      const Eigen::Vector3d n = 0.5 * (at(1) - at(0)).cross(at(2) - at(0));
      (n.y() > 0.0 ? up : down) += n.norm();
    }
  };
  double keptUp = 0.0, keptDown = 0.0, allUp = 0.0, allDown = 0.0;
  facing(trimmed.surface.mesh, keptUp, keptDown);
  facing(whole.surface.mesh, allUp, allDown);
  INFO("kept: " << keptUp << " up, " << keptDown << " down; whole: " << allUp << " up, " << allDown
                << " down");
  CHECK(keptDown < 0.01 * keptUp);
  // The scan's area: the square [-0.625, 0.625]^2 (the pillow's rim reaches a little beyond).
  CHECK(keptUp == Approx(1.5625).epsilon(0.05));
  CHECK(allUp > keptUp);
}

TEST_CASE("export_surface: the resolution chosen from a tolerance meets it and is the smallest",
          "[spline]") {
  // A T-spline: its estimate is close (a triangular B-spline's second derivatives in chart units
  // make it far larger than the chord error).
  const spline::SplineModel& model = test::fittedModel("knot1.off", "tspline", test::kSmallFit);
  spline::ExportOptions options;
  options.trimFills = false;
  int previous = 0;
  for (const double tolerance : {1e-2, 1e-3}) {
    options.tolerance = tolerance;
    const spline::ExportResult result = spline::exportSurface(model, "head", options);
    INFO("tolerance " << tolerance << ": resolution " << result.resolution << ", estimate "
                      << result.chordErrorEstimate);
    CHECK(result.toleranceMet);
    CHECK(result.chordErrorEstimate <= tolerance);
    CHECK(result.diagonal == Approx(structure::boundingBoxDiagonal(model.surfaceVertices)));
    // The estimate falls as 1 / resolution^2: one step coarser would not meet the tolerance.
    const int r = result.resolution;
    if (r > 1) CHECK(result.chordErrorEstimate * r * r / double((r - 1) * (r - 1)) > tolerance);
    CHECK(r >= previous);
    previous = r;

    // The actual chord error: a 4 times finer tessellation of the same surface against it.
    spline::ExportOptions fine;
    fine.trimFills = false;
    fine.resolution = 4 * r;
    const spline::ExportResult finer = spline::exportSurface(model, "head", fine);
    const structure::TriangleMeshDistance coarse(
        structure::pointMatrix(result.surface.mesh.positions),
        structure::triangleIndices(result.surface.mesh));
    double chord = 0.0;
    for (const auto& hit : coarse.queryAll(structure::pointMatrix(finer.surface.mesh.positions)))
      chord = std::max(chord, hit.distance);
    INFO("chord error " << chord / result.diagonal);
    CHECK(chord <= tolerance * result.diagonal);
  }
  options.tolerance = 1e-9;
  options.maxToleranceResolution = 16;
  const spline::ExportResult capped = spline::exportSurface(model, "head", options);
  CHECK(capped.resolution == 16);
  CHECK(capped.chordErrorEstimate > options.tolerance);
  CHECK_FALSE(capped.toleranceMet);
}
