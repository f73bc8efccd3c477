#pragma once
// A plain-text list of points on a mesh, the input of `mspline voronoi --sites FILE`.
//
// Format: one point per line, "face b0 b1 b2", a face index (0-based, as in the mesh file) and
// three barycentric coordinates in it. '#' starts a comment that runs to the end of the line;
// blank lines are ignored.
#include <string>
#include <vector>

#include "mspline/structure/core/surface_point.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::io {

/// Reads a site file whose faces are faces of `mesh`. Throws IoError when it cannot be opened or
/// read (a directory), InputError when it is not a regular file, InputError naming "path:line"
/// for a malformed line or an invalid point (structure::checkSurfacePoint), and for a file
/// without sites.
std::vector<structure::SurfacePoint> readSiteFile(const std::string& path,
                                                  const structure::TriMesh& mesh);

/// Parses site-file text as readSiteFile does (the fuzz target's entry); `sourceName` stands for
/// the file in messages.
std::vector<structure::SurfacePoint> parseSiteList(const std::string& text,
                                                   const std::string& sourceName,
                                                   const structure::TriMesh& mesh);

}  // namespace mspline::io
