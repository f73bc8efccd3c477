#include "support/test_tmeshes.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <map>

#include "mspline/structure/core/constants.h"

namespace mspline::test {

std::vector<double> unitKnots(int n) {
  std::vector<double> values;
  for (int i = 0; i <= n; ++i) values.push_back(i);
  return values;
}

spline::TMesh gridWithMerges(int n, const std::vector<std::array<int, 4>>& merged) {
  std::vector<std::array<int, 4>> rectangles = merged;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool covered = std::any_of(merged.begin(), merged.end(), [&](const auto& r) {
        return i >= r[0] && i < r[2] && j >= r[1] && j < r[3];
      });
      if (!covered) rectangles.push_back({i, j, i + 1, j + 1});
    }
  Eigen::MatrixX2d lo(rectangles.size(), 2), hi(rectangles.size(), 2);
  for (std::size_t r = 0; r < rectangles.size(); ++r) {
    lo.row(Eigen::Index(r)) << rectangles[r][0], rectangles[r][1];
    hi.row(Eigen::Index(r)) << rectangles[r][2], rectangles[r][3];
  }
  return spline::planarTMesh(lo, hi);
}

spline::TMesh mergedBlock() {
  return gridWithMerges(6, {{2, 2, 4, 4}});
}

spline::TMesh stoppedLine() {
  return gridWithMerges(8, {{3, 4, 5, 5}, {3, 5, 5, 6}, {3, 6, 5, 7}, {3, 7, 5, 8}});
}

CubeTMesh cubeTMesh(int k, unsigned seed) {
  std::map<std::array<int, 3>, int> id;
  std::vector<std::array<int, 3>> lattice;
  const auto vertex = [&](const std::array<int, 3>& p) {
    const auto [at, inserted] = id.emplace(p, static_cast<int>(lattice.size()));
    if (inserted) lattice.push_back(p);
    return at->second;
  };
  std::vector<spline::TMeshFace> faces;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // e1 x e2 is the outward normal: +e_axis on side 1, -e_axis on side 0.
      const int a1 = (axis + (side ? 1 : 2)) % 3, a2 = (axis + (side ? 2 : 1)) % 3;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const auto at = [&](int di, int dj) {
            std::array<int, 3> p{};
            p[axis] = side * k;
            p[a1] = i + di;
            p[a2] = j + dj;
            return vertex(p);
          };
          spline::TMeshFace face;
          face.vertices = {at(0, 0), at(1, 0), at(1, 1), at(0, 1)};
          face.positions = {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
          faces.push_back(face);
        }
    }
  CubeTMesh cube;
  cube.mesh = spline::buildTMesh(static_cast<int>(lattice.size()), std::move(faces));
  cube.latticePoints.resize(static_cast<Eigen::Index>(lattice.size()), 3);
  for (std::size_t v = 0; v < lattice.size(); ++v)
    for (int c = 0; c < 3; ++c)
      cube.latticePoints(Eigen::Index(v), c) = 2.0 * lattice[v][c] / k - 1.0;
  cube.vertexPoints =
      cube.latticePoints + randomPoints(static_cast<int>(lattice.size()), seed) * 0.02;
  return cube;
}

std::vector<Eigen::Vector2d> faceOrigins(const spline::TMesh& mesh, const Eigen::Vector2d& first) {
  std::vector<Eigen::Vector2d> origin(mesh.faces.size(), first);
  std::vector<char> done(mesh.faces.size(), 0);
  std::vector<int> stack{0};
  done[0] = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (std::size_t k = 0; k < mesh.faces[f].vertices.size(); ++k) {
      const int g = mesh.faces[f].twinFace[k];
      if (g < 0 || done[std::size_t(g)]) continue;
      // A point x of f's frame is x + origin(f) globally and across(x) + origin(g).
      const spline::QuarterMotion across = mesh.acrossEdge(f, int(k));
      if (across.quarterTurns != 0)
        FAIL("T-mesh faces " << f << " and " << g << " have turned frames: not a planar T-mesh");
      origin[std::size_t(g)] = origin[std::size_t(f)] - across.translation;
      done[std::size_t(g)] = 1;
      stack.push_back(g);
    }
  }
  return origin;
}

