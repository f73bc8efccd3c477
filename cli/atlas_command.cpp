// mspline atlas: the affine atlas of the flat metric (charts, transitions, checks), written as an
// atlas file.
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_options.h"
#include "mspline/io/atlas_file.h"
#include "mspline/io/atomic_file.h"
#include "mspline/io/load_mesh.h"
#include "mspline/structure/atlas/affine_atlas.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

using namespace structure;

struct AtlasArguments {
  std::string mesh;
  std::string output;
  FlattenSettings settings;
  bool check = false;
};

Json atlasFigures(const AffineAtlas& atlas) {
  return {{"charts", atlas.charts.size()},
          {"transitions", atlas.transitions.size()},
          {"max_transition_residual", atlas.maxTransitionResidual},
          {"max_cocycle_residual", atlas.maxCocycleResidual},
          {"transition_kind", transitionKindName(atlas.kind)},
          {"max_kind_angle_error", atlas.maxKindAngleError},
          {"flatness_defect", atlas.flatnessDefect},
          {"uncovered_faces", atlas.uncoveredFaces}};
}

}  // namespace

void addAtlasCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<AtlasArguments>();
  auto* sub = app.add_subcommand(
      "atlas",
      "The affine atlas of the flat metric: one chart per vertex star (cones excepted), rigid "
      "transition maps, checked (transition residuals, cocycle condition), written as an atlas "
      "file (JSON).");
  sub->add_option("MESH", arguments->mesh, "Mesh file (must pass validation)")->required();
  sub->add_option("-o,--output", arguments->output, "Atlas file to write (.json)")->required();
  addFlattenOptions(*sub, arguments->settings);
  sub->add_flag("--check", arguments->check,
                "Read the written file back and check it gives the same atlas");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "atlas";
    command.files = {arguments->mesh, arguments->output, coneFile(arguments->settings)};
    command.run = [&command, arguments] {
      const AtlasArguments& a = *arguments;
      const Progress progress = progressLines(command, a.settings.quiet);
      Stopwatch clock;
      Json stages;
      io::LoadedMesh loaded = io::loadMesh(a.mesh);
      stages["load"] = clock.lap();
      const FlattenOptions options = toFlattenOptions(a.settings, a.mesh);
      const Flattening flattening = flattenSurface(*loaded.mesh, options, progress);
      const Json flat = flatteningJson(flattening, options, stages, command);
      clock.lap();
      structure::report(progress, "building the atlas");
      const AffineAtlas atlas =
          buildAffineAtlas(flattening.surface(), flattening.flatLengths, flattening.layout);
      stages["atlas"] = clock.lap();
      io::writeAtlas(a.output, flattening.surface(), atlas);
      stages["write"] = clock.lap();

      Json report{{"file", a.mesh}, {"output", a.output}};
      report.update(atlasFigures(atlas));
      Json cones = Json::array();
      for (const auto& cone : atlas.cones)
        cones.push_back({{"vertex", cone.vertex}, {"curvature", cone.curvature}});
      report["cones"] = cones;
      report["flatten"] = {{"converged", flat["converged"]},
                           {"iterations", flat["iterations"]},
                           {"max_curvature_error", flat["max_curvature_error"]},
                           {"flips", flat["flips"]},
                           {"flipped_triangles", flat["flipped_triangles"]}};
      if (flat.contains("holonomy")) report["flatten"]["holonomy"] = flat["holonomy"];
      if (a.check) {
        // The file as written, not yet under its name (outputs are named when the command ends).
        const io::OutputBatch* outputs = io::OutputBatch::current();
        const io::LoadedAtlas back =
            io::readAtlas(outputs ? outputs->readablePath(a.output) : a.output);
        const bool identical = back.mesh.n_faces() == flattening.surface().n_faces() &&
                               identicalAtlases(back.atlas, atlas);
        report["check"] = atlasFigures(back.atlas);
        report["check"]["identical"] = identical;
        stages["check"] = clock.lap();
        if (!identical)
          throw InternalError(a.output + ": the atlas read back differs from the one written");
      }
      double total = 0.0;
      for (const auto& [name, seconds] : stages.items()) total += seconds.get<double>();
      report["seconds"] = total;
      report["stage_seconds"] = stages;
      if (command.json) {
        printJson(report);
      } else {
        std::cout << atlas.charts.size() << " charts, " << atlas.transitions.size()
                  << " transitions (" << transitionKindName(atlas.kind) << "), transition residual "
                  << atlas.maxTransitionResidual << ", cocycle residual "
                  << atlas.maxCocycleResidual << "\nwrote " << a.output << std::endl;
      }
      return int(kExitSuccess);
    };
  });
}

}  // namespace mspline::cli
