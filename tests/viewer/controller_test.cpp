#include "mspline/viewer/controller.h"

#include <catch2/catch.hpp>

#include "mspline/io/spline_model_file.h"
#include "support/test_data.h"

using namespace mspline;
using namespace mspline::viewer;

namespace {

struct Scene {
  std::string path;
  std::unique_ptr<EditSession> session;
  Camera camera;
  std::unique_ptr<Controller> controller;
  explicit Scene(const std::string& testName) {
    const std::string dir = test::scratchDirectory(testName);
    path = test::fitModel("knot1.off", "subd", dir + "/knot.msp");
    session = std::make_unique<EditSession>(io::readSplineModel(path), path, EditSessionOptions{2});
    camera.width = 800;
    camera.height = 600;
    camera.fitTo(session->positions().colwise().minCoeff().transpose(),
                 session->positions().colwise().maxCoeff().transpose());
    controller = std::make_unique<Controller>(camera, session.get());
  }
  Eigen::Vector3d point(int row) const {
    return session->model().controlPoints.row(row).transpose();
  }
  // A shown control point that the pointer picks at its own place on the screen.
  int pickable() const {
    for (int row : session->net().points) {
      const Eigen::Vector3d s = camera.project(point(row));
      if (controller->pick(s.x(), s.y()) == row) return row;
    }
    return -1;
  }
};

}  // namespace

TEST_CASE("controller: a drag picks the point and moves it with the pointer", "[viewer]") {
  Scene scene("controller_drag");
  const int row = scene.pickable();
  REQUIRE(row >= 0);
  const Eigen::Vector3d start = scene.camera.project(scene.point(row));
  // Far from every point nothing is picked.
  CHECK(scene.controller->pick(-500.0, -500.0) == -1);
  scene.controller->press(start.x(), start.y(), MouseButton::Left, {});
  REQUIRE(scene.controller->moving());
  CHECK(scene.controller->selection() == std::vector<int>{row});
  scene.controller->move(start.x() + 30.0, start.y() - 12.0);
  scene.controller->release(start.x() + 40.0, start.y() - 20.0);
  CHECK(!scene.controller->moving());
  CHECK(scene.session->undoSteps() == 1);
  // The point followed the pointer in the view plane.
  const Eigen::Vector3d end = scene.camera.project(scene.point(row));
  CHECK(end.x() == Approx(start.x() + 40.0).margin(1e-6));
  CHECK(end.y() == Approx(start.y() - 20.0).margin(1e-6));
  CHECK(end.z() == Approx(start.z()).epsilon(1e-9));
}

TEST_CASE("controller: Alt drags along the normal, Shift drags select a box", "[viewer]") {
  Scene scene("controller_normal_box");
  const int row = scene.pickable();
  REQUIRE(row >= 0);
  const Eigen::Vector3d before = scene.point(row);
  const Eigen::Vector3d normal = scene.session->controlNormal(row);
  CHECK(normal.norm() == Approx(1.0));
  const Eigen::Vector3d s = scene.camera.project(before);
  Modifiers alt;
  alt.alt = true;
  scene.controller->press(s.x(), s.y(), MouseButton::Left, alt);
  scene.controller->release(s.x(), s.y() - 25.0);  // up the screen: out along the normal
  const Eigen::Vector3d moved = scene.point(row) - before;
  CHECK(moved.norm() == Approx(25.0 * scene.camera.pixelSize(s.z())).epsilon(1e-9));
  CHECK(moved.normalized().dot(normal) == Approx(1.0));

  // A box around everything selects every shown point.
  Modifiers shift;
  shift.shift = true;
  scene.controller->setSelection({});
  scene.controller->press(-1e4, -1e4, MouseButton::Left, shift);
  REQUIRE(scene.controller->boxSelecting());
  scene.controller->move(1e4, 1e4);
  scene.controller->release(1e4, 1e4);
  CHECK(scene.controller->selection().size() == scene.session->net().points.size());
  // A box around one point's projection only.
  scene.controller->setSelection({});
  const Eigen::Vector3d p = scene.camera.project(scene.point(row));
  const std::vector<int> inBox =
      scene.controller->pointsInBox(p.x() - 0.01, p.y() - 0.01, p.x() + 0.01, p.y() + 0.01);
  CHECK(std::find(inBox.begin(), inBox.end(), row) != inBox.end());
  CHECK(inBox.size() < 4);
}
