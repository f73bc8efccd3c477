#include "mspline/io/atlas_file.h"

#include <cstdint>

#include <nlohmann/json.hpp>

#include "mspline/io/atomic_file.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/whole_file.h"

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
  return parseAtlas(structure::readWholeFile(path), path);
}

LoadedAtlas parseAtlas(std::string_view text, const std::string& sourceName) {
  const std::string& path = sourceName;
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::exception& error) {
    throw InputError(path + ": not a JSON atlas file (" + error.what() + ")");
  }
  const auto fail = [&](const std::string& problem) {
    return InputError(path + ": not a valid atlas: " + problem);
  };
  // JSON may hold a string where a number belongs, and a string, a fraction, a negative or a huge
  // number where an index does (its numbers are finite: the parser refuses "1e999").
  const auto number = [&](const Json& value, const std::string& what) {
    if (!value.is_number()) throw fail(what + " is not a number");
    return value.get<double>();
  };
  const auto index = [&](const Json& value, std::size_t count, const std::string& what,
                         const char* noun) {
    if (!value.is_number_integer()) throw fail(what + " names a " + noun + " that is no index");
    const bool inRange =
        value.is_number_unsigned()
            ? value.get<std::uint64_t>() < count
            : value.get<std::int64_t>() >= 0 && std::uint64_t(value.get<std::int64_t>()) < count;
    if (!inRange) throw fail(what + " names " + noun + " " + value.dump());
    return value.get<int>();
  };
  LoadedAtlas out;
  try {
    if (document.value("format", "") != kFormat)
      throw fail("its format is not " + std::string(kFormat));
    if (document.value("version", 0) != kVersion)
      throw fail("version " + document.value("version", Json()).dump() + " is not " +
                 std::to_string(kVersion));
    auto& mesh = out.mesh;
    for (const auto& p : document.at("mesh").at("vertices")) {
      const std::string what = "a coordinate of vertex " + std::to_string(mesh.n_vertices());
      if (!p.is_array() || p.size() != 3)
        throw fail("vertex " + std::to_string(mesh.n_vertices()) + " is not 3D");
      mesh.add_vertex({number(p[0], what), number(p[1], what), number(p[2], what)});
    }
    const std::size_t n = mesh.n_vertices();
    const auto vertexIndex = [&](const Json& value, const std::string& what) {
      return index(value, n, what, "vertex");
    };
    for (const auto& face : document.at("mesh").at("faces")) {
      if (!face.is_array() || face.size() != 3) throw fail("a face is not a triangle");
      const int a = vertexIndex(face[0], "a face"), b = vertexIndex(face[1], "a face"),
                c = vertexIndex(face[2], "a face");
      if (a == b || b == c || c == a) throw fail("a face repeats a vertex");
      const auto f =
          mesh.add_face(structure::TriMesh::VertexHandle(a), structure::TriMesh::VertexHandle(b),
                        structure::TriMesh::VertexHandle(c));
      if (!f.is_valid()) throw fail("its mesh is not a manifold");
    }
    auto& atlas = out.atlas;
    atlas.diameter = number(document.at("diameter"), "the diameter");
    if (!(atlas.diameter > 0.0)) throw fail("the diameter is not positive");
    atlas.flatnessDefect = number(document.at("flatness_defect"), "the flatness defect");
    if (!(atlas.flatnessDefect >= 0.0)) throw fail("the flatness defect is negative");
    for (const auto& cone : document.at("cones"))
      atlas.cones.push_back(
          {vertexIndex(cone.at(0), "a cone"), number(cone.at(1), "a cone's curvature")});
    atlas.chartOfVertex.assign(n, -1);
    for (const auto& entry : document.at("charts")) {
      structure::Chart chart;
      chart.vertex = vertexIndex(entry.at("vertex"), "a chart");
      for (const auto& f : entry.at("faces"))
        chart.faces.push_back(index(f, mesh.n_faces(), "a chart", "face"));
      for (const auto& v : entry.at("vertices"))
        chart.vertices.push_back(vertexIndex(v, "a chart"));
      const auto& positions = entry.at("positions");
      if (positions.size() != chart.vertices.size() || chart.vertices.empty() ||
          chart.vertices.front() != chart.vertex)
        throw fail("the chart of vertex " + std::to_string(chart.vertex) +
                   " does not list its vertices and positions alike");
      chart.positions.resize(2, Eigen::Index(positions.size()));
      const std::string position =
          "a position of the chart of vertex " + std::to_string(chart.vertex);
      for (std::size_t k = 0; k < positions.size(); ++k) {
        if (!positions[k].is_array() || positions[k].size() != 2)
          throw fail(position + " is not 2D");
        chart.positions.col(Eigen::Index(k)) << number(positions[k][0], position),
            number(positions[k][1], position);
      }
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
    const std::size_t charts = atlas.charts.size();
    std::pair<int, int> previous(-1, -1);
    for (const auto& entry : document.at("transitions")) {
      structure::Transition t;
      if (!entry.is_array() || entry.size() != 5)
        throw fail("a transition is not [from, to, angle, tx, ty]");
      t.from = index(entry[0], charts, "a transition", "chart");
      t.to = index(entry[1], charts, "a transition", "chart");
      if (t.from >= t.to)
        throw fail("a transition joins charts " + std::to_string(t.from) + " and " +
                   std::to_string(t.to));
      if (std::make_pair(t.from, t.to) <= previous) throw fail("transitions are not sorted");
      previous = {t.from, t.to};
      t.motion.angle = number(entry[2], "a transition's angle");
      t.motion.translation << number(entry[3], "a transition's translation"),
          number(entry[4], "a transition's translation");
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
