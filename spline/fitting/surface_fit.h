#pragma once
// Fitting a spline surface to scan points (in the style of G+Smo's gsFitting): linear least
// squares for the control points with a thin-plate fairing term, then parameter correction (each
// sample moved to the parameters of its closest point on the current surface, by Newton's method
// on the parameters, across faces and charts) and a refit, a few rounds. Works on any FitSpace
// (fit_space.h); adaptive refinement is the caller's (tspline_adaptive_fit.h and the fit command).
//
// The solve: (D^T W D + lambda K + epsilon I) C = D^T W P, D the samples' basis values (one row
// per sample), W their weights, K the thin-plate energy integral of |S_ss|^2 + 2 |S_st|^2 +
// |S_tt|^2 over the parameter domain (quadrature), lambda = smoothing * trace(D^T D) / (n median
// K_ii) (n functions; the median, not the trace of K, which a few functions with blowing-up second
// derivatives would dominate), and a light pull (epsilon = 1e-7 of the mean diagonal of D^T D)
// towards the quasi-interpolant G on the right side (epsilon G) for functions that neither samples
// nor the energy determine.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "mspline/spline/fitting/fit_space.h"

namespace mspline::spline {

struct SurfaceFitOptions {
  /// Weight of the fairing term relative to the data term (see above). Negative: chosen
  /// automatically among 10^-1 .. 10^-7 by hold-out validation on the first solve (parameter
  /// correction keeps it): the largest whose fit on 7/8 of the samples predicts the other 1/8 as
  /// well as the best candidate, within 5 % of its RMS error and a tenth of the errors' range.
  double smoothing = -1.0;
  /// Rounds of parameter correction (project the samples, refit).
  int correctionRounds = 3;
  /// Newton steps per sample and projection.
  int projectionSteps = 12;
  /// Per sample, the weight of its squared distance (empty: all 1); e.g. small weights for
  /// points of fill patches that only keep the surface near them where there is no scan.
  Eigen::VectorXd sampleWeights;
  /// Per face of the space's domain, a factor on the fairing energy there (empty: all 1); e.g.
  /// larger where the surface folded between the samples.
  Eigen::VectorXd faceFairing;
};

struct SurfaceFitResult {
  /// One row per function of the space, three columns.
  Eigen::MatrixXd controlPoints;
  /// The samples' parameters after the last projection (the closest points' parameters).
  std::vector<FacePoint> parameters;
  /// Per sample: distance from the scan point to the surface at its parameters after the last
  /// projection; NaN for samples where the surface is undefined.
  Eigen::VectorXd distances;
  /// Root mean square and maximum of the finite distances (absolute, the targets' units), with the
  /// sample weights: sqrt(sum w d^2 / sum w) and max sqrt(w) d.
  double rmsError = 0.0;
  double maxError = 0.0;
  /// The relative smoothing weight of the last solve and its absolute lambda.
  double smoothing = 0.0;
  double lambda = 0.0;
  /// Parameter correction rounds done.
  int rounds = 0;
  /// RMS distance after the first solve (before parameter correction), at the input parameters.
  double initialRmsError = 0.0;
  /// Samples left out because the surface is undefined at their parameters (a cone point).
  int samplesOutside = 0;
  /// Functions of the space that no sample lies under in the last solve (held by the pull towards
  /// the quasi-interpolant and the fairing alone).
  int basisWithoutSamples = 0;
};

/// Reports a stage and a fraction done in [0, 1].
using FitProgress = std::function<void(const std::string& stage, double fraction)>;

/// Fits the surface of `space` to `targets` (one row per sample, three columns) starting from the
/// samples' `parameters`. Throws InputError when the counts differ, SolverError when no sample
/// has a defined surface or the system cannot be factored.
SurfaceFitResult fitSurface(const FitSpace& space, const std::vector<FacePoint>& parameters,
                            const Eigen::MatrixX3d& targets, const SurfaceFitOptions& options = {},
                            const FitProgress& progress = {});

/// The surface point of `control` at `p` (NaN where the surface is undefined).
Eigen::Vector3d evaluateFitSurface(const FitSpace& space, const Eigen::MatrixXd& control,
                                   const FacePoint& p);

/// The first derivatives ds, dt of the surface of `control` at `p`; false where the surface is
/// undefined. `terms` is scratch space, reused across calls.
bool evaluateFitTangents(const FitSpace& space, const Eigen::MatrixXd& control, const FacePoint& p,
                         std::vector<FitBasisTerm>& terms, Eigen::Vector3d& ds,
                         Eigen::Vector3d& dt);

/// A closest point found by Newton's method on the parameters from a start.
struct SurfaceProjection {
  FacePoint parameter;
  /// |S(parameter) - target|; NaN where the surface is undefined at the start.
  double distance = 0.0;
};

/// Moves `start` to a local minimum of |S(u) - target| (Newton steps, the Hessian's curvature
/// part dropped where it is not positive definite, steps halved until the distance decreases).
SurfaceProjection projectOntoSurface(const FitSpace& space, const Eigen::MatrixXd& control,
                                     const FacePoint& start, const Eigen::Vector3d& target,
                                     int steps = 12);

/// The thin-plate energy matrix K of the space (see above), numBasis x numBasis; with
/// `faceFactors` (one per face of the domain, else empty) each face's share times its factor.
Eigen::SparseMatrix<double> thinPlateEnergy(const FitSpace& space,
                                            const Eigen::VectorXd& faceFactors = {});

}  // namespace mspline::spline
