#include "mspline/spline/model/export_surface.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "mspline/spline/model/filled_faces.h"
#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"

namespace mspline::spline {

namespace {

// A piece of the parameter domain (a domain face, a T-mesh face) for the chord error estimate:
// the longest edge its grid has at resolution 1, and the largest norm of the second derivatives
// seen in it.
struct PieceCurvature {
  double length = 0.0;
  double secondDerivative = 0.0;
};

// The largest sqrt(|xuu|^2 + 2 |xuv|^2 + |xvv|^2) (a bound of |x''| along every unit direction in
// the chart) of the surface at `points`, those where it is undefined (a cone point, a hole)
// skipped.
double largestSecondDerivative(const FitSpace& space, const Eigen::MatrixXd& control,
                               const std::vector<FacePoint>& points) {
  double largest = 0.0;
  std::vector<FitBasisTerm> terms;
  for (const FacePoint& p : points) {
    space.basisAt(p, terms, 2);
    if (terms.empty()) continue;
    Eigen::Vector3d ss = Eigen::Vector3d::Zero(), st = ss, tt = ss;
    for (const FitBasisTerm& b : terms) {
      ss += b.dss * control.row(b.index).transpose();
      st += b.dst * control.row(b.index).transpose();
      tt += b.dtt * control.row(b.index).transpose();
    }
    const double m = std::sqrt(ss.squaredNorm() + 2.0 * st.squaredNorm() + tt.squaredNorm());
    if (std::isfinite(m)) largest = std::max(largest, m);
  }
  return largest;
}

// The model's pieces: per domain face its longest side and the points of its barycentric grid of
// 3 steps other than the corners (where cones would have no derivative); per T-mesh face its
// diagonal and the 3 x 3 interior points of its 4 x 4 grid.
std::vector<PieceCurvature> modelCurvature(const ModelSurface& surface, const SplineModel& model) {
  std::vector<PieceCurvature> pieces;
  std::vector<FacePoint> points;
  const auto add = [&](double length) {
    pieces.push_back(
        {length, largestSecondDerivative(surface.fitSpace(), model.controlPoints, points)});
    points.clear();
  };
  if (surface.kind() == SplineKind::TriangularBSpline) {
    const SplineDomain& domain = model.domain;
    for (int f = 0; f < domain.faceCount(); ++f) {
      const auto corners = canonicalCorners(domain, f);
      for (int i = 0; i <= 3; ++i)
        for (int j = 0; i + j <= 3; ++j)
          if (i < 3 && j < 3 && i + j > 0)
            points.push_back(
                {f, ((3 - i - j) * corners[0] + i * corners[1] + j * corners[2]) / 3.0});
      const auto& sides = domain.sideLengths[std::size_t(f)];
      add(std::max({sides[0], sides[1], sides[2]}));
    }
    return pieces;
  }
  for (int f = 0; f < model.tmesh.numFaces(); ++f) {
    const TMeshFace& face = model.tmesh.faces[std::size_t(f)];
    for (int i = 1; i < 4; ++i)
      for (int j = 1; j < 4; ++j)
        points.push_back({f, Eigen::Vector2d(face.width * i / 4.0, face.height * j / 4.0)});
    add(std::hypot(face.width, face.height));
  }
  return pieces;
}

// The smallest resolution whose chord error estimate h^2 max|x''| / 8 (h: the piece's longest
// grid edge) is at most `bound` on every piece, capped at `cap`.
int resolutionForChordError(const std::vector<PieceCurvature>& pieces, double bound, int cap) {
  double needed = 1.0;
  for (const PieceCurvature& piece : pieces)
    needed = std::max(needed,
                      std::ceil(piece.length * std::sqrt(piece.secondDerivative / (8.0 * bound))));
  return int(std::min(needed, double(cap)));
}

double chordErrorEstimate(const std::vector<PieceCurvature>& pieces, int resolution) {
  double estimate = 0.0;
  for (const PieceCurvature& piece : pieces) {
    const double h = piece.length / resolution;
    estimate = std::max(estimate, h * h * piece.secondDerivative / 8.0);
  }
  return estimate;
}

ExportControlNet controlNetOf(const ModelSurface& surface, const SplineModel& model) {
  const ModelControlNet net = surface.controlNet();
  ExportControlNet out;
  std::vector<std::int64_t> pointOfRow(std::size_t(surface.numControlPoints()), -1);
  for (int row : net.points) {
    pointOfRow[std::size_t(row)] = std::int64_t(out.points.size());
    out.points.push_back(
        {model.controlPoints(row, 0), model.controlPoints(row, 1), model.controlPoints(row, 2)});
  }
  for (const auto& [a, b] : net.lines)
    out.lines.push_back({pointOfRow[std::size_t(a)], pointOfRow[std::size_t(b)]});
  if (surface.kind() == SplineKind::TriangularBSpline) {
    out.domainFaces = model.domain.faceCount();
  } else if (surface.kind() == SplineKind::TSpline) {
    // Every T-mesh edge once: the sides with a twin count half.
    std::size_t sides = 0, boundary = 0;
    for (const TMeshFace& face : model.tmesh.faces) {
      sides += face.vertices.size();
      boundary += std::size_t(std::count(face.twinFace.begin(), face.twinFace.end(), -1));
    }
    out.missingAnchors = std::int64_t(model.tmesh.numVertices) - std::int64_t(out.points.size());
    out.edgesSkipped = int((sides + boundary) / 2 - out.lines.size());
  }
  return out;
}

// Drops the faces of `surface` not marked in `keep`, with the vertices only they used.
void keepSurfaceFaces(ModelTessellation& surface, const std::vector<char>& keep) {
  const std::vector<int> newIndex = keepFaces(surface.mesh, keep);
  const auto move = [&](auto& values) {
    std::remove_reference_t<decltype(values)> kept(surface.mesh.positions.size());
    for (std::size_t v = 0; v < newIndex.size() && v < values.size(); ++v)
      if (newIndex[v] >= 0) kept[std::size_t(newIndex[v])] = values[v];
    values = std::move(kept);
  };
  move(surface.normals);
  move(surface.uvs);
}

}  // namespace

ExportResult exportSurface(const SplineModel& model, const std::string& name,
                           const ExportOptions& options) {
  if (options.resolution < 1 || options.maxToleranceResolution < 1 || !(options.tolerance >= 0.0))
    throw structure::InputError(name + ": export needs a resolution >= 1 and a tolerance >= 0");
  const ModelSurface modelSurface(model, name);
  ExportResult result;
  result.kind = modelSurface.kind();
  result.kindName = modelSurface.kindName();
  result.resolution = options.resolution;
  std::vector<PieceCurvature> pieces;
  if (options.tolerance > 0.0) {
    result.diagonal = structure::boundingBoxDiagonal(model.surfaceVertices.rows() > 0
                                                         ? model.surfaceVertices
                                                         : Eigen::MatrixX3d(model.controlPoints));
    pieces = modelCurvature(modelSurface, model);
    const double bound = options.tolerance * result.diagonal;
    result.resolution = resolutionForChordError(pieces, bound, options.maxToleranceResolution);
    const double estimate = chordErrorEstimate(pieces, result.resolution);
    result.chordErrorEstimate = estimate / result.diagonal;
    result.toleranceMet = estimate <= bound;
  }
  result.surface = modelSurface.tessellate(model.controlPoints, result.resolution);
  if (options.trimFills) {
    // A scan's holes were closed by fill patches for the fit: trimmed away again here.
    const std::vector<char> keep = facesToKeep(result.surface.mesh, model);
    result.trimmedFaces = std::size_t(std::count(keep.begin(), keep.end(), char(0)));
    if (result.trimmedFaces > 0) keepSurfaceFaces(result.surface, keep);
  }
  if (options.controlNet) result.controlNet = controlNetOf(modelSurface, model);
  return result;
}

}  // namespace mspline::spline
