#include "mspline/io/atlas_file.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mspline/io/atomic_file.h"
#include "mspline/structure/core/errors.h"

namespace mspline::io {

namespace {

using Json = nlohmann::json;
using structure::InputError;

constexpr const char* kFormat = "mspline-atlas";
constexpr int kVersion = 1;

}  // namespace

void writeAtlas(const std::string& path, const structure::TriMesh& mesh,
                const structure::AffineAtlas& atlas) {
  Json vertices = Json::array(), faces = Json::array();
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    vertices.push_back({p[0], p[1], p[2]});
  }
  for (const auto f : mesh.faces()) {
    Json face = Json::array();
    for (const auto v : mesh.fv_range(f)) face.push_back(v.idx());
    faces.push_back(face);
  }
  Json cones = Json::array();
  for (const auto& cone : atlas.cones) cones.push_back({cone.vertex, cone.curvature});
  Json charts = Json::array();
  for (const auto& chart : atlas.charts) {
    Json positions = Json::array();
    for (Eigen::Index k = 0; k < chart.positions.cols(); ++k)
      positions.push_back({chart.positions(0, k), chart.positions(1, k)});
    charts.push_back({{"vertex", chart.vertex},
                      {"faces", chart.faces},
                      {"vertices", chart.vertices},
                      {"positions", positions}});
  }
  Json transitions = Json::array();
  for (const auto& t : atlas.transitions)
    transitions.push_back(
        {t.from, t.to, t.motion.angle, t.motion.translation.x(), t.motion.translation.y()});
  const Json document = {{"format", kFormat},
                         {"version", kVersion},
                         {"mesh", {{"vertices", vertices}, {"faces", faces}}},
                         {"diameter", atlas.diameter},
                         {"flatness_defect", atlas.flatnessDefect},
                         {"cones", cones},
                         {"charts", charts},
                         {"transitions", transitions}};
  writeFileAtomically(path, [&](std::ostream& out) {
    out << document.dump(-1, ' ', false, Json::error_handler_t::replace) << '\n';
  });
}

LoadedAtlas readAtlas(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw structure::IoError(path + ": cannot open the atlas file");
  Json document;
  try {
    document = Json::parse(in);
  } catch (const Json::exception& error) {
    throw InputError(path + ": not a JSON atlas file (" + error.what() + ")");
  }
  const auto fail = [&](const std::string& problem) {
    return InputError(path + ": not a valid atlas: " + problem);
  };
  LoadedAtlas out;
  try {
    if (document.value("format", "") != kFormat)
      throw fail("its format is not " + std::string(kFormat));
    if (document.value("version", 0) != kVersion)
      throw fail("version " + document.value("version", Json()).dump() + " is not " +
                 std::to_string(kVersion));
    auto& mesh = out.mesh;
    for (const auto& p : document.at("mesh").at("vertices"))
      mesh.add_vertex({p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()});
    const int n = int(mesh.n_vertices());
    const auto vertexIndex = [&](const Json& value, const std::string& what) {
      const int v = value.get<int>();
      if (v < 0 || v >= n) throw fail(what + " names vertex " + std::to_string(v));
      return v;
    };
    for (const auto& face : document.at("mesh").at("faces")) {
      if (face.size() != 3) throw fail("a face is not a triangle");
      const auto f =
          mesh.add_face(structure::TriMesh::VertexHandle(vertexIndex(face[0], "a face")),
                        structure::TriMesh::VertexHandle(vertexIndex(face[1], "a face")),
                        structure::TriMesh::VertexHandle(vertexIndex(face[2], "a face")));
      if (!f.is_valid()) throw fail("its mesh is not a manifold");
    }
    auto& atlas = out.atlas;
    atlas.diameter = document.at("diameter").get<double>();
    if (!(atlas.diameter > 0.0)) throw fail("the diameter is not positive");
    atlas.flatnessDefect = document.at("flatness_defect").get<double>();
    if (!(atlas.flatnessDefect >= 0.0)) throw fail("the flatness defect is negative");
    for (const auto& cone : document.at("cones"))
      atlas.cones.push_back({vertexIndex(cone.at(0), "a cone"), cone.at(1).get<double>()});
    atlas.chartOfVertex.assign(std::size_t(n), -1);
    for (const auto& entry : document.at("charts")) {
      structure::Chart chart;
      chart.vertex = vertexIndex(entry.at("vertex"), "a chart");
      for (const auto& f : entry.at("faces")) {
        const int face = f.get<int>();
        if (face < 0 || face >= int(mesh.n_faces()))
          throw fail("a chart names face " + std::to_string(face));
        chart.faces.push_back(face);
      }
      for (const auto& v : entry.at("vertices"))
        chart.vertices.push_back(vertexIndex(v, "a chart"));
      const auto& positions = entry.at("positions");
      if (positions.size() != chart.vertices.size() || chart.vertices.empty() ||
          chart.vertices.front() != chart.vertex)
        throw fail("the chart of vertex " + std::to_string(chart.vertex) +
                   " does not list its vertices and positions alike");
      chart.positions.resize(2, Eigen::Index(positions.size()));
      for (std::size_t k = 0; k < positions.size(); ++k)
        chart.positions.col(Eigen::Index(k)) << positions[k].at(0).get<double>(),
            positions[k].at(1).get<double>();
      for (int f : chart.faces)
        for (const auto v : mesh.fv_range(structure::TriMesh::FaceHandle(f)))
          if (!chart.contains(v.idx()))
            throw fail("the chart of vertex " + std::to_string(chart.vertex) +
                       " lacks a vertex of its face " + std::to_string(f));
      if (atlas.chartOfVertex[std::size_t(chart.vertex)] >= 0)
        throw fail("vertex " + std::to_string(chart.vertex) + " has two charts");
      atlas.chartOfVertex[std::size_t(chart.vertex)] = int(atlas.charts.size());
      atlas.charts.push_back(std::move(chart));
    }
    const int charts = int(atlas.charts.size());
    std::pair<int, int> previous(-1, -1);
    for (const auto& entry : document.at("transitions")) {
      structure::Transition t;
      t.from = entry.at(0).get<int>();
      t.to = entry.at(1).get<int>();
      if (t.from < 0 || t.to >= charts || t.from >= t.to)
        throw fail("a transition joins charts " + std::to_string(t.from) + " and " +
                   std::to_string(t.to));
      if (std::make_pair(t.from, t.to) <= previous) throw fail("transitions are not sorted");
      previous = {t.from, t.to};
      t.motion.angle = entry.at(2).get<double>();
      t.motion.translation << entry.at(3).get<double>(), entry.at(4).get<double>();
      const auto& a = atlas.charts[std::size_t(t.from)];
      if (!a.contains(atlas.charts[std::size_t(t.to)].vertex))
        throw fail("a transition joins the charts of vertices " + std::to_string(a.vertex) +
                   " and " + std::to_string(atlas.charts[std::size_t(t.to)].vertex) +
                   ", which are not adjacent");
      atlas.transitions.push_back(t);
    }
  } catch (const Json::exception& error) {
    throw fail(error.what());
  }
  try {
    structure::measureAtlas(out.mesh, out.atlas);
  } catch (const InputError& error) {
    throw fail(error.what());
  }
  return out;
}

}  // namespace mspline::io
