#include "mspline/io/export_model.h"

#include <algorithm>

#include "mspline/io/atomic_file.h"
#include "mspline/io/error_map.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/shaded_picture.h"
#include "mspline/io/write_mesh.h"
#include "mspline/spline/quality/surface_quality.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/bounding_box.h"
#include "mspline/structure/mesh/closest_point.h"

namespace mspline::io {

namespace {

// Every scan vertex's distance to the surface, and the scan written with colors to `outPath`.
ScanErrors writeErrorMap(const std::string& scanPath, const std::string& outPath,
                         const spline::ModelTessellation& surface) {
  MeshReadResult scan = readMesh(scanPath);
  if (scan.soup.positions.empty())
    throw structure::InputError(scanPath + ": the scan has no vertices");
  const structure::TriangleMeshDistance distance(structure::pointMatrix(surface.mesh.positions),
                                                 structure::triangleIndices(surface.mesh));
  const ErrorMap map = errorMap(structure::pointMatrix(scan.soup.positions), distance);
  VertexAttributes attributes;
  attributes.colors = map.colors;
  scan.soup.sourceName = scanPath;
  writeMesh(outPath, scan.soup, attributes);
  const double diagonal = structure::boundingBoxDiagonal(scan.soup.positions);
  ScanErrors errors;
  errors.vertices = map.distances.size();
  errors.rms = diagonal > 0 ? map.rms / diagonal : 0.0;
  errors.max = diagonal > 0 ? map.max / diagonal : 0.0;
  errors.maxAbsolute = map.max;
  errors.colorScale = map.scale;
  return errors;
}

}  // namespace

void checkExportFiles(const ExportFileOptions& options) {
  meshFormatFromPath(options.output);
  if (!options.controlNet.empty() && meshFormatFromPath(options.controlNet) != MeshFormat::Obj)
    throw structure::InputError("control net '" + options.controlNet + "' must be a .obj file");
  if (options.scan.empty() != options.errorMap.empty())
    throw structure::InputError("an error map needs both a scan and a file to write");
  if (!options.errorMap.empty() && meshFormatFromPath(options.errorMap) != MeshFormat::Ply)
    throw structure::InputError("error map '" + options.errorMap +
                                "' must be a .ply file (colors)");
}

ExportFileResult exportModel(const spline::SplineModel& model, const std::string& name,
                             const ExportFileOptions& options) {
  checkExportFiles(options);
  spline::ExportOptions surfaceOptions = options.surface;
  surfaceOptions.controlNet = !options.controlNet.empty();
  ExportFileResult result;
  result.surface = spline::exportSurface(model, name, surfaceOptions);
  spline::ModelTessellation& surface = result.surface.surface;
  surface.mesh.sourceName = options.output;
  OutputBatch outputs;
  VertexAttributes attributes;
  attributes.normals = surface.normals;
  if (meshFormatFromPath(options.output) == MeshFormat::Obj) attributes.uvs = surface.uvs;
  writeMesh(options.output, surface.mesh, attributes);

  if (!options.controlNet.empty())
    writeObjLines(options.controlNet, result.surface.controlNet.points,
                  result.surface.controlNet.lines);
  if (!options.scan.empty())
    result.scanErrors = writeErrorMap(options.scan, options.errorMap, surface);
  if (!options.png.empty()) {
    ShadedPictureOptions picture;
    if (options.markDefects) {
      picture.marked = spline::creasedFaces(surface.mesh, options.creaseDegrees);
      result.markedFaces = std::size_t(std::count(picture.marked.begin(), picture.marked.end(), 1));
    }
    writePng(options.png, renderShaded(structure::pointMatrix(surface.mesh.positions),
                                       structure::triangleIndices(surface.mesh),
                                       structure::pointMatrix(surface.normals), picture));
  }
  outputs.commit();
  return result;
}

}  // namespace mspline::io
