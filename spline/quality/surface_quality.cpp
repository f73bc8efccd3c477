#include "mspline/spline/quality/surface_quality.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <unordered_set>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include "mspline/spline/fitting/surface_fit.h"
#include "mspline/spline/model/filled_faces.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"

namespace mspline::spline {

namespace {

using Eigen::Vector3d;
using structure::PolygonSoup;

double degrees(double cosine) {
  return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi;
}

Vector3d positionOf(const PolygonSoup& soup, std::int64_t v) {
  const auto& p = soup.positions[std::size_t(v)];
  return {p[0], p[1], p[2]};
}

// The value at rank ceil(q n) - 1 of the sorted values (the smallest value that at least a share
// q of them do not exceed); `values` is reordered.
double percentile(std::vector<double>& values, double q) {
  if (values.empty()) return 0.0;
  const std::size_t rank = std::min(
      values.size() - 1, std::size_t(std::max(1.0, std::ceil(q * double(values.size()))) - 1));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(rank), values.end());
  return values[rank];
}

// Faces a and b of a triangle soup share the edge from vertex `from` to `to`.
struct FacePair {
  int a, b;
  std::int64_t from, to;
};

// The faces' unit normals (zero for a degenerate face) and the pairs of faces marked in `kept`
// that share an edge, both with a normal.
struct AdjacentFaces {
  std::vector<Vector3d> normals;
  std::vector<FacePair> pairs;
};

AdjacentFaces adjacentFaces(const PolygonSoup& soup, const std::vector<char>& kept) {
  AdjacentFaces out;
  out.normals.resize(soup.faces.size());
  // Edges as (smaller vertex, larger vertex, face), sorted: an interior edge is two in a row.
  std::vector<std::tuple<std::int64_t, std::int64_t, int>> edges;
  edges.reserve(3 * soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    const Vector3d a = positionOf(soup, face[0]), b = positionOf(soup, face[1]),
                   c = positionOf(soup, face[2]);
    const Vector3d n = (b - a).cross(c - a);
    const double scale = std::max((b - a).squaredNorm(), (c - a).squaredNorm());
    out.normals[f] = n.norm() > 1e-12 * scale ? Vector3d(n.normalized()) : Vector3d::Zero();
    if (!kept[f]) continue;
    for (std::size_t k = 0; k < face.size(); ++k) {
      const std::int64_t u = face[k], v = face[(k + 1) % face.size()];
      edges.emplace_back(std::min(u, v), std::max(u, v), int(f));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t end = k + 1;
    while (end < edges.size() && std::get<0>(edges[end]) == std::get<0>(edges[k]) &&
           std::get<1>(edges[end]) == std::get<1>(edges[k]))
      ++end;
    // Only manifold edges: a pair across a boundary does not exist, and a non-manifold edge has no
    // dihedral angle.
    if (end == k + 2) {
      const int a = std::get<2>(edges[k]), b = std::get<2>(edges[k + 1]);
      if (!out.normals[std::size_t(a)].isZero() && !out.normals[std::size_t(b)].isZero())
        out.pairs.push_back({a, b, std::get<0>(edges[k]), std::get<1>(edges[k])});
    }
    k = end;
  }
  return out;
}

double pairDegrees(const AdjacentFaces& faces, const FacePair& pair) {
  return degrees(faces.normals[std::size_t(pair.a)].dot(faces.normals[std::size_t(pair.b)]));
}

// A tessellation with what every measure of it needs: which faces are over the scan, and the
// normals and adjacent pairs of those.
struct MeasuredTessellation {
  ModelTessellation t;
  std::vector<char> kept;
  AdjacentFaces faces;

  SurfaceLocation locate(std::int64_t vertex) const {
    return {positionOf(t.mesh, vertex),
            t.samplePoints[std::size_t(t.sampleOffsets[std::size_t(vertex)])]};
  }
  Vector3d centroid(std::size_t face) const {
    Vector3d sum = Vector3d::Zero();
    for (const auto v : t.mesh.faces[face]) sum += positionOf(t.mesh, v);
    return sum / double(t.mesh.faces[face].size());
  }
};

MeasuredTessellation measuredTessellation(const SplineModel& surfaceModel,
                                          const ModelSurface& surface,
                                          const Eigen::MatrixXd& control, int resolution) {
  MeasuredTessellation m;
  m.t = surface.tessellate(control, resolution);
  m.kept = facesOverScan(m.t.mesh, surfaceModel);
  m.faces = adjacentFaces(m.t.mesh, m.kept);
  return m;
}

SurfaceLocation pairLocation(const MeasuredTessellation& m, const FacePair& pair) {
  SurfaceLocation at = m.locate(pair.from);
  at.position = 0.5 * (positionOf(m.t.mesh, pair.from) + positionOf(m.t.mesh, pair.to));
  return at;
}

DihedralPercentiles dihedrals(const MeasuredTessellation& m, int resolution) {
  DihedralPercentiles out;
  out.resolution = resolution;
  std::vector<double> angles;
  angles.reserve(m.faces.pairs.size());
  for (const auto& pair : m.faces.pairs) angles.push_back(pairDegrees(m.faces, pair));
  out.pairs = int(angles.size());
  if (angles.empty()) return out;
  const std::size_t largest =
      std::size_t(std::max_element(angles.begin(), angles.end()) - angles.begin());
  out.max = angles[largest];
  out.maxAt = pairLocation(m, m.faces.pairs[largest]);
  out.p50 = percentile(angles, 0.5);
  out.p99 = percentile(angles, 0.99);
  out.p999 = percentile(angles, 0.999);
  return out;
}

// projectOntoSurface from `start`, and whether it ended at a critical point of the distance: the
// offset to x along the surface normal to 1e-3 rad (then the distance is within 5e-7 of it of
// the local minimum's), or x on the surface to `onSurface`. Not on the spline where it is
// undefined at the start.
ClosestSurfacePoint project(const FitSpace& space, const Eigen::MatrixXd& control,
                            const Vector3d& x, const FacePoint& start, int steps, double onSurface,
                            std::vector<FitBasisTerm>& terms) {
  const SurfaceProjection found = projectOntoSurface(space, control, start, x, steps);
  ClosestSurfacePoint out;
  if (!std::isfinite(found.distance)) return out;
  out.onSpline = true;
  out.distance = found.distance;
  out.parameter = found.parameter;
  out.position = evaluateFitSurface(space, control, found.parameter);
  Vector3d ds, dt;
  const Vector3d offset = x - out.position;
  if (offset.norm() > onSurface &&
      evaluateFitTangents(space, control, found.parameter, terms, ds, dt)) {
    const Vector3d normal = ds.cross(dt);
    if (normal.norm() > 0.0)
      out.converged = (offset - offset.dot(normal.normalized()) * normal.normalized()).norm() <=
                      1e-3 * offset.norm();
  }
  return out;
}

// The cosine of the smallest angle between `normal` and the scan's normal at the point of face
// `face` with barycentric coordinates `at`: the face's own unit normal (`faceNormals`), or inside
// an edge or at a vertex the nearest of those of the faces holding it; -2 when all of those are
// degenerate (zero normals). A face `flipped` (folded against most of its neighbours: a sliver
// turned over, as scanners leave them at rims; empty: none is) has no one normal: the nearest of
// its own and its neighbours' counts.
double cosineToScan(const structure::TriMesh& scan, const std::vector<Vector3d>& faceNormals,
                    const std::vector<char>& flipped, int face, const Vector3d& at,
                    const Vector3d& normal) {
  const auto cosine = [&](structure::TriMesh::FaceHandle f) {
    const auto faceCosine = [&](structure::TriMesh::FaceHandle g) {
      const Vector3d& n = faceNormals[std::size_t(g.idx())];
      return n.isZero() ? -2.0 : normal.dot(n);
    };
    double best = faceCosine(f);
    if (!flipped.empty() && flipped[std::size_t(f.idx())])
      for (const auto g : scan.ff_range(f)) best = std::max(best, faceCosine(g));
    return best;
  };
  if ((at.array() > 0.0).all()) return cosine(scan.face_handle(face));
  std::array<structure::TriMesh::VertexHandle, 3> corners;
  int k = 0;
  for (const auto v : scan.fv_range(scan.face_handle(face))) corners[std::size_t(k++)] = v;
  std::vector<structure::TriMesh::VertexHandle> holding;
  for (int c = 0; c < 3; ++c)
    if (at[c] > 0.0) holding.push_back(corners[std::size_t(c)]);
  double best = -2.0;
  for (const auto f : scan.vf_range(holding.front())) {
    bool holds = true;
    for (const auto v : holding) {
      bool corner = false;
      for (const auto w : scan.fv_range(f)) corner = corner || w == v;
      holds = holds && corner;
    }
    if (holds) best = std::max(best, cosine(f));
  }
  return best;
}

// Where the scan folds (adjacent triangles' normals more than 90 degrees apart, as along a
// crumpled fin a scanner left) it has no one normal, and a smooth surface rounds the fold off.
// The cosine of the smallest angle between `normal` and the normals of the triangles on either
// side of the folds within `reach` of `closest` (on face `face`), walking from `face` over the
// edges within `reach` of it, but not into `flipped` triangles (a sliver turned over a face does
// not excuse a surface that turns over above the face); -2 when there is no such fold.
double cosineAtScanFolds(const structure::TriMesh& scan, const std::vector<Vector3d>& faceNormals,
                         const std::vector<char>& flipped, int face, const Vector3d& closest,
                         double reach, const Vector3d& normal) {
  const auto withinReach = [&](structure::TriMesh::HalfedgeHandle h) {
    const auto& a = scan.point(scan.from_vertex_handle(h));
    const auto& b = scan.point(scan.to_vertex_handle(h));
    const Vector3d from(a[0], a[1], a[2]), to(b[0], b[1], b[2]);
    const double t = structure::segmentParameter(closest, from, to);
    return (closest - from - t * (to - from)).norm() <= reach;
  };
  double best = -2.0;
  std::vector<int> walk{face};
  std::unordered_set<int> visited{face};
  for (std::size_t next = 0; next < walk.size(); ++next) {
    const auto f = scan.face_handle(walk[next]);
    const Vector3d& nf = faceNormals[std::size_t(f.idx())];
    for (const auto h : scan.fh_range(f)) {
      const auto g = scan.opposite_face_handle(h);
      if (!g.is_valid() || flipped[std::size_t(g.idx())] || !withinReach(h)) continue;
      const Vector3d& ng = faceNormals[std::size_t(g.idx())];
      if (!nf.isZero() && !ng.isZero() && nf.dot(ng) < 0.0)
        best = std::max({best, normal.dot(nf), normal.dot(ng)});
      if (visited.insert(g.idx()).second) walk.push_back(g.idx());
    }
  }
  return best;
}

// The spread of `distances` (absolute) relative to `unit`, the maximum at locate(its index).
template <class Locate>
DistanceSpread spread(const std::vector<double>& distances, double unit, Locate&& locate) {
  DistanceSpread out;
  std::vector<double> finite;
  finite.reserve(distances.size());
  std::size_t largest = 0;
  double squares = 0.0;
  for (std::size_t k = 0; k < distances.size(); ++k) {
    if (!std::isfinite(distances[k])) continue;
    if (finite.empty() || distances[k] > distances[largest]) largest = k;
    finite.push_back(distances[k]);
    squares += distances[k] * distances[k];
  }
  out.count = int(finite.size());
  if (finite.empty()) return out;
  out.rms = std::sqrt(squares / double(finite.size())) / unit;
  out.max = distances[largest] / unit;
  out.p99 = percentile(finite, 0.99) / unit;
  out.maxAt = locate(largest);
  return out;
}

// The scan as the matrix of its points and its triangles.
std::pair<Eigen::MatrixX3d, std::vector<std::array<int, 3>>> scanTriangles(
    const structure::TriMesh& scan) {
  Eigen::MatrixX3d points(Eigen::Index(scan.n_vertices()), 3);
  for (const auto v : scan.vertices())
    points.row(v.idx()) << scan.point(v)[0], scan.point(v)[1], scan.point(v)[2];
  std::vector<std::array<int, 3>> faces;
  faces.reserve(scan.n_faces());
  for (const auto f : scan.faces()) {
    std::array<int, 3> corners{};
    int k = 0;
    for (const auto v : scan.fv_range(f)) corners[std::size_t(k++)] = v.idx();
    faces.push_back(corners);
  }
  return {std::move(points), std::move(faces)};
}

// Distances both ways and the folds against the scan's normals.
void measureAgainstScan(const ModelSurface& surface, const Eigen::MatrixXd& control,
                        const structure::TriMesh& scan, const std::vector<FacePoint>& fitted,
                        const MeasuredTessellation& coarse, const MeasuredTessellation& fine,
                        const QualityOptions& options, SurfaceQuality& quality) {
  auto [scanPoints, scanFaces] = scanTriangles(scan);
  SurfaceDistances& d = quality.distances;
  d.diagonal = structure::boundingBoxDiagonal(scanPoints);
  const double unit = d.diagonal > 0.0 ? d.diagonal : 1.0;
  const structure::TriangleMeshDistance scanDistance(scanPoints, scanFaces);

  // Scan to surface: Newton on the spline from the fine tessellation (all of it: the surface is
  // there, over the fills too) and from the fit's parameters.
  const std::vector<ClosestSurfacePoint> projections =
      closestSurfacePoints(surface, control, fine.t, scanPoints, fitted, options.newtonSteps);
  std::vector<double> distances(projections.size());
  for (std::size_t k = 0; k < projections.size(); ++k) {
    distances[k] = projections[k].distance;
    d.unconvergedProjections += projections[k].converged ? 0 : 1;
  }
  d.scanToSurface = spread(distances, unit, [&](std::size_t k) {
    return SurfaceLocation{projections[k].position, projections[k].parameter};
  });
  if (options.details) {
    quality.details.scanDistances =
        Eigen::Map<Eigen::VectorXd>(distances.data(), Eigen::Index(distances.size()));
    for (const ClosestSurfacePoint& p : projections)
      quality.details.scanClosest.push_back(p.parameter);
  }

  // Surface to scan: the fine tessellation's vertices on kept faces.
  const PolygonSoup& soup = fine.t.mesh;
  std::vector<char> used(soup.positions.size(), 0);
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    if (fine.kept[f])
      for (const auto v : soup.faces[f]) used[std::size_t(v)] = 1;
  std::vector<std::int64_t> samples;
  std::vector<Vector3d> samplePoints;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) {
      samples.push_back(std::int64_t(v));
      samplePoints.push_back(positionOf(soup, std::int64_t(v)));
    }
  distances.clear();
  for (const auto& hit : scanDistance.queryAll(samplePoints)) distances.push_back(hit.distance);
  d.surfaceToScan = spread(distances, unit, [&](std::size_t k) { return fine.locate(samples[k]); });
  if (options.details) {
    quality.details.surfaceDistances =
        Eigen::Map<Eigen::VectorXd>(distances.data(), Eigen::Index(distances.size()));
    for (const std::int64_t v : samples)
      quality.details.surfaceSamples.push_back(fine.locate(v).parameter);
  }

  // Folds against the scan: the coarse tessellation's kept triangles, at their centroids.
  std::vector<std::size_t> faces;
  std::vector<Vector3d> centroids;
  for (std::size_t f = 0; f < coarse.t.mesh.faces.size(); ++f)
    if (coarse.kept[f] && !coarse.faces.normals[f].isZero()) {
      faces.push_back(f);
      centroids.push_back(coarse.centroid(f));
    }
  const std::vector<structure::ClosestPoint> onScan = scanDistance.queryAll(centroids);
  SurfaceFolds& folds = quality.folds;
  folds.triangles = int(faces.size());
  // The scan's normal is its triangles': interpolated vertex normals turn away from the faces of
  // a coarse polyhedron (a third of 3torus's triangles would have counted as folds).
  std::vector<Vector3d> scanFaceNormals;
  scanFaceNormals.reserve(scanFaces.size());
  for (const auto& t : scanFaces) {
    const Vector3d n = (scanPoints.row(t[1]) - scanPoints.row(t[0]))
                           .cross(scanPoints.row(t[2]) - scanPoints.row(t[0]))
                           .transpose();
    scanFaceNormals.push_back(n.norm() > 0.0 ? Vector3d(n.normalized()) : Vector3d::Zero());
  }
  std::vector<char> flippedScanFaces(scanFaceNormals.size(), 0);
  for (const auto f : scan.faces()) {
    int neighbours = 0, against = 0;
    for (const auto g : scan.ff_range(f)) {
      ++neighbours;
      against +=
          scanFaceNormals[std::size_t(f.idx())].dot(scanFaceNormals[std::size_t(g.idx())]) < 0.0;
    }
    flippedScanFaces[std::size_t(f.idx())] = 2 * against > neighbours;
  }
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const Vector3d& normal = coarse.faces.normals[faces[k]];
    const structure::ClosestPoint& closest = onScan[k];
    // Without the rules for the scan's slivers and folds first: most triangles face its way.
    const double plain =
        cosineToScan(scan, scanFaceNormals, {}, closest.face, closest.barycentric, normal);
    if (plain < -1.5 || plain >= 0.0) continue;
    double cosine = cosineToScan(scan, scanFaceNormals, flippedScanFaces, closest.face,
                                 closest.barycentric, normal);
    if (cosine < 0.0) {
      const auto& corners = coarse.t.mesh.faces[faces[k]];
      double reach = 0.0;
      for (std::size_t c = 0; c < corners.size(); ++c)
        reach = std::max(reach, (positionOf(coarse.t.mesh, corners[c]) -
                                 positionOf(coarse.t.mesh, corners[(c + 1) % corners.size()]))
                                    .norm());
      cosine = std::max(cosine, cosineAtScanFolds(scan, scanFaceNormals, flippedScanFaces,
                                                  closest.face, closest.closest, reach, normal));
    }
    const double angle = degrees(cosine);
    if (angle <= 90.0) {
      ++folds.atScanFolds;
      continue;
    }
    ++folds.againstScan;
    const SurfaceLocation at{centroids[k],
                             coarse.locate(coarse.t.mesh.faces[faces[k]][0]).parameter};
    if (angle > folds.worstAgainstScanDegrees) {
      folds.worstAgainstScanDegrees = angle;
      folds.worstAgainstScan = at;
    }
    if (options.details) quality.details.folds.push_back(at.parameter);
  }
  folds.fraction = faces.empty() ? 0.0 : double(folds.againstScan) / double(faces.size());
}

