#include "mspline/spline/tspline/layout_tmesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <Eigen/Core>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/layout/quantize_segments.h"

namespace mspline::spline {

using structure::LayoutRectangle;
using structure::MotorcycleLayout;
using structure::Quantization;
using structure::QuantizeOptions;
using structure::SegmentSum;

namespace {

// Cells and flat lengths summed along a side, per half-edge boundary.
struct SideScale {
  std::vector<double> flat{0.0};
  std::vector<int> cells{0};
  double map(double offset) const {
    if (flat.back() <= 0.0) return 0.0;
    offset = std::clamp(offset, 0.0, flat.back());
    std::size_t k = 0;
    while (k + 2 < flat.size() && flat[k + 1] < offset) ++k;
    const double span = flat[k + 1] - flat[k];
    const double f = span > 0.0 ? (offset - flat[k]) / span : 0.0;
    return cells[k] + f * (cells[k + 1] - cells[k]);
  }
};

SideScale sideScale(const MotorcycleLayout& layout, const std::vector<int>& segmentCells,
                    const std::vector<int>& side) {
  SideScale scale;
  for (int he : side) {
    scale.flat.push_back(scale.flat.back() + layout.segments()[std::size_t(he / 2)].length());
    scale.cells.push_back(scale.cells.back() + segmentCells[std::size_t(he / 2)]);
  }
  return scale;
}

// When collapses break the mesh, those of segments at least this many cells long are undone
// first, and all of them only if the mesh still breaks.
constexpr double kSliver = 0.1;

// Vertex ids joined into one T-mesh vertex by collapses.
struct VertexClasses {
  std::vector<int> parent;
  explicit VertexClasses(int count) : parent(std::size_t(count)) {
    for (int v = 0; v < count; ++v) parent[std::size_t(v)] = v;
  }
  int find(int v) {
    while (parent[std::size_t(v)] != v)
      v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
    return v;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::size_t(std::max(a, b))] = std::min(a, b);
  }
};

// The value below which `fraction` of the cells lie, given (value, cells) per rectangle.
double cellPercentile(std::vector<std::pair<double, int>> values, double fraction) {
  if (values.empty()) return 1.0;
  std::sort(values.begin(), values.end());
  long total = 0;
  for (const auto& [value, cells] : values) total += cells;
  long seen = 0;
  for (const auto& [value, cells] : values) {
    seen += cells;
    if (double(seen) >= fraction * double(total)) return value;
  }
  return values.back().first;
}

// Why assembling the cells failed: sets of segments that need more cells in all (a chain of
// collapses that may not all collapse again, or the sides of a rectangle whose cells repeat a
// vertex that no collapse joined, as a 1 x 1 rectangle with one cone at opposite corners), or
// collapsed segments to give a cell again.
struct AssemblyFailure {
  std::vector<SegmentSum> separations;
  std::vector<int> uncollapse;
  bool failed() const { return !separations.empty() || !uncollapse.empty(); }
};

// The joins of collapsed segments and rectangles, each with the segments whose cells would undo
// it (the segment itself, or the sides across the rectangle).
struct Joins {
  std::vector<std::vector<int>> undoneBy;
  std::vector<std::vector<std::pair<int, int>>> at;  // per vertex: (other vertex, join)
  explicit Joins(int vertices) : at(std::size_t(vertices)) {}
  void add(int a, int b, int join) {
    at[std::size_t(a)].emplace_back(b, join);
    at[std::size_t(b)].emplace_back(a, join);
  }
  // The segments that undo one chain of joins from a to b (empty when a == b or none leads there).
  std::vector<int> separating(int a, int b) const {
    if (a == b) return {};
    std::vector<std::pair<int, int>> reachedBy(at.size(), {-1, -1});
    std::vector<int> queue{a};
    reachedBy[std::size_t(a)] = {a, -1};
    for (std::size_t k = 0; k < queue.size() && reachedBy[std::size_t(b)].first < 0; ++k)
      for (const auto& [other, join] : at[std::size_t(queue[k])])
        if (reachedBy[std::size_t(other)].first < 0) {
          reachedBy[std::size_t(other)] = {queue[k], join};
          queue.push_back(other);
        }
    std::vector<int> segments;
    if (reachedBy[std::size_t(b)].first < 0) return segments;
    for (int v = b; v != a; v = reachedBy[std::size_t(v)].first) {
      const auto& undo = undoneBy[std::size_t(reachedBy[std::size_t(v)].second)];
      segments.insert(segments.end(), undo.begin(), undo.end());
    }
    return segments;
  }
};

// The cells of every rectangle, glued along the segments, collapsed segments and rectangles
// joining their vertices.
AssemblyFailure assembleCells(const MotorcycleLayout& layout, LayoutTMesh& grid) {
  const auto& segments = layout.segments();
  const auto& rectangles = layout.rectangles();
  const auto& nodes = layout.nodes();
  // Vertex ids: nodes, then inner points of segments, then inner points of rectangles.
  std::vector<int> segmentBase(segments.size());
  int next = int(nodes.size());
  for (std::size_t e = 0; e < segments.size(); ++e) {
    segmentBase[e] = next;
    next += std::max(0, grid.segmentCells[e] - 1);
  }
  const auto sideCells = [&](const std::vector<int>& side) {
    int cells = 0;
    for (int he : side) cells += grid.segmentCells[std::size_t(he / 2)];
    return cells;
  };
  grid.rectangleCells.clear();
  grid.maxAnisotropy = 1.0;
  std::vector<std::pair<double, int>> anisotropyOfCells;  // (ratio, cells) per rectangle
  grid.collapsedRectangles = 0;
  std::vector<int> innerBase(rectangles.size(), -1);
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    const LayoutRectangle& rect = rectangles[r];
    const int cellsX = sideCells(rect.sides[0]), cellsY = sideCells(rect.sides[1]);
    grid.rectangleCells.push_back({cellsX, cellsY});
    if (cellsX == 0 || cellsY == 0) {
      ++grid.collapsedRectangles;
      continue;
    }
    const double sx = cellsX / rect.width(), sy = cellsY / rect.height();
    const double anisotropy = std::max(sx / sy, sy / sx);
    grid.maxAnisotropy = std::max(grid.maxAnisotropy, anisotropy);
    anisotropyOfCells.emplace_back(anisotropy, cellsX * cellsY);
    innerBase[r] = next;
    next += (cellsX - 1) * (cellsY - 1);
  }
  grid.anisotropyP99 = cellPercentile(anisotropyOfCells, 0.99);
  // The vertex at `offset` cells along side k of rectangle r, from its first corner.
  const auto onSide = [&](std::size_t r, int k, int offset) {
    const LayoutRectangle& rect = rectangles[r];
    for (int he : rect.sides[std::size_t(k)]) {
      const int cells = grid.segmentCells[std::size_t(he / 2)];
      const auto& segment = segments[std::size_t(he / 2)];
      if (offset == 0) return he % 2 == 0 ? segment.from : segment.to;
      if (offset < cells)
        return segmentBase[std::size_t(he / 2)] + (he % 2 == 0 ? offset : cells - offset) - 1;
      offset -= cells;
    }
    // The far corner: the first node of the next side.
    const int he = rect.sides[std::size_t((k + 1) % 4)].front();
    const auto& segment = segments[std::size_t(he / 2)];
    return he % 2 == 0 ? segment.from : segment.to;
  };
  VertexClasses classes(next);
  Joins joins(next);
  const auto join = [&](int a, int b, int undo) {
    classes.join(a, b);
    joins.add(a, b, undo);
  };
  grid.collapsedSegments = 0;
  for (std::size_t e = 0; e < segments.size(); ++e)
    if (grid.segmentCells[e] == 0) {
      ++grid.collapsedSegments;
      joins.undoneBy.push_back({int(e)});
      join(segments[e].from, segments[e].to, int(joins.undoneBy.size()) - 1);
    }
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    const auto [cellsX, cellsY] = grid.rectangleCells[r];
    if (cellsX != 0 && cellsY != 0) continue;
    // A cell across it (along x when it has none along x) undoes the glue.
    std::vector<int> across;
    for (int he : rectangles[r].sides[cellsX == 0 ? 0 : 1]) across.push_back(he / 2);
    joins.undoneBy.push_back(across);
    const int undo = int(joins.undoneBy.size()) - 1;
    if (cellsX == 0)
      for (int j = 0; j <= cellsY; ++j) join(onSide(r, 1, j), onSide(r, 3, cellsY - j), undo);
    else
      for (int i = 0; i <= cellsX; ++i) join(onSide(r, 0, i), onSide(r, 2, cellsX - i), undo);
  }
  AssemblyFailure failure;
  // Two cones joined would change the layout's structure: the chain that joined them may not
  // collapse again.
  std::vector<int> coneOfClass(std::size_t(next), -1);
  for (std::size_t v = 0; v < nodes.size(); ++v) {
    if (nodes[v].vertex < 0) continue;
    int& cone = coneOfClass[std::size_t(classes.find(int(v)))];
    if (cone >= 0) failure.separations.push_back({joins.separating(cone, int(v)), 1});
    cone = int(v);
  }
  if (!failure.separations.empty()) return failure;
  std::vector<TMeshFace> faces;
  grid.firstCell.assign(rectangles.size(), -1);
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    const auto [cellsX, cellsY] = grid.rectangleCells[r];
    if (innerBase[r] < 0) continue;
    const auto vertexAt = [&, cellsX = cellsX, cellsY = cellsY](int i, int j) {
      if (j == 0) return onSide(r, 0, i);
      if (i == cellsX) return onSide(r, 1, j);
      if (j == cellsY) return onSide(r, 2, cellsX - i);
      if (i == 0) return onSide(r, 3, cellsY - j);
      return innerBase[r] + (j - 1) * (cellsX - 1) + (i - 1);
    };
    grid.firstCell[r] = int(faces.size());
    for (int j = 0; j < cellsY; ++j)
      for (int i = 0; i < cellsX; ++i) {
        TMeshFace face;
        face.vertices = {classes.find(vertexAt(i, j)), classes.find(vertexAt(i + 1, j)),
                         classes.find(vertexAt(i + 1, j + 1)), classes.find(vertexAt(i, j + 1))};
        face.positions = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
        // A vertex repeated in a cell: the chain of joins that made it so may not collapse again;
        // without one, the rectangle needs more cells along the directions in which the two
        // corners differ (one more in all: the cheapest way is the quantization's to choose).
        for (int a = 0; a < 4; ++a)
          for (int b = a + 1; b < 4; ++b)
            if (face.vertices[std::size_t(a)] == face.vertices[std::size_t(b)]) {
              const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
              std::vector<int> chain =
                  joins.separating(vertexAt(i + corner[a][0], j + corner[a][1]),
                                   vertexAt(i + corner[b][0], j + corner[b][1]));
              if (!chain.empty()) {
                failure.separations.push_back({std::move(chain), 1});
                return failure;
              }
              SegmentSum wider;
              for (int axis = 0; axis < 2; ++axis)
                if (corner[a][axis] != corner[b][axis]) {
                  for (int he : rectangles[r].sides[std::size_t(axis)])
                    wider.segments.push_back(he / 2);
                  wider.atLeast += axis == 0 ? cellsX : cellsY;
                }
              failure.separations.push_back(std::move(wider));
              return failure;
            }
        faces.push_back(std::move(face));
      }
  }
  // Compact ids: the classes' roots in order.
  std::vector<int> id(std::size_t(next), -1);
  int count = 0;
  for (int v = 0; v < next; ++v)
    if (classes.find(v) == v) id[std::size_t(v)] = count++;
  for (TMeshFace& face : faces)
    for (int& v : face.vertices) v = id[std::size_t(v)];
  try {
    grid.mesh = buildTMesh(count, std::move(faces));
  } catch (const structure::InputError& error) {
    if (grid.collapsedSegments > 0) {
      for (std::size_t e = 0; e < segments.size(); ++e)
        if (grid.segmentCells[e] == 0) failure.uncollapse.push_back(int(e));
      return failure;
    }
    throw structure::SolverError(std::string("layout T-mesh: the grid does not close up: ") +
                                 error.what());
  }
  grid.collapsedSteps.assign(rectangles.size(), {});
  if (grid.collapsedRectangles == 0) return failure;
  // Where the points of collapsed rectangles go: the cell sides of the side they kept.
  std::map<std::pair<int, int>, FacePoint> edgeStart;
  std::vector<FacePoint> atVertex(static_cast<std::size_t>(count));
  for (int f = 0; f < grid.mesh.numFaces(); ++f) {
    const TMeshFace& face = grid.mesh.faces[std::size_t(f)];
    for (std::size_t k = 0; k < 4; ++k) {
      edgeStart[{face.vertices[k], face.vertices[(k + 1) % 4]}] = {f, face.positions[k]};
      atVertex[std::size_t(face.vertices[k])] = {f, face.positions[k]};
    }
  }
  const auto step = [&](int from, int to) -> std::array<FacePoint, 2> {
    from = id[std::size_t(classes.find(from))];
    to = id[std::size_t(classes.find(to))];
    const auto endOf = [&](const FacePoint& start, int vertex) {
      const TMeshFace& face = grid.mesh.faces[std::size_t(start.face)];
      const auto k = std::size_t(std::find(face.vertices.begin(), face.vertices.end(), vertex) -
                                 face.vertices.begin());
      return FacePoint{start.face, face.positions[(k + 1) % 4]};
    };
    if (const auto it = edgeStart.find({from, to}); it != edgeStart.end())
      return {it->second, endOf(it->second, from)};
    if (const auto it = edgeStart.find({to, from}); it != edgeStart.end())
      return {endOf(it->second, to), it->second};
    // Both neighbours across collapsed too: the points of the step share its start.
    return {atVertex[std::size_t(from)], atVertex[std::size_t(from)]};
  };
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    const auto [cellsX, cellsY] = grid.rectangleCells[r];
    auto& steps = grid.collapsedSteps[r];
    if (cellsX == 0 && cellsY == 0) {
      const FacePoint point = atVertex[std::size_t(id[std::size_t(classes.find(onSide(r, 0, 0)))])];
      steps.push_back({point, point});
    } else if (cellsX == 0) {
      for (int j = 0; j < cellsY; ++j) steps.push_back(step(onSide(r, 1, j), onSide(r, 1, j + 1)));
    } else if (cellsY == 0) {
      for (int i = 0; i < cellsX; ++i) steps.push_back(step(onSide(r, 0, i), onSide(r, 0, i + 1)));
    }
  }
  return failure;
}

}  // namespace

