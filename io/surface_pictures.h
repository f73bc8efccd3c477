#pragma once
// Pictures of a flat structure drawn by a small software rasterizer (no GPU): the cut layout, the
// surface textured through its flat coordinates, and a piece of the universal cover of a torus.
//
// The texture lives in the flat coordinates (the layout's per-corner UVs). On a flat torus it is
// built on the period lattice (cells spanned by p0 / N0 and p1 / N1 of a reduced basis, N0 and N1
// even for the checkerboard), so it is invariant under the deck translations: the checkerboard and
// the lines continue across the seams without a jump. Elsewhere it is axis-aligned in the layout:
// squares, and lines u = const.
#include <vector>

#include "mspline/io/raster_image.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::io {

/// The two checkerboard colors (orange and blue, far apart in hue so that shaded versions of them
/// stay distinguishable), the background, and the colors of the lines texture.
constexpr Rgb kCheckerColors[2] = {{235, 140, 40}, {50, 110, 210}};
constexpr Rgb kBackground = {255, 255, 255};
constexpr Rgb kLinesPaper = {225, 222, 210};
constexpr Rgb kLinesInk = {200, 30, 30};
/// Face edges (PictureOptions::edges), seams on the surface (PictureOptions::seams) and the
/// fundamental parallelogram of the cover.
constexpr Rgb kEdgeColor = {40, 40, 40};
constexpr Rgb kSeamColor = {20, 170, 60};
constexpr Rgb kOutlineColor = {0, 0, 0};

struct PictureOptions {
  /// Image size in pixels; the picture is fitted inside with a margin, keeping its aspect ratio.
  int width = 800;
  int height = 800;
  /// Side of a checkerboard cell, relative to the square root of the layout's area (not to its
  /// diameter, which long thin layouts such as a knotted tube's would make coarse).
  double checkerSize = 1.0 / 20.0;
  /// Distance between neighbouring lines, relative to the square root of the layout's area, and
  /// the share of that distance the ink covers.
  double lineSpacing = 1.0 / 40.0;
  double lineWidth = 0.2;
  /// Draw every face's edges, one pixel wide.
  bool edges = false;
  /// On the surface: draw the layout's cut edges, two pixels wide, to show where the charts meet.
  bool seams = true;
  /// Orthographic view of the surface: turn it by `yawDegrees` about the y axis, then by
  /// `pitchDegrees` about the x axis, and look along -z.
  double yawDegrees = 30.0;
  double pitchDegrees = 20.0;
  /// Cover: the copies translated by m p0 + n p1 for all |m|, |n| <= coverRadius, and the width
  /// in pixels of the fundamental parallelogram's outline (0 draws none).
  int coverRadius = 1;
  double outlineWidth = 3.0;
};

enum class SurfaceTexture { Checker, Lines };

/// The cut layout in the plane, every face filled with the checkerboard.
RasterImage renderLayout(const structure::TriMesh& surface, const structure::FlatLayout& layout,
                         const PictureOptions& options = {});

/// The surface in 3D (z-buffer, Lambert shading by face normals, lit from both sides), textured
/// through the per-corner UVs.
RasterImage renderSurface(const structure::TriMesh& surface, const structure::FlatLayout& layout,
                          const PictureOptions& options, SurfaceTexture texture);

/// A color per label, hues a golden angle apart so that neighbouring labels differ.
Rgb labelColor(int label);

/// The surface in 3D as renderSurface shows it, each face in the color of its label (e.g. a
/// Voronoi cell). InputError unless there is one label per face.
RasterImage renderSurfaceLabels(const structure::TriMesh& surface,
                                const std::vector<int>& faceLabel, const PictureOptions& options);

/// A flat torus' universal cover: the layout translated by the periods, the home copy (m = n = 0)
/// in kCheckerColors and every other copy's checkerboard in a light and a dark shade of its own
/// tint, and the fundamental parallelogram outlined. The checkerboard's cells are 2 coverRadius + 1
/// times larger than on the layout, so that about as many show. Throws InputError for a layout
/// without periods or a negative coverRadius.
RasterImage renderCover(const structure::TriMesh& surface, const structure::FlatLayout& layout,
                        const PictureOptions& options = {});

/// What `mspline picture` draws: the layout, the surface with either texture, or the cover.
enum class PictureKind { Layout, Checker, Lines, Cover };

/// The picture of `kind` (renderLayout, renderSurface or renderCover).
RasterImage renderPicture(const structure::TriMesh& surface, const structure::FlatLayout& layout,
                          PictureKind kind, const PictureOptions& options = {});

}  // namespace mspline::io
