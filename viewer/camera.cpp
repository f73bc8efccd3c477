#include "mspline/viewer/camera.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <cmath>

namespace mspline::viewer {

namespace {

constexpr double kDegree = kPi / 180.0;

}  // namespace

void Camera::fitTo(const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  target = 0.5 * (low + high);
  const double radius = std::max(0.5 * (high - low).norm(), 1e-12);
  // The bounding sphere fits the smaller of the two fields of view.
  const double aspect = double(width) / double(std::max(height, 1));
  const double half = 0.5 * fieldOfView * kDegree;
  const double narrowest = std::min(half, std::atan(std::tan(half) * aspect));
  distance = radius / std::sin(narrowest) * 1.05;
}

void Camera::orbit(double degreesRight, double degreesUp) {
  azimuth = std::fmod(azimuth - degreesRight, 360.0);
  elevation = std::clamp(elevation + degreesUp, -89.0, 89.0);
}

void Camera::pan(double dxPixels, double dyPixels) {
  target -= screenOffset(dxPixels, dyPixels, distance);
}

void Camera::zoom(double factor) {
  distance = std::max(distance * factor, 1e-9);
}

Eigen::Vector3d Camera::eye() const {
  const double a = azimuth * kDegree, e = elevation * kDegree;
  // y is up; azimuth 0 looks along -z.
  return target + distance * Eigen::Vector3d(std::cos(e) * std::sin(a), std::sin(e),
                                             std::cos(e) * std::cos(a));
}

Eigen::Matrix4d Camera::view() const {
  const Eigen::Vector3d forward = (target - eye()).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = right.transpose();
  m.block<1, 3>(1, 0) = up.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m.block<3, 1>(0, 3) = -m.block<3, 3>(0, 0) * eye();
  return m;
}

Eigen::Matrix4d Camera::projection() const {
  // Near and far planes around the target keep depth precision where the scene is.
  const double nearPlane = distance * 0.01, farPlane = distance * 100.0;
  const double f = 1.0 / std::tan(0.5 * fieldOfView * kDegree);
  const double aspect = double(width) / double(std::max(height, 1));
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
  m(2, 3) = 2.0 * farPlane * nearPlane / (nearPlane - farPlane);
  m(3, 2) = -1.0;
  return m;
}

Eigen::Vector3d Camera::project(const Eigen::Vector3d& point) const {
  const Eigen::Vector4d eyeSpace = view() * point.homogeneous();
  const Eigen::Vector4d clip = projection() * eyeSpace;
  const double x = (clip.x() / clip.w() * 0.5 + 0.5) * width;
  const double y = (0.5 - clip.y() / clip.w() * 0.5) * height;
  return {x, y, -eyeSpace.z()};
}

Ray Camera::ray(double x, double y) const {
  const double f = std::tan(0.5 * fieldOfView * kDegree);
  const double aspect = double(width) / double(std::max(height, 1));
  const double nx = (2.0 * x / width - 1.0) * f * aspect;
  const double ny = (1.0 - 2.0 * y / height) * f;
  const Eigen::Matrix3d toWorld = view().block<3, 3>(0, 0).transpose();
  return {eye(), (toWorld * Eigen::Vector3d(nx, ny, -1.0)).normalized()};
}

double Camera::pixelSize(double depth) const {
  return 2.0 * depth * std::tan(0.5 * fieldOfView * kDegree) / double(std::max(height, 1));
}

Eigen::Vector3d Camera::screenOffset(double dxPixels, double dyPixels, double depth) const {
  const Eigen::Matrix3d toWorld = view().block<3, 3>(0, 0).transpose();
  const double s = pixelSize(depth);
  return toWorld * Eigen::Vector3d(dxPixels * s, -dyPixels * s, 0.0);
}

}  // namespace mspline::viewer
