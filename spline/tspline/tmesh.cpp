#include "mspline/spline/tspline/tmesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

int TMesh::numTJunctions() const {
  int count = 0;
  for (const auto& face : faces) count += int(face.vertices.size()) - 4;
  return count;
}

int TMesh::numExtraordinary() const {
  int count = 0;
  for (int v = 0; v < numVertices; ++v) count += isExtraordinary(v);
  return count;
}

bool TMesh::hasBoundary() const {
  return std::any_of(onBoundary.begin(), onBoundary.end(), [](char b) { return b != 0; });
}

QuarterMotion TMesh::acrossEdge(int face, int edge) const {
  const TMeshFace& f = faces.at(face);
  const int other = f.twinFace.at(edge);
  if (other < 0)
    throw InputError("T-mesh face " + std::to_string(face) + " edge " + std::to_string(edge) +
                     " is on the boundary");
  const TMeshFace& g = faces[other];
  const int j = f.twinEdge[edge];
  const std::size_t k = static_cast<std::size_t>(edge), n = f.positions.size();
  const Eigen::Vector2d p = f.positions[k], q = f.positions[(k + 1) % n];
  const Eigen::Vector2d a = g.positions[j], b = g.positions[(j + 1) % g.positions.size()];
  QuarterMotion best;
  double bestError = INFINITY;
  for (int turns = 0; turns < 4; ++turns) {
    const QuarterMotion m{turns, Eigen::Vector2d::Zero()};
    const double error = (m.rotate(q - p) - (a - b)).norm();
    if (error < bestError) bestError = error, best = m;
  }
  best.translation = b - best.rotate(p);
  return best;
}

namespace {

std::string faceName(int face) {
  return "T-mesh face " + std::to_string(face);
}

// Completes width and height and checks the rectangle.
void checkRectangle(TMeshFace& face, int index, int numVertices) {
  const std::size_t n = face.vertices.size();
  if (n < 4 || face.positions.size() != n)
    throw InputError(faceName(index) + " needs at least 4 vertices, each with a position");
  for (int v : face.vertices)
    if (v < 0 || v >= numVertices)
      throw InputError(faceName(index) + " has vertex id " + std::to_string(v) + " out of range");
  std::vector<int> sorted = face.vertices;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw InputError(faceName(index) + " repeats a vertex");
  double width = 0.0, height = 0.0;
  for (const auto& p : face.positions) {
    if (!p.allFinite()) throw InputError(faceName(index) + " has a non-finite position");
    width = std::max(width, p.x());
    height = std::max(height, p.y());
  }
  face.width = width;
  face.height = height;
  const double tolerance = 1e-9 * std::max(width, height);
  if (!(width > 0.0 && height > 0.0) || face.positions[0].norm() > tolerance)
    throw InputError(faceName(index) + " does not start at the corner (0, 0) of a rectangle");
  // Walk the sides in order: bottom (y = 0, x rising), right, top, left.
  const auto sideOf = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    if (std::abs(p.y()) <= tolerance && std::abs(q.y()) <= tolerance && q.x() > p.x() + tolerance)
      return 0;
    if (std::abs(p.x() - width) <= tolerance && std::abs(q.x() - width) <= tolerance &&
        q.y() > p.y() + tolerance)
      return 1;
    if (std::abs(p.y() - height) <= tolerance && std::abs(q.y() - height) <= tolerance &&
        q.x() < p.x() - tolerance)
      return 2;
    if (std::abs(p.x()) <= tolerance && std::abs(q.x()) <= tolerance && q.y() < p.y() - tolerance)
      return 3;
    return -1;
  };
  int previousSide = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const int side = sideOf(face.positions[k], face.positions[(k + 1) % n]);
    if (side < previousSide || side < 0 || (k + 1 == n && side != 3))
      throw InputError(faceName(index) +
                       " is not a rectangle walked counter-clockwise from (0, 0) (edge " +
                       std::to_string(k) + ")");
    previousSide = side;
  }
}

}  // namespace

