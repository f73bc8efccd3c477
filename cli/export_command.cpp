// mspline export: the evaluated surface of a spline model as a triangle mesh, with normals and
// chart coordinates, and optionally its control net, an error map of a scan and a picture.
//
// Each model kind contributes a KindSurface (how to tessellate it at a resolution, how curved its
// pieces are, its control net); everything after that is common.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>

#include "cli/command.h"
#include "cli/flatten_pipeline.h"
#include "io/read_mesh.h"
#include "io/shaded_picture.h"
#include "io/spline_model_file.h"
#include "io/write_mesh.h"
#include "spline/filled_faces.h"
#include "spline/tessellate.h"
#include "spline/tri_bspline.h"
#include "spline/tspline_tessellate.h"
#include "structure/closest_point.h"
#include "structure/errors.h"

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

// A tessellation of any kind: the mesh, a unit normal and chart coordinates per vertex, and the
// kind's own entries for the report.
struct Surface {
  structure::PolygonSoup mesh;
  std::vector<Point3> normals;
  std::vector<std::array<double, 2>> uvs;
  Json report = Json::object();
  std::string note = "";  // appended to the human-readable summary
};

// A piece of the parameter domain (a domain face, a T-mesh face) for the chord error estimate:
// the longest edge its grid has at resolution 1, and the largest norm of the second derivatives
// seen in it.
struct PieceCurvature {
  double length = 0.0;
  double secondDerivative = 0.0;
};

struct ControlNet {
  std::vector<Point3> points;
  std::vector<std::array<std::int64_t, 2>> lines;
  Json report = Json::object();
};

struct KindSurface {
  std::string kind;
  std::function<Surface(int resolution)> tessellate;
  std::function<std::vector<PieceCurvature>()> curvature;
  std::function<ControlNet()> controlNet;
};

Point3 point3(const Eigen::VectorXd& x) {
  return {x[0], x[1], x[2]};
}

// sqrt(|xuu|^2 + 2 |xuv|^2 + |xvv|^2) bounds |x''| along every unit direction in the chart.
double secondDerivativeNorm(const Eigen::VectorXd& uu, const Eigen::VectorXd& uv,
                            const Eigen::VectorXd& vv) {
  return std::sqrt(uu.squaredNorm() + 2.0 * uv.squaredNorm() + vv.squaredNorm());
}

// Per T-mesh face: its diagonal, and the largest second derivative norm among the 3 x 3 interior
// points of its 4 x 4 grid (`second` gives x_ss, x_st, x_tt at a point; false where undefined).
template <class SecondDerivatives>
std::vector<PieceCurvature> tmeshCurvature(const spline::TMesh& mesh, SecondDerivatives&& second) {
  std::vector<PieceCurvature> pieces;
  Eigen::VectorXd ss, st, tt;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const spline::TMeshFace& face = mesh.faces[std::size_t(f)];
    PieceCurvature piece{std::hypot(face.width, face.height), 0.0};
    for (int i = 1; i < 4; ++i)
      for (int j = 1; j < 4; ++j) {
        const Eigen::Vector2d p(face.width * i / 4.0, face.height * j / 4.0);
        if (!second(f, p, ss, st, tt)) continue;
        const double m = secondDerivativeNorm(ss, st, tt);
        if (std::isfinite(m)) piece.secondDerivative = std::max(piece.secondDerivative, m);
      }
    pieces.push_back(piece);
  }
  return pieces;
}

// Calls edge(a, b) once for every T-mesh edge (vertices a to b).
template <class Edge>
void forEachTMeshEdge(const spline::TMesh& mesh, Edge&& edge) {
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const spline::TMeshFace& face = mesh.faces[std::size_t(f)];
    const std::size_t n = face.vertices.size();
    for (std::size_t k = 0; k < n; ++k) {
      const int g = face.twinFace[k];
      if (g >= 0 && (g < f || (g == f && std::size_t(face.twinEdge[k]) < k))) continue;
      edge(face.vertices[k], face.vertices[(k + 1) % n]);
    }
  }
}

