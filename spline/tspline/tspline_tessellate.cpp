#include "mspline/spline/tspline/tspline_tessellate.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "mspline/spline/tribspline/tessellate.h"
#include "mspline/spline/tspline/tspline_bezier.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

// Off a hole towards the face centre: close enough to stand for the hole's boundary, far enough
// for the denominator (which vanishes in the hole) to keep rounding small (as tessellate.h's
// cone offset).
constexpr double kHoleOffset = 1e-3;
// How far towards the face centre samples of a collapsed edge are taken.
constexpr double kCollapsedEdgeOffset = 1e-2;
// Below this denominator (times the largest weight) points are evaluated directly.
constexpr double kSmallDenominator = 1e-6;

// Coordinate along side s of a rectangle (0 bottom, 1 right, 2 top, 3 left), increasing in the
// counter-clockwise direction.
double alongSide(int s, const Eigen::Vector2d& p) {
  switch (s) {
    case 0:
      return p.x();
    case 1:
      return p.y();
    case 2:
      return -p.x();
    default:
      return -p.y();
  }
}

}  // namespace

Eigen::Vector3d unitNormal(const Eigen::Vector3d& ds, const Eigen::Vector3d& dt) {
  const Eigen::Vector3d n = ds.cross(dt);
  return n.norm() > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
}

