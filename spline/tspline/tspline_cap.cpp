#include "mspline/spline/tspline/tspline_cap.h"

#include <algorithm>
#include <cmath>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"

namespace mspline::spline {

namespace {

constexpr int kMaxValence = 64;

// Uniform cubic B-spline to Bezier: row i gives b_i from the B-spline coefficients P_{-1..2}.
constexpr double kToBezier[4][4] = {{1.0 / 6, 4.0 / 6, 1.0 / 6, 0.0},
                                    {0.0, 4.0 / 6, 2.0 / 6, 0.0},
                                    {0.0, 2.0 / 6, 4.0 / 6, 0.0},
                                    {0.0, 1.0 / 6, 4.0 / 6, 1.0 / 6}};

// The motion of face f's frame into the sector frame of its corner `corner` (4 boundary vertices).
QuarterMotion toSector(const TMeshFace& face, int corner) {
  QuarterMotion m{(4 - corner) & 3, Eigen::Vector2d::Zero()};
  m.translation = -m.rotate(face.positions[std::size_t(corner)]);
  return m;
}

// 16 Bezier coefficients (sector-frame index 4 j + i), each an affine combination of vertices.
class CoefficientGrid {
 public:
  void add(int coefficient, int vertex, double weight) {
    if (weight == 0.0) return;
    auto at = std::find(vertices_.begin(), vertices_.end(), vertex);
    if (at == vertices_.end()) {
      vertices_.push_back(vertex);
      weights_.emplace_back();
      weights_.back().fill(0.0);
      at = vertices_.end() - 1;
    }
    weights_[std::size_t(at - vertices_.begin())][std::size_t(coefficient)] += weight;
  }
  const std::vector<int>& vertices() const { return vertices_; }
  double weight(std::size_t column, int coefficient) const {
    return weights_[column][std::size_t(coefficient)];
  }

