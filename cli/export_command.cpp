// mspline export: the evaluated surface of a spline model as a triangle mesh, with normals and
// chart coordinates, and optionally its control net, an error map of a scan and a picture.
//
// spline::ModelSurface tessellates every model kind and gives its control net; the chord error
// estimate of --tolerance reads second derivatives from its fit space.
#include <algorithm>
#include <cmath>
#include <iostream>

#include "cli/command.h"
#include "mspline/io/error_map.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/shaded_picture.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/io/write_mesh.h"
#include "mspline/spline/model/filled_faces.h"
#include "mspline/spline/model/model_surface.h"
#include "mspline/spline/tribspline/spline_domain.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/stopwatch.h"

namespace mspline::cli {

namespace {

using Point3 = std::array<double, 3>;

// --tolerance never asks for more (resolution^2 triangles per face); the report then says
// tolerance_met false.
constexpr int kMaxToleranceResolution = 256;

struct ExportArguments {
  std::string model;
  std::string output;
  int resolution = 8;
  double tolerance = 0.0;
  std::string controlNet;
  std::vector<std::string> errorMap;  // SCAN OUT.ply
  std::string png;
};

// A piece of the parameter domain (a domain face, a T-mesh face) for the chord error estimate:
// the longest edge its grid has at resolution 1, and the largest norm of the second derivatives
// seen in it.
struct PieceCurvature {
  double length = 0.0;
  double secondDerivative = 0.0;
};

Point3 point3(const Eigen::VectorXd& x) {
  return {x[0], x[1], x[2]};
}

// The largest sqrt(|xuu|^2 + 2 |xuv|^2 + |xvv|^2) (a bound of |x''| along every unit direction in
// the chart) of the surface at `points`, those where it is undefined (a cone point, a hole)
// skipped.
double largestSecondDerivative(const spline::FitSpace& space, const Eigen::MatrixXd& control,
                               const std::vector<spline::FitParameter>& points) {
  double largest = 0.0;
  std::vector<spline::FitBasisTerm> terms;
  for (const spline::FitParameter& p : points) {
    space.basisAt(p, terms, 2);
    if (terms.empty()) continue;
    Eigen::Vector3d ss = Eigen::Vector3d::Zero(), st = ss, tt = ss;
    for (const spline::FitBasisTerm& b : terms) {
      ss += b.dss * control.row(b.index).transpose();
      st += b.dst * control.row(b.index).transpose();
      tt += b.dtt * control.row(b.index).transpose();
    }
    const double m = std::sqrt(ss.squaredNorm() + 2.0 * st.squaredNorm() + tt.squaredNorm());
    if (std::isfinite(m)) largest = std::max(largest, m);
  }
  return largest;
}

// The model's pieces: per domain face its longest side and the points of its barycentric grid of
// 3 steps other than the corners (where cones would have no derivative); per T-mesh face its
// diagonal and the 3 x 3 interior points of its 4 x 4 grid.
std::vector<PieceCurvature> modelCurvature(const spline::ModelSurface& surface,
                                           const spline::SplineModel& model) {
  std::vector<PieceCurvature> pieces;
  std::vector<spline::FitParameter> points;
  const auto add = [&](double length) {
    pieces.push_back(
        {length, largestSecondDerivative(surface.fitSpace(), model.controlPoints, points)});
    points.clear();
  };
  if (surface.kind() == spline::SplineKind::TriangularBSpline) {
    const spline::SplineDomain& domain = model.domain;
    for (int f = 0; f < domain.faceCount(); ++f) {
      const auto corners = spline::canonicalCorners(domain, f);
      for (int i = 0; i <= 3; ++i)
        for (int j = 0; i + j <= 3; ++j)
          if (i < 3 && j < 3 && i + j > 0)
            points.push_back(
                {f, ((3 - i - j) * corners[0] + i * corners[1] + j * corners[2]) / 3.0});
      const auto& sides = domain.sideLengths[std::size_t(f)];
      add(std::max({sides[0], sides[1], sides[2]}));
    }
    return pieces;
  }
  for (int f = 0; f < model.tmesh.numFaces(); ++f) {
    const spline::TMeshFace& face = model.tmesh.faces[std::size_t(f)];
    for (int i = 1; i < 4; ++i)
      for (int j = 1; j < 4; ++j)
        points.push_back({f, Eigen::Vector2d(face.width * i / 4.0, face.height * j / 4.0)});
    add(std::hypot(face.width, face.height));
  }
  return pieces;
}

// The control net's points and lines (as indices into the points) and the kind's figures.
Json writeControlNet(const std::string& path, const spline::ModelSurface& surface,
                     const spline::SplineModel& model) {
  const spline::ModelControlNet net = surface.controlNet();
  std::vector<Point3> points;
  std::vector<std::int64_t> pointOfRow(std::size_t(surface.numControlPoints()), -1);
  for (int row : net.points) {
    pointOfRow[std::size_t(row)] = std::int64_t(points.size());
    points.push_back(point3(model.controlPoints.row(row).transpose()));
  }
  std::vector<std::array<std::int64_t, 2>> lines;
  for (const auto& [a, b] : net.lines)
    lines.push_back({pointOfRow[std::size_t(a)], pointOfRow[std::size_t(b)]});
  io::writeObjLines(path, points, lines);
  Json entry{{"output", path}, {"points", points.size()}, {"lines", lines.size()}};
  if (surface.kind() == spline::SplineKind::TriangularBSpline) {
    entry["faces"] = model.domain.faceCount();
  } else if (surface.kind() == spline::SplineKind::TSpline) {
    // Every T-mesh edge once: the sides with a twin count half.
    std::size_t sides = 0, boundary = 0;
    for (const spline::TMeshFace& face : model.tmesh.faces) {
      sides += face.vertices.size();
      boundary += std::size_t(std::count(face.twinFace.begin(), face.twinFace.end(), -1));
    }
    entry["missing_anchors"] = std::size_t(model.tmesh.numVertices) - points.size();
    entry["edges_skipped"] = int((sides + boundary) / 2 - lines.size());
    entry["note"] = "vertices without a blending function are left out, with their edges";
  }
  return entry;
}

double boxDiagonal(const std::vector<Point3>& points) {
  if (points.empty()) return 0.0;
  Point3 low = points.front(), high = points.front();
  for (const Point3& p : points)
    for (std::size_t k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], p[k]);
      high[k] = std::max(high[k], p[k]);
    }
  return std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
}