TMeshTessellation tessellateTMeshSurface(const TMesh& mesh, const TMeshSurface& surface,
                                         int resolution, const std::string& what) {
  if (resolution < 1)
    throw InputError(what + ": resolution " + std::to_string(resolution) + " is below 1");
  const int r = resolution;
  TMeshTessellation out;
  out.mesh.sourceName = what;
  out.holeOffset = kHoleOffset;
  const auto surfaceAt = [&](int f, const Eigen::Vector2d& p, Eigen::Vector3d& x) {
    return surface(f, p, x, nullptr) && x.allFinite();
  };
  out.sampleOffsets.push_back(0);
  // A sample at the surface point given by `placements` (the same point in the frames of every
  // face holding it); all of them are used only in a hole.
  const auto add = [&](const std::vector<FacePoint>& placements) {
    const auto index = std::int64_t(out.mesh.positions.size());
    const FacePoint& point = placements.front();
    Eigen::Vector3d x;
    if (surfaceAt(point.face, point.position, x)) {
      out.samplePoints.push_back(point);
    } else {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int count = 0;
      for (const FacePoint& q : placements) {
        const TMeshFace& face = mesh.faces[std::size_t(q.face)];
        const Eigen::Vector2d centre(face.width / 2.0, face.height / 2.0);
        // Steps fine enough that the samples along a side in a hole stay apart (a coarse step
        // would put them all at the face centre: degenerate triangles).
        for (double t : {kHoleOffset, 1e-2, 0.03, 0.06, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 1.0}) {
          Eigen::Vector3d y;
          const Eigen::Vector2d off = q.position + t * (centre - q.position);
          if (surfaceAt(q.face, off, y)) {
            out.samplePoints.push_back({q.face, off});
            sum += y;
            ++count;
            break;
          }
        }
      }
      if (count == 0)
        throw InputError(what + ": T-mesh face " + std::to_string(point.face) +
                         " lies in a hole of the surface up to its centre");
      x = sum / count;
      out.holeVertices.push_back(int(index));
    }
    out.sampleOffsets.push_back(std::int64_t(out.samplePoints.size()));
    out.mesh.positions.push_back({x.x(), x.y(), x.z()});
    out.vertexPoints.push_back(point);
    return index;
  };

  // Vertices: one sample each, at the vertex's place in every face that has it on its boundary.
  std::vector<std::vector<FacePoint>> vertexPlacements(std::size_t(mesh.numVertices));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (std::size_t k = 0; k < mesh.faces[std::size_t(f)].vertices.size(); ++k)
      vertexPlacements[std::size_t(mesh.faces[std::size_t(f)].vertices[k])].push_back(
          {f, mesh.faces[std::size_t(f)].positions[k]});
  std::vector<std::int64_t> vertexSample;
  for (const auto& placements : vertexPlacements) vertexSample.push_back(add(placements));

  // Edges: samples 1 .. r-1 from boundary vertex k to k + 1, made by whichever of the edge and
  // its twin comes first (the twin runs the other way, so it takes them reversed).
  const auto edgePoint = [&](int f, std::size_t k, int i) {
    const TMeshFace& face = mesh.faces[std::size_t(f)];
    const Eigen::Vector2d& p = face.positions[k];
    const Eigen::Vector2d& q = face.positions[(k + 1) % face.positions.size()];
    return Eigen::Vector2d(p + double(i) / r * (q - p));
  };
  std::vector<std::vector<std::vector<std::int64_t>>> edgeSamples(std::size_t(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const TMeshFace& face = mesh.faces[std::size_t(f)];
    auto& samples = edgeSamples[std::size_t(f)];
    samples.resize(face.vertices.size());
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      const int g = face.twinFace[k];
      if (g >= 0 && g < f) {
        const auto& across = edgeSamples[std::size_t(g)][std::size_t(face.twinEdge[k])];
        samples[k].assign(across.rbegin(), across.rend());
        continue;
      }
      if (g == f && std::size_t(face.twinEdge[k]) < k) {  // glued to itself: made already
        const auto& across = samples[std::size_t(face.twinEdge[k])];
        samples[k].assign(across.rbegin(), across.rend());
        continue;
      }
      for (int i = 1; i < r; ++i) {
        std::vector<FacePoint> placements{{f, edgePoint(f, k, i)}};
        if (g >= 0)
          placements.push_back({g, mesh.acrossEdge(f, int(k)).apply(placements[0].position)});
        const std::int64_t index = add(placements);
        // Where a surface collapses a whole edge to one point, its samples are taken just inside
        // the face, so that no triangle between them has zero area.
        const std::int64_t previous =
            i == 1 ? vertexSample[std::size_t(face.vertices[k])] : samples[k].back();
        const auto position = [&](std::int64_t v) {
          const auto& p = out.mesh.positions[std::size_t(v)];
          return Eigen::Vector3d(p[0], p[1], p[2]);
        };
        const Eigen::Vector2d centre(face.width / 2.0, face.height / 2.0);
        Eigen::Vector3d middle;
        const std::int64_t next =
            vertexSample[std::size_t(face.vertices[(k + 1) % face.vertices.size()])];
        const auto coincides = [&](std::int64_t other) {
          return (position(index) - position(other)).norm() <=
                 1e-6 * (middle - position(other)).norm();
        };
        if (surfaceAt(f, centre, middle) && (coincides(previous) || coincides(next))) {
          Eigen::Vector3d x;
          const Eigen::Vector2d inside =
              placements[0].position + kCollapsedEdgeOffset * (centre - placements[0].position);
          if (surfaceAt(f, inside, x)) {
            out.mesh.positions[std::size_t(index)] = {x.x(), x.y(), x.z()};
            out.vertexPoints[std::size_t(index)] = {f, inside};
            // The last sample added: its evaluated points are the last ones.
            out.samplePoints.resize(std::size_t(out.sampleOffsets[std::size_t(index)]));
            out.samplePoints.push_back({f, inside});
            out.sampleOffsets.back() = std::int64_t(out.samplePoints.size());
            ++out.collapsedEdgeSamples;
          }
        }
        samples[k].push_back(index);
      }
    }
  }

  // Faces.
  const auto triangle = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
    out.mesh.faces.push_back({a, b, c});
  };
  std::vector<std::int64_t> ring, grid;
  std::vector<Eigen::Vector2d> ringPosition;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const TMeshFace& face = mesh.faces[std::size_t(f)];
    const std::size_t n = face.vertices.size();
    const auto gridPoint = [&](int i, int j) {
      return Eigen::Vector2d(face.width * i / r, face.height * j / r);
    };
    const auto at = [r](int i, int j) { return std::size_t(j * (r + 1) + i); };
    // The boundary ring counter-clockwise from the corner (0, 0).
    ring.clear();
    ringPosition.clear();
    for (std::size_t k = 0; k < n; ++k) {
      ring.push_back(vertexSample[std::size_t(face.vertices[k])]);
      ringPosition.push_back(face.positions[k]);
      for (int i = 1; i < r; ++i) {
        ring.push_back(edgeSamples[std::size_t(f)][k][std::size_t(i - 1)]);
        ringPosition.push_back(edgePoint(f, k, i));
      }
    }
    grid.assign(std::size_t((r + 1) * (r + 1)), -1);
    for (int j = 1; j < r; ++j)
      for (int i = 1; i < r; ++i) grid[at(i, j)] = add({{f, gridPoint(i, j)}});
    if (n == 4) {
      // The grid's boundary is the ring: r samples per side.
      for (int i = 0; i < r; ++i) {
        grid[at(i, 0)] = ring[std::size_t(i)];
        grid[at(r, i)] = ring[std::size_t(r + i)];
        grid[at(r - i, r)] = ring[std::size_t(2 * r + i)];
        grid[at(0, r - i)] = ring[std::size_t(3 * r + i)];
      }
      // Each quadrant's diagonals point at its face corner: at a cone of valence 2 the corner's
      // right angle opens to a straight one, and a triangle with the corner between its other
      // two vertices would be flat, facing anywhere (a false fold).
      for (int j = 0; j < r; ++j)
        for (int i = 0; i < r; ++i) {
          if ((2 * i < r) == (2 * j < r)) {
            triangle(grid[at(i, j)], grid[at(i + 1, j)], grid[at(i + 1, j + 1)]);
            triangle(grid[at(i, j)], grid[at(i + 1, j + 1)], grid[at(i, j + 1)]);
          } else {
            triangle(grid[at(i, j)], grid[at(i + 1, j)], grid[at(i, j + 1)]);
            triangle(grid[at(i + 1, j)], grid[at(i + 1, j + 1)], grid[at(i, j + 1)]);
          }
        }
      continue;
    }
    // A face with T-junctions: the grid inside, then the ring between it and the boundary.
    if (r <= 2) {
      const std::int64_t centre =
          r == 2 ? grid[at(1, 1)]
                 : add({{f, Eigen::Vector2d(face.width / 2.0, face.height / 2.0)}});
      for (std::size_t m = 0; m < ring.size(); ++m)
        triangle(ring[m], ring[(m + 1) % ring.size()], centre);
      continue;
    }
    for (int j = 1; j + 1 < r; ++j)
      for (int i = 1; i + 1 < r; ++i) {
        triangle(grid[at(i, j)], grid[at(i + 1, j)], grid[at(i + 1, j + 1)]);
        triangle(grid[at(i, j)], grid[at(i + 1, j + 1)], grid[at(i, j + 1)]);
      }
    // Ring index of each rectangle corner (ring[0] is the corner (0, 0)).
    const Eigen::Vector2d corners[4] = {
        {0.0, 0.0}, {face.width, 0.0}, {face.width, face.height}, {0.0, face.height}};
    const double tolerance = 1e-9 * std::max(face.width, face.height);
    std::size_t cornerAt[5] = {0, 0, 0, 0, ring.size()};
    for (int s = 1; s < 4; ++s)
      for (std::size_t m = 0; m < ring.size(); ++m)
        if ((ringPosition[m] - corners[s]).norm() <= tolerance) cornerAt[s] = m;
    for (int s = 0; s < 4; ++s) {
      // Outer chain: the ring from corner s to corner s + 1. Inner chain: the outermost interior
      // grid points along side s, in the same direction.
      std::vector<std::int64_t> inner;
      std::vector<double> innerAlong;
      for (int m = 1; m < r; ++m) {
        const int i = s == 0 ? m : s == 1 ? r - 1 : s == 2 ? r - m : 1;
        const int j = s == 0 ? 1 : s == 1 ? m : s == 2 ? r - 1 : r - m;
        inner.push_back(grid[at(i, j)]);
        innerAlong.push_back(alongSide(s, gridPoint(i, j)));
      }
      const std::size_t begin = cornerAt[s], end = cornerAt[s + 1];
      std::size_t a = begin, b = 0;
      while (a < end || b + 1 < inner.size()) {
        const bool outer =
            b + 1 == inner.size() ||
            (a < end && alongSide(s, ringPosition[(a + 1) % ring.size()]) <= innerAlong[b + 1]);
        if (outer) {
          triangle(ring[a], ring[(a + 1) % ring.size()], inner[b]);
          ++a;
        } else {
          triangle(ring[a % ring.size()], inner[b + 1], inner[b]);
          ++b;
        }
      }
    }
  }
  // Normals and chart coordinates at the samples' T-mesh points; hole samples stay zero here
  // and get the triangles' normal.
  std::vector<char> inHole(out.vertexPoints.size(), 0);
  for (int v : out.holeVertices) inHole[std::size_t(v)] = 1;
  for (std::size_t v = 0; v < out.vertexPoints.size(); ++v) {
    const FacePoint& point = out.vertexPoints[v];
    out.uvs.push_back({point.position.x(), point.position.y()});
    Eigen::Vector3d x, normal = Eigen::Vector3d::Zero();
    if (!inHole[v] && !surface(point.face, point.position, x, &normal)) normal.setZero();
    out.normals.push_back({normal.x(), normal.y(), normal.z()});
  }
  fillMissingNormals(out.mesh, out.normals);
  return out;
}

