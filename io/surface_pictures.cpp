#include "mspline/io/surface_pictures.h"
#include "mspline/structure/core/constants.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using structure::FlatLayout;
using structure::InputError;
using structure::TriMesh;

double cross(const Vector2d& a, const Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Rgb scaled(Rgb c, double s) {
  auto channel = [s](std::uint8_t v) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(v * s), 0L, 255L));
  };
  return {channel(c.r), channel(c.g), channel(c.b)};
}

Rgb mixed(Rgb a, Rgb b, double t) {
  auto channel = [t](std::uint8_t x, std::uint8_t y) {
    return static_cast<std::uint8_t>(std::lround((1.0 - t) * x + t * y));
  };
  return {channel(a.r, b.r), channel(a.g, b.g), channel(a.b, b.b)};
}

void checkOptions(const TriMesh& surface, const FlatLayout& layout, const PictureOptions& options) {
  MSPLINE_ASSERT(layout.cornerUV.rows() == static_cast<Eigen::Index>(3 * surface.n_faces()),
                 "layout does not belong to this mesh");
  if (!(options.checkerSize > 0.0) || !(options.lineSpacing > 0.0))
    throw InputError("picture: the checker size and the line spacing must be positive");
  if (!(options.lineWidth > 0.0 && options.lineWidth < 1.0))
    throw InputError("picture: the line width must lie strictly between 0 and 1");
}

// Affine map from flat coordinates to pattern coordinates, in which checker cells are the unit
// squares and lines sit at the integers of the first coordinate.
struct PatternFrame {
  Vector2d origin = Vector2d::Zero();
  Eigen::Matrix2d toPattern = Eigen::Matrix2d::Identity();
  Vector2d operator()(const Vector2d& uv) const { return toPattern * (uv - origin); }
};

// Lagrange-Gauss reduction: the shortest basis of the period lattice, whose cells are the
// closest to squares.
std::array<Vector2d, 2> reducedBasis(Vector2d p0, Vector2d p1) {
  while (true) {
    if (p1.squaredNorm() < p0.squaredNorm()) std::swap(p0, p1);
    const double k = std::round(p0.dot(p1) / p0.squaredNorm());
    if (k == 0.0) return {p0, p1};
    p1 -= k * p0;
  }
}

// Cells of about `relativeSize` times the square root of the layout's area. On a torus the cells
// divide the reduced period basis, N0 x N1 cells per fundamental domain, with N0, N1 even when
// `even` (the checkerboard's colors are then invariant under the periods too).
PatternFrame patternFrame(const FlatLayout& layout, double relativeSize, bool even) {
  double area = 0.0;
  for (Eigen::Index f = 0; f < layout.cornerUV.rows() / 3; ++f) {
    const Vector2d a = layout.cornerUV.row(3 * f).transpose();
    area += 0.5 * std::abs(cross(layout.cornerUV.row(3 * f + 1).transpose() - a,
                                 layout.cornerUV.row(3 * f + 2).transpose() - a));
  }
  if (!(area > 0.0)) throw InputError("picture: the layout has no area");
  const double size = relativeSize * std::sqrt(area);
  PatternFrame frame;
  if (!layout.hasPeriods) {
    frame.toPattern /= size;
    return frame;
  }
  const auto [p0, p1] = reducedBasis(layout.periods[0], layout.periods[1]);
  const double fundamentalArea = std::abs(cross(p0, p1));
  auto count = [&](double height) {
    const long n = std::max(1L, std::lround(height / size));
    return static_cast<double>(even ? n + n % 2 : n);
  };
  Eigen::Matrix2d basis;
  basis << p0, p1;
  // Lattice lines parallel to p1 are fundamentalArea / |p1| apart, those parallel to p0
  // fundamentalArea / |p0|.
  frame.toPattern =
      Eigen::Vector2d(count(fundamentalArea / p1.norm()), count(fundamentalArea / p0.norm()))
          .asDiagonal() *
      basis.inverse();
  frame.origin = layout.fundamentalParallelogram[0];
  return frame;
}

int checkerParity(const PatternFrame& frame, const Vector2d& uv) {
  const Vector2d s = frame(uv);
  return static_cast<int>(
      (static_cast<long long>(std::floor(s.x())) + static_cast<long long>(std::floor(s.y()))) & 1);
}

bool onLine(const PatternFrame& frame, double width, const Vector2d& uv) {
  const double s = frame(uv).x();
  return s - std::floor(s) < width;
}

