#include "support/test_meshes.h"

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/subdivide.h"

namespace mspline::test {

namespace {

using Point = TriMesh::Point;
using VH = TriMesh::VertexHandle;

void requireAtLeast(int value, int minimum, const char* what) {
  if (value < minimum)
    throw structure::InputError(std::string(what) + " must be at least " + std::to_string(minimum) +
                                ", got " + std::to_string(value));
}

void addFace(TriMesh& mesh, VH a, VH b, VH c) {
  MSPLINE_ASSERT(mesh.add_face(a, b, c).is_valid(),
                 "test mesh generator produced a non-manifold face");
}

/// Splits the quad a b c d (counter-clockwise) along the diagonal a-c.
void addQuad(TriMesh& mesh, VH a, VH b, VH c, VH d) {
  addFace(mesh, a, b, c);
  addFace(mesh, a, c, d);
}

/// A 2D region made of unit "blocks" of resolution x resolution cells: a (2 * holes + 1) x 3 block
/// rectangle with `holes` one-block square holes in its middle row, separated by one block of
/// material. Holes never touch each other or the outer border, so no two cells meet only at a
/// corner.
struct PlateRegion {
  int cellsX = 0, cellsY = 0;
  std::vector<char> filled;  // indexed x + cellsX * y

  PlateRegion(int holes, int resolution)
      : cellsX((2 * holes + 1) * resolution),
        cellsY(3 * resolution),
        filled(std::size_t(cellsX) * cellsY, 1) {
    for (int k = 0; k < holes; ++k)
      for (int y = resolution; y < 2 * resolution; ++y)
        for (int x = (2 * k + 1) * resolution; x < (2 * k + 2) * resolution; ++x)
          filled[index(x, y)] = 0;
  }
  std::size_t index(int x, int y) const { return std::size_t(x) + std::size_t(cellsX) * y; }
  bool isFilled(int x, int y) const {
    return x >= 0 && y >= 0 && x < cellsX && y < cellsY && filled[index(x, y)];
  }
};

/// Lattice-point -> vertex map on a (nx+1) x (ny+1) x (nz+1) grid, creating vertices on demand.
class LatticeVertices {
 public:
  LatticeVertices(TriMesh& mesh, int nx, int ny, int nz, double spacing)
      : mesh_(mesh),
        nx_(nx),
        ny_(ny),
        spacing_(spacing),
        ids_(std::size_t(nx + 1) * (ny + 1) * (nz + 1), -1) {}
  VH at(int x, int y, int z) {
    int& id =
        ids_[std::size_t(x) + std::size_t(nx_ + 1) * (std::size_t(y) + std::size_t(ny_ + 1) * z)];
    if (id < 0) id = mesh_.add_vertex(Point(x * spacing_, y * spacing_, z * spacing_)).idx();
    return VH(id);
  }

 private:
  TriMesh& mesh_;
  int nx_, ny_;
  double spacing_;
  std::vector<int> ids_;
};

/// Taubin smoothing (alternating shrink and inflate steps of the uniform Laplacian): rounds sharp
/// features without shrinking the shape overall. Boundary vertices stay fixed.
void taubinSmooth(TriMesh& mesh, int iterations) {
  std::vector<Point> next(mesh.n_vertices());
  for (int it = 0; it < 2 * iterations; ++it) {
    const double factor = (it % 2 == 0) ? 0.5 : -0.53;
    for (const auto v : mesh.vertices()) {
      Point sum(0, 0, 0);
      int count = 0;
      for (const auto w : mesh.vv_range(v)) {
        sum += mesh.point(w);
        ++count;
      }
      const Point& p = mesh.point(v);
      next[v.idx()] = (mesh.is_boundary(v) || count == 0) ? p : p + factor * (sum / count - p);
    }
    for (const auto v : mesh.vertices()) mesh.set_point(v, next[v.idx()]);
  }
}

void centre(TriMesh& mesh) {
  Point lo = mesh.point(VH(0)), hi = lo;
  for (const auto v : mesh.vertices()) {
    lo.minimize(mesh.point(v));
    hi.maximize(mesh.point(v));
  }
  const Point mid = 0.5 * (lo + hi);
  for (const auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v) - mid);
}

}  // namespace

