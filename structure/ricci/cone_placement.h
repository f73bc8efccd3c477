#pragma once
// Automatic placement of cone singularities for a flat metric (greedy, as in BFF and CEPS).
//
// Each round solves the linearized flattening problem once: the Newton step from u = 0 of the
// Ricci energy, L u = K_target - K_input, with L the cotangent Laplacian of the input, K_target = 0
// at every free vertex and u = 0 at the cones placed so far and on the boundary. The curvature the
// linear solve leaves at a cone, K_input + (L u), becomes that cone's curvature, so on a closed
// surface the cones carry exactly 2 pi chi. The next cone goes to the vertex of largest |u|. The
// Laplacian is factorized once (boundary held, or one gauge vertex on a closed surface); each cone
// adds one solve with that factor, its Green's function, and every round's u follows from a small
// dense capacitance system, so the whole placement costs about one factorization plus one solve
// per round. The Green's functions are kept: memory is (cones + 2) doubles per vertex.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

struct ConePlacementOptions {
  /// -1: place cones until the distortion is at most `maxDistortion` and every cone angle is at
  /// least `minConeAngle`, at most `maxCones`. N >= 0: place exactly N cones (InputError when
  /// some cone angle then comes out below `minConeAngle`, e.g. N = 0 on a sphere). 0 is valid on
  /// closed genus 1 and on surfaces with boundary.
  int targetCount = -1;
  /// Stop threshold on the distortion of the linear solve (see ConePlacementResult::distortion):
  /// 1.0 lets the area scale exp(2u) vary by at most a factor e^4 (about 55) over the surface.
  double maxDistortion = 1.0;
  /// Upper bound on the number of cones when targetCount is -1. With `quantize` a closed surface
  /// gets at least as many as rounding needs (4 chi / maxQuarterTurns when chi > 0, -chi when
  /// chi < 0: cone angles of at most 4 pi), and the bound is at least half as many again.
  int maxCones = 64;
  /// Automatic placement goes on while a cone angle 2 pi - curvature is below this (radians):
  /// nearly degenerate cones make the Newton solve hard. Default pi / 4.
  double minConeAngle = kPi / 4;
  /// A new cone is at least this many edges away from every other cone and from the boundary;
  /// when no vertex is that far and the surface still needs cones (a coarse polyhedron), any
  /// vertex that is not a cone and not on the boundary.
  int minSeparation = 2;
  /// When > 0, the separation is measured along edges in the mesh's own lengths instead, and a
  /// new cone is at least this far from every other cone and from the boundary (a quad layout's
  /// corners closer than a cell make sliver cells).
  double minSeparationLength = 0.0;
  /// Round every cone curvature to a multiple k pi / 2 (see ConePlacementResult::quarterTurns).
  /// Automatic placement then goes on until the cones can carry 2 pi chi in such multiples; with
  /// maxQuarterTurns 1, each round caps a cone's curvature at one quarter turn (the curvature
  /// above it stays in the distortion, so the next cones go near it); on closed surfaces each
  /// round likewise holds a cone's curvature at -4 quarter turns at least.
  /// On closed surfaces the integers sum to exactly 4 chi (largest-remainder rounding); then
  /// quarter turns move between cones (closed) or are added or taken (with a boundary) while that
  /// lowers the area-weighted squared conformal factor of the linear solve, so that the rounding
  /// errors do not pile up (-4 <= k). Cones that end at 0 are dropped. Every cone angle
  /// 2 pi - k pi / 2 stays positive (k <= 3), and on closed surfaces at most 4 pi (-4 <= k: a
  /// layout corner of valence 8 at most).
  bool quantize = false;
  /// With `quantize`: the largest multiple k allowed. 3 (default) lets a cone angle go down to
  /// pi/2. In a quad layout a cone of k quarter turns is a corner of valence 4 - k: 2 keeps every
  /// corner's valence at least 2, 1 at least 3. The curvature cut off goes to other cones by the
  /// same rounding.
  int maxQuarterTurns = 3;
  /// Closed genus >= 2 only (TopologyError otherwise): one cone carrying all of 2 pi chi
  /// (Gu et al. 2008), at the vertex of largest |u| of the cone-free linear solve; `targetCount`
  /// and `maxDistortion` are ignored. Its curvature 2 pi (2 - 2g) is a multiple of pi/2, so
  /// `quantize` changes nothing.
  bool singleCone = false;
};

struct ConePlacementResult {
  /// Interior vertices with their Gauss curvature 2 pi - (cone angle); ordered by placement. Use
  /// with flatTarget(mesh, cones, BoundaryCondition::FixedScale).
  std::vector<Cone> cones;
  /// When quantized (or singleCone): cones[i].curvature == quarterTurns[i] * pi / 2 exactly as
  /// computed in double; empty otherwise.
  std::vector<int> quarterTurns;
  /// Distortion after each round (entry i: with the first i cones, before quantization), the
  /// half range (max u - min u) / 2 of the linear solve on closed surfaces, max |u| with u = 0 on
  /// the boundary otherwise.
  std::vector<double> distortionPerRound;
  /// Distortion of the linear solve for the returned cones (after quantization), u = 0 on the
  /// boundary, the cones as curvature targets (not held at u = 0).
  double distortion = 0.0;
  /// That linear solution, per vertex (mean zero on closed surfaces); a cheap predictor of the
  /// Newton solution's scale factors.
  Eigen::VectorXd u;
  /// Automatic placement stopped at maxCones while the distortion was still above
  /// maxDistortion: the cones flatten the surface, but its metric stretches more than asked.
  bool reachedMaxCones = false;
  /// One line describing the outcome (number of cones, rounds, why it stopped).
  std::string message;
};

/// Places cones on a connected triangle mesh (closed or with boundary; boundary vertices get
/// u = 0, i.e. BoundaryCondition::FixedScale). Throws TopologyError for several components or no
/// interior vertex, InputError for contradictory options (e.g. targetCount 0 on a sphere) and
/// SolverError when the automatic placement finds no cones that flatten the surface or the
/// cotangent Laplacian cannot be factorized (e.g. the input's degenerate faces disconnect it).
ConePlacementResult placeCones(const TriMesh& mesh, const ConePlacementOptions& options = {});

/// Quantized placement needs a cone, at its own vertex, for every `maxQuarterTurns` of the
/// 4 chi quarter turns of a closed surface of positive Euler characteristic: a tetrahedron's 4
/// vertices cannot carry a quad layout's 8 corners. Returns how many rounds of subdivideMidpoint
/// (structure/mesh/subdivide.h, the same surface) give `mesh` that many vertices: 0 for a mesh
/// with enough, with a boundary or with chi <= 0.
int midpointLevelsForQuarterTurnCones(const TriMesh& mesh, int maxQuarterTurns);

}  // namespace mspline::structure
