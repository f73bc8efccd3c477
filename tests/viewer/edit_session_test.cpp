#include "mspline/viewer/edit_session.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <random>

#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "support/test_data.h"

using namespace mspline;
using viewer::EditSession;

namespace {

// A small fitted model of every kind: knot1 has no cones, eight (genus 2) has cones, so its
// T-spline surface has vertices that are means around cone holes.
std::string model(const std::string& dir, const std::string& mesh, const std::string& kind) {
  return test::fitModel(mesh, kind, dir + "/" + mesh + "-" + kind + ".msp");
}

Eigen::MatrixX3d tessellationPositions(const spline::SplineModel& m, int resolution) {
  const spline::ModelSurface surface(m, "model");
  const spline::ModelTessellation t = surface.tessellate(m.controlPoints, resolution);
  return structure::pointMatrix(t.mesh.positions);
}

}  // namespace

TEST_CASE("edit_session: moving control points re-evaluates their supports exactly", "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_session_local");
  for (const auto& [mesh, kind] : std::vector<std::pair<std::string, std::string>>{
           {"eight.off", "tspline"}, {"eight.off", "tribspline"}, {"eight.off", "subd"}}) {
    INFO(mesh << " " << kind);
    const std::string path = model(dir, mesh, kind);
    EditSession session(io::readSplineModel(path), path, {4});
    const Eigen::MatrixX3d before = session.positions();
    const double size = structure::boundingBoxDiagonal(before);
    std::mt19937 random(7);
    const int rows = int(session.model().controlPoints.rows());
    for (int trial = 0; trial < 3; ++trial) {
      const int row = int(random() % unsigned(rows));
      const Eigen::MatrixX3d start = session.positions();
      session.beginDrag({row});
      session.dragTo({Eigen::Vector3d(0.05, -0.02, 0.03) * size});
      session.endDrag();
      const std::vector<int> support = session.support(row);
      REQUIRE(!support.empty());
      const std::vector<int>& changed = session.changedVertices();
      CHECK(std::includes(changed.begin(), changed.end(), support.begin(), support.end()));
      // Every vertex against a full tessellation of the edited model.
      const Eigen::MatrixX3d full = tessellationPositions(session.model(), 4);
      REQUIRE(full.rows() == session.positions().rows());
      CHECK((full - session.positions()).cwiseAbs().maxCoeff() <= 1e-12 * size);
      // Outside the support nothing changed, not even a bit; inside, something did.
      std::vector<char> inSupport(std::size_t(start.rows()), 0);
      for (int v : support) inSupport[std::size_t(v)] = 1;
      int moved = 0;
      for (Eigen::Index v = 0; v < start.rows(); ++v) {
        if (!inSupport[std::size_t(v)])
          REQUIRE(start.row(v) == session.positions().row(v));
        else if (start.row(v) != session.positions().row(v))
          ++moved;
      }
      CHECK(moved > 0);
    }
  }
}

TEST_CASE("edit_session: local normals equal the tessellation's", "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_session_normals");
  const std::string path = model(dir, "eight.off", "tspline");
  EditSession session(io::readSplineModel(path), path, {3});
  session.beginDrag({5, 6});
  session.dragTo({Eigen::Vector3d(0.01, 0.02, -0.01), Eigen::Vector3d(-0.02, 0.0, 0.01)});
  session.endDrag();
  const spline::ModelSurface surface(session.model(), path);
  const spline::ModelTessellation t = surface.tessellate(session.model().controlPoints, 3);
  REQUIRE(t.normals.size() == std::size_t(session.normals().rows()));
  // Where ds x dt nearly vanishes (next to a cone's hole) either normal is rounding noise: those
  // vertices are left out, and they are few.
  const Eigen::MatrixX3d ds = session.samples().ds * session.model().controlPoints;
  const Eigen::MatrixX3d dt = session.samples().dt * session.model().controlPoints;
  double worst = 0.0;
  int compared = 0;
  for (std::size_t v = 0; v < t.normals.size(); ++v) {
    const auto i = Eigen::Index(v);
    const double scale = std::max(ds.row(i).squaredNorm(), dt.row(i).squaredNorm());
    const bool fromTriangles = session.samples().isMean[v] != 0;
    if (!fromTriangles && ds.row(i).cross(dt.row(i)).norm() <= 1e-4 * scale) continue;
    ++compared;
    worst = std::max(worst, (Eigen::Vector3d(t.normals[v][0], t.normals[v][1], t.normals[v][2]) -
                             session.normals().row(i).transpose())
                                .norm());
  }
  CHECK(compared >= 0.95 * double(t.normals.size()));
  CHECK(worst <= 1e-9);
}