KindSurface triBSplineSurface(const ExportArguments& a, const spline::SplineModel& model) {
  auto space = std::make_shared<spline::TriBSplineSpace>(model.domain, model.knots);
  if (model.controlPoints.rows() != space->numBasis() || model.controlPoints.cols() != 3)
    throw structure::InputError(a.model + ": the control points do not fit the spline");
  KindSurface out;
  out.kind = "tribspline";
  out.tessellate = [space, &model](int resolution) {
    spline::Tessellation t = spline::tessellate(*space, model.controlPoints, resolution);
    Surface s{std::move(t.mesh), std::move(t.normals), std::move(t.uvs)};
    s.report = {{"min_denominator", t.minDenominator}, {"cone_vertices", t.coneVertices}};
    return s;
  };
  // Per domain face: its longest side, and second derivatives at the points of its barycentric
  // grid of 3 steps other than the corners (where cones would have no derivative).
  out.curvature = [space, &model] {
    std::vector<PieceCurvature> pieces;
    const spline::SplineDomain& domain = space->domain();
    for (int f = 0; f < domain.faceCount(); ++f) {
      PieceCurvature piece;
      for (double side : domain.sideLengths[std::size_t(f)])
        piece.length = std::max(piece.length, side);
      for (int i = 0; i <= 3; ++i)
        for (int j = 0; i + j <= 3; ++j) {
          if (i == 3 || j == 3 || i + j == 0) continue;
          const spline::DomainPoint point{f, Eigen::Vector3d(3 - i - j, i, j) / 3.0};
          const spline::SplinePoint x = space->evaluate(model.controlPoints, point, 2);
          const double m = secondDerivativeNorm(x.duu, x.duv, x.dvv);
          if (std::isfinite(m)) piece.secondDerivative = std::max(piece.secondDerivative, m);
        }
      pieces.push_back(piece);
    }
    return pieces;
  };
  // Per domain face, lines between the control points of beta and beta - e_i + e_j.
  out.controlNet = [space, &model] {
    ControlNet net;
    for (Eigen::Index k = 0; k < model.controlPoints.rows(); ++k)
      net.points.push_back(point3(model.controlPoints.row(k).transpose()));
    const int n = space->degree();
    // Row of beta within its face: beta_0 descending, then beta_1 descending.
    std::vector<std::array<int, 3>> betas;
    for (int b0 = n; b0 >= 0; --b0)
      for (int b1 = n - b0; b1 >= 0; --b1) betas.push_back({b0, b1, n - b0 - b1});
    const auto rowOf = [&](const std::array<int, 3>& beta) {
      return int(std::find(betas.begin(), betas.end(), beta) - betas.begin());
    };
    for (int f = 0; f < space->domain().faceCount(); ++f)
      for (std::size_t k = 0; k < betas.size(); ++k)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            std::array<int, 3> other = betas[k];
            if (i == j || other[std::size_t(i)] == 0) continue;
            --other[std::size_t(i)];
            ++other[std::size_t(j)];
            const int m = rowOf(other);
            if (m > int(k))
              net.lines.push_back({std::int64_t(f) * space->basisPerFace() + std::int64_t(k),
                                   std::int64_t(f) * space->basisPerFace() + m});
          }
    net.report = {{"faces", space->domain().faceCount()}};
    return net;
  };
  return out;
}

