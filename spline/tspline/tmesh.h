#pragma once
// A T-mesh on a surface: rectangles glued side to side, with T-junctions where a vertex of one
// rectangle lies inside a side of its neighbour. Each face has its own frame, the rectangle
// [0, width] x [0, height] measured in knot intervals; crossing a side changes frames by a quarter
// turn and a translation. A planar T-mesh is the special case where all those motions are
// translations; on a torus they are the deck translations; on a flat surface with cones whose
// angles are multiples of pi/2 they include quarter turns, and the cones are the vertices whose
// face angles do not add up to a full turn (extraordinary points).
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"

namespace mspline::spline {

using structure::FacePoint;
using structure::SurfacePoint;

/// A motion x -> R x + translation, R the rotation by quarterTurns * 90 degrees counter-clockwise.
/// With integer translations (knot intervals on an integer grid) every operation is exact.
struct QuarterMotion {
  int quarterTurns = 0;  // 0 .. 3
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();

  // Inline: they sit in the inner loops of the developments (tspline.cpp).
  Eigen::Vector2d rotate(const Eigen::Vector2d& d) const {
    switch (quarterTurns & 3) {
      case 1:
        return {-d.y(), d.x()};
      case 2:
        return {-d.x(), -d.y()};
      case 3:
        return {d.y(), -d.x()};
      default:
        return d;
    }
  }
  Eigen::Vector2d apply(const Eigen::Vector2d& p) const { return rotate(p) + translation; }
  /// The motion "this, then next".
  QuarterMotion then(const QuarterMotion& next) const {
    return {(quarterTurns + next.quarterTurns) & 3, next.apply(translation)};
  }
  QuarterMotion inverse() const {
    QuarterMotion back{(4 - quarterTurns) & 3, Eigen::Vector2d::Zero()};
    back.translation = -back.rotate(translation);
    return back;
  }
};

struct TMeshFace {
  /// The face is [0, width] x [0, height] in its frame.
  double width = 0.0;
  double height = 0.0;
  /// Its boundary, counter-clockwise from the corner (0, 0): T-mesh vertex ids and positions in
  /// the face frame. Boundary edge k runs from vertex k to vertex k + 1 (cyclically).
  std::vector<int> vertices;
  std::vector<Eigen::Vector2d> positions;
  /// Per boundary edge: the face on the other side and the index of the edge there, -1 at the
  /// boundary of the T-mesh.
  std::vector<int> twinFace;
  std::vector<int> twinEdge;
};

struct TMesh {
  int numVertices = 0;
  std::vector<TMeshFace> faces;
  /// Per vertex: the face angles at it in quarter turns (1 at a corner, 2 inside a side), summed.
  /// An interior vertex is regular when this is 4.
  std::vector<int> quarterTurnsAround;
  /// Per vertex: on an edge without twin.
  std::vector<char> onBoundary;

  int numFaces() const { return static_cast<int>(faces.size()); }
  /// An interior vertex whose angle is not a full turn: a cone of the flat structure.
  bool isExtraordinary(int vertex) const {
    return !onBoundary[vertex] && quarterTurnsAround[vertex] != 4;
  }
  /// T-junctions (vertices inside a side of a face, counted per face side) and extraordinary
  /// vertices; a boundary vertex counts when it lies on an edge without twin.
  int numTJunctions() const;
  int numExtraordinary() const;
  bool hasBoundary() const;
  /// Frame change across boundary edge `edge` of `face`: maps the face's frame onto its twin's.
  /// Throws InputError at the boundary.
  QuarterMotion acrossEdge(int face, int edge) const;
};

/// Completes faces given by vertices and positions (width, height, twins, vertex angles) and
/// checks them. Throws InputError, naming the face, when a face is not a rectangle with its
/// boundary counter-clockwise from (0, 0) (to 1e-9 of its size), a vertex id is out of range or
/// repeated in a face, two faces use the same edge in the same direction, twin edges differ in
/// length, a vertex is unused, or the faces around a vertex do not form one fan.
TMesh buildTMesh(int numVertices, std::vector<TMeshFace> faces);

/// A tensor grid of faces on the knot lines xKnots x yKnots (strictly increasing). Periodic in a
/// direction: the last line is glued to the first (then at least 4 lines are needed, so that no
/// two edges join the same vertices). Vertex (i, j) has id j * (columns of vertices) + i.
TMesh gridTMesh(const std::vector<double>& xKnots, const std::vector<double>& yKnots,
                bool periodicX = false, bool periodicY = false);

/// A planar T-mesh from rectangles [lo, hi] (x and y of lo and hi per row of the two n x 2
/// matrices) that tile a region without overlapping: the vertices are the rectangles' corners, and
/// a corner lying inside another rectangle's side is a T-junction of it. Coordinates are the
/// knot values (compared to 1e-9 of the largest side). The rectangles must not overlap; what
/// shows of an overlap (a corner inside a rectangle, an edge used twice) throws InputError, as does
/// an empty rectangle and whatever buildTMesh rejects.
TMesh planarTMesh(const Eigen::MatrixX2d& lo, const Eigen::MatrixX2d& hi);

}  // namespace mspline::spline