TMesh buildTMesh(int numVertices, std::vector<TMeshFace> faces) {
  if (numVertices <= 0 || faces.empty()) throw InputError("empty T-mesh");
  TMesh mesh;
  mesh.numVertices = numVertices;
  mesh.quarterTurnsAround.assign(static_cast<std::size_t>(numVertices), 0);
  mesh.onBoundary.assign(static_cast<std::size_t>(numVertices), 0);
  // Per vertex, the directed edges leaving it: {to, face, side}. Vertices have few edges, so a
  // scan of a short list beats a map (splitting faces rebuilds the mesh every time).
  struct Outgoing {
    int to, face, side;
  };
  std::vector<std::vector<Outgoing>> leaving(static_cast<std::size_t>(numVertices));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    TMeshFace& face = faces[f];
    checkRectangle(face, static_cast<int>(f), numVertices);
    const std::size_t n = face.vertices.size();
    face.twinFace.assign(n, -1);
    face.twinEdge.assign(n, -1);
    const double tolerance = 1e-9 * std::max(face.width, face.height);
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d& p = face.positions[k];
      const bool corner =
          (std::abs(p.x()) <= tolerance || std::abs(p.x() - face.width) <= tolerance) &&
          (std::abs(p.y()) <= tolerance || std::abs(p.y() - face.height) <= tolerance);
      mesh.quarterTurnsAround[face.vertices[k]] += corner ? 1 : 2;
      const int from = face.vertices[k], to = face.vertices[(k + 1) % n];
      auto& out = leaving[static_cast<std::size_t>(from)];
      for (const Outgoing& e : out)
        if (e.to == to)
          throw InputError(faceName(static_cast<int>(f)) + " uses the edge from vertex " +
                           std::to_string(from) + " to " + std::to_string(to) +
                           " that another face uses in the same direction");
      out.push_back({to, static_cast<int>(f), static_cast<int>(k)});
    }
  }
  std::vector<int> edgesAt(static_cast<std::size_t>(numVertices), 0);
  std::vector<int> boundaryEdgesAt(static_cast<std::size_t>(numVertices), 0);
  for (int from = 0; from < numVertices; ++from)
    for (const Outgoing& e : leaving[static_cast<std::size_t>(from)]) {
      ++edgesAt[from];
      const Outgoing* twin = nullptr;
      for (const Outgoing& back : leaving[static_cast<std::size_t>(e.to)])
        if (back.to == from) twin = &back;
      TMeshFace& face = faces[e.face];
      if (!twin) {
        mesh.onBoundary[from] = mesh.onBoundary[e.to] = 1;
        ++boundaryEdgesAt[from];
        continue;
      }
      const TMeshFace& other = faces[twin->face];
      const std::size_t k = e.side, j = twin->side;
      const double length =
          (face.positions[(k + 1) % face.positions.size()] - face.positions[k]).norm();
      const double otherLength =
          (other.positions[(j + 1) % other.positions.size()] - other.positions[j]).norm();
      if (std::abs(length - otherLength) > 1e-9 * std::max(length, otherLength))
        throw InputError(faceName(e.face) + " edge " + std::to_string(k) + " has length " +
                         std::to_string(length) + " but its twin in " + faceName(twin->face) +
                         " has " + std::to_string(otherLength));
      face.twinFace[k] = twin->face;
      face.twinEdge[k] = static_cast<int>(j);
    }
  for (int v = 0; v < numVertices; ++v) {
    if (edgesAt[v] == 0) throw InputError("T-mesh vertex " + std::to_string(v) + " is in no face");
    // One fan: at most one boundary edge leaves the vertex.
    if (boundaryEdgesAt[v] > 1)
      throw InputError("the faces at T-mesh vertex " + std::to_string(v) +
                       " do not form one fan (it is pinched)");
  }
  mesh.faces = std::move(faces);
  return mesh;
}

TMesh gridTMesh(const std::vector<double>& xKnots, const std::vector<double>& yKnots,
                bool periodicX, bool periodicY) {
  const auto check = [](const std::vector<double>& knots, bool periodic, const char* name) {
    if (knots.size() < (periodic ? 4u : 2u))
      throw InputError(std::string("grid T-mesh: too few ") + name + " knot lines");
    for (std::size_t i = 0; i + 1 < knots.size(); ++i)
      if (!(knots[i + 1] > knots[i]))
        throw InputError(std::string("grid T-mesh: ") + name + " knots are not increasing");
  };
  check(xKnots, periodicX, "x");
  check(yKnots, periodicY, "y");
  const int cellsX = static_cast<int>(xKnots.size()) - 1,
            cellsY = static_cast<int>(yKnots.size()) - 1;
  const int columns = periodicX ? cellsX : cellsX + 1, rows = periodicY ? cellsY : cellsY + 1;
  const auto id = [&](int i, int j) { return (j % rows) * columns + (i % columns); };
  std::vector<TMeshFace> faces;
  faces.reserve(static_cast<std::size_t>(cellsX) * cellsY);
  for (int j = 0; j < cellsY; ++j)
    for (int i = 0; i < cellsX; ++i) {
      const double w = xKnots[i + 1] - xKnots[i], h = yKnots[j + 1] - yKnots[j];
      TMeshFace face;
      face.vertices = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      face.positions = {{0.0, 0.0}, {w, 0.0}, {w, h}, {0.0, h}};
      faces.push_back(std::move(face));
    }
  return buildTMesh(columns * rows, std::move(faces));
}

