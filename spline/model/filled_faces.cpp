#include "mspline/spline/model/filled_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mspline/spline/subd/subd_fit_space.h"
#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/spline/tspline/tspline.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"

namespace mspline::spline {

Eigen::MatrixX3d surfaceVertexSpline(const SplineModel& model) {
  const Eigen::Index count = model.surfaceVertices.rows();
  Eigen::MatrixX3d spline =
      Eigen::MatrixX3d::Constant(count, 3, std::numeric_limits<double>::quiet_NaN());
  if (model.kind == SplineKind::TriangularBSpline) {
    const TriBSplineSpace space(model.domain, model.knots);
    for (Eigen::Index v = 0; v < count; ++v) {
      const SurfacePoint& p = model.surfaceVertexLocations[std::size_t(v)];
      try {
        spline.row(v) = space.evaluate(model.controlPoints, p, 0).position.transpose();
      } catch (const structure::InputError&) {
        // A cone point: the spline is undefined there.
      }
    }
  } else if (model.kind == SplineKind::TSpline) {
    const TSplineSpace space(model.tmesh);
    for (Eigen::Index v = 0; v < count; ++v) {
      const FacePoint& p = model.surfaceVertexTMeshPoints[std::size_t(v)];
      const TSplinePoint point =
          space.evaluate(model.controlPoints, model.weights, p.face, p.position, 0);
      if (point.position.allFinite()) spline.row(v) = point.position.transpose();
    }
  } else {
    const SubdSpace space(model.tmesh);
    for (Eigen::Index v = 0; v < count; ++v) {
      const FacePoint& p = model.surfaceVertexTMeshPoints[std::size_t(v)];
      Eigen::Vector3d position;
      if (space.evaluate(model.controlPoints, p.face, p.position, position))
        spline.row(v) = position.transpose();
    }
  }
  return spline;
}

Eigen::MatrixX3d surfaceVertexImages(const SplineModel& model) {
  Eigen::MatrixX3d images = surfaceVertexSpline(model);
  for (Eigen::Index v = 0; v < images.rows(); ++v)
    if (!images.row(v).allFinite()) images.row(v) = model.surfaceVertices.row(v);
  return images;
}

std::vector<char> facesOverScan(const structure::PolygonSoup& tessellation,
                                const SplineModel& model) {
  std::vector<char> over(tessellation.faces.size(), 1);
  bool anyFilled = false;
  for (const char filled : model.surfaceFaceFilled) anyFilled = anyFilled || filled;
  if (!anyFilled) return over;
  const Eigen::MatrixX3d images = surfaceVertexImages(model);
  std::vector<std::array<int, 3>> scanFaces, fillFaces;
  for (std::size_t f = 0; f < model.surfaceFaces.size(); ++f)
    (model.surfaceFaceFilled[f] ? fillFaces : scanFaces).push_back(model.surfaceFaces[f]);
  if (scanFaces.empty()) return std::vector<char>(tessellation.faces.size(), 0);
  const structure::TriangleMeshDistance scan(images, scanFaces);
  const structure::TriangleMeshDistance fill(images, fillFaces);
  std::vector<Eigen::Vector3d> centroids, normals;
  for (const auto& face : tessellation.faces) {
    std::vector<Eigen::Vector3d> corners;
    for (const auto v : face) {
      const auto& p = tessellation.positions[std::size_t(v)];
      corners.emplace_back(p[0], p[1], p[2]);
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < corners.size(); ++k) {
      sum += corners[k];
      normal += corners[k].cross(corners[(k + 1) % corners.size()]);
    }
    centroids.push_back(sum / double(corners.size()));
    normals.push_back(normal);
  }
  const auto onScan = scan.queryAll(centroids);
  const auto onFill = fill.queryAll(centroids);
  const auto faceNormal = [&](const structure::TriangleMeshDistance& mesh, int f) {
    const auto& t = mesh.triangles()[std::size_t(f)];
    const Eigen::Vector3d a = images.row(t[0]), b = images.row(t[1]), c = images.row(t[2]);
    return Eigen::Vector3d((b - a).cross(c - a));
  };
  // A fill may lie on the scan itself (a planar hole in a plane: the closed surface is a flat
  // pillow), so distance alone cannot tell the sides apart. Within the fit's tolerance of both,
  // the side that faces the way the triangle does wins.
  const double tie = 1e-3 * structure::boundingBoxDiagonal(images);
  for (std::size_t f = 0; f < centroids.size(); ++f) {
    const double ds = onScan[f].distance, df = onFill[f].distance;
    bool scanSide = ds <= df;
    if (std::abs(ds - df) <= tie) {
      const bool scanAgrees = faceNormal(scan, onScan[f].face).dot(normals[f]) > 0.0;
      const bool fillAgrees = faceNormal(fill, onFill[f].face).dot(normals[f]) > 0.0;
      if (scanAgrees != fillAgrees) scanSide = scanAgrees;
    }
    over[f] = scanSide ? 1 : 0;
  }
  return over;
}

void dropBowTies(const structure::PolygonSoup& soup, std::vector<char>& keep) {
  std::vector<std::vector<int>> around(soup.positions.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    for (const auto v : soup.faces[f]) around[std::size_t(v)].push_back(int(f));
  // Dropping a fan can make a neighbour a bow-tie in turn: repeat until nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t v = 0; v < around.size(); ++v) {
      std::vector<int> faces;
      for (const int f : around[v])
        if (keep[std::size_t(f)]) faces.push_back(f);
      if (faces.size() < 2) continue;
      // Fans: kept faces around v joined through edges at v (a shared second vertex).
      std::vector<int> fan(faces.size(), -1);
      int fans = 0;
      for (std::size_t seed = 0; seed < faces.size(); ++seed) {
        if (fan[seed] >= 0) continue;
        std::vector<std::size_t> stack{seed};
        fan[seed] = fans;
        while (!stack.empty()) {
          const std::size_t a = stack.back();
          stack.pop_back();
          for (std::size_t b = 0; b < faces.size(); ++b) {
            if (fan[b] >= 0) continue;
            bool shareEdge = false;
            for (const auto x : soup.faces[std::size_t(faces[a])])
              for (const auto y : soup.faces[std::size_t(faces[b])])
                shareEdge = shareEdge || (x == y && std::size_t(x) != v);
            if (shareEdge) {
              fan[b] = fans;
              stack.push_back(b);
            }
          }
        }
        ++fans;
      }
      if (fans < 2) continue;
      std::vector<int> size(std::size_t(fans), 0);
      for (const int k : fan) ++size[std::size_t(k)];
      const int largest = int(std::max_element(size.begin(), size.end()) - size.begin());
      for (std::size_t k = 0; k < faces.size(); ++k)
        if (fan[k] != largest) keep[std::size_t(faces[k])] = 0;
      changed = true;
    }
  }
}

std::vector<char> facesToKeep(const structure::PolygonSoup& tessellation,
                              const SplineModel& model) {
  std::vector<char> keep = facesOverScan(tessellation, model);
  dropBowTies(tessellation, keep);
  return keep;
}

std::vector<int> keepFaces(structure::PolygonSoup& soup, const std::vector<char>& keep) {
  MSPLINE_ASSERT(keep.size() == soup.faces.size(), "keepFaces: one flag per face");
  std::vector<int> newIndex(soup.positions.size(), -1);
  structure::PolygonSoup kept;
  kept.sourceName = soup.sourceName;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (!keep[f]) continue;
    std::vector<std::int64_t> face;
    for (const auto v : soup.faces[f]) {
      int& index = newIndex[std::size_t(v)];
      if (index < 0) {
        index = int(kept.positions.size());
        kept.positions.push_back(soup.positions[std::size_t(v)]);
      }
      face.push_back(index);
    }
    kept.faces.push_back(std::move(face));
    if (!soup.cornerUVs.empty()) kept.cornerUVs.push_back(soup.cornerUVs[f]);
  }
  soup = std::move(kept);
  return newIndex;
}

}  // namespace mspline::spline
