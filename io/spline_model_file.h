#pragma once
// The spline model file (.msp): a spline::SplineModel (spline/core/spline_model.h) in binary, so
// that a fitted spline can be saved and loaded without recomputing anything. Doubles are stored bit
// for bit, so save -> load -> save gives the same bytes and a loaded spline evaluates to the
// same bits.
//
// Types: u8 and u32 unsigned, i32 two's complement, f64 IEEE 754 binary64; all little-endian.
// Counts are u32 and at most 2^31 - 1 (the model indexes with int). Sections follow one another
// without padding, in this order:
//
//   header (16 bytes)
//     u8[8]  magic: "MSPLINE" then 0x1A (a control byte: a text file never starts like this)
//     u32    format version: 4 (versions 1 to 3 are read too, see below)
//     u32    kind: 1 = triangular B-spline, 2 = T-spline, 3 = subdivision surface
//            (spline::SplineKind)
//   common part (every kind)
//     surface vertices         u32 V; V times f64 x, y, z
//     surface faces            u32 F (at least 1); F times i32 a, b, c (surface vertices,
//                              counter-clockwise)
//     filled surface faces     (version 3) u32 count (0, or F); count times u8: 1 when the
//                              surface face fills a hole of the scan (structure/mesh/cap_holes.h)
//   kind 1 part: triangular B-spline
//     surface vertex locations V times i32 domain face, f64 b0, b1, b2 (barycentric)
//     domain vertices          u32 N; N times u8 cone (0 or 1), i32 source surface vertex
//     domain faces             u32 M (at least 1); M times i32 corner[3], f64 side length[3],
//                              i32 neighbour[3] (domain faces), u8 neighbour side[3] (0 to 2)
//     degree                   i32 n (at least 1)
//     knots                    M faces times 3 corners times n + 1 points f64 x, y
//     control points           u32 rows (M (n + 1)(n + 2) / 2), u32 columns (3), then
//                              rows times columns f64, row-major
//   kind 2 part: cubic T-spline (spline/tspline/tspline.h; the degree is 3 and not stored)
//     T-mesh                   u32 vertex count, u32 face count (at least 1); per face u32 k
//                              (at least 4), then k times i32 vertex, f64 x, y: its boundary
//                              counter-clockwise from the corner (0, 0), positions in the face's
//                              frame (what spline::buildTMesh takes and must accept)
//     surface vertex T-mesh points
//                              V times i32 T-mesh face, f64 x, y (inside that face's rectangle,
//                              to 1e-9 of its size)
//     weights                  u32 W; W times f64 (positive)
//     control points           u32 rows, u32 columns (3), then rows times columns f64,
//                              row-major; rows = W = the blending functions of
//                              spline::TSplineSpace(T-mesh), one per row in the order of its
//                              anchors
//   kind 3 part: Catmull-Clark subdivision surface (spline/subd/subd_fit_space.h)
//     T-mesh, surface vertex T-mesh points
//                              as for kind 2; every face has exactly 4 boundary vertices (no
//                              T-junctions: the T-mesh is the control net)
//     control points           u32 rows, u32 columns (3), then rows times columns f64,
//                              row-major; rows = the T-mesh's vertex count, row v the net point
//                              of vertex v
//
// Nothing may follow the last section. Field meanings are those of SplineModel, SplineDomain and
// TMesh (side k of a domain face joins corners k and k + 1; knots in the face's home frame). A
// model holds only its own kind's fields: the writer refuses one with data of another kind.
//
// Version 1 knew only kind 1 and counted its first three sections to the common part; since they
// come right after the surface faces, a version 1 file holds the same bytes as the version 2 file
// of the same model but for the version number. Readers read both.
// Kind 3 came to version 2 as the extension rule below allows: a reader that does not know it
// rejects it by number. Version 3 added the filled surface faces to the common part; a version 1
// or 2 file reads as a model without filled faces. Version 4 has the same sections; its T-splines
// anchor functions at cones and their one-rings (caps, spline/tspline/tspline_cap.h), where
// older ones had none (a hole): an older T-spline's rows go to the other anchors in vertex order,
// and the cap anchors get the ring averages of their anchored neighbours (control points and
// weights as (w c, w)); an older T-mesh that cannot have caps is rejected, asking for a new fit.
//
// Extending the format: the header and the common part are the same for every kind, and the
// kind-specific part comes last. A new kind takes the next kind number and defines its own part
// after the common part; readers reject kinds they do not know, naming the number (and the
// version, which tells the kinds it knows). Any change to the header, the common part or an
// existing kind's part takes the next format version; a reader reads every version up to its own
// and rejects newer ones, naming both. Since nothing may follow the last section, an old reader
// never silently drops data.
#include <string>
#include <string_view>

#include "mspline/spline/core/spline_model.h"

namespace mspline::io {

/// Writes atomically. InputError when the model is one the reader would reject (sizes that
/// disagree, an index out of range, a non-finite number, an inconsistent domain, a T-mesh that
/// spline::buildTMesh rejects, a weight that is not positive, a subdivision surface's T-mesh with
/// T-junctions, data of another kind), and then
/// no file is written; IoError when the file cannot be written.
void writeSplineModel(const std::string& path, const spline::SplineModel& model);

/// Reads and checks a spline model file: InputError naming the file and the problem when it is
/// not a valid one (not an .msp file, an unsupported version or kind, truncated in a section,
/// no surface faces, no domain or T-mesh faces, counts that do not match, control points with
/// other than 3 coordinates, an index out of range, a non-finite number, a domain that
/// spline::validateDomain or a T-mesh that spline::buildTMesh rejects, a T-mesh point outside its
/// face, a weight that is not positive, a subdivision surface's T-mesh with T-junctions or control
/// points other than one per T-mesh vertex, bytes after the end); IoError when it cannot be read.
/// The tmesh of a T-spline or a subdivision surface comes back completed by buildTMesh.
spline::SplineModel readSplineModel(const std::string& path);

/// Reads a model file's bytes as readSplineModel does (the fuzz target's entry); `sourceName`
/// stands for the file in messages.
spline::SplineModel parseSplineModel(std::string_view data, const std::string& sourceName);

}  // namespace mspline::io
