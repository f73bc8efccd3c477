#pragma once
// The spline surface as a triangle mesh: every domain face sampled on a regular barycentric grid,
// the samples on shared sides and vertices computed once and shared, so the mesh is watertight.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tribspline/tri_bspline.h"
#include "mspline/structure/mesh/polygon_soup.h"

namespace mspline::spline {

struct Tessellation {
  /// The surface's triangles (resolution^2 per domain face), counter-clockwise like the domain.
  structure::PolygonSoup mesh;
  /// Smallest denominator (sum of the raw basis functions) met at a sample.
  double minDenominator = 0.0;
  /// Cone vertices, where the spline is undefined: their samples are the mean of the spline at
  /// the points `coneOffset` (barycentric) into each face around them.
  int coneVertices = 0;
  double coneOffset = 0.0;
  /// The mesh vertices of those cone samples (ascending).
  std::vector<std::int64_t> coneSamples;
  /// Per mesh vertex: the unit normal du x dv / |du x dv| of the spline (derivatives in the
  /// sampling face's frame, which is counter-clockwise, so the normal points to the side the
  /// triangles face). A cone vertex gets the normalized mean of the normals at its offset points;
  /// where that or du x dv vanishes, vertexNormalsOfMesh's normal of the triangles.
  std::vector<std::array<double, 3>> normals;
  /// Per mesh vertex: its position in the frame of the domain face that sampled it (the first face
  /// that reaches it: a vertex shared by faces gets that face's chart coordinates only). Chart
  /// coordinates, not a texture atlas: they jump between faces.
  std::vector<std::array<double, 2>> uvs;
  /// Where the spline was evaluated (CSR): mesh vertex v is the mean of the spline at
  /// samplePoints[sampleOffsets[v] .. sampleOffsets[v + 1]), one point per vertex but the cone
  /// samples (one per face around the cone). A point is the grid point, or where rounding breaks
  /// the normalization there, the point moved a little towards its face's centre that was
  /// evaluated instead. sampleOffsets has one entry more than the mesh has vertices.
  std::vector<std::int64_t> sampleOffsets;
  std::vector<SurfacePoint> samplePoints;
};

/// Samples the spline with control points `control` (3 columns) `resolution` times along every
/// side of every domain face (resolution >= 1; InputError otherwise).
Tessellation tessellate(const TriBSplineSpace& space, const Eigen::MatrixXd& control,
                        int resolution);

/// Per vertex of the triangles of `soup`, the normalized sum of its triangles' normals weighted by
/// their areas (zero for a vertex without area around it).
std::vector<std::array<double, 3>> vertexNormalsOfMesh(const structure::PolygonSoup& soup);

/// Replaces every normal in `normals` (one per soup vertex) that is not finite or not of unit
/// length (to 1e-6) by vertexNormalsOfMesh's.
void fillMissingNormals(const structure::PolygonSoup& soup,
                        std::vector<std::array<double, 3>>& normals);

}  // namespace mspline::spline