TriMesh gridDisk(int n) {
  requireAtLeast(n, 1, "gridDisk: n");
  TriMesh mesh;
  mesh.reserve(std::size_t(n + 1) * (n + 1), 3 * std::size_t(n) * n + 2 * n,
               2 * std::size_t(n) * n);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) mesh.add_vertex(Point(double(i) / n, double(j) / n, 0));
  const auto at = [n](int i, int j) { return VH(i + (n + 1) * j); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      addQuad(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  return mesh;
}

TriMesh polygonFan(const std::vector<OpenMesh::Vec3d>& corners) {
  requireAtLeast(int(corners.size()), 3, "polygonFan: corners");
  TriMesh mesh;
  for (const auto& p : corners) mesh.add_vertex(p);
  for (int i = 1; i + 1 < int(corners.size()); ++i) mesh.add_face(VH(0), VH(i), VH(i + 1));
  return mesh;
}

// The annulus 0.5 <= r <= 1 with its rings lifted linearly to z = (r - 0.5) * 2: a truncated cone
// (open at both ends) whose normals point away from the axis. 2 * around * along faces.
TriMesh cylinder(int around, int along) {
  requireAtLeast(around, 3, "cylinder: around");
  requireAtLeast(along, 1, "cylinder: along");
  TriMesh mesh;
  for (int j = 0; j <= along; ++j) {
    const double t = double(j) / along;
    const double radius = 0.5 + 0.5 * t;
    for (int i = 0; i < around; ++i) {
      const double phi = 2 * kPi * i / around;
      mesh.add_vertex(Point(radius * std::cos(phi), radius * std::sin(phi), t));
    }
  }
  const auto at = [around](int i, int j) { return VH(i % around + around * j); };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i)
      addQuad(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  return mesh;
}

TriMesh cubeSurface(int m) {
  TriMesh mesh;
  std::map<std::array<int, 3>, TriMesh::VertexHandle> vertices;
  // Integer lattice points 0..2m per axis, corners first so that they are vertices 0 .. 7.
  const auto vertex = [&](std::array<int, 3> p) {
    auto [it, inserted] = vertices.try_emplace(p);
    if (inserted)
      it->second = mesh.add_vertex(
          TriMesh::Point(p[0] / double(m) - 1.0, p[1] / double(m) - 1.0, p[2] / double(m) - 1.0));
    return it->second;
  };
  for (int corner = 0; corner < 8; ++corner)
    vertex({corner & 1 ? 2 * m : 0, corner & 2 ? 2 * m : 0, corner & 4 ? 2 * m : 0});
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i < 2 * m; ++i)
        for (int j = 0; j < 2 * m; ++j) {
          std::array<std::array<int, 3>, 4> quad;
          for (int k = 0; k < 4; ++k) {
            quad[std::size_t(k)][std::size_t(axis)] = side * 2 * m;
            quad[std::size_t(k)][std::size_t(u)] = i + (k == 1 || k == 2);
            quad[std::size_t(k)][std::size_t(w)] = j + (k >= 2);
          }
          auto a = vertex(quad[0]), b = vertex(quad[1]), c = vertex(quad[2]), d = vertex(quad[3]);
          // Outward orientation: (u, w) is counter-clockwise seen from +axis.
          if (side == 0) std::swap(b, d);
          mesh.add_face(a, b, c);
          mesh.add_face(a, c, d);
        }
    }
  return mesh;
}

spline::SplineDomain flatTorusDomain(int n, double shear) {
  const auto vertex = [n](int i, int j) { return ((i + n) % n) + n * ((j + n) % n); };
  const auto lower = [n](int i, int j) { return 2 * (((i + n) % n) + n * ((j + n) % n)); };
  const auto upper = [&](int i, int j) { return lower(i, j) + 1; };
  const double bottom = 1.0, left = std::hypot(shear, 1.0), diagonal = std::hypot(1.0 + shear, 1.0);
  spline::SplineDomain domain;
  domain.cone.assign(std::size_t(n * n), 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Lower: (i, j) -> (i+1, j) -> (i+1, j+1); upper: (i, j) -> (i+1, j+1) -> (i, j+1).
      domain.faces.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      domain.sideLengths.push_back({bottom, left, diagonal});
      domain.neighbour.push_back({upper(i, j - 1), upper(i + 1, j), upper(i, j)});
      domain.neighbourSide.push_back({1, 2, 0});
      domain.faces.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
      domain.sideLengths.push_back({diagonal, bottom, left});
      domain.neighbour.push_back({lower(i, j), lower(i, j + 1), lower(i - 1, j)});
      domain.neighbourSide.push_back({2, 0, 1});
    }
  return domain;
}