// Maps drawing coordinates (y up) onto the image (y down): the box [low, high] is centered and
// scaled to fit inside a margin.
struct Fit {
  Fit(const Vector2d& low, const Vector2d& high, const PictureOptions& options)
      : center(0.5 * (low + high)), imageCenter(0.5 * options.width, 0.5 * options.height) {
    const double margin = 0.04 * std::min(options.width, options.height);
    const Vector2d extent = (high - low).cwiseMax(1e-300);
    scale = std::min((options.width - 2 * margin) / extent.x(),
                     (options.height - 2 * margin) / extent.y());
  }
  Vector2d operator()(const Vector2d& p) const {
    return {imageCenter.x() + (p.x() - center.x()) * scale,
            imageCenter.y() - (p.y() - center.y()) * scale};
  }
  Vector2d center;
  Vector2d imageCenter;
  double scale = 1.0;
};

// The image with a depth buffer; pixels are sampled at their centers.
struct Canvas {
  explicit Canvas(const PictureOptions& options)
      : image(options.width, options.height, kBackground),
        depth(image.pixels.size(), std::numeric_limits<double>::infinity()),
        edges(options.edges) {}

  // Fills the triangle with image positions p[k] and depths z[k] (smaller is nearer) where it is
  // nearest, coloring each covered pixel by shade(barycentric coordinates). Bit k of `seams`
  // marks the edge opposite corner k as a seam.
  template <class Shade>
  void fill(const std::array<Vector2d, 3>& p, const std::array<double, 3>& z, Shade shade,
            unsigned seams = 0) {
    const double area = cross(p[1] - p[0], p[2] - p[0]);
    if (!(std::abs(area) > 1e-12)) return;
    const Vector2d low = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    const Vector2d high = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    const int x0 = std::max(0, static_cast<int>(std::floor(low.x())));
    const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(high.x())));
    const int y0 = std::max(0, static_cast<int>(std::floor(low.y())));
    const int y1 = std::min(image.height - 1, static_cast<int>(std::ceil(high.y())));
    // Pixel distance from a point with barycentric coordinate w[k] to the edge opposite corner k
    // is w[k] * height[k].
    std::array<double, 3> height;
    for (int k = 0; k < 3; ++k)
      height[k] = std::abs(area) / (p[(k + 2) % 3] - p[(k + 1) % 3]).norm();
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Vector2d q(x + 0.5, y + 0.5);
        const double w0 = cross(p[2] - p[1], q - p[1]) / area;
        const double w1 = cross(p[0] - p[2], q - p[2]) / area;
        const Vector3d w(w0, w1, 1.0 - w0 - w1);
        if (w.minCoeff() < 0.0) continue;
        const double d = w[0] * z[0] + w[1] * z[1] + w[2] * z[2];
        double& nearest = depth[static_cast<std::size_t>(y) * image.width + x];
        if (d >= nearest) continue;
        nearest = d;
        bool onSeam = false, onEdge = false;
        for (int k = 0; k < 3; ++k) {
          onSeam = onSeam || ((seams >> k & 1u) && w[k] * height[k] < 1.0);
          onEdge = onEdge || (edges && w[k] * height[k] < 0.5);
        }
        image.at(x, y) = onSeam ? kSeamColor : onEdge ? kEdgeColor : shade(w);
      }
  }

  RasterImage image;
  std::vector<double> depth;
  bool edges = false;
};

