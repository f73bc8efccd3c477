#include "mspline/io/shaded_picture.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

double cross(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

std::uint8_t channel(std::uint8_t value, double brightness) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(value * brightness), 0L, 255L));
}

}  // namespace

RasterImage renderShaded(const Eigen::MatrixX3d& positions,
                         const std::vector<std::array<int, 3>>& triangles,
                         const Eigen::MatrixX3d& normals, const ShadedPictureOptions& options) {
  if (options.width < 1 || options.height < 1)
    throw structure::InputError("shaded picture: the image size must be positive");
  if (normals.rows() != 0 && normals.rows() != positions.rows())
    throw structure::InputError("shaded picture: " + std::to_string(normals.rows()) +
                                " normals for " + std::to_string(positions.rows()) + " vertices");
  if (!options.marked.empty() && options.marked.size() != triangles.size())
    throw structure::InputError("shaded picture: " + std::to_string(options.marked.size()) +
                                " marks for " + std::to_string(triangles.size()) + " triangles");
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int v : triangles[f])
      if (v < 0 || v >= positions.rows())
        throw structure::InputError("shaded picture: triangle " + std::to_string(f) +
                                    " refers to vertex " + std::to_string(v) + " of " +
                                    std::to_string(positions.rows()));
  RasterImage image(options.width, options.height, options.background);
  if (positions.rows() == 0 || triangles.empty()) return image;

  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(options.pitchDegrees * kPi / 180.0, Vector3d::UnitX()) *
       Eigen::AngleAxisd(options.yawDegrees * kPi / 180.0, Vector3d::UnitY()))
          .toRotationMatrix();
  const Eigen::MatrixX3d view = positions * rotation.transpose();
  const Eigen::MatrixX3d viewNormals = normals * rotation.transpose();
  const Vector2d low = view.leftCols<2>().colwise().minCoeff().transpose();
  const Vector2d high = view.leftCols<2>().colwise().maxCoeff().transpose();
  const double margin = 0.04 * std::min(options.width, options.height);
  const Vector2d extent = (high - low).cwiseMax(1e-300);
  const double scale = std::min((options.width - 2 * margin) / extent.x(),
                                (options.height - 2 * margin) / extent.y());
  const Vector2d center = 0.5 * (low + high);
  const auto toImage = [&](const Vector3d& x) {
    return Vector2d(0.5 * options.width + (x.x() - center.x()) * scale,
                    0.5 * options.height - (x.y() - center.y()) * scale);
  };
  const Vector3d light = Vector3d(-0.4, 0.5, 1.0).normalized();
  std::vector<double> depth(image.pixels.size(), std::numeric_limits<double>::infinity());

  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    const Rgb color =
        !options.marked.empty() && options.marked[f] ? options.markColor : options.color;
    std::array<Vector3d, 3> x, n;
    std::array<Vector2d, 3> p;
    for (int k = 0; k < 3; ++k) {
      x[std::size_t(k)] = view.row(t[std::size_t(k)]).transpose();
      p[std::size_t(k)] = toImage(x[std::size_t(k)]);
    }
    const Vector3d faceNormal = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    for (int k = 0; k < 3; ++k)
      n[std::size_t(k)] =
          normals.rows() ? Vector3d(viewNormals.row(t[std::size_t(k)]).transpose()) : faceNormal;
    const double area = cross(p[1] - p[0], p[2] - p[0]);
    if (!(std::abs(area) > 1e-12)) continue;
    const Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    const Vector2d hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    const int x0 = std::max(0, int(std::floor(lo.x()))),
              x1 = std::min(image.width - 1, int(hi.x()));
    const int y0 = std::max(0, int(std::floor(lo.y()))),
              y1 = std::min(image.height - 1, int(hi.y()));
    for (int y = y0; y <= y1; ++y)
      for (int xx = x0; xx <= x1; ++xx) {
        const Vector2d q(xx + 0.5, y + 0.5);
        const double w0 = cross(p[2] - p[1], q - p[1]) / area;
        const double w1 = cross(p[0] - p[2], q - p[2]) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        // The viewer looks along -z: larger z is nearer.
        const double d = -(w0 * x[0].z() + w1 * x[1].z() + w2 * x[2].z());
        double& nearest = depth[std::size_t(y) * std::size_t(image.width) + std::size_t(xx)];
        if (d >= nearest) continue;
        nearest = d;
        Vector3d normal = w0 * n[0] + w1 * n[1] + w2 * n[2];
        if (!(normal.norm() > 0.0)) normal = faceNormal;
        normal.normalize();
        if (normal.z() < 0.0) normal = -normal;
        const double brightness =
            options.ambient + (1.0 - options.ambient) * std::max(0.0, normal.dot(light));
        image.at(xx, y) = {channel(color.r, brightness), channel(color.g, brightness),
                           channel(color.b, brightness)};
      }
  }
  return image;
}

}  // namespace mspline::io
