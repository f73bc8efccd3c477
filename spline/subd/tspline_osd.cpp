#include "mspline/spline/subd/tspline_osd.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>

#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/tspline/tspline_bezier.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// OpenSubdiv's view of a quad face of a net without T-junctions (valence = faces around a vertex,
// since every vertex is a corner of each of its faces): a regular patch when its four vertices
// are interior of valence 4; no limit surface under BoundaryRule::None when one is on the boundary.
bool osdHasSurface(const TMesh& mesh, int f) {
  for (int v : mesh.faces[f].vertices)
    if (mesh.onBoundary[v]) return false;
  return true;
}

bool osdRegular(const TMesh& mesh, int f) {
  for (int v : mesh.faces[f].vertices)
    if (mesh.onBoundary[v] || mesh.quarterTurnsAround[v] != 4) return false;
  return true;
}

// Whether the T-spline over face f is the uniform bicubic B-spline of OpenSubdiv's 16 patch
// points (see OsdFaceClass::Regular).
bool completeUniformFace(const TSplineSpace& space, FaceDeveloper& developer, int f,
                         const Eigen::VectorXd& weights) {
  const TMesh& mesh = space.mesh();
  const TMeshFace& face = mesh.faces[f];
  const std::vector<TSplinePiece>& pieces = space.pieces(f);
  if (pieces.size() != 16) return false;
  const double w = face.width, h = face.height, tolerance = 1e-9 * std::max(w, h);
  // Grid index of a face-frame coordinate in units of `step`, or -2 when not a grid line of the
  // 4 x 4 neighbourhood (indices -1 .. 2).
  const auto gridIndex = [&](double x, double step) {
    const double i = std::round(x / step);
    return std::abs(x - i * step) <= tolerance && i >= -1 && i <= 2 ? int(i) : -2;
  };
  // The vertices at the 4 x 4 grid positions around the face, developed into its frame (an open
  // box: an extraordinary vertex on its boundary, next to a cap, is not wound around).
  std::map<std::pair<int, int>, int> vertexAt;
  for (const DevelopedFace& d :
       developer.develop(f, QuarterMotion{}, {-w, -h}, {2.0 * w, 2.0 * h}, true)) {
    const TMeshFace& other = mesh.faces[d.face];
    for (std::size_t k = 0; k < other.vertices.size(); ++k) {
      const Eigen::Vector2d p = d.toChart.apply(other.positions[k]);
      const int i = gridIndex(p.x(), w), j = gridIndex(p.y(), h);
      if (i == -2 || j == -2) continue;
      const auto [at, inserted] = vertexAt.emplace(std::make_pair(i, j), other.vertices[k]);
      if (!inserted && at->second != other.vertices[k]) return false;  // overlapping development
    }
  }
  std::map<std::pair<int, int>, int> used;
  const double weight = weights.size() ? weights[pieces[0].anchor] : 1.0;
  for (const TSplinePiece& piece : pieces) {
    const TSplineAnchor& a = space.anchors()[piece.anchor];
    if (weights.size() && weights[piece.anchor] != weight) return false;
    const QuarterMotion back = piece.toChart.inverse();
    const Eigen::Vector2d anchor = back.apply({0.0, 0.0});
    const int i = gridIndex(anchor.x(), w), j = gridIndex(anchor.y(), h);
    if (i == -2 || j == -2 || !used.emplace(std::make_pair(i, j), 0).second) return false;
    const auto at = vertexAt.find({i, j});
    if (at == vertexAt.end() || at->second != a.vertex) return false;
    const FaceKnots2d knots = knotsInFace(a, piece.toChart);
    for (std::size_t k = 0; k < 5; ++k) {
      const double offset = double(k) - 2.0;
      if (std::abs(knots.xKnots[k] - (anchor.x() + offset * w)) > tolerance ||
          std::abs(knots.yKnots[k] - (anchor.y() + offset * h)) > tolerance)
        return false;
    }
  }
  return true;
}

