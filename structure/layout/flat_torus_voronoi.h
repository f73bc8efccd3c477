#pragma once
// Voronoi diagrams on a flat torus (Jin, Luo and Gu, "Manifold splines", section 5.2): the cells
// of sites on a closed genus-1 surface with respect to its flat metric, computed on the universal
// cover, where the metric is the plane's and every site repeats by the deck translations.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::structure {

struct TorusVoronoiOptions {
  /// Each site is copied by m p0 + n p1 for |m|, |n| <= windowRadius (p0, p1 the reduced periods)
  /// around the fundamental parallelogram. 1 holds the nearest copy of every site for every
  /// point (proof in flat_torus_voronoi.cpp); larger windows only cost time. Must be >= 1.
  int windowRadius = 1;
};

/// A piece of cell boundary inside one face.
struct VoronoiSegment {
  /// The two sites whose cells it separates, smaller first.
  std::array<int, 2> cells = {-1, -1};
  /// Its ends, both given in the segment's face: ends[0] lies on an edge (one barycentric
  /// coordinate is 0) where it is equidistant to the two sites; ends[1] too, or it is the junction
  /// of three cells inside a face whose corners carry three labels.
  std::array<SurfacePoint, 2> ends;
};

/// Segments chained across faces into one curve between two cells.
struct VoronoiPolyline {
  /// The two sites whose cells it separates, smaller first.
  std::array<int, 2> cells = {-1, -1};
  /// Points in space; a closed polyline repeats its first point at the end.
  std::vector<Eigen::Vector3d> points;
  /// It closes on itself (a loop around the torus or around a cell), rather than running between
  /// two junctions.
  bool closed = false;
};

struct TorusVoronoi {
  /// Per face: the site whose cell contains the face's centroid (in the layout).
  std::vector<int> faceLabel;
  /// Per vertex: the site whose cell contains the vertex.
  std::vector<int> vertexLabel;
  /// The cell boundaries: where the labels of an edge's ends differ, the edge is crossed at the
  /// point equidistant to the two sites; the crossings are joined inside the faces.
  std::vector<VoronoiSegment> segments;
  /// The segments chained into polylines.
  std::vector<VoronoiPolyline> polylines;
  /// Sites whose cell holds at least one face centroid.
  int cells = 0;
  /// Points of the planar Delaunay triangulation: sites times (2 windowRadius + 1)^2.
  int replicatedSites = 0;
  /// Check: max over the edge crossings x of |d(x, s1) - d(x, s2)| / max(d(x, s1), d(x, s2)),
  /// with d the flat distance on the torus (the nearest copy of the site); round-off unless a
  /// site's nearest copy changes along a crossed edge.
  double maxEquidistanceError = 0.0;
};

/// The Voronoi diagram of `sites` on the flat torus given by `layout` (of `mesh`). Throws
/// InputError when the layout has no periods (not a closed genus-1 surface laid out without
/// cones), for no sites, an invalid site (naming it), two sites at the same point of the torus,
/// or windowRadius < 1.
TorusVoronoi flatTorusVoronoi(const TriMesh& mesh, const FlatLayout& layout,
                              const std::vector<SurfacePoint>& sites,
                              const TorusVoronoiOptions& options = {});

}  // namespace mspline::structure
