#pragma once
// The atlas file: a JSON document holding the mesh and its affine atlas, so that later commands
// (and the spline model file, which embeds it) need nothing else.
//
//   {"format": "mspline-atlas", "version": 1,
//    "mesh": {"vertices": [[x, y, z], ...], "faces": [[a, b, c], ...]},
//    "diameter": d, "flatness_defect": e,
//    "cones": [[vertex, curvature], ...],
//    "charts": [{"vertex": v, "faces": [f, ...], "vertices": [v, w, ...],
//                "positions": [[x, y], ...]}, ...],
//    "transitions": [[from, to, angle, tx, ty], ...]}
//
// Charts and transitions are as in structure/atlas/affine_atlas.h (a transition maps chart `from`
// to chart `to` by x -> R(angle) x + (tx, ty)); numbers are written with 17 significant digits, so
// reading gives back the same doubles.
#include <string>
#include <string_view>

#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/mesh/tri_mesh.h"

namespace mspline::io {

/// Writes atomically; IoError when the file cannot be written.
void writeAtlas(const std::string& path, const structure::TriMesh& mesh,
                const structure::AffineAtlas& atlas);

struct LoadedAtlas {
  structure::TriMesh mesh;
  /// With its figures recomputed from the charts and transitions (measureAtlas).
  structure::AffineAtlas atlas;
};

/// Reads and checks an atlas file: InputError naming the file and the problem when it is not
/// one (not JSON, wrong format or version, indices out of range, a number that is not finite, a
/// chart or transition that does not fit the mesh); IoError when it cannot be read.
LoadedAtlas readAtlas(const std::string& path);

/// Reads an atlas file's text as readAtlas does (the fuzz target's entry); `sourceName` stands for
/// the file in messages.
LoadedAtlas parseAtlas(std::string_view text, const std::string& sourceName);

}  // namespace mspline::io