KindSurface tSplineSurface(const ExportArguments& a, const spline::SplineModel& model) {
  auto space = std::make_shared<spline::TSplineSpace>(model.tmesh);
  if (model.controlPoints.rows() != space->numBasis() || model.controlPoints.cols() != 3)
    throw structure::InputError(a.model + ": the control points do not fit the T-spline");
  KindSurface out;
  out.kind = "tspline";
  out.tessellate = [space, &model, &a](int resolution) {
    spline::TSplineTessellation t;
    try {
      t = spline::tessellateTSpline(*space, model.controlPoints, model.weights, resolution);
    } catch (const structure::InputError& e) {
      throw structure::InputError(a.model + ": " + e.what());
    }
    Surface s{std::move(t.mesh), std::move(t.normals), std::move(t.uvs)};
    s.report = {{"min_denominator", t.minDenominator},
                {"hole_samples", t.holeVertices.size()},
                {"hole_offset", t.holeOffset},
                {"collapsed_edge_samples", t.collapsedEdgeSamples}};
    if (!t.holeVertices.empty())
      s.note = ", " + std::to_string(t.holeVertices.size()) + " samples closing holes";
    return s;
  };
  // Second derivatives at the 3 x 3 interior points of each face's 4 x 4 grid (points in a hole,
  // NaN, are skipped).
  out.curvature = [space, &model] {
    return tmeshCurvature(space->mesh(), [&](int f, const Eigen::Vector2d& p, Eigen::VectorXd& ss,
                                             Eigen::VectorXd& st, Eigen::VectorXd& tt) {
      const spline::TSplinePoint x = space->evaluate(model.controlPoints, model.weights, f, p, 2);
      ss = x.dss;
      st = x.dst;
      tt = x.dtt;
      return true;
    });
  };
  // Every anchored T-mesh vertex's control point, and the T-mesh edges between two of them.
  out.controlNet = [space, &model] {
    ControlNet net;
    const spline::TMesh& mesh = space->mesh();
    std::vector<std::int64_t> pointOf(std::size_t(mesh.numVertices), -1);
    for (int v = 0; v < mesh.numVertices; ++v) {
      const int anchor = space->anchorOfVertex()[std::size_t(v)];
      if (anchor < 0) continue;
      pointOf[std::size_t(v)] = std::int64_t(net.points.size());
      net.points.push_back(point3(model.controlPoints.row(anchor).transpose()));
    }
    int skipped = 0;
    forEachTMeshEdge(mesh, [&](int from, int to) {
      const std::int64_t p = pointOf[std::size_t(from)], q = pointOf[std::size_t(to)];
      if (p < 0 || q < 0)
        ++skipped;
      else
        net.lines.push_back({p, q});
    });
    net.report = {{"missing_anchors", space->missingAnchors().size()},
                  {"edges_skipped", skipped},
                  {"note", "vertices without a blending function are left out, with their edges"}};
    return net;
  };
  return out;
}

