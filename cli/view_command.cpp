// mspline view: the viewer (viewer/viewer_app.h): see a mesh, a model, or a scan with its model;
// edit control points with the mouse or a script; screenshots without a person.
#include <iostream>
#include <sstream>

#include "cli/command.h"
#include "mspline/structure/core/errors.h"
#ifdef MSPLINE_HAVE_VIEWER
#include "mspline/viewer/viewer_app.h"
#endif

namespace mspline::cli {

namespace {

struct ViewArguments {
  std::vector<std::string> files;
  std::string screenshot;
  int width = 1280, height = 800;
  std::string camera;
  std::string show;
  std::string apply;
  std::string output;
  double autosave = 60.0;
  int resolution = 6;
  bool quiet = false;
};

#ifdef MSPLINE_HAVE_VIEWER
Eigen::Vector3d parseCamera(const std::string& text) {
  std::stringstream stream(text);
  Eigen::Vector3d out;
  char comma1 = 0, comma2 = 0;
  if (!(stream >> out[0] >> comma1 >> out[1] >> comma2 >> out[2]) || comma1 != ',' ||
      comma2 != ',' || !stream.eof() || !out.allFinite() || out[2] <= 0.0)
    throw structure::InputError(
        "--camera: expected AZIMUTH,ELEVATION,DISTANCE (degrees, "
        "degrees, a positive multiple of the fit distance), got '" +
        text + "'");
  return out;
}
#endif

}  // namespace

void addViewCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<ViewArguments>();
  auto* sub = app.add_subcommand(
      "view",
      "Shows a mesh, a spline model (.msp), or a scan and its model overlaid: shaded surface, "
      "control net, scan and its error map, chart checkerboard, cones. Drag control points "
      "(left button; Alt: along the normal), Shift+drag selects a box, Ctrl+Z/Ctrl+Y undo/redo, "
      "Ctrl+S saves (with a .bak of the old file); unsaved edits are autosaved. With "
      "--screenshot or --apply it renders off screen and exits (works under xvfb-run).");
  sub->add_option("FILES", arguments->files, "A mesh, a .msp model, or both")
      ->required()
      ->expected(1, 2);
  sub->add_option("--screenshot", arguments->screenshot, "Render one frame to this PNG and exit");
  sub->add_option("--width", arguments->width, "Picture or window width (default 1280)")
      ->check(CLI::Range(16, 8192));
  sub->add_option("--height", arguments->height, "Picture or window height (default 800)")
      ->check(CLI::Range(16, 8192));
  sub->add_option("--camera", arguments->camera,
                  "AZIMUTH,ELEVATION,DISTANCE: degrees, degrees, multiple of the distance that "
                  "fits the model in view (default 30,20,1)");
  sub->add_option("--show", arguments->show,
                  "What to draw: surface,net,scan,checker,lines,cones,errors (default: surface, "
                  "net and cones; with a scan also scan)");
  sub->add_option("--apply", arguments->apply,
                  "Run the scripted edits of this JSON file (as mouse drags), then save the model");
  sub->add_option("-o,--output", arguments->output,
                  "Save the edited model here instead of over the model file");
  sub->add_option("--autosave", arguments->autosave,
                  "Seconds between autosaves of unsaved edits (default 60)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--resolution", arguments->resolution,
                  "Samples per face side of the shown surface (default 6)")
      ->check(CLI::Range(1, 64));
  sub->add_flag("-q,--quiet", arguments->quiet, "No progress on stderr");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "view";
    command.outputsTogether = false;
    command.files = arguments->files;
    for (const std::string* file : {&arguments->apply, &arguments->output, &arguments->screenshot})
      command.files.push_back(*file);
    command.run = [&command, arguments]() -> int {
#ifdef MSPLINE_HAVE_VIEWER
      const ViewArguments& a = *arguments;
      viewer::ViewerOptions options;
      options.files = a.files;
      options.screenshot = a.screenshot;
      options.width = a.width;
      options.height = a.height;
      if (!a.camera.empty()) options.camera = parseCamera(a.camera);
      if (!a.show.empty()) options.display = viewer::parseShowList(a.show);
      options.apply = a.apply;
      options.output = a.output;
      options.autosaveSeconds = a.autosave;
      options.resolution = a.resolution;
      options.quiet = a.quiet;
      const Json report = viewer::runViewer(options);
      if (command.json) printJson(report);
      return kExitSuccess;
#else
      (void)command;
      (void)arguments;
      throw structure::InputError(
          "this mspline was built without the viewer (GLFW, OpenGL or Dear ImGui were not found "
          "at build time; scripts/install-deps installs them)");
#endif
    };
  });
}

}  // namespace mspline::cli