// 2 * major * minor faces.
TriMesh torus(int major, int minor) {
  requireAtLeast(major, 3, "torus: major");
  requireAtLeast(minor, 3, "torus: minor");
  const double R = 1.0, r = 0.4;
  TriMesh mesh;
  for (int j = 0; j < minor; ++j) {
    const double theta = 2 * kPi * j / minor;
    for (int i = 0; i < major; ++i) {
      const double phi = 2 * kPi * i / major;
      const double rho = R + r * std::cos(theta);
      mesh.add_vertex(Point(rho * std::cos(phi), rho * std::sin(phi), r * std::sin(theta)));
    }
  }
  const auto at = [major, minor](int i, int j) { return VH(i % major + major * (j % minor)); };
  // Increasing phi then increasing theta: d/dphi x d/dtheta points out of the tube.
  for (int j = 0; j < minor; ++j)
    for (int i = 0; i < major; ++i)
      addQuad(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  return mesh;
}

TriMesh icosphere(int subdivisions) {
  requireAtLeast(subdivisions, 0, "icosphere: subdivisions");
  const double g = (1 + std::sqrt(5.0)) / 2;
  const std::array<Point, 12> corners = {Point(-1, g, 0),  Point(1, g, 0),   Point(-1, -g, 0),
                                         Point(1, -g, 0),  Point(0, -1, g),  Point(0, 1, g),
                                         Point(0, -1, -g), Point(0, 1, -g),  Point(g, 0, -1),
                                         Point(g, 0, 1),   Point(-g, 0, -1), Point(-g, 0, 1)};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  TriMesh mesh;
  for (const Point& p : corners) mesh.add_vertex(p.normalized());
  for (const auto& f : faces) addFace(mesh, VH(f[0]), VH(f[1]), VH(f[2]));
  for (const auto f : mesh.faces()) {
    const auto h = mesh.halfedge_handle(f);
    const Point a = mesh.point(mesh.from_vertex_handle(h));
    const Point b = mesh.point(mesh.to_vertex_handle(h));
    const Point c = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
    MSPLINE_ASSERT(OpenMesh::dot(OpenMesh::cross(b - a, c - a), a + b + c) > 0,
                   "icosphere: base face not outward");
  }
  for (int s = 0; s < subdivisions; ++s) {
    mesh = structure::subdivideMidpoint(mesh);
    for (const auto v : mesh.vertices()) mesh.set_point(v, mesh.point(v).normalized());
  }
  return mesh;
}

TriMesh doubleTorus(int resolution) {
  return genusSurface(2, resolution);
}

// The boundary surface of the plate region extruded to a slab one block thick, built from the
// voxel faces between filled and empty cells, then Taubin-smoothed. Coordinates: one block = 1,
// centred at the origin. Faces: (36 g + 28) * resolution^2, e.g. genus 2: 400 at resolution 2,
// 1600 at 4, 6400 at 8.
TriMesh genusSurface(int genus, int resolution) {
  requireAtLeast(genus, 1, "genusSurface: genus");
  requireAtLeast(resolution, 1, "genusSurface: resolution");
  const PlateRegion plate(genus, resolution);
  const int nz = resolution;
  const auto filled = [&](int x, int y, int z) { return z >= 0 && z < nz && plate.isFilled(x, y); };

  TriMesh mesh;
  LatticeVertices lattice(mesh, plate.cellsX, plate.cellsY, nz, 1.0 / resolution);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < plate.cellsY; ++y)
      for (int x = 0; x < plate.cellsX; ++x) {
        if (!filled(x, y, z)) continue;
        const std::array<int, 3> cell = {x, y, z};
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side < 2; ++side) {
            std::array<int, 3> neighbour = cell;
            neighbour[axis] += side == 0 ? -1 : 1;
            if (filled(neighbour[0], neighbour[1], neighbour[2])) continue;
            // Corners of the face in the plane of axes b, c with e_b x e_c = e_axis, so the
            // order (0,0),(1,0),(1,1),(0,1) turns counter-clockwise around +axis.
            const int b = (axis + 1) % 3, c = (axis + 2) % 3;
            std::array<VH, 4> quad;
            const int offsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
              std::array<int, 3> corner = cell;
              corner[axis] += side;
              corner[b] += offsets[k][0];
              corner[c] += offsets[k][1];
              quad[k] = lattice.at(corner[0], corner[1], corner[2]);
            }
            if (side == 1)
              addQuad(mesh, quad[0], quad[1], quad[2], quad[3]);
            else
              addQuad(mesh, quad[0], quad[3], quad[2], quad[1]);
          }
      }
  taubinSmooth(mesh, 4 * resolution);
  centre(mesh);
  return mesh;
}