// |S_s x S_t| at the coarse tessellation's kept vertices, but the means and cone points.
void measureRegularity(const FitSpace& space, const Eigen::MatrixXd& control,
                       const MeasuredTessellation& coarse, SurfaceRegularity& regularity) {
  const PolygonSoup& soup = coarse.t.mesh;
  std::vector<char> measured(soup.positions.size(), 0);
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    if (coarse.kept[f])
      for (const auto v : soup.faces[f]) measured[std::size_t(v)] = 1;
  for (const std::int64_t v : coarse.t.meanVertices) measured[std::size_t(v)] = 0;
  for (const std::int64_t v : coarse.t.coneVertices) measured[std::size_t(v)] = 0;
  std::vector<double> jacobian(soup.positions.size(), std::numeric_limits<double>::quiet_NaN());
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, measured.size(), 1024), [&](const auto& range) {
        std::vector<FitBasisTerm> terms;
        Vector3d ds, dt;
        for (std::size_t v = range.begin(); v < range.end(); ++v)
          if (measured[v] &&
              evaluateFitTangents(space, control, coarse.locate(std::int64_t(v)).parameter, terms,
                                  ds, dt))
            jacobian[v] = ds.cross(dt).norm();
      });
  std::vector<double> values;
  std::size_t smallest = 0;
  for (std::size_t v = 0; v < jacobian.size(); ++v) {
    if (!std::isfinite(jacobian[v])) continue;
    if (values.empty() || jacobian[v] < jacobian[smallest]) smallest = v;
    values.push_back(jacobian[v]);
  }
  regularity.samples = int(values.size());
  if (values.empty()) return;
  regularity.medianJacobian = percentile(values, 0.5);
  regularity.minRelativeJacobian =
      regularity.medianJacobian > 0.0 ? jacobian[smallest] / regularity.medianJacobian : 0.0;
  regularity.minAt = coarse.locate(std::int64_t(smallest));
}

}  // namespace