std::vector<Eigen::Vector2d> planarVertices(const spline::TMesh& mesh) {
  const std::vector<Eigen::Vector2d> origin = faceOrigins(mesh);
  std::vector<Eigen::Vector2d> vertex(std::size_t(mesh.numVertices), Eigen::Vector2d::Zero());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (std::size_t k = 0; k < mesh.faces[f].vertices.size(); ++k)
      vertex[std::size_t(mesh.faces[f].vertices[k])] = origin[f] + mesh.faces[f].positions[k];
  return vertex;
}

int vertexAt(const spline::TMesh& mesh, const std::vector<Eigen::Vector2d>& origin,
             const Eigen::Vector2d& p) {
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (std::size_t k = 0; k < mesh.faces[f].vertices.size(); ++k)
      if ((origin[std::size_t(f)] + mesh.faces[f].positions[k] - p).norm() < 1e-12)
        return mesh.faces[f].vertices[k];
  return -1;
}

Eigen::Vector2d randomPointIn(const spline::TMeshFace& face, std::mt19937& rng, double lo,
                              double hi) {
  std::uniform_real_distribution<double> unit(lo, hi);
  return {unit(rng) * face.width, unit(rng) * face.height};
}

Eigen::MatrixXd randomPoints(int rows, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::MatrixXd points(rows, 3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 3; ++c) points(r, c) = unit(rng);
  return points;
}

Eigen::MatrixXd randomPoints(int rows, unsigned seed) {
  std::mt19937 rng(seed);
  return randomPoints(rows, rng);
}

Eigen::VectorXd randomWeights(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  Eigen::VectorXd weights(n);
  for (int i = 0; i < n; ++i) weights[i] = weight(rng);
  return weights;
}

Eigen::VectorXd randomWeights(int n, unsigned seed) {
  std::mt19937 rng(seed);
  return randomWeights(n, rng);
}

Eigen::MatrixXd anchorControl(const spline::TSplineSpace& space,
                              const Eigen::MatrixXd& vertexPoints) {
  Eigen::MatrixXd control(space.numBasis(), 3);
  for (int a = 0; a < space.numBasis(); ++a)
    control.row(a) = vertexPoints.row(space.anchors()[a].vertex);
  return control;
}

int StarTMesh::id(int k, int i, int j) const {
  if (i == 0 && j == 0) return 0;
  if (i == 0) return id((k + 1) % n, j, 0);
  return 1 + k * kSide * (kSide + 1) + j * kSide + (i - 1);
}

StarTMesh starTMesh(int n) {
  constexpr int kSide = StarTMesh::kSide;
  StarTMesh star;
  star.n = n;
  std::vector<spline::TMeshFace> faces;
  for (int k = 0; k < n; ++k)
    for (int b = 0; b < kSide; ++b)
      for (int a = 0; a < kSide; ++a) {
        spline::TMeshFace face;
        const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (const auto& c : corner) {
          face.vertices.push_back(star.id(k, a + c[0], b + c[1]));
          face.positions.emplace_back(c[0], c[1]);
        }
        faces.push_back(face);
      }
  const int numVertices = 1 + n * kSide * (kSide + 1);
  star.where.assign(std::size_t(numVertices), {0, 0, 0});
  for (int k = 0; k < n; ++k)
    for (int j = 0; j <= kSide; ++j)
      for (int i = 1; i <= kSide; ++i) star.where[std::size_t(star.id(k, i, j))] = {k, i, j};
  star.mesh = spline::buildTMesh(numVertices, faces);
  return star;
}

Eigen::MatrixXd starControl(const StarTMesh& star, const spline::TSplineSpace& space, double h) {
  const auto smooth = [](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(p.x(), p.y(),
                           0.4 * p.x() * p.x() - 0.3 * p.x() * p.y() + 0.6 * p.y() * p.y() +
                               0.2 * std::pow(p.x(), 3));
  };
  Eigen::MatrixXd control(space.numBasis(), 3);
  for (int a = 0; a < space.numBasis(); ++a) {
    const auto [k, i, j] = star.where[std::size_t(space.anchors()[std::size_t(a)].vertex)];
    const std::complex<double> z(i, j);
    const double angle =
        (i == 0 && j == 0 ? 0.0 : std::arg(z)) * 4.0 / star.n + 2.0 * kPi * k / star.n;
    const std::complex<double> w = h * std::abs(z) * std::polar(1.0, angle);
    control.row(a) = smooth({w.real(), w.imag()}).transpose();
  }
  return control;
}

}  // namespace mspline::test
