#pragma once
// A cubic T-spline against OpenSubdiv's Catmull-Clark limit of the same control net. On a T-mesh
// without T-junctions every face is a quad and every vertex a net point, so the T-mesh is a
// Catmull-Clark control net; where the T-spline is a uniform bicubic B-spline (a complete 4 x 4
// neighbourhood of blending functions with equal knot intervals) its surface is the limit surface
// of that net, and the two must agree to rounding: every face but those around extraordinary
// vertices and T-junctions. Around an extraordinary vertex OpenSubdiv refines and caps with
// Gregory patches and the T-spline has its cap patches (tspline_cap.h): two different surfaces of
// one net, and the comparison measures how far apart they are.
//
// Parameters: OpenSubdiv is uniform, one unit of its (u, v) per face; the T-spline's knot
// intervals in a face are the face's width and height. A point (x, y) of face f is (u, v) =
// (x / width, y / height), and d/du = width d/dx. Only regions of equal knot intervals can agree
// (with unit intervals the derivatives coincide too).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/tspline/tspline.h"

namespace mspline::spline {

struct OsdCompareOptions {
  /// Sample points: sample k lies in face k mod F (F faces; every face gets samples once there
  /// are at least F) at a uniformly random (u, v) in [0, 1)^2.
  int samples = 10000;
  /// Seed of the random (u, v); equal seeds give equal points.
  unsigned seed = 1;
  /// OpenSubdiv's isolation level at extraordinary vertices (CatmullClarkOptions, 1 .. 10).
  int isolationLevel = 2;
  /// Optional numVertices x 3 positions of the net points at T-mesh vertices without a blending
  /// function (other rows are ignored); empty: the ring averages of tsplineControlNet.
  Eigen::MatrixXd unanchoredPoints;
};

/// How a face of the T-mesh compares.
enum class OsdFaceClass {
  /// OpenSubdiv's limit is one regular patch (depth 0: its four vertices are interior with four
  /// faces each) and the T-spline face is complete: exactly 16 blending functions over it,
  /// anchored at the 4 x 4 vertices around it (the same vertices as OpenSubdiv's patch points),
  /// each with knot intervals equal to the face's width along x and height along y, and with
  /// equal weights (so the rational sum is the polynomial one). Both are then the same uniform
  /// bicubic B-spline.
  Regular,
  /// Every other face with a surface on both sides.
  Irregular,
  /// OpenSubdiv has no limit surface there (a face touching the boundary: the net is compared
  /// under BoundaryRule::None), or the T-spline is undefined (denominator 0) at one of the face's
  /// samples.
  WithoutSurface,
};

struct OsdComparison {
  /// Per T-mesh face its class.
  std::vector<OsdFaceClass> faceClass;
  /// Faces of each class.
  int regularFaces = 0;
  int irregularFaces = 0;
  int facesWithoutSurface = 0;
  /// Sample points compared (those in regular and irregular faces), and of them in regular faces.
  int samples = 0;
  int regularSamples = 0;
  /// Diagonal of the bounding box of the control points: the position scale.
  double scale = 0.0;
  /// Largest OpenSubdiv first derivative |du|, |dv| over the compared samples: the derivative
  /// scale (first derivatives per face parameter are on the order of the net's edge lengths).
  double derivativeScale = 0.0;
  /// Largest |mspline position - OpenSubdiv position| / scale over the samples in regular faces;
  /// 0 without such samples.
  double regularMaxDeviation = 0.0;
  /// The same over the samples in irregular faces.
  double irregularMaxDeviation = 0.0;
  /// Largest |width d/dx - d/du| and |height d/dy - d/dv| (mspline - OpenSubdiv) / derivativeScale
  /// over the samples in regular faces.
  double regularMaxDerivativeDeviation = 0.0;
  /// The same over the samples in irregular faces.
  double irregularMaxDerivativeDeviation = 0.0;
  /// Position + first derivatives of the compared samples, one batch, serial, best of two runs,
  /// without setup: TSplineBezier::evaluate and CatmullClarkLimit::evaluate.
  double msplinePointsPerSecond = 0.0;
  double osdPointsPerSecond = 0.0;
  /// Setup: Bezier extraction (TSplineBezier; the TSplineSpace is an input) and CatmullClarkLimit
  /// construction (refinement, patch tables, refined points).
  double msplineSetupSeconds = 0.0;
  double osdSetupSeconds = 0.0;
};

/// The Catmull-Clark net of a T-mesh without T-junctions: point v for T-mesh vertex v, faces the
/// T-mesh faces (vertices counter-clockwise from the frame's corner (0, 0), so OpenSubdiv's u runs
/// along x and v along y).
struct TSplineControlNet {
  /// numVertices x 3.
  Eigen::MatrixXd points;
  std::vector<std::vector<int>> faces;
};

/// The faces of the Catmull-Clark net of a T-mesh without T-junctions: per T-mesh face its four
/// vertices counter-clockwise from the frame's corner (0, 0), so that OpenSubdiv's u runs along x
/// and v along y, and patch face f is T-mesh face f. Throws InputError, starting with `context`,
/// when the T-mesh has T-junctions (a face with other than 4 boundary vertices).
std::vector<std::vector<int>> catmullClarkNetFaces(const TMesh& mesh, const std::string& context);

/// The net of `control` (numBasis x 3, a row per blending function): an anchored vertex (every
/// vertex, extraordinary ones included, unless TSplineSpace::missingAnchors lists it) takes its
/// function's control point. A vertex without a function takes its row of `unanchoredPoints` when
/// that is given (numVertices x 3), else the ring average of fillByRingAverages (tspline_cap.h).
/// Throws InputError when the T-mesh has T-junctions (a face with other than 4 boundary vertices),
/// for wrong sizes, or when a vertex has no anchored vertex in its component.
TSplineControlNet tsplineControlNet(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                    const Eigen::MatrixXd& unanchoredPoints = {});

/// Compares the T-spline of `control` and `weights` (as TSplineBezier) with the Catmull-Clark limit
/// of its net (tsplineControlNet, CatmullClarkLimit with BoundaryRule::None) at
/// `options.samples` points. Throws InputError when the T-mesh has T-junctions, for wrong sizes
/// or options.
OsdComparison compareWithOpenSubdiv(const TSplineSpace& space, const Eigen::MatrixXd& control,
                                    const Eigen::VectorXd& weights,
                                    const OsdCompareOptions& options = {});

}  // namespace mspline::spline
