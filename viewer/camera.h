#pragma once
// An orbit camera: the eye turns around a target at a distance, given by azimuth and elevation;
// perspective projection onto a viewport of pixels (origin top left, y down, as mouse events
// give them).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mspline::viewer {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  // unit
};

class Camera {
 public:
  /// Azimuth and elevation in degrees, distance in units of the scene.
  double azimuth = 30.0;
  double elevation = 20.0;
  double distance = 3.0;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  /// Vertical field of view in degrees.
  double fieldOfView = 35.0;
  int width = 800, height = 600;

  /// Looks at the bounding box's centre from a distance where the whole box fits.
  void fitTo(const Eigen::Vector3d& low, const Eigen::Vector3d& high);
  void orbit(double degreesRight, double degreesUp);
  /// Moves the target by a pixel offset in the view plane at the target's depth.
  void pan(double dxPixels, double dyPixels);
  /// Multiplies the distance by `factor`.
  void zoom(double factor);

  Eigen::Vector3d eye() const;
  Eigen::Matrix4d view() const;
  Eigen::Matrix4d projection() const;
  /// The point's pixel coordinates and its depth along the viewing direction.
  Eigen::Vector3d project(const Eigen::Vector3d& point) const;
  /// The ray through pixel (x, y).
  Ray ray(double x, double y) const;
  /// The world offset that moves a point at depth `depth` by (dx, dy) pixels on the screen.
  Eigen::Vector3d screenOffset(double dxPixels, double dyPixels, double depth) const;
  /// World length of one pixel at depth `depth`.
  double pixelSize(double depth) const;
};

}  // namespace mspline::viewer
