#include "mspline/viewer/camera.h"

#include <catch2/catch.hpp>

using mspline::viewer::Camera;

TEST_CASE("camera: rays and projections are inverse, offsets move by pixels", "[viewer]") {
  Camera camera;
  camera.width = 640;
  camera.height = 480;
  camera.azimuth = 35.0;
  camera.elevation = -20.0;
  camera.target = Eigen::Vector3d(0.3, -1.0, 2.0);
  camera.distance = 4.0;
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0, 0}, {320, 240}, {600, 17}}) {
    const auto ray = camera.ray(x, y);
    CHECK(ray.direction.norm() == Approx(1.0));
    const Eigen::Vector3d p = camera.project(ray.origin + 2.5 * ray.direction);
    CHECK(p.x() == Approx(x).margin(1e-9));
    CHECK(p.y() == Approx(y).margin(1e-9));
    // Depth is measured along the view axis: at most the distance along the ray.
    CHECK(p.z() <= 2.5 + 1e-12);
  }
  const Eigen::Vector3d point(0.5, -0.7, 2.2);
  const Eigen::Vector3d before = camera.project(point);
  const Eigen::Vector3d after = camera.project(point + camera.screenOffset(12.0, -7.0, before.z()));
  CHECK(after.x() - before.x() == Approx(12.0).margin(1e-9));
  CHECK(after.y() - before.y() == Approx(-7.0).margin(1e-9));
  CHECK(after.z() == Approx(before.z()).margin(1e-12));
  // The target projects to the centre.
  const Eigen::Vector3d centre = camera.project(camera.target);
  CHECK(centre.x() == Approx(320.0));
  CHECK(centre.y() == Approx(240.0));
}

TEST_CASE("camera: fitTo puts the whole box in view", "[viewer]") {
  Camera camera;
  camera.width = 300;
  camera.height = 900;  // narrow: the width decides
  const Eigen::Vector3d low(-2.0, 0.0, 1.0), high(3.0, 1.0, 4.0);
  for (double azimuth : {0.0, 70.0, 200.0}) {
    camera.azimuth = azimuth;
    camera.fitTo(low, high);
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d c((corner & 1) ? high.x() : low.x(), (corner & 2) ? high.y() : low.y(),
                              (corner & 4) ? high.z() : low.z());
      const Eigen::Vector3d p = camera.project(c);
      CHECK(p.x() >= 0.0);
      CHECK(p.x() <= 300.0);
      CHECK(p.y() >= 0.0);
      CHECK(p.y() <= 900.0);
      CHECK(p.z() > 0.0);
    }
  }
}
