#include <catch2/catch.hpp>

#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/intrinsic/intrinsic_flattening.h"
#include "mspline/structure/layout/flat_layout.h"
#include "mspline/structure/ricci/cone_placement.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/vertex_scaling_energy.h"
#include "mspline/structure/topology/topology.h"
#include "support/test_data.h"

using namespace mspline;
using structure::TriMesh;

TEST_CASE("intrinsic_flattening: mannequin-devil with a circular boundary, doubled",
          "[structure]") {
  // The circle's geodesic curvature pushes interior vertices across boundary edges: on the input
  // triangulation the flow degenerates, on the double it converges.
  const TriMesh mesh = test::realMesh("mannequin-devil.off");
  std::vector<int> loop;
  for (const auto v : mesh.vertices())
    if (mesh.is_boundary(v)) loop.push_back(v.idx());
  std::vector<structure::Cone> boundary;
  for (int v : loop) boundary.push_back({v, 2 * kPi / double(loop.size())});
  const auto target = structure::flatTarget(
      mesh, boundary, structure::BoundaryCondition::PrescribedGeodesicCurvature);
  structure::RicciNewtonOptions options;
  options.tolerance = 1e-10 / (2 * kPi);
  const auto result = structure::flattenWithFlips(mesh, target, options);
  INFO(result.solve.ricci.message);
  REQUIRE(result.solve.ricci.converged);
  CHECK(result.doubled);
  CHECK(result.solve.flips > 0);
  const auto& overlay = result.overlay;
  const auto input = structure::analyzeTopology(mesh);
  const auto half = structure::analyzeTopology(overlay.mesh);
  CHECK(half.euler == input.euler);
  CHECK(half.boundaryLoops == 1);
  CHECK(overlay.mesh.n_vertices() >= mesh.n_vertices() + std::size_t(result.splitEdges));
  REQUIRE(result.u.size() == Eigen::Index(mesh.n_vertices()));

  // Every boundary vertex of the half turns by its target (crossing points on the boundary by 0):
  // the boundary is the prescribed circle, traced through the overlay.
  const structure::FlatLayout layout =
      structure::layoutFlatMetric(overlay.mesh, overlay.edgeLengths);
  CHECK(layout.flippedTriangles == 0);
  CHECK(layout.cones.empty());
  const Eigen::VectorXd curvature = structure::vertexCurvatures(overlay.mesh, overlay.edgeLengths);
  double worst = 0.0;
  for (const auto v : overlay.mesh.vertices()) {
    if (!overlay.mesh.is_boundary(v)) continue;
    const double wanted = v.idx() < int(mesh.n_vertices()) ? target.curvature[v.idx()] : 0.0;
    worst = std::max(worst, std::abs(curvature[v.idx()] - wanted));
  }
  WARN("mannequin-devil on a circle: " << result.solve.flips << " flips on the double, "
                                       << overlay.mesh.n_faces() << " overlay faces, worst "
                                       << "boundary turning error " << worst);
  CHECK(worst <= 1e-8);
}