SurfaceQuality measureQuality(const SplineModel& model, const ModelSurface& surface,
                              const Eigen::MatrixXd& control, const structure::TriMesh* scan,
                              const QualityOptions& options, const structure::Progress& progress) {
  structure::Stopwatch clock;
  if (options.resolution < 1)
    throw structure::InputError(options.name + ": the quality resolution must be at least 1");
  if (control.rows() != surface.numControlPoints() || control.cols() != 3 || !control.allFinite())
    throw structure::InputError(
        options.name + ": the control points do not fit the surface (" +
        std::to_string(control.rows()) + " x " + std::to_string(control.cols()) + " for " +
        std::to_string(surface.numControlPoints()) + " functions, or not finite)");
  if (scan) {
    const auto [scanPoints, scanFaces] = scanTriangles(*scan);
    if (!scanPoints.allFinite())
      throw structure::InputError(options.scanName + ": a vertex position is not finite");
    if (model.surfaceVertices.rows() < scanPoints.rows() ||
        !model.surfaceVertices.topRows(scanPoints.rows()).isApprox(scanPoints, 1e-12))
      throw structure::InputError(options.scanName + ": not the scan " + options.name +
                                  " was fitted to (the model's surface does not start with its " +
                                  std::to_string(scanPoints.rows()) + " vertices)");
  }
  // The fills are classified on the spline with these control points.
  const bool anyFilled = std::any_of(model.surfaceFaceFilled.begin(), model.surfaceFaceFilled.end(),
                                     [](char filled) { return filled != 0; });
  SplineModel withControl;
  if (anyFilled) {
    withControl = model;
    withControl.controlPoints = control;
  }
  const SplineModel& fills = anyFilled ? withControl : model;

  SurfaceQuality quality;
  quality.withScan = scan != nullptr;
  structure::report(progress, "quality: tessellating", 0.0);
  const MeasuredTessellation coarse =
      measuredTessellation(fills, surface, control, options.resolution);
  const MeasuredTessellation fine =
      measuredTessellation(fills, surface, control, 2 * options.resolution);

  SurfaceSmoothness& smooth = quality.smoothness;
  smooth.coarse = dihedrals(coarse, options.resolution);
  smooth.fine = dihedrals(fine, 2 * options.resolution);
  if (smooth.fine.p99 >= SurfaceSmoothness::kFlatDegrees)
    smooth.p99Ratio = smooth.coarse.p99 / smooth.fine.p99;
  smooth.creaseDegrees = options.creaseDegrees;
  double sharpest = 0.0;
  for (const auto& pair : coarse.faces.pairs) {
    const double angle = pairDegrees(coarse.faces, pair);
    smooth.creases += angle > options.creaseDegrees ? 1 : 0;
    if (angle <= 90.0) continue;
    ++quality.folds.adjacentPairs;
    const SurfaceLocation at = pairLocation(coarse, pair);
    if (angle > sharpest) {
      sharpest = angle;
      quality.folds.worstPair = at;
    }
    if (options.details) quality.details.folds.push_back(at.parameter);
  }

  structure::report(progress, "quality: regularity", 0.3);
  measureRegularity(surface.fitSpace(), control, coarse, quality.regularity);
  if (scan) {
    structure::report(progress, "quality: distances to the scan", 0.5);
    // The T-mesh kinds keep each scan vertex's parameters from the fit.
    const std::vector<FacePoint> none;
    const std::vector<FacePoint>& fitted =
        model.kind == SplineKind::TriangularBSpline ? none : model.surfaceVertexTMeshPoints;
    measureAgainstScan(surface, control, *scan, fitted, coarse, fine, options, quality);
  }
  quality.seconds = clock.lap();
  structure::report(progress, "quality measured", 1.0);
  return quality;
}