double boundingBoxDiagonal(const Eigen::MatrixXd& points) {
  if (points.rows() == 0) return 0.0;
  return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
}

}  // namespace

std::vector<std::vector<int>> catmullClarkNetFaces(const TMesh& mesh, const std::string& context) {
  std::vector<std::vector<int>> faces;
  faces.reserve(mesh.faces.size());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    if (mesh.faces[f].vertices.size() != 4)
      throw InputError(context + ": the T-mesh has T-junctions (face " + std::to_string(f) +
                       " has " + std::to_string(mesh.faces[f].vertices.size()) +
                       " boundary vertices, a Catmull-Clark net needs 4)");
    faces.push_back(mesh.faces[f].vertices);
  }
  return faces;
}

TSplineControlNet tsplineControlNet(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                    const Eigen::MatrixXd& unanchoredPoints) {
  const TMesh& mesh = space.mesh();
  TSplineControlNet net;
  net.faces = catmullClarkNetFaces(mesh, "OpenSubdiv comparison");
  const int n = mesh.numVertices;
  if (control.rows() != space.numBasis() || control.cols() != 3)
    throw InputError("OpenSubdiv comparison: control points must be " +
                     std::to_string(space.numBasis()) + " x 3");
  if (unanchoredPoints.size() != 0 &&
      (unanchoredPoints.rows() != n || unanchoredPoints.cols() != 3))
    throw InputError("OpenSubdiv comparison: points of unanchored vertices must be " +
                     std::to_string(n) + " x 3");
  net.points.setZero(n, 3);
  std::vector<char> placed(static_cast<std::size_t>(n), 0);
  for (int v = 0; v < n; ++v) {
    const int anchor = space.anchorOfVertex()[v];
    if (anchor >= 0) {
      net.points.row(v) = control.row(anchor);
      placed[v] = 1;
    } else if (unanchoredPoints.size() != 0) {
      net.points.row(v) = unanchoredPoints.row(v);
      placed[v] = 1;
    }
  }
  fillByRingAverages(mesh, net.points, std::move(placed), "OpenSubdiv comparison");
  return net;
}