TMesh planarTMesh(const Eigen::MatrixX2d& lo, const Eigen::MatrixX2d& hi) {
  if (lo.rows() == 0 || lo.rows() != hi.rows()) throw InputError("planar T-mesh: no rectangles");
  double scale = 0.0;
  for (Eigen::Index r = 0; r < lo.rows(); ++r) {
    if (!lo.row(r).allFinite() || !hi.row(r).allFinite() || !(hi(r, 0) > lo(r, 0)) ||
        !(hi(r, 1) > lo(r, 1)))
      throw InputError("planar T-mesh: rectangle " + std::to_string(r) + " is empty");
    scale = std::max(scale, (hi.row(r) - lo.row(r)).maxCoeff());
  }
  const double tolerance = 1e-9 * scale;
  const auto key = [&](double x, double y) {
    return std::make_pair(std::llround(x / tolerance), std::llround(y / tolerance));
  };
  std::map<std::pair<long long, long long>, int> ids;
  std::vector<Eigen::Vector2d> points;
  for (Eigen::Index r = 0; r < lo.rows(); ++r)
    for (const Eigen::Vector2d& c :
         {Eigen::Vector2d(lo(r, 0), lo(r, 1)), Eigen::Vector2d(hi(r, 0), lo(r, 1)),
          Eigen::Vector2d(hi(r, 0), hi(r, 1)), Eigen::Vector2d(lo(r, 0), hi(r, 1))})
      if (ids.emplace(key(c.x(), c.y()), int(points.size())).second) points.push_back(c);
  std::vector<TMeshFace> faces;
  for (Eigen::Index r = 0; r < lo.rows(); ++r) {
    const Eigen::Vector2d a(lo(r, 0), lo(r, 1)), b(hi(r, 0), hi(r, 1));
    // Boundary points sorted by their position along the counter-clockwise walk from a.
    const double w = b.x() - a.x(), h = b.y() - a.y();
    std::vector<std::pair<double, int>> walk;
    for (std::size_t v = 0; v < points.size(); ++v) {
      const Eigen::Vector2d p = points[v] - a;
      if (p.x() < -tolerance || p.y() < -tolerance || p.x() > w + tolerance ||
          p.y() > h + tolerance)
        continue;
      double along;
      if (std::abs(p.y()) <= tolerance && p.x() < w - tolerance)
        along = p.x();
      else if (std::abs(p.x() - w) <= tolerance && p.y() < h - tolerance)
        along = w + p.y();
      else if (std::abs(p.y() - h) <= tolerance && p.x() > tolerance)
        along = w + h + (w - p.x());
      else if (std::abs(p.x()) <= tolerance && p.y() > tolerance)
        along = 2 * w + h + (h - p.y());
      else
        throw InputError("planar T-mesh: a corner lies inside rectangle " + std::to_string(r));
      walk.emplace_back(along, int(v));
    }
    std::sort(walk.begin(), walk.end());
    TMeshFace face;
    for (const auto& [along, v] : walk) {
      face.vertices.push_back(v);
      Eigen::Vector2d p = points[std::size_t(v)] - a;
      // Snap to the sides so that the rectangle test in buildTMesh sees exact coordinates.
      for (int c = 0; c < 2; ++c) {
        const double side = c == 0 ? w : h;
        if (std::abs(p[c]) <= tolerance) p[c] = 0.0;
        if (std::abs(p[c] - side) <= tolerance) p[c] = side;
      }
      face.positions.push_back(p);
    }
    faces.push_back(std::move(face));
  }
  return buildTMesh(int(points.size()), std::move(faces));
}

}  // namespace mspline::spline