TSplineTessellation tessellateTSpline(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                      const Eigen::VectorXd& weights, int resolution) {
  if (resolution < 1)
    throw InputError("T-spline tessellation: resolution " + std::to_string(resolution) +
                     " is below 1");
  const TSplineBezier bezier(space, control, weights);
  double minDenominator = std::numeric_limits<double>::infinity();
  // Where the denominator is small the Bezier patches' rounding (about 1e-17 in their
  // coefficients) is no longer small against it, and the direct sum over the blending functions
  // decides: exactly 0 in a hole.
  const double smallDenominator = kSmallDenominator * (weights.size() ? weights.maxCoeff() : 1.0);
  const auto surface = [&](int f, const Eigen::Vector2d& p, Eigen::Vector3d& x,
                           Eigen::Vector3d* normal) {
    Eigen::Vector3d ds, dt;
    double d = 0.0;
    bezier.evaluate(f, p, x, normal ? &ds : nullptr, normal ? &dt : nullptr, &d);
    if (d < smallDenominator) {
      const TSplinePoint direct = space.evaluate(control, weights, f, p, normal ? 1 : 0);
      d = direct.denominator;
      x = direct.position;
      if (normal) {
        ds = direct.ds;
        dt = direct.dt;
      }
    }
    if (!(d > 0.0) || !x.allFinite()) return false;
    if (normal) *normal = unitNormal(ds, dt);
    minDenominator = std::min(minDenominator, d);
    return true;
  };
  TSplineTessellation out;
  static_cast<TMeshTessellation&>(out) =
      tessellateTMeshSurface(space.mesh(), surface, resolution, "T-spline tessellation");
  out.minDenominator = minDenominator;
  return out;
}

}  // namespace mspline::spline