// A segment `halfWidth` pixels to each side of a -> b, over everything.
void drawSegment(RasterImage& image, const Vector2d& a, const Vector2d& b, double halfWidth,
                 Rgb color) {
  const Vector2d low = a.cwiseMin(b).array() - halfWidth;
  const Vector2d high = a.cwiseMax(b).array() + halfWidth;
  const Vector2d d = b - a;
  for (int y = std::max(0, int(std::floor(low.y())));
       y <= std::min(image.height - 1, int(std::floor(high.y()))); ++y)
    for (int x = std::max(0, int(std::floor(low.x())));
         x <= std::min(image.width - 1, int(std::floor(high.x()))); ++x) {
      const Vector2d q(x + 0.5, y + 0.5);
      const double t = std::clamp((q - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      if ((q - a - t * d).norm() <= halfWidth) image.at(x, y) = color;
    }
}

Vector2d cornerUV(const FlatLayout& layout, int face, int k) {
  return layout.cornerUV.row(3 * face + k).transpose();
}

// The layout translated by each shift, face by face, colored by the checkerboard `frame` of the
// home copy's coordinates; copy i takes colors[i]. `outline` draws the fundamental parallelogram.
RasterImage renderPlane(const TriMesh& surface, const FlatLayout& layout,
                        const PictureOptions& options, const PatternFrame& frame,
                        const std::vector<Vector2d>& shifts,
                        const std::vector<std::array<Rgb, 2>>& colors, bool outline) {
  Vector2d low = Vector2d::Constant(std::numeric_limits<double>::infinity());
  Vector2d high = -low;
  for (const Vector2d& s : shifts)
    for (Eigen::Index k = 0; k < layout.cornerUV.rows(); ++k) {
      low = low.cwiseMin(layout.cornerUV.row(k).transpose() + s);
      high = high.cwiseMax(layout.cornerUV.row(k).transpose() + s);
    }
  const Fit fit(low, high, options);
  Canvas canvas(options);
  for (std::size_t i = 0; i < shifts.size(); ++i)
    for (auto f : surface.faces()) {
      std::array<Vector2d, 3> uv, p;
      for (int k = 0; k < 3; ++k) {
        uv[k] = cornerUV(layout, f.idx(), k);
        p[k] = fit(uv[k] + shifts[i]);
      }
      canvas.fill(p, {0.0, 0.0, 0.0}, [&](const Vector3d& w) {
        return colors[i][checkerParity(frame, w[0] * uv[0] + w[1] * uv[1] + w[2] * uv[2])];
      });
    }
  if (outline && options.outlineWidth > 0.0) {
    const auto& corners = layout.fundamentalParallelogram;
    for (int k = 0; k < 4; ++k)
      drawSegment(canvas.image, fit(corners[k]), fit(corners[(k + 1) % 4]),
                  0.5 * options.outlineWidth, kOutlineColor);
  }
  return std::move(canvas.image);
}

}  // namespace

RasterImage renderLayout(const TriMesh& surface, const FlatLayout& layout,
                         const PictureOptions& options) {
  checkOptions(surface, layout, options);
  return renderPlane(surface, layout, options, patternFrame(layout, options.checkerSize, true),
                     {Vector2d::Zero()}, {{kCheckerColors[0], kCheckerColors[1]}}, false);
}

namespace {

// The surface seen from the options' direction (z-buffer, Lambert shading by face normals, lit
// from both sides), the pixel at barycentric coordinates w of face f colored color(f, w) and
// edges with cut[e] drawn as seams.
template <class Color>
RasterImage renderView(const TriMesh& surface, const std::vector<char>& cut,
                       const PictureOptions& options, Color color) {
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(options.pitchDegrees * kPi / 180.0, Vector3d::UnitX()) *
       Eigen::AngleAxisd(options.yawDegrees * kPi / 180.0, Vector3d::UnitY()))
          .toRotationMatrix();
  std::vector<Vector3d> view(surface.n_vertices());
  Vector2d low = Vector2d::Constant(std::numeric_limits<double>::infinity());
  Vector2d high = -low;
  for (auto v : surface.vertices()) {
    const auto& x = surface.point(v);
    view[v.idx()] = rotation * Vector3d(x[0], x[1], x[2]);
    low = low.cwiseMin(view[v.idx()].head<2>());
    high = high.cwiseMax(view[v.idx()].head<2>());
  }
  const Fit fit(low, high, options);
  const Vector3d light = Vector3d(-0.4, 0.5, 1.0).normalized();  // from the upper left, in front
  constexpr double kAmbient = 0.3;
  Canvas canvas(options);
  for (auto f : surface.faces()) {
    std::array<Vector3d, 3> x;
    std::array<Vector2d, 3> p;
    std::array<double, 3> z;
    int k = 0;
    for (auto v : surface.fv_range(f)) {
      x[k] = view[v.idx()];
      p[k] = fit(x[k].head<2>());
      z[k] = -x[k].z();  // the viewer looks along -z
      ++k;
    }
    // The k-th halfedge joins corners k - 1 and k: its edge is opposite corner k + 1.
    unsigned seams = 0;
    int j = 0;
    for (auto h : surface.fh_range(f)) {
      if (!cut.empty() && cut[surface.edge_handle(h).idx()]) seams |= 1u << (j + 1) % 3;
      ++j;
    }
    const Vector3d normal = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    const double brightness = kAmbient + (1.0 - kAmbient) * std::abs(normal.dot(light));
    canvas.fill(
        p, z, [&](const Vector3d& w) { return scaled(color(f.idx(), w), brightness); }, seams);
  }
  return std::move(canvas.image);
}

}  // namespace

