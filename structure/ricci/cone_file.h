#pragma once
// A plain-text list of cones, the input of `mspline flatten --cones FILE`.
//
// Format: one cone per line, "<vertex> <curvature>", the vertex index (0-based, as in the mesh
// file) and the curvature in radians (Gauss curvature 2 pi - cone angle inside, geodesic curvature
// pi - angle on a boundary), separated by blanks. '#' starts a comment that runs to the end of the
// line; blank lines are ignored. Example: a cone of angle pi/2 at vertex 12 is
// "12 4.71238898038469".
#include <string>
#include <vector>

#include "mspline/structure/ricci/curvature_target.h"

namespace mspline::structure {

/// Reads a cone file. Throws IoError when it cannot be opened or read (a directory), InputError
/// when it is not a regular file, InputError naming "path:line" for a malformed line (not exactly
/// an integer >= 0 and a finite number) or a vertex listed twice. Vertex ranges are checked later
/// against the mesh (flatTarget).
std::vector<Cone> readConeFile(const std::string& path);

/// Parses cone-file text; `sourceName` stands for the path in error messages.
std::vector<Cone> parseConeList(const std::string& text, const std::string& sourceName);

/// The cone-file text of `cones`: a header comment, then one line per cone, curvatures with 17
/// significant digits so that parseConeList gives back the same doubles.
std::string formatConeFile(const std::vector<Cone>& cones);

}  // namespace mspline::structure
