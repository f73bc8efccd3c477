#pragma once
// Straight walks on a T-mesh (tmesh.h): a segment in one face's frame continued across the face's
// sides into the neighbours' frames, its direction turned with the frame changes. This is how
// parameter correction moves a point over the surface of any spline built on a T-mesh.
#include <Eigen/Core>

#include "mspline/spline/tspline/tmesh.h"

namespace mspline::spline {

/// The point reached from `start` by the segment start.position + step of start.face's frame,
/// continued across face sides (a side may be made of several edges, at T-junctions) into the
/// neighbouring faces. Stops where the segment leaves the T-mesh through an edge without twin:
/// the result is then the point on that edge, and *reachedBoundary (when given) is set to true
/// (false otherwise). A segment that would pass exactly through a vertex, where the next face is
/// ambiguous (and around a cone undefined), is moved sideways by about 1e-7 of the face's size.
/// Throws InputError for a face out of range or a non-finite position or step.
FacePoint walkTMesh(const TMesh& mesh, const FacePoint& start, const Eigen::Vector2d& step,
                    bool* reachedBoundary = nullptr);

}  // namespace mspline::spline