SurfaceQuality measureQuality(const SplineModel& model, const structure::TriMesh* scan,
                              const QualityOptions& options, const structure::Progress& progress) {
  const ModelSurface surface(model, options.name);
  return measureQuality(model, surface, model.controlPoints, scan, options, progress);
}

std::vector<ClosestSurfacePoint> closestSurfacePoints(const ModelSurface& surface,
                                                      const Eigen::MatrixXd& control,
                                                      const ModelTessellation& tessellation,
                                                      const Eigen::MatrixX3d& points,
                                                      const std::vector<FacePoint>& starts,
                                                      int newtonSteps) {
  const FitSpace& space = surface.fitSpace();
  const PolygonSoup& soup = tessellation.mesh;
  const structure::TriangleMeshDistance near(structure::pointMatrix(soup.positions),
                                             structure::triangleIndices(soup));
  const std::vector<structure::ClosestPoint> hits = near.queryAll(points);
  // Converged: the point on the surface to 1e-9 of the tessellation's size.
  const double onSurface = 1e-9 * structure::boundingBoxDiagonal(soup.positions);
  std::vector<ClosestSurfacePoint> out(hits.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.size(), 256), [&](const auto& range) {
    std::vector<FitBasisTerm> terms;
    std::vector<FacePoint> from;
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const structure::ClosestPoint& hit = hits[k];
      const auto& corners = soup.faces[std::size_t(hit.face)];
      // The triangle's corners that are surface points (not the means that close a hole), the
      // nearest first, and its closest point's parameter interpolated when they lie in one face.
      from.clear();
      FacePoint interpolated{-1, Eigen::Vector2d::Zero()};
      std::array<int, 3> order{0, 1, 2};
      std::sort(order.begin(), order.end(),
                [&](int a, int b) { return hit.barycentric[a] > hit.barycentric[b]; });
      for (const int c : order) {
        const std::int64_t v = corners[std::size_t(c)];
        if (std::binary_search(tessellation.meanVertices.begin(), tessellation.meanVertices.end(),
                               v))
          continue;
        const FacePoint& corner =
            tessellation.samplePoints[std::size_t(tessellation.sampleOffsets[std::size_t(v)])];
        from.push_back(corner);
        if (from.size() == 1) interpolated.face = corner.face;
        if (corner.face == interpolated.face)
          interpolated.position += hit.barycentric[c] * corner.position;
      }
      if (from.size() == 3 && interpolated.face == from[1].face &&
          interpolated.face == from[2].face)
        from.insert(from.begin() + 1, interpolated);
      if (k < starts.size()) from.push_back(starts[k]);
      const Vector3d x = points.row(Eigen::Index(k)).transpose();
      ClosestSurfacePoint& best = out[k];
      // The first critical point found ends the search (the starts are the closest point's
      // nearest parameters): the others only matter where Newton stopped short of one.
      for (std::size_t i = 0; i < from.size() && !(best.onSpline && best.converged); ++i) {
        const ClosestSurfacePoint found =
            project(space, control, x, from[i], newtonSteps, onSurface, terms);
        if (found.onSpline && !(found.distance >= best.distance)) best = found;
      }
      if (!best.onSpline) {
        best.distance = hit.distance;
        best.position = hit.closest;
        best.parameter =
            tessellation
                .samplePoints[std::size_t(tessellation.sampleOffsets[std::size_t(corners[0])])];
      }
    }
  });
  return out;
}

std::vector<char> creasedFaces(const structure::PolygonSoup& tessellation, double creaseDegrees) {
  const AdjacentFaces faces =
      adjacentFaces(tessellation, std::vector<char>(tessellation.faces.size(), 1));
  std::vector<char> creased(tessellation.faces.size(), 0);
  for (const FacePair& pair : faces.pairs)
    if (pairDegrees(faces, pair) > creaseDegrees)
      creased[std::size_t(pair.a)] = creased[std::size_t(pair.b)] = 1;
  return creased;
}

}  // namespace mspline::spline
