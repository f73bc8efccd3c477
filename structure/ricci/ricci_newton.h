#pragma once
// Newton's method on the convex Ricci energy of a metric scheme (ricci_scheme.h): finds conformal
// factors u whose metric has the target curvatures, on a fixed triangulation (no edge flips).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/structure/core/index_map.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/mesh/tri_mesh.h"
#include "mspline/structure/ricci/curvature_target.h"
#include "mspline/structure/ricci/ricci_scheme.h"

namespace mspline::structure {

struct RicciNewtonOptions {
  /// Stop when max |K_i - K_target_i| over the unknowns is at most tolerance * 2 pi.
  double tolerance = 1e-10;
  /// Newton steps before giving up (status MaxIterations).
  int maxIterations = 100;
  /// Armijo constant: a step t is accepted when E(u + t d) <= E(u) + armijo * t * grad . d.
  double armijo = 1e-4;
  /// Halvings of the step before the line search gives up.
  int maxBacktracks = 60;
  /// The first trial step changes no u_i by more than this (a length factor of e^(maxUStep/2)).
  double maxUStep = 8.0;
  /// Fixed triangulations only: give up with DegenerateTriangles after this many consecutive
  /// steps whose line search was cut short by triangles degenerating. The iterates then press
  /// against the triangle inequality, so the solution most likely lies beyond what the
  /// triangulation can represent; solveVertexScalingWithFlips goes on from there.
  int maxDegenerateSteps = 8;
};

enum class RicciStatus {
  /// max curvature error <= tolerance.
  Converged,
  /// maxIterations steps without reaching the tolerance.
  MaxIterations,
  /// No step along the Newton direction decreased the energy (numerical stagnation).
  LineSearchFailed,
  /// Every step along the Newton direction made some triangle violate the triangle inequality
  /// (or maxDegenerateSteps steps in a row were cut short so), or the input already had such
  /// triangles: this triangulation has no valid solution nearby (intrinsic Delaunay flips would be
  /// needed).
  DegenerateTriangles,
  /// The Newton system could not be factorized.
  SolverFailed,
};

/// One Newton iteration, recorded before its step.
struct RicciIteration {
  /// Energy at the iterate (up to a constant).
  double energy = 0.0;
  /// max |K_i - K_target_i| over the unknowns at the iterate.
  double maxCurvatureError = 0.0;
  /// Accepted step length t in u + t d (0 when no step was taken).
  double step = 0.0;
  /// Step halvings the line search needed.
  int backtracks = 0;
};

struct RicciResult {
  /// status == Converged.
  bool converged = false;
  RicciStatus status = RicciStatus::MaxIterations;
  /// One line saying why the solve stopped (always set; names faces on DegenerateTriangles).
  std::string message;
  /// Newton steps taken.
  int iterations = 0;
  /// max |K_i - K_target_i| over the unknowns at the returned u.
  double maxCurvatureError = 0.0;
  /// One entry per iterate, the last one being the returned u.
  std::vector<RicciIteration> log;
  /// Wall-clock seconds of the whole solve.
  double seconds = 0.0;
  /// Scale factors per vertex (0 at fixed vertices and at the pinned gauge vertex).
  Eigen::VectorXd u;
  /// Edge lengths of the returned metric, by edge index (exp((u_i + u_j) / 2) l0_ij for vertex
  /// scaling).
  Eigen::VectorXd edgeLengths;
  /// Faces that violated the triangle inequality, in the input or in the rejected trial steps that
  /// stopped the solve (the returned metric is valid unless the input was not); empty unless status
  /// is DegenerateTriangles.
  std::vector<int> degenerateFaces;
};

/// Minimizes the Ricci energy for `target` on a connected mesh. When no vertex is fixed, the
/// target must satisfy Gauss-Bonnet (InputError otherwise, checked before solving) and the
/// additive gauge is fixed by holding u = 0 at vertex 0. Throws TopologyError for a mesh with
/// several components or no faces. Numerical failure is reported in the result, never thrown.
RicciResult solveVertexScaling(const TriMesh& mesh, const CurvatureTarget& target,
                               const RicciNewtonOptions& options = {});

/// What every Ricci solver checks first (a connected mesh with faces: TopologyError; one target
/// per vertex; Gauss-Bonnet: InputError), and its unknowns: the vertices that are not fixed, with
/// vertex 0 pinned for the additive gauge when none is.
IndexMap ricciUnknowns(const TriMesh& mesh, const CurvatureTarget& target);

/// The Newton direction -H^-1 g, re-running the symbolic analysis when `reanalyze` (the pattern
/// changed). Throws SolverError when H cannot be factorized or the direction does not descend.
Eigen::VectorXd newtonDirection(SparseCholesky& solver, const Eigen::SparseMatrix<double>& hessian,
                                const Eigen::VectorXd& gradient, bool reanalyze);

/// The same Newton method for any scheme (vertex scaling, circle packings); the degeneracy checks
/// use the scheme's lengths, since a circle packing's initial metric need not be the input's.
RicciResult solveRicciFlow(const TriMesh& mesh, const RicciScheme& scheme,
                           const CurvatureTarget& target, const RicciNewtonOptions& options = {});

}  // namespace mspline::structure