// The two-hole plate region in the z = 0 plane, lifted by a gentle bump. Coordinates: the region
// spans [0,5] x [0,3]; normals point up. Faces: 26 * resolution^2 (104 at 2, 416 at 4, 1664 at 8).
TriMesh pairOfPants(int resolution) {
  requireAtLeast(resolution, 1, "pairOfPants: resolution");
  const PlateRegion plate(2, resolution);
  TriMesh mesh;
  LatticeVertices lattice(mesh, plate.cellsX, plate.cellsY, 0, 1.0 / resolution);
  for (int y = 0; y < plate.cellsY; ++y)
    for (int x = 0; x < plate.cellsX; ++x)
      if (plate.isFilled(x, y))
        addQuad(mesh, lattice.at(x, y, 0), lattice.at(x + 1, y, 0), lattice.at(x + 1, y + 1, 0),
                lattice.at(x, y + 1, 0));
  const double width = plate.cellsX / double(resolution),
               height = plate.cellsY / double(resolution);
  for (const auto v : mesh.vertices()) {
    Point p = mesh.point(v);
    p[2] = 0.3 * std::sin(kPi * p[0] / width) * std::sin(kPi * p[1] / height);
    mesh.set_point(v, p);
  }
  return mesh;
}

}  // namespace mspline::test

namespace mspline::test {

PolygonSoup tetrahedronSoup() {
  PolygonSoup s;
  s.sourceName = "tet.off";
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return s;
}

PolygonSoup needleSoup() {
  PolygonSoup s = tetrahedronSoup();
  s.sourceName = "needle.off";
  s.positions[3] = {0.2, 0.2, 100.0};
  return s;
}

PolygonSoup octahedronSoup(double offset) {
  PolygonSoup s;
  s.sourceName = "oct.off";
  s.positions = {{offset + 1, 0, 0}, {offset - 1, 0, 0}, {offset, 1, 0},
                 {offset, -1, 0},    {offset, 0, 1},     {offset, 0, -1}};
  // Octant (sx, sy, sz) gets one face; odd octants reverse the order to keep normals outward.
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const std::int64_t x = sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0)
          s.faces.push_back({x, y, z});
        else
          s.faces.push_back({x, z, y});
      }
  return s;
}

PolygonSoup gridSoup(int n, bool quads) {
  PolygonSoup s;
  s.sourceName = "grid";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.positions.push_back({double(i) / n, double(j) / n, 0.0});
  auto id = [n](int i, int j) { return std::int64_t(j) * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (quads) {
        s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return s;
}

PolygonSoup moebiusSoup(int n) {
  PolygonSoup s;
  s.sourceName = "moebius";
  for (double w : {0.3, -0.3})
    for (int i = 0; i < n; ++i) {
      const double u = 2 * kPi * i / n;
      s.positions.push_back({(1 + w * std::cos(u / 2)) * std::cos(u),
                             (1 + w * std::cos(u / 2)) * std::sin(u), w * std::sin(u / 2)});
    }
  for (int i = 0; i < n; ++i) {
    const std::int64_t t1 = i + 1 < n ? i + 1 : n, b1 = i + 1 < n ? n + i + 1 : 0;
    s.faces.push_back({i, n + i, b1});
    s.faces.push_back({i, b1, t1});
  }
  return s;
}

void appendSoup(PolygonSoup& soup, const PolygonSoup& other) {
  const auto base = static_cast<std::int64_t>(soup.positions.size());
  soup.positions.insert(soup.positions.end(), other.positions.begin(), other.positions.end());
  for (auto face : other.faces) {
    for (auto& v : face) v += base;
    soup.faces.push_back(face);
  }
}

}  // namespace mspline::test

namespace mspline::test {

int nearestVertex(const TriMesh& mesh, const OpenMesh::Vec3d& p) {
  int best = -1;
  double bestDistance = 1e300;
  for (const auto v : mesh.vertices()) {
    const double d = (mesh.point(v) - p).sqrnorm();
    if (d < bestDistance) {
      bestDistance = d;
      best = v.idx();
    }
  }
  return best;
}

std::vector<structure::Cone> cubeCornerCones(const TriMesh& mesh) {
  std::vector<structure::Cone> cones;
  for (int i = 0; i < 8; ++i) {
    const OpenMesh::Vec3d corner((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    cones.push_back({nearestVertex(mesh, corner / std::sqrt(3.0)), kPi / 2});
  }
  return cones;
}

}  // namespace mspline::test
