#pragma once
// A flat metric with cones as `mspline flatten` computes it, for tests: Newton on the input
// triangulation, or with intrinsic flips and their common subdivision where it degenerates.
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::test {

struct FlatMetric {
  /// The surface laid out: the input, or the overlay after flips.
  structure::TriMesh surface;
  /// Its flat edge lengths (curvature error 1e-12 at most).
  Eigen::VectorXd lengths;
};

/// Flat everywhere but at `cones` (closed surfaces); fails the running test when the flow does not
/// converge.
FlatMetric flatMetric(const structure::TriMesh& mesh, const std::vector<structure::Cone>& cones);

/// The flat metric `fit` lays quad grids out on: cones placed automatically and quantized to
/// quarter turns, every cone angle at least pi; fails the running test when it does not converge.
FlatMetric seamlessFlatMetric(const structure::TriMesh& mesh);

/// An icosphere(3) made flat but for eight cones of curvature pi/2 (angle 3 pi / 2) at scattered
/// vertices: quarter-turn cones in general position (no trace of a rectangle layout runs into a
/// cone).
FlatMetric eightConeSphere();

/// cow.off with the 39 cones that rounding each cone's curvature to quarter turns on its own gave
/// (before cone placement lowered the rounding's distortion): pairs of opposite cones a hundredth
/// of a cell apart in the flat metric, and intrinsic flips whose common subdivision has faces 1e-4
/// of the surface's size. A hard case for layouts.
FlatMetric clusteredConesCow();

}  // namespace mspline::test