 private:
  std::vector<int> vertices_;
  std::vector<std::array<double, 16>> weights_;
};

}  // namespace

void cubicBernstein(double u, double b[4], double* d1, double* d2) {
  const double v = 1.0 - u;
  b[0] = v * v * v;
  b[1] = 3.0 * u * v * v;
  b[2] = 3.0 * u * u * v;
  b[3] = u * u * u;
  if (d1) {
    d1[0] = -3.0 * v * v;
    d1[1] = 3.0 * v * v - 6.0 * u * v;
    d1[2] = 6.0 * u * v - 3.0 * u * u;
    d1[3] = 3.0 * u * u;
  }
  if (d2) {
    d2[0] = 6.0 * v;
    d2[1] = 18.0 * u - 12.0;
    d2[2] = 6.0 - 18.0 * u;
    d2[3] = 6.0 * u;
  }
}

int TSplineCapRegion::vertexAt(int sector, int i, int j) const {
  const int n = valence;
  if (j < 0) return vertexAt((sector + n - 1) % n, -j, i);
  if (i < 0) return vertexAt((sector + 1) % n, j, -i);
  return vertices[std::size_t(sector)][std::size_t((kCapCells + 1) * j + i)];
}

std::string findCapRegion(const TMesh& mesh, int vertex, TSplineCapRegion& region,
                          FaceDeveloper& developer) {
  region = TSplineCapRegion{};
  region.vertex = vertex;
  double scale = 1.0;
  for (const auto& f : mesh.faces) scale = std::max({scale, f.width, f.height});
  const double tolerance = 1e-9 * scale;
  // Sector 0: a face with the vertex at one of its 4 corners.
  int face = -1, corner = -1;
  for (int f = 0; f < mesh.numFaces() && face < 0; ++f) {
    const TMeshFace& candidate = mesh.faces[std::size_t(f)];
    for (std::size_t k = 0; k < candidate.vertices.size(); ++k)
      if (candidate.vertices[k] == vertex) {
        if (candidate.vertices.size() != 4)
          return "face " + std::to_string(f) + " around it has T-junctions";
        face = f;
        corner = int(k);
      }
  }
  if (face < 0) return "it is on no face";
  // Around the vertex: F_{k+1} lies across edge corner - 1 of F_k, where the vertex starts the
  // twin.
  std::vector<std::pair<int, int>> sectors;
  for (int f = face, c = corner;;) {
    sectors.emplace_back(f, c);
    const TMeshFace& current = mesh.faces[std::size_t(f)];
    const std::size_t edge = std::size_t((c + 3) % 4);
    const int next = current.twinFace[edge];
    if (next < 0) return "it lies on the boundary";
    c = current.twinEdge[edge];
    f = next;
    if (mesh.faces[std::size_t(f)].vertices.size() != 4)
      return "face " + std::to_string(f) + " around it has T-junctions";
    if (f == face && c == corner) break;
    if (int(sectors.size()) >= kMaxValence)
      return "its valence exceeds " + std::to_string(kMaxValence);
  }
  const int n = int(sectors.size());
  if (n < 2) return "valence 1";
  region.valence = n;
  region.cellSize = mesh.faces[std::size_t(face)].width;
  const double d = region.cellSize;
  region.cells.resize(std::size_t(n));
  region.vertices.resize(std::size_t(n));
  std::vector<int> allFaces;
  std::vector<DevelopedFace> developed;
  for (int k = 0; k < n; ++k) {
    const auto [f, c] = sectors[std::size_t(k)];
    const TMeshFace& first = mesh.faces[std::size_t(f)];
    if (std::abs(first.width - d) > tolerance || std::abs(first.height - d) > tolerance)
      return "its faces are not squares of one size";
    developed = developer.develop(f, toSector(first, c), Eigen::Vector2d::Zero(),
                                  Eigen::Vector2d::Constant(kCapCells * d), true);
    std::array<bool, kCapCells * kCapCells> filled{};
    auto& vertices = region.vertices[std::size_t(k)];
    vertices.fill(-1);
    for (const DevelopedFace& cell : developed) {
      const TMeshFace& cf = mesh.faces[std::size_t(cell.face)];
      const Eigen::Vector2d a = cell.toChart.apply({0.0, 0.0}),
                            b = cell.toChart.apply({cf.width, cf.height});
      const Eigen::Vector2d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
      const Eigen::Vector2d index = lo / d;
      const int ia = int(std::lround(index.x())), ib = int(std::lround(index.y()));
      if (cf.vertices.size() != 4 || (lo - d * Eigen::Vector2d(ia, ib)).norm() > tolerance ||
          (hi - lo - Eigen::Vector2d::Constant(d)).norm() > tolerance || ia < 0 || ib < 0 ||
          ia >= kCapCells || ib >= kCapCells)
        return "face " + std::to_string(cell.face) +
               " near it is not a square cell of the grid around it (T-junctions or another size)";
      if (filled[std::size_t(kCapCells * ib + ia)]) return "the cells around it overlap";
      filled[std::size_t(kCapCells * ib + ia)] = true;
      region.cells[std::size_t(k)][std::size_t(kCapCells * ib + ia)] = cell;
      allFaces.push_back(cell.face);
      for (std::size_t m = 0; m < 4; ++m) {
        const Eigen::Vector2d p = cell.toChart.apply(cf.positions[m]) / d;
        int& at = vertices[std::size_t((kCapCells + 1) * std::lround(p.y()) + std::lround(p.x()))];
        if (at >= 0 && at != cf.vertices[m]) return "the grid around it is not a simple one";
        at = cf.vertices[m];
      }
    }
    if (!std::all_of(filled.begin(), filled.end(), [](bool b) { return b; }))
      return "the grid around it has too few cells (a boundary or a gap)";
    if (vertices[0] != vertex) return "the grid around it is not a simple one";
    for (std::size_t m = 1; m < vertices.size(); ++m) {
      const int u = vertices[m];
      if (mesh.onBoundary[std::size_t(u)])
        return "the boundary is within " + std::to_string(kCapCells) + " cells of it";
      if (mesh.quarterTurnsAround[std::size_t(u)] != 4)
        return "extraordinary vertex " + std::to_string(u) + " is within " +
               std::to_string(kCapCells) + " cells of it";
    }
  }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j <= kCapCells; ++j)
      if (region.vertices[std::size_t(k)][std::size_t((kCapCells + 1) * j)] !=
          region.vertices[std::size_t((k + 1) % n)][std::size_t(j)])
        return "its sectors do not glue into one grid";
  std::sort(allFaces.begin(), allFaces.end());
  if (std::adjacent_find(allFaces.begin(), allFaces.end()) != allFaces.end())
    return "the grid around it wraps onto itself";
  return "";
}

std::vector<TSplineCapRegion> capRegions(const TMesh& mesh) {
  std::vector<TSplineCapRegion> regions;
  FaceDeveloper developer(mesh);
  for (int v = 0; v < mesh.numVertices; ++v) {
    if (!mesh.isExtraordinary(v)) continue;
    TSplineCapRegion region;
    const std::string failure = findCapRegion(mesh, v, region, developer);
    if (!failure.empty())
      throw structure::SolverError("T-spline: no cap at extraordinary vertex " + std::to_string(v) +
                                   ": " + failure);
    regions.push_back(std::move(region));
  }
  return regions;
}

namespace {

// Adds weight times the uniform B-spline's Bezier coefficient (i, j) of sector k (never (0, 0),
// which would need the missing P_{-1,-1}) to coefficient `coefficient` of the grid.
void addNatural(CoefficientGrid& grid, const TSplineCapRegion& region, int coefficient, int k,
                int i, int j, double weight) {
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a)
      grid.add(coefficient, region.vertexAt(k, a - 1, b - 1),
               weight * kToBezier[i][a] * kToBezier[j][b]);
}

}  // namespace