TEST_CASE("edit_session: 150 edits undo to the original bits and redo to the edited ones",
          "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_session_undo");
  const std::string path = model(dir, "knot1.off", "tspline");
  EditSession session(io::readSplineModel(path), path);
  const Eigen::MatrixXd original = session.model().controlPoints;
  const Eigen::MatrixX3d originalPositions = session.positions();
  std::mt19937 random(3);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  for (int step = 0; step < 150; ++step) {
    const int row = int(random() % unsigned(original.rows()));
    session.beginDrag({row, (row + 7) % int(original.rows())});
    for (int frame = 1; frame <= 3; ++frame)
      session.dragTo({Eigen::Vector3d(offset(random), offset(random), offset(random))});
    session.endDrag();
  }
  CHECK(session.undoSteps() == 150);
  CHECK(session.modified());
  const Eigen::MatrixXd edited = session.model().controlPoints;
  const Eigen::MatrixX3d editedPositions = session.positions();
  while (session.canUndo()) session.undo();
  CHECK(session.model().controlPoints == original);  // bit for bit
  CHECK(!session.modified());
  CHECK((session.positions() - originalPositions).cwiseAbs().maxCoeff() <=
        1e-12 * structure::boundingBoxDiagonal(originalPositions));
  while (session.canRedo()) session.redo();
  CHECK(session.model().controlPoints == edited);
  CHECK(session.positions() == editedPositions);
  // A new edit after undo drops the redo steps.
  session.undo();
  session.beginDrag({0});
  session.dragTo({Eigen::Vector3d(0.1, 0.0, 0.0)});
  session.endDrag();
  CHECK(!session.canRedo());
  // A drag that ends where it started is no step.
  const int steps = session.undoSteps();
  session.beginDrag({1});
  session.dragTo({Eigen::Vector3d(0.1, 0.0, 0.0)});
  session.dragTo({Eigen::Vector3d::Zero()});
  session.endDrag();
  CHECK(session.undoSteps() == steps);
}

TEST_CASE("edit_session: save keeps a backup, autosave holds unsaved edits", "[viewer]") {
  namespace fs = std::filesystem;
  const std::string dir = test::scratchDirectory("edit_session_save");
  const std::string path = model(dir, "knot1.off", "subd");
  const std::string originalBytes = test::fileText(path);
  EditSession session(io::readSplineModel(path), path);
  const std::string autosave = EditSession::autosavePath(path);
  CHECK(autosave == dir + "/knot1.off-subd.autosave.msp");
  CHECK(!session.autosave());  // nothing to autosave
  session.beginDrag({3});
  session.dragTo({Eigen::Vector3d(0.0, 0.2, 0.0)});
  session.endDrag();
  REQUIRE(session.autosave());
  CHECK(!session.autosave());  // written already
  const spline::SplineModel autosaved = io::readSplineModel(autosave);
  CHECK(autosaved.controlPoints == session.model().controlPoints);
  CHECK(test::fileText(path) == originalBytes);  // autosave leaves the model file alone

  session.save();
  CHECK(!session.modified());
  CHECK(test::fileText(path + ".bak") == originalBytes);
  CHECK(io::readSplineModel(path).controlPoints == session.model().controlPoints);
  CHECK(!fs::exists(autosave));
  // Saving into a directory that does not exist fails cleanly: nothing written, still modified.
  session.undo();
  session.setPath(dir + "/missing/model.msp");
  CHECK_THROWS_AS(session.save(), structure::IoError);
  CHECK(session.modified());
  CHECK(!fs::exists(dir + "/missing"));
}

TEST_CASE("edit_session: a model whose control points do not fit is an input error", "[viewer]") {
  const std::string dir = test::scratchDirectory("edit_session_bad");
  const std::string path = model(dir, "knot1.off", "tspline");
  spline::SplineModel broken = io::readSplineModel(path);
  broken.controlPoints.conservativeResize(broken.controlPoints.rows() - 1, 3);
  CHECK_THROWS_AS(EditSession(broken, "broken.msp"), structure::InputError);
  CHECK_THROWS_WITH(EditSession(broken, "broken.msp"), Catch::Contains("broken.msp"));
}
