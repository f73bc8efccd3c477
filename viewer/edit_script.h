#pragma once
// Scripted edits (`mspline view MODEL --apply EDITS.json`): moves of control points run through
// the Controller as mouse drags would, so editing is testable without a person. The file:
//
//   {"edits": [
//     {"points": [12], "pixels": [40, -25]},      a mouse drag from point 12's place on the screen
//                                                 by (dx, dy) pixels (all points move with it)
//     {"points": [12, 13], "offset": [0, 0.01, 0]},  the points moved by a world offset
//     {"points": [12], "normal": 0.01},           each point along its normal, by a world distance
//     {"undo": 1}, {"redo": 1},                   undo / redo that many steps
//     {"save": true},                             save (as Ctrl+S)
//     {"wait": 0.5}                               let seconds pass (frames keep being drawn)
//   ]}
//
// Moves take "steps" frames (default 8), each one re-evaluation of the surface, as a drag's mouse
// events would.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "mspline/viewer/controller.h"
#include "mspline/viewer/edit_session.h"

namespace mspline::viewer {

struct ScriptedEdit {
  enum class Kind { Pixels, Offset, Normal, Undo, Redo, Save, Wait };
  Kind kind = Kind::Wait;
  std::vector<int> points;
  /// Pixels: (dx, dy, 0); Offset: the world offset.
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
  /// Normal: the distance; Wait: the seconds.
  double amount = 0.0;
  /// Undo, Redo: how many steps.
  int count = 1;
  int steps = 8;
};

/// Reads an edit script; throws InputError naming the file (and the edit, counted from 1) when it
/// is not JSON of the form above, names a control point out of range, or asks for more than
/// 10000 steps or undos or redos at once, or a wait beyond 600 seconds; IoError when it cannot be
/// read.
std::vector<ScriptedEdit> readEditScript(const std::string& path, int numControlPoints);

/// Parses an edit script's text as readEditScript does (the fuzz target's entry); `sourceName`
/// stands for the file in messages.
std::vector<ScriptedEdit> parseEditScript(std::string_view text, const std::string& sourceName,
                                          int numControlPoints);

/// Runs one edit through `controller` and `session`, calling `frame` after every step (the
/// window redraws there; it may also autosave). Throws InputError when a pixel drag would not
/// pick its first point (another control point is nearer to the pointer on the screen).
void runScriptedEdit(const ScriptedEdit& edit, std::size_t number, Controller& controller,
                     EditSession& session, const Camera& camera,
                     const std::function<void()>& frame);

}  // namespace mspline::viewer