LayoutTMesh layoutTMesh(const MotorcycleLayout& layout, const LayoutTMeshOptions& options) {
  const auto& segments = layout.segments();
  const auto& rectangles = layout.rectangles();
  if (!(options.cellSize > 0.0))
    throw structure::InputError("layout T-mesh: cell size must be positive");
  if (!(options.collapseBelow >= 0.0 && options.collapseBelow < 1.0))
    throw structure::InputError("layout T-mesh: the collapse threshold must be in [0, 1) cells");
  const std::size_t n = segments.size();
  // A segment from a node back to itself needs two cells, or its cells would repeat the node;
  // other segments need one, or none when shorter than collapseBelow cells and their collapse
  // holds.
  std::vector<int> required(n, 1);
  std::vector<char> collapsible(n, 1);
  for (std::size_t e = 0; e < n; ++e)
    if (segments[e].from == segments[e].to) {
      required[e] = 2;
      collapsible[e] = 0;
    }
  LayoutTMesh grid;
  grid.cellSize = options.cellSize;
  grid.quantizationOptimal = true;
  QuantizeOptions quantize;
  quantize.cellSize = options.cellSize;
  quantize.minimumCells.resize(n);
  for (int attempt = 0; attempt < 64; ++attempt) {
    for (std::size_t e = 0; e < n; ++e)
      quantize.minimumCells[e] =
          collapsible[e] && segments[e].length() < options.collapseBelow * options.cellSize
              ? 0
              : required[e];
    const Quantization quantization = quantizeSegments(layout, quantize);
    ++grid.quantizations;
    grid.quantizationSeconds += quantization.seconds;
    grid.quantizationOptimal = grid.quantizationOptimal && quantization.optimal;
    grid.segmentCells = quantization.segmentCells;
    grid.maxRoundingError = quantization.maxRoundingError;
    const AssemblyFailure failure = assembleCells(layout, grid);
    if (!failure.failed()) return grid;
    for (const auto& separation : failure.separations) quantize.separations.push_back(separation);
    // Undoing every collapse gives slivers a whole cell across (man's cells 368 times longer than
    // wide): the collapses of segments longer than a sliver go first.
    const auto longerThanSliver = [&](int e) {
      return segments[std::size_t(e)].length() >= kSliver * options.cellSize;
    };
    const bool anyLonger =
        std::any_of(failure.uncollapse.begin(), failure.uncollapse.end(), longerThanSliver);
    for (int e : failure.uncollapse)
      if (!anyLonger || longerThanSliver(e)) collapsible[std::size_t(e)] = 0;
  }
  throw structure::SolverError("layout T-mesh: no valid grid after " +
                               std::to_string(grid.quantizations) + " quantizations");
}