TSplineCapPatch capPatch(const TSplineCapRegion& region, int sector) {
  const int n = region.valence;
  const int next = (sector + 1) % n;
  // The corner coefficients the cap replaces: b_00, b_10, b_01, and for valence 2 also b_20, b_11,
  // b_02.
  const auto replaced = [n](int i, int j) { return i + j <= (n == 2 ? 2 : 1); };
  CoefficientGrid grid;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      if (!replaced(i, j)) addNatural(grid, region, 4 * j + i, sector, i, j, 1.0);
  // The limit point L.
  const double norm = 1.0 / (double(n) * (n + 5));
  const auto addLimitPoint = [&](int coefficient, double weight) {
    grid.add(coefficient, region.vertex, weight * n * n * norm);
    for (int k = 0; k < n; ++k) {
      grid.add(coefficient, region.vertexAt(k, 1, 0), weight * 4.0 * norm);
      grid.add(coefficient, region.vertexAt(k, 1, 1), weight * norm);
    }
  };
  addLimitPoint(0, 1.0);
  if (n == 2) {
    // Two quadrants make a half-plane: the characteristic map is z^2, so the first derivatives
    // vanish at the cone (b_10 = b_01 = L) and the second-order coefficients are projected onto
    // L + Re/Im (A (x + iy)^2)-like terms: b_20 - L = -(b_02 - L) = (N_20 - N_02) / 2 and
    // b_11 - L = (N_11 - N'_11) / 2 (N natural, N' of the other sector), which gives every
    // point near the cone the normal A x B.
    addLimitPoint(1, 1.0);
    addLimitPoint(4, 1.0);
    for (const auto& [coefficient, sign] : {std::pair{2, 1.0}, std::pair{8, -1.0}}) {
      addLimitPoint(coefficient, 1.0);
      addNatural(grid, region, coefficient, sector, 2, 0, 0.5 * sign);
      addNatural(grid, region, coefficient, sector, 0, 2, -0.5 * sign);
    }
    addLimitPoint(5, 1.0);
    addNatural(grid, region, 5, sector, 1, 1, 0.5);
    addNatural(grid, region, 5, next, 1, 1, -0.5);
  } else {
    // b_10 = E'_k and b_01 = E'_{k+1}: L + (2/n) sum_j cos(2 pi (j - k) / n) (E_j - L), E_j the
    // natural b_10 of sector j.
    const auto addEdgeCoefficient = [&](int coefficient, int k) {
      double cosines = 0.0;
      for (int j = 0; j < n; ++j) {
        const double c = 2.0 / n * std::cos(2.0 * kPi * (j - k) / n);
        cosines += c;
        addNatural(grid, region, coefficient, j, 1, 0, c);
      }
      addLimitPoint(coefficient, 1.0 - cosines);
    };
    addEdgeCoefficient(1, sector);
    addEdgeCoefficient(4, next);
  }
  // Sector-frame coefficient (i, j) sits at (i, j) d / 3; the face frame's index is where that
  // point lies in the face.
  const DevelopedFace& corner = region.cells[std::size_t(sector)][0];
  const QuarterMotion back = corner.toChart.inverse();
  TSplineCapPatch patch;
  patch.face = corner.face;
  patch.vertices = grid.vertices();
  patch.coefficients.setZero(16, Eigen::Index(patch.vertices.size()));
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d p =
          back.apply(Eigen::Vector2d(i, j) * region.cellSize / 3.0) * 3.0 / region.cellSize;
      const Eigen::Index row = 4 * std::lround(p.y()) + std::lround(p.x());
      for (std::size_t c = 0; c < patch.vertices.size(); ++c)
        patch.coefficients(row, Eigen::Index(c)) = grid.weight(c, 4 * j + i);
    }
  return patch;
}

void fillByRingAverages(const TMesh& mesh, Eigen::MatrixXd& points, std::vector<char> placed,
                        const std::string& context) {
  std::vector<std::vector<int>> neighbours(std::size_t(mesh.numVertices));
  for (const TMeshFace& face : mesh.faces)
    for (std::size_t k = 0; k < face.vertices.size(); ++k) {
      // An interior edge is met from both faces: duplicates are removed below.
      const int a = face.vertices[k], b = face.vertices[(k + 1) % face.vertices.size()];
      neighbours[std::size_t(a)].push_back(b);
      neighbours[std::size_t(b)].push_back(a);
    }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<int> pending;
  for (int v = 0; v < mesh.numVertices; ++v)
    if (!placed[std::size_t(v)]) pending.push_back(v);
  // Rings outwards from the placed vertices: each ring averages only earlier rings.
  while (!pending.empty()) {
    std::vector<std::pair<int, Eigen::RowVectorXd>> ring;
    std::vector<int> rest;
    for (int v : pending) {
      Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(points.cols());
      int count = 0;
      for (int u : neighbours[std::size_t(v)])
        if (placed[std::size_t(u)]) sum += points.row(u), ++count;
      if (count > 0)
        ring.emplace_back(v, sum / count);
      else
        rest.push_back(v);
    }
    if (ring.empty())
      throw structure::InputError(context + ": T-mesh vertex " + std::to_string(rest.front()) +
                                  " has no anchored vertex in its component");
    for (const auto& [v, point] : ring) {
      points.row(v) = point;
      placed[std::size_t(v)] = 1;
    }
    pending = std::move(rest);
  }
}

}  // namespace mspline::spline
