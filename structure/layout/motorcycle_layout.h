#pragma once
// A layout of rectangles on a flat surface with cones (Eppstein et al.'s motorcycle graph, as used
// for quad layouts by Campen and Zorin and by Bommes et al.): when every cone angle is a multiple
// of pi/2 and the holonomy consists of quarter turns, the two axis directions of any face frame
// carried across the surface agree everywhere (a cross field without singularities away from the
// cones). From every cone a straight trace leaves along each axis direction (k traces at a cone
// of angle k pi/2); all traces grow at the same pace and one stops where it meets another. Two
// traces on one line running towards each other (on symmetric surfaces and polyhedra, from cones
// facing each other or a trace aimed exactly at a cone) meet head-on half-way and end at one node,
// and a trace that reaches such a node crosses it; a trace that crossed a whole face in one step
// stops where a trace that got there first crossed its path. The traces cut the surface into
// rectangles: each face of the graph has four corners of pi/2 (at cones between consecutive
// traces, and at the ends of traces, which are T-nodes) and straight sides.
//
// The rectangles are the charts of a quad layout; spline/tspline/layout_tmesh.h gives each side an
// integer length and grids every rectangle into unit cells, which makes a seamless quad mesh whose
// only extraordinary vertices are the cones.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct MotorcycleLayoutOptions {
  /// A vertex is a cone when its angle differs from 2 pi by more than this (radians).
  double coneTolerance = 1e-6;
  /// Cone angles and the holonomy must be multiples of pi/2 to this (radians).
  double angleTolerance = 1e-6;
  /// A trace longer than this times the square root of the surface's area is an error (a trace on
  /// a flat surface can wind densely; with cones around, traces meet long before).
  double maxTraceLength = 50.0;
  /// The cross field's first axis in face 0, counter-clockwise from the face's first edge
  /// (radians). Any angle gives a valid field; turning it moves every trace, which breaks the
  /// coincidences of symmetric surfaces (a trace through a cone or through another's end).
  double frameAngle = 0.0;
};

/// A node of the layout: a cone, the point where a trace ended on another trace, or where traces
/// met head-on (two of them, or four where two such pairs cross).
struct LayoutNode {
  /// The cone's mesh vertex, or -1 for a T-node.
  int vertex = -1;
  /// The angle at the node in quarter turns: k for a cone of angle k pi/2, 4 at T-nodes.
  int quarterTurns = 4;
};

/// A piece of a trace between two consecutive nodes on it.
struct LayoutSegment {
  int trace = -1;
  /// Arc lengths along the trace and the nodes there.
  double start = 0.0;
  double end = 0.0;
  int from = -1;
  int to = -1;
  double length() const { return end - start; }
};

/// A rectangle of the layout. Half-edge 2 s runs along segment s in the trace's direction, 2 s + 1
/// against it; each has the rectangle on its left.
struct LayoutRectangle {
  /// Half-edges along each side, counter-clockwise: side 0 runs from corner 0 along the
  /// rectangle's +x axis, side 1 along +y, side 2 along -x, side 3 along -y.
  std::array<std::vector<int>, 4> sides;
  /// Flat lengths of the sides (opposite ones equal up to the metric's error).
  std::array<double, 4> sideLength{};
  /// Width (along x) and height: means of the opposite sides.
  double width() const { return 0.5 * (sideLength[0] + sideLength[2]); }
  double height() const { return 0.5 * (sideLength[1] + sideLength[3]); }
};

/// Where a surface point lies in the layout.
struct RectanglePoint {
  int rectangle = -1;
  /// Position in the rectangle's frame, [0, width] x [0, height].
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  /// The side the locating walk ended on, and how far along it (flat length from its corner).
  int side = -1;
  double alongSide = 0.0;
};

/// The traces, the layout graph and a point locator. Immutable after construction.
class MotorcycleLayout {
 public:
  /// Traces the layout of the flat metric `lengths` (by edge index) on a closed mesh. Throws
  /// InputError for a mesh with boundary, lengths of the wrong size, a metric without cones;
  /// SolverError when a cone angle or the holonomy is not a multiple of pi/2 (the flattening
  /// before failed to quantize them), a trace does not end or a face of the graph is not a
  /// rectangle (named, with its corner count or the mismatch of its opposite sides: events that
  /// coincide in ways the tracing does not resolve, e.g. crossings at a mesh vertex).
  MotorcycleLayout(const TriMesh& mesh, const Eigen::VectorXd& lengths,
                   const MotorcycleLayoutOptions& options = {});
  ~MotorcycleLayout();
  MotorcycleLayout(MotorcycleLayout&&) noexcept;
  MotorcycleLayout& operator=(MotorcycleLayout&&) noexcept;

  const std::vector<LayoutNode>& nodes() const;
  const std::vector<LayoutSegment>& segments() const;
  const std::vector<LayoutRectangle>& rectangles() const;
  /// Per half-edge: its rectangle, its side there and the flat distance from the side's first
  /// corner to the half-edge's start.
  const std::vector<int>& halfedgeRectangle() const;
  const std::vector<int>& halfedgeSide() const;
  const std::vector<double>& halfedgeOffset() const;
  int numTraces() const;
  /// Sum of all trace lengths, and the longest.
  double totalTraceLength() const;
  double longestTrace() const;

  /// The rectangle holding the point with barycentric coordinates `barycentric` (corner k = k-th
  /// vertex of the face's vertex circulator) in mesh face `face`, found by walking straight along
  /// an axis direction until a trace is met.
  RectanglePoint locate(int face, const Eigen::Vector3d& barycentric) const;

 private:
  struct Data;
  std::unique_ptr<Data> data_;
};

}  // namespace mspline::structure