// The smallest resolution whose chord error estimate h^2 max|x''| / 8 (h: the piece's longest
// grid edge) is at most `bound` on every piece, capped at kMaxToleranceResolution.
int resolutionForChordError(const std::vector<PieceCurvature>& pieces, double bound) {
  double needed = 1.0;
  for (const PieceCurvature& piece : pieces)
    needed = std::max(needed,
                      std::ceil(piece.length * std::sqrt(piece.secondDerivative / (8.0 * bound))));
  return int(std::min(needed, double(kMaxToleranceResolution)));
}

double chordErrorEstimate(const std::vector<PieceCurvature>& pieces, int resolution) {
  double estimate = 0.0;
  for (const PieceCurvature& piece : pieces) {
    const double h = piece.length / resolution;
    estimate = std::max(estimate, h * h * piece.secondDerivative / 8.0);
  }
  return estimate;
}

Eigen::MatrixX3d toMatrix(const std::vector<Point3>& points) {
  Eigen::MatrixX3d m(Eigen::Index(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) m(Eigen::Index(i), Eigen::Index(k)) = points[i][k];
  return m;
}

std::vector<std::array<int, 3>> triangles(const structure::PolygonSoup& soup) {
  std::vector<std::array<int, 3>> out;
  for (const auto& face : soup.faces) out.push_back({int(face[0]), int(face[1]), int(face[2])});
  return out;
}

// Every scan vertex's distance to the surface, and the scan written with colors
// (io/error_map.h).
Json writeErrorMap(const std::string& scanPath, const std::string& outPath,
                   const spline::ModelTessellation& surface) {
  if (io::meshFormatFromPath(outPath) != io::MeshFormat::Ply)
    throw structure::InputError("--error-map: '" + outPath + "' must be a .ply file (colors)");
  io::MeshReadResult scan = io::readMesh(scanPath);
  if (scan.soup.positions.empty())
    throw structure::InputError(scanPath + ": the scan has no vertices");
  const structure::TriangleMeshDistance distance(toMatrix(surface.mesh.positions),
                                                 triangles(surface.mesh));
  const io::ErrorMap map = io::errorMap(toMatrix(scan.soup.positions), distance);
  io::VertexAttributes attributes;
  attributes.colors = map.colors;
  scan.soup.sourceName = scanPath;
  io::writeMesh(outPath, scan.soup, attributes);
  const double diagonal = boxDiagonal(scan.soup.positions);
  return {{"scan", scanPath},
          {"output", outPath},
          {"vertices", map.distances.size()},
          {"rms", diagonal > 0 ? map.rms / diagonal : 0.0},
          {"max", diagonal > 0 ? map.max / diagonal : 0.0},
          {"max_absolute", map.max},
          {"color_scale", map.scale},
          {"note",
           "rms, max relative to the scan's bounding-box diagonal; colors blue (0), white, "
           "red (color_scale, the 99th percentile, and above)"}};
}

int runExport(const ExportArguments& a, const Command& command) {
  // Refuse bad output names before the work.
  io::meshFormatFromPath(a.output);
  if (!a.controlNet.empty() && io::meshFormatFromPath(a.controlNet) != io::MeshFormat::Obj)
    throw structure::InputError("--control-net: '" + a.controlNet + "' must be a .obj file");
  if (!a.errorMap.empty() && io::meshFormatFromPath(a.errorMap[1]) != io::MeshFormat::Ply)
    throw structure::InputError("--error-map: '" + a.errorMap[1] + "' must be a .ply file");
  structure::Stopwatch clock;
  const spline::SplineModel model = io::readSplineModel(a.model);
  const spline::ModelSurface modelSurface(model, a.model);
  Json report{{"file", a.model}, {"kind", modelSurface.kindName()}, {"output", a.output}};

  int resolution = a.resolution;
  std::vector<PieceCurvature> pieces;
  double diagonal = 0.0;
  if (a.tolerance > 0.0) {
    std::vector<Point3> box;
    for (Eigen::Index v = 0; v < model.surfaceVertices.rows(); ++v)
      box.push_back(point3(model.surfaceVertices.row(v).transpose()));
    if (box.empty())
      for (Eigen::Index v = 0; v < model.controlPoints.rows(); ++v)
        box.push_back(point3(model.controlPoints.row(v).transpose()));
    diagonal = boxDiagonal(box);
    pieces = modelCurvature(modelSurface, model);
    resolution = resolutionForChordError(pieces, a.tolerance * diagonal);
  }
  spline::ModelTessellation surface = modelSurface.tessellate(model.controlPoints, resolution);
  surface.mesh.sourceName = a.output;
  // A scan's holes were closed by fill patches for the fit: trimmed away again here.
  const auto renumber = [&](const std::vector<int>& newIndex) {
    const auto move = [&](auto& values) {
      std::remove_reference_t<decltype(values)> kept(surface.mesh.positions.size());
      for (std::size_t v = 0; v < newIndex.size() && v < values.size(); ++v)
        if (newIndex[v] >= 0) kept[std::size_t(newIndex[v])] = values[v];
      values = std::move(kept);
    };
    move(surface.normals);
    move(surface.uvs);
  };
  std::vector<char> overScan = spline::facesOverScan(surface.mesh, model);
  spline::dropBowTies(surface.mesh, overScan);
  const std::size_t trimmed = std::size_t(std::count(overScan.begin(), overScan.end(), char(0)));
  if (trimmed > 0) renumber(spline::keepFaces(surface.mesh, overScan));
  io::VertexAttributes attributes;
  attributes.normals = surface.normals;
  if (io::meshFormatFromPath(a.output) == io::MeshFormat::Obj) attributes.uvs = surface.uvs;
  io::writeMesh(a.output, surface.mesh, attributes);
  report["resolution"] = resolution;
  if (a.tolerance > 0.0) {
    report["tolerance"] = a.tolerance;
    report["chord_error_estimate"] = chordErrorEstimate(pieces, resolution) / diagonal;
    report["tolerance_met"] = chordErrorEstimate(pieces, resolution) <= a.tolerance * diagonal;
  }
  report["vertices"] = surface.mesh.positions.size();
  report["faces"] = surface.mesh.faces.size();
  report["trimmed_faces"] = trimmed;
  report["normals"] = surface.normals.size();
  std::string note;  // appended to the human-readable summary
  for (const spline::TessellationFigure& figure : surface.report) {
    if (figure.count)
      report[figure.name] = std::int64_t(figure.value);
    else
      report[figure.name] = figure.value;
    if (modelSurface.kind() == spline::SplineKind::TSpline && figure.name == "hole_samples" &&
        figure.value > 0)
      note = ", " + std::to_string(std::int64_t(figure.value)) + " samples closing holes";
  }

  if (!a.controlNet.empty())
    report["control_net"] = writeControlNet(a.controlNet, modelSurface, model);
  if (!a.errorMap.empty())
    report["error_map"] = writeErrorMap(a.errorMap[0], a.errorMap[1], surface);
  if (!a.png.empty()) {
    const io::RasterImage image = io::renderShaded(
        toMatrix(surface.mesh.positions), triangles(surface.mesh), toMatrix(surface.normals));
    io::writePng(a.png, image);
    report["png"] = a.png;
  }
  report["seconds"] = clock.lap();
  if (command.json) {
    printJson(report);
  } else {
    std::cout << "wrote " << a.output << " (" << surface.mesh.faces.size() << " triangles" << note
              << ", resolution " << resolution << ")" << std::endl;
    if (report.contains("error_map"))
      std::cout << "error map " << a.errorMap[1] << ": rms "
                << report["error_map"]["rms"].get<double>() << ", max "
                << report["error_map"]["max"].get<double>() << " of the scan's diagonal"
                << std::endl;
  }
  return int(kExitSuccess);
}

}  // namespace