OsdComparison compareWithOpenSubdiv(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                    const Eigen::VectorXd& weights,
                                    const OsdCompareOptions& options) {
  const TMesh& mesh = space.mesh();
  if (options.samples < 1) throw InputError("OpenSubdiv comparison: samples must be at least 1");
  if (weights.size() != 0 && weights.size() != space.numBasis())
    throw InputError("OpenSubdiv comparison: weights do not match the blending functions");
  const TSplineControlNet net = tsplineControlNet(space, control, options.unanchoredPoints);
  const int numFaces = mesh.numFaces();

  OsdComparison result;
  auto start = Clock::now();
  const TSplineBezier bezier(space, control, weights);
  result.msplineSetupSeconds = since(start);
  CatmullClarkOptions osdOptions;
  osdOptions.boundary = BoundaryRule::None;
  osdOptions.isolationLevel = options.isolationLevel;
  start = Clock::now();
  const CatmullClarkLimit limit(net.points, net.faces, osdOptions);
  result.osdSetupSeconds = since(start);

  result.faceClass.resize(static_cast<std::size_t>(numFaces));
  int osdRegularFaces = 0, osdWithoutSurface = 0;
  FaceDeveloper developer(mesh);
  for (int f = 0; f < numFaces; ++f) {
    OsdFaceClass& c = result.faceClass[f];
    if (!osdHasSurface(mesh, f)) {
      c = OsdFaceClass::WithoutSurface;
      ++osdWithoutSurface;
    } else if (osdRegular(mesh, f)) {
      ++osdRegularFaces;
      c = completeUniformFace(space, developer, f, weights) ? OsdFaceClass::Regular
                                                            : OsdFaceClass::Irregular;
    } else {
      c = OsdFaceClass::Irregular;
    }
  }
  const FaceCounts counts = limit.faceCounts();
  MSPLINE_ASSERT(counts.regular == osdRegularFaces && counts.withoutSurface == osdWithoutSurface,
                 "OpenSubdiv's patches differ from the expected regular faces and holes");

  // The samples; patch face f is base face f in a net of quads.
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<FacePoint> points(static_cast<std::size_t>(options.samples));
  std::vector<FaceParameter> parameters(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const int f = static_cast<int>(k % static_cast<std::size_t>(numFaces));
    const double u = unit(rng), v = unit(rng);
    parameters[k] = {f, u, v};
    points[k] = {f, Eigen::Vector2d(u * mesh.faces[f].width, v * mesh.faces[f].height)};
  }
  Eigen::MatrixX3d position, ds, dt;
  bezier.evaluate(points, position, ds, dt);
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!position.row(Eigen::Index(k)).allFinite())
      result.faceClass[points[k].face] = OsdFaceClass::WithoutSurface;

  std::vector<std::size_t> comparedIndex;
  std::vector<FacePoint> compared;
  std::vector<FaceParameter> comparedParameters;
  for (std::size_t k = 0; k < points.size(); ++k)
    if (result.faceClass[points[k].face] != OsdFaceClass::WithoutSurface) {
      comparedIndex.push_back(k);
      compared.push_back(points[k]);
      comparedParameters.push_back(parameters[k]);
    }
  LimitPoints reference;
  limit.evaluate(comparedParameters, reference);

  result.scale = boundingBoxDiagonal(control);
  const double scale = result.scale > 0.0 ? result.scale : 1.0;
  for (std::size_t k = 0; k < compared.size(); ++k) {
    const Eigen::Index r = static_cast<Eigen::Index>(k);
    result.derivativeScale =
        std::max({result.derivativeScale, reference.du.row(r).norm(), reference.dv.row(r).norm()});
  }
  const double derivativeScale = result.derivativeScale > 0.0 ? result.derivativeScale : 1.0;
  for (std::size_t k = 0; k < compared.size(); ++k) {
    const Eigen::Index r = static_cast<Eigen::Index>(k), s = Eigen::Index(comparedIndex[k]);
    const TMeshFace& face = mesh.faces[compared[k].face];
    const double deviation = (position.row(s) - reference.position.row(r)).norm() / scale;
    const double derivativeDeviation =
        std::max((face.width * ds.row(s) - reference.du.row(r)).norm(),
                 (face.height * dt.row(s) - reference.dv.row(r)).norm()) /
        derivativeScale;
    ++result.samples;
    if (result.faceClass[compared[k].face] == OsdFaceClass::Regular) {
      ++result.regularSamples;
      result.regularMaxDeviation = std::max(result.regularMaxDeviation, deviation);
      result.regularMaxDerivativeDeviation =
          std::max(result.regularMaxDerivativeDeviation, derivativeDeviation);
    } else {
      result.irregularMaxDeviation = std::max(result.irregularMaxDeviation, deviation);
      result.irregularMaxDerivativeDeviation =
          std::max(result.irregularMaxDerivativeDeviation, derivativeDeviation);
    }
  }
  for (OsdFaceClass c : result.faceClass) {
    result.regularFaces += c == OsdFaceClass::Regular;
    result.irregularFaces += c == OsdFaceClass::Irregular;
    result.facesWithoutSurface += c == OsdFaceClass::WithoutSurface;
  }

  // Timing: best of two runs of each batch over the compared points.
  if (!compared.empty()) {
    double msplineSeconds = INFINITY, osdSeconds = INFINITY;
    for (int run = 0; run < 2; ++run) {
      start = Clock::now();
      bezier.evaluate(compared, position, ds, dt);
      msplineSeconds = std::min(msplineSeconds, since(start));
      start = Clock::now();
      limit.evaluate(comparedParameters, reference);
      osdSeconds = std::min(osdSeconds, since(start));
    }
    result.msplinePointsPerSecond = double(compared.size()) / std::max(msplineSeconds, 1e-12);
    result.osdPointsPerSecond = double(compared.size()) / std::max(osdSeconds, 1e-12);
  }
  return result;
}

}  // namespace mspline::spline
