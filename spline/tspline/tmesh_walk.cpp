#include "mspline/spline/tspline/tmesh_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

using structure::InputError;

namespace {

// Exits closer than this (times the face's size) to a vertex count as hitting it.
constexpr double kVertexTolerance = 1e-9;
// The first sideways move of a segment that hits a vertex (times the face's size); it doubles
// and changes side on every further hit.
constexpr double kNudge = 1e-7;
// More face crossings than this mean a walk that never ends (a bug, not an input).
constexpr int kMaxCrossings = 1000000;

Eigen::Vector2d clampToFace(const TMeshFace& face, const Eigen::Vector2d& p) {
  return {std::clamp(p.x(), 0.0, face.width), std::clamp(p.y(), 0.0, face.height)};
}

// Side s of the rectangle (0 bottom, 1 right, 2 top, 3 left): the coordinate that is constant
// on it, and its value.
int sideAxis(int s) {
  return s % 2 == 0 ? 1 : 0;
}
double sideValue(const TMeshFace& face, int s) {
  return s == 1 ? face.width : s == 2 ? face.height : 0.0;
}

}  // namespace

FacePoint walkTMesh(const TMesh& mesh, const FacePoint& start, const Eigen::Vector2d& step,
                    bool* reachedBoundary) {
  if (start.face < 0 || start.face >= mesh.numFaces())
    throw InputError("T-mesh walk: face " + std::to_string(start.face) + " out of range (" +
                     std::to_string(mesh.numFaces()) + " faces)");
  if (!start.position.allFinite() || !step.allFinite())
    throw InputError("T-mesh walk: the start position or the step is not finite");
  if (reachedBoundary) *reachedBoundary = false;
  int f = start.face;
  Eigen::Vector2d p = clampToFace(mesh.faces[std::size_t(f)], start.position);
  Eigen::Vector2d d = step;
  int nudges = 0;
  for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
    const TMeshFace& face = mesh.faces[std::size_t(f)];
    const double size = face.width + face.height;
    const double tolerance = kVertexTolerance * size;
    const Eigen::Vector2d q = p + d;
    if (q.x() >= 0.0 && q.x() <= face.width && q.y() >= 0.0 && q.y() <= face.height) return {f, q};
    // Where the segment leaves the rectangle: the first side it crosses.
    double t = std::numeric_limits<double>::infinity();
    int side = -1;
    const auto consider = [&](int s) {
      const int axis = sideAxis(s);
      if (d(axis) == 0.0) return;
      const double time = std::max((sideValue(face, s) - p(axis)) / d(axis), 0.0);
      if (time < t) {
        t = time;
        side = s;
      }
    };
    consider(d.y() < 0.0 ? 0 : 2);
    consider(d.x() > 0.0 ? 1 : 3);
    MSPLINE_ASSERT(side >= 0, "T-mesh walk: a segment leaving its face crosses no side");
    const Eigen::Vector2d exit = p + t * d;
    const int axis = sideAxis(side), alongAxis = 1 - axis;
    // The edge of that side the exit lies on; none when it is at a vertex.
    const std::size_t n = face.vertices.size();
    int edge = -1;
    bool atVertex = false;
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d& a = face.positions[k];
      const Eigen::Vector2d& b = face.positions[(k + 1) % n];
      if ((a - exit).lpNorm<Eigen::Infinity>() <= tolerance) atVertex = true;
      const double value = sideValue(face, side);
      if (std::abs(a(axis) - value) > tolerance || std::abs(b(axis) - value) > tolerance) continue;
      const double lo = std::min(a(alongAxis), b(alongAxis)),
                   hi = std::max(a(alongAxis), b(alongAxis));
      if (exit(alongAxis) > lo && exit(alongAxis) < hi) edge = int(k);
    }
    if (atVertex || edge < 0) {
      // Move the segment sideways, off the vertex, and try again.
      const Eigen::Vector2d normal = Eigen::Vector2d(-d.y(), d.x()).normalized();
      const double amount = kNudge * size * double(1 << std::min(nudges / 2, 20));
      p = clampToFace(face, p + (nudges % 2 == 0 ? amount : -amount) * normal);
      ++nudges;
      MSPLINE_ASSERT(nudges < 64, "T-mesh walk: cannot move a segment off a vertex");
      continue;
    }
    nudges = 0;
    if (face.twinFace[std::size_t(edge)] < 0) {
      if (reachedBoundary) *reachedBoundary = true;
      return {f, exit};
    }
    const QuarterMotion across = mesh.acrossEdge(f, edge);
    f = face.twinFace[std::size_t(edge)];
    p = clampToFace(mesh.faces[std::size_t(f)], across.apply(exit));
    d = across.rotate((1.0 - t) * d);
  }
  throw structure::InternalError("T-mesh walk: more than " + std::to_string(kMaxCrossings) +
                                 " face crossings");
}

}  // namespace mspline::spline
