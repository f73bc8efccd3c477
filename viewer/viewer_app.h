#pragma once
// The viewer's window: `mspline view` (cli/view_command.cpp) fills ViewerOptions and calls
// runViewer. Interactive by default; with a screenshot or an edit script it renders off screen
// and returns when done (under Xvfb with Mesa's software OpenGL as well as on a desktop).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "mspline/viewer/renderer.h"

namespace mspline::viewer {

struct ViewerOptions {
  /// One or two files: a mesh, a .msp model, or a scan and its model (any order).
  std::vector<std::string> files;
  /// Render one frame to this PNG and exit (after the edit script, if any).
  std::string screenshot;
  int width = 1280, height = 800;
  /// Azimuth and elevation in degrees and the distance as a multiple of the fit-to-view distance;
  /// unset: the default view.
  std::optional<Eigen::Vector3d> camera;
  /// What is shown; unset: surface, net and cones for a model, plus the scan when given.
  std::optional<DisplayOptions> display;
  /// An edit script (edit_script.h) to run, then save.
  std::string apply;
  /// Where the edited model is saved (default: the model file itself).
  std::string output;
  /// Seconds between autosaves of unsaved edits (autosave file: EditSession::autosavePath).
  double autosaveSeconds = 60.0;
  /// Samples per face side of the shown surface.
  int resolution = 6;
  /// Progress lines on stderr.
  bool quiet = false;
};

/// Opens the files and runs the viewer. Returns what it did as JSON (files, model statistics,
/// scripted edits with per-frame timings, screenshot, saves). Throws the mspline errors
/// (InputError and IoError naming the file; IoError when no OpenGL 3.3 window can be opened).
nlohmann::ordered_json runViewer(const ViewerOptions& options);

/// Parses "surface,net,scan,checker,lines,cones,errors" (any subset); throws InputError naming
/// an unknown entry.
DisplayOptions parseShowList(const std::string& list);

}  // namespace mspline::viewer