FacePoint layoutPoint(const MotorcycleLayout& layout, const LayoutTMesh& grid,
                      const structure::RectanglePoint& point) {
  const LayoutRectangle& rect = layout.rectangles().at(std::size_t(point.rectangle));
  const auto [cellsX, cellsY] = grid.rectangleCells[std::size_t(point.rectangle)];
  std::array<SideScale, 4> sides;
  for (int k = 0; k < 4; ++k)
    sides[std::size_t(k)] = sideScale(layout, grid.segmentCells, rect.sides[std::size_t(k)]);
  const double w = rect.width(), h = rect.height();
  const double x = point.position.x(), y = point.position.y();
  const double fy = h > 0.0 ? std::clamp(y / h, 0.0, 1.0) : 0.5;
  const double fx = w > 0.0 ? std::clamp(x / w, 0.0, 1.0) : 0.5;
  const double gridX = (1.0 - fy) * sides[0].map(fx * sides[0].flat.back()) +
                       fy * (cellsX - sides[2].map((1.0 - fx) * sides[2].flat.back()));
  const double gridY = (1.0 - fx) * (cellsY - sides[3].map((1.0 - fy) * sides[3].flat.back())) +
                       fx * sides[1].map(fy * sides[1].flat.back());
  const int first = grid.firstCell[std::size_t(point.rectangle)];
  if (first < 0) {
    // Collapsed: along the side it kept.
    const auto& steps = grid.collapsedSteps[std::size_t(point.rectangle)];
    const double along = cellsX == 0 ? gridY : gridX;
    const int k = std::clamp(int(std::floor(along)), 0, int(steps.size()) - 1);
    const double t = std::clamp(along - k, 0.0, 1.0);
    const auto& [start, end] = steps[std::size_t(k)];
    return {start.face, (1.0 - t) * start.position + t * end.position};
  }
  const int i = std::clamp(int(std::floor(gridX)), 0, cellsX - 1);
  const int j = std::clamp(int(std::floor(gridY)), 0, cellsY - 1);
  return {first + j * cellsX + i,
          Eigen::Vector2d(std::clamp(gridX - i, 0.0, 1.0), std::clamp(gridY - j, 0.0, 1.0))};
}

}  // namespace mspline::spline
