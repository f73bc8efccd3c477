#pragma once
// A shaded picture of a triangle mesh by software rasterization (no GPU): an orthographic view
// along a fixed direction, a z-buffer, and Lambert shading of the per-pixel interpolated vertex
// normals under one fixed light. Used for pictures of fitted and exported spline surfaces.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/io/raster_image.h"

namespace mspline::io {

struct ShadedPictureOptions {
  /// Image size in pixels; the mesh's projection is fitted inside with a margin of 4%.
  int width = 800;
  int height = 800;
  /// The view, as in io/surface_pictures.h: turn the mesh by `yawDegrees` about the y axis, then
  /// by `pitchDegrees` about the x axis, and look along -z.
  double yawDegrees = 30.0;
  double pitchDegrees = 20.0;
  /// Surface and background colors. The light comes from the upper left, in front (the
  /// direction (-0.4, 0.5, 1) in view coordinates); brightness is ambient + (1 - ambient)
  /// max(0, n . light), with n turned towards the viewer (back faces are lit like front faces).
  Rgb color = {170, 185, 215};
  Rgb background = {255, 255, 255};
  double ambient = 0.25;
  /// Per triangle, 1 to draw it in `markColor` instead of `color` (shaded alike), e.g. the creases
  /// and folds export marks; empty: none.
  std::vector<char> marked;
  Rgb markColor = {225, 30, 30};
};

/// The mesh (`positions` one row per vertex, `triangles` indexing them) shaded with `normals`
/// (one unit normal per vertex, interpolated across each triangle and renormalized; empty: each
/// triangle's own normal, flat shading). Throws InputError for an index out of range, normals
/// that are not one per vertex, marks that are not one per triangle, or a non-positive image
/// size.
RasterImage renderShaded(const Eigen::MatrixX3d& positions,
                         const std::vector<std::array<int, 3>>& triangles,
                         const Eigen::MatrixX3d& normals, const ShadedPictureOptions& options = {});

}  // namespace mspline::io