RasterImage renderSurface(const TriMesh& surface, const FlatLayout& layout,
                          const PictureOptions& options, SurfaceTexture texture) {
  checkOptions(surface, layout, options);
  const bool checker = texture == SurfaceTexture::Checker;
  const PatternFrame frame = checker ? patternFrame(layout, options.checkerSize, true)
                                     : patternFrame(layout, options.lineSpacing, false);
  std::vector<char> cut(surface.n_edges(), 0);
  if (options.seams)
    for (int e : layout.cutEdges) cut[e] = 1;
  return renderView(surface, cut, options, [&](int f, const Vector3d& w) {
    const Vector2d at = w[0] * cornerUV(layout, f, 0) + w[1] * cornerUV(layout, f, 1) +
                        w[2] * cornerUV(layout, f, 2);
    return checker ? kCheckerColors[checkerParity(frame, at)]
                   : (onLine(frame, options.lineWidth, at) ? kLinesInk : kLinesPaper);
  });
}

Rgb labelColor(int label) {
  // Hues a golden angle apart, so that neighbouring labels differ; HSV with s = 0.6, v = 0.95.
  const double hue = std::fmod(label * 137.50776405, 360.0) / 60.0;
  const double c = 0.95 * 0.6, x = c * (1.0 - std::abs(std::fmod(hue, 2.0) - 1.0)), m = 0.95 - c;
  const int sector = static_cast<int>(hue) % 6;
  const double rgb[6][3] = {{c, x, 0}, {x, c, 0}, {0, c, x}, {0, x, c}, {x, 0, c}, {c, 0, x}};
  const auto channel = [&](double value) {
    return static_cast<std::uint8_t>(std::lround(255.0 * (value + m)));
  };
  return {channel(rgb[sector][0]), channel(rgb[sector][1]), channel(rgb[sector][2])};
}

RasterImage renderSurfaceLabels(const TriMesh& surface, const std::vector<int>& faceLabel,
                                const PictureOptions& options) {
  if (faceLabel.size() != surface.n_faces())
    throw InputError("picture: " + std::to_string(faceLabel.size()) + " labels for " +
                     std::to_string(surface.n_faces()) + " faces");
  return renderView(surface, {}, options,
                    [&](int f, const Vector3d&) { return labelColor(faceLabel[std::size_t(f)]); });
}

RasterImage renderCover(const TriMesh& surface, const FlatLayout& layout,
                        const PictureOptions& options) {
  checkOptions(surface, layout, options);
  if (!layout.hasPeriods)
    throw InputError(
        "picture: the universal cover needs a layout with periods (a closed genus-1 surface "
        "flattened without cones)");
  if (options.coverRadius < 0) throw InputError("picture: negative cover radius");
  static constexpr Rgb kTints[] = {{230, 60, 60},  {60, 170, 60},  {150, 80, 210},  {230, 210, 40},
                                   {40, 190, 200}, {210, 90, 160}, {120, 120, 120}, {90, 90, 240}};
  std::vector<Vector2d> shifts;
  std::vector<std::array<Rgb, 2>> colors;
  const int r = options.coverRadius;
  int tint = 0;
  for (int m = -r; m <= r; ++m)
    for (int n = -r; n <= r; ++n) {
      shifts.push_back(m * layout.periods[0] + n * layout.periods[1]);
      if (m == 0 && n == 0) {
        colors.push_back({kCheckerColors[0], kCheckerColors[1]});
      } else {
        const Rgb t = kTints[tint++ % std::size(kTints)];
        colors.push_back({mixed(t, kBackground, 0.45), scaled(t, 0.8)});
      }
    }
  // Cells grow with the copies, so that the picture shows as many as the layout's.
  const PatternFrame frame = patternFrame(layout, options.checkerSize * (2 * r + 1), true);
  return renderPlane(surface, layout, options, frame, shifts, colors, true);
}

RasterImage renderPicture(const TriMesh& surface, const FlatLayout& layout, PictureKind kind,
                          const PictureOptions& options) {
  switch (kind) {
    case PictureKind::Layout:
      return renderLayout(surface, layout, options);
    case PictureKind::Checker:
      return renderSurface(surface, layout, options, SurfaceTexture::Checker);
    case PictureKind::Lines:
      return renderSurface(surface, layout, options, SurfaceTexture::Lines);
    case PictureKind::Cover:
      break;
  }
  return renderCover(surface, layout, options);
}

}  // namespace mspline::io