// Subdivision surfaces: the Catmull-Clark limit of the T-mesh's net (spline::tessellateSubd).
KindSurface subdSurface(const ExportArguments& a, const spline::SplineModel& model) {
  std::shared_ptr<spline::SubdSpace> space;
  try {
    space = std::make_shared<spline::SubdSpace>(model.tmesh);
  } catch (const structure::InputError& e) {
    throw structure::InputError(a.model + ": " + e.what());
  }
  if (model.controlPoints.rows() != space->numBasis() || model.controlPoints.cols() != 3)
    throw structure::InputError(a.model + ": the control points do not fit the subdivision net");
  KindSurface out;
  out.kind = "subd";
  out.tessellate = [space, &model](int resolution) {
    spline::TMeshTessellation t = spline::tessellateSubd(*space, model.controlPoints, resolution);
    return Surface{std::move(t.mesh), std::move(t.normals), std::move(t.uvs)};
  };
  // Second derivatives at the 3 x 3 interior points of each face's 4 x 4 grid.
  out.curvature = [space, &model] {
    std::vector<spline::FitBasisTerm> terms;
    return tmeshCurvature(space->mesh(), [&](int f, const Eigen::Vector2d& p, Eigen::VectorXd& ss,
                                             Eigen::VectorXd& st, Eigen::VectorXd& tt) {
      space->basisAt(f, p, terms, 2);
      ss = st = tt = Eigen::VectorXd::Zero(3);
      for (const spline::FitBasisTerm& b : terms) {
        ss += b.dss * model.controlPoints.row(b.index).transpose();
        st += b.dst * model.controlPoints.row(b.index).transpose();
        tt += b.dtt * model.controlPoints.row(b.index).transpose();
      }
      return !terms.empty();
    });
  };
  // The net: a point per T-mesh vertex, every T-mesh edge once.
  out.controlNet = [space, &model] {
    ControlNet net;
    const spline::TMesh& mesh = space->mesh();
    for (int v = 0; v < mesh.numVertices; ++v)
      net.points.push_back(point3(model.controlPoints.row(v).transpose()));
    forEachTMeshEdge(mesh, [&](int from, int to) { net.lines.push_back({from, to}); });
    return net;
  };
  return out;
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

// Blue (0) through white (half the scale) to red (the scale and above).
std::array<std::uint8_t, 3> errorColor(double t) {
  t = std::clamp(t, 0.0, 1.0);
  const auto c = [](double x) { return std::uint8_t(std::lround(255.0 * x)); };
  if (t < 0.5) return {c(2.0 * t), c(2.0 * t), 255};
  return {255, c(2.0 - 2.0 * t), c(2.0 - 2.0 * t)};
}

// Every scan vertex's distance to the surface, and the scan written with colors. The color
// scale is the distances' 99th percentile (robust to a few stray scan points; larger distances
// are red too).
Json writeErrorMap(const std::string& scanPath, const std::string& outPath,
                   const Surface& surface) {
  if (io::meshFormatFromPath(outPath) != io::MeshFormat::Ply)
    throw structure::InputError("--error-map: '" + outPath + "' must be a .ply file (colors)");
  io::MeshReadResult scan = io::readMesh(scanPath);
  if (scan.soup.positions.empty())
    throw structure::InputError(scanPath + ": the scan has no vertices");
  const structure::TriangleMeshDistance distance(toMatrix(surface.mesh.positions),
                                                 triangles(surface.mesh));
  const auto hits = distance.queryAll(toMatrix(scan.soup.positions));
  std::vector<double> d;
  double squares = 0.0, largest = 0.0;
  for (const auto& hit : hits) {
    d.push_back(hit.distance);
    squares += hit.distance * hit.distance;
    largest = std::max(largest, hit.distance);
  }
  std::vector<double> sorted = d;
  const std::size_t rank = std::min(sorted.size() - 1, std::size_t(0.99 * double(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(rank), sorted.end());
  const double scale = sorted[rank] > 0.0 ? sorted[rank] : (largest > 0.0 ? largest : 1.0);
  io::VertexAttributes attributes;
  for (double x : d) attributes.colors.push_back(errorColor(x / scale));
  scan.soup.sourceName = scanPath;
  io::writeMesh(outPath, scan.soup, attributes);
  const double diagonal = boxDiagonal(scan.soup.positions);
  const double rms = std::sqrt(squares / double(d.size()));
  return {{"scan", scanPath},
          {"output", outPath},
          {"vertices", d.size()},
          {"rms", diagonal > 0 ? rms / diagonal : 0.0},
          {"max", diagonal > 0 ? largest / diagonal : 0.0},
          {"max_absolute", largest},
          {"color_scale", scale},
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
  Stopwatch clock;
  const spline::SplineModel model = io::readSplineModel(a.model);
  const KindSurface kind = model.kind == spline::SplineKind::TSpline ? tSplineSurface(a, model)
                           : model.kind == spline::SplineKind::Subdivision
                               ? subdSurface(a, model)
                               : triBSplineSurface(a, model);
  Json report{{"file", a.model}, {"kind", kind.kind}, {"output", a.output}};

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
    pieces = kind.curvature();
    resolution = resolutionForChordError(pieces, a.tolerance * diagonal);
  }
  Surface surface = kind.tessellate(resolution);
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
  report.update(surface.report);

  if (!a.controlNet.empty()) {
    const ControlNet net = kind.controlNet();
    io::writeObjLines(a.controlNet, net.points, net.lines);
    Json entry{
        {"output", a.controlNet}, {"points", net.points.size()}, {"lines", net.lines.size()}};
    entry.update(net.report);
    report["control_net"] = entry;
  }
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
    std::cout << "wrote " << a.output << " (" << surface.mesh.faces.size() << " triangles"
              << surface.note << ", resolution " << resolution << ")" << std::endl;
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