void addExportCommand(CLI::App& app, Command& command) {
  auto arguments = std::make_shared<ExportArguments>();
  auto* sub = app.add_subcommand(
      "export",
      "Writes the surface of a spline model as a watertight triangle mesh (OBJ, PLY or STL) with "
      "a unit normal per vertex (OBJ vn, PLY nx ny nz; STL has facet normals) and, in OBJ, each "
      "vertex's chart coordinates (vt): every domain face sampled on a regular grid, shared "
      "sides sampled once. For a T-spline, every T-mesh edge gets R segments and every face an "
      "R x R grid inside, stitched to faces' T-junctions; samples at extraordinary points "
      "(holes) are the surface's limit around them.");
  sub->add_option("MODEL", arguments->model, "Model file (.msp)")->required();
  sub->add_option("-o,--output", arguments->output, "Mesh to write (.obj, .ply, .stl)")->required();
  auto* resolution = sub->add_option("--resolution", arguments->resolution,
                                     "Segments along each domain side or T-mesh edge (default 8)")
                         ->check(CLI::Range(1, 1000));
  sub->add_option("--tolerance", arguments->tolerance,
                  "Instead of --resolution: the smallest resolution whose chord error estimate "
                  "h^2 max|x''| / 8 (h the longest grid edge of a face, x'' the second "
                  "derivatives at a few points of it) is at most T times the model's "
                  "bounding-box diagonal (resolution at most 256)")
      ->check(CLI::PositiveNumber)
      ->excludes(resolution);
  sub->add_option("--control-net", arguments->controlNet,
                  "Also write the control net as OBJ points and `l` lines");
  sub->add_option("--error-map", arguments->errorMap,
                  "SCAN OUT.ply: the scan with its vertices colored by their distance to the "
                  "exported surface")
      ->expected(2);
  sub->add_option("--png", arguments->png, "Also write a shaded picture of the surface (PNG)");
  sub->add_flag("--json", command.json, "Print one JSON object on stdout");
  sub->callback([&command, arguments] {
    command.name = "export";
    command.run = [&command, arguments] { return runExport(*arguments, command); };
  });
}

}  // namespace mspline::cli
