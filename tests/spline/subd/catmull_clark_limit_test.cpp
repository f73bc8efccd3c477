#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/spline/core/uniform_bspline.h"
#include "mspline/spline/subd/catmull_clark_limit.h"
#include "mspline/spline/subd/triangle_quad_split.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_meshes.h"

using namespace mspline;
using spline::BoundaryRule;
using spline::CatmullClarkLimit;
using spline::CatmullClarkOptions;
using spline::LimitPoint;

namespace {

using Faces = std::vector<std::vector<int>>;

struct Net {
  Eigen::MatrixXd points;
  Faces faces;
};

// nx x ny control points (i + jitter, j + jitter, random height), point (i, j) at row j nx + i;
// face (i, j) = [(i,j), (i+1,j), (i+1,j+1), (i,j+1)] at index j (nx-1) + i.
Net randomGrid(int nx, int ny, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  Net net;
  net.points.resize(nx * ny, 3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      net.points.row(j * nx + i) << i + jitter(rng), j + jitter(rng), 2 * jitter(rng);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
      net.faces.push_back({j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1, (j + 1) * nx + i});
  return net;
}

// A closed torus net of n x m quads, every vertex of valence 4, with noise on the points; point
// (i, j) at row j n + i, face (i, j) = [(i,j), (i+1,j), (i+1,j+1), (i,j+1)] (indices mod n, m).
Net randomTorus(int n, int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  Net net;
  net.points.resize(n * m, 3);
  const double pi = kPi;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * pi * i / n, b = 2 * pi * j / m, r = 1.0 + 0.4 * std::cos(b);
      net.points.row(j * n + i) << r * std::cos(a) + noise(rng), r * std::sin(a) + noise(rng),
          0.4 * std::sin(b) + noise(rng);
    }
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      net.faces.push_back(
          {j * n + i, j * n + (i + 1) % n, ((j + 1) % m) * n + (i + 1) % n, ((j + 1) % m) * n + i});
  return net;
}

// The uniform bicubic B-spline over the 4 x 4 grid whose point (a, b) is `point(a, b)`.
template <class PointAt>
LimitPoint bicubic(PointAt point, double s, double t) {
  double w[16], ws[16], wt[16], wss[16], wst[16], wtt[16];
  spline::uniformBicubicBasis(s, t, w, ws, wt, wss, wst, wtt);
  LimitPoint r;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d p = point(a, b);
      const int k = 4 * b + a;
      r.position += w[k] * p;
      r.du += ws[k] * p;
      r.dv += wt[k] * p;
      r.duu += wss[k] * p;
      r.duv += wst[k] * p;
      r.dvv += wtt[k] * p;
    }
  return r;
}

// |a - b| relative to the size of the net (the largest control point norm, at least 1).
double relativeError(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double scale) {
  return (a - b).norm() / std::max(1.0, scale);
}

double maxError(const LimitPoint& a, const LimitPoint& b, double scale, bool second) {
  double e = std::max({relativeError(a.position, b.position, scale),
                       relativeError(a.du, b.du, scale), relativeError(a.dv, b.dv, scale)});
  if (second)
    e = std::max({e, relativeError(a.duu, b.duu, scale), relativeError(a.duv, b.duv, scale),
                  relativeError(a.dvv, b.dvv, scale)});
  return e;
}

const std::vector<std::pair<double, double>>& parameters() {
  static const std::vector<std::pair<double, double>> uv = {
      {0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.25, 0.75}, {0.9, 0.13}, {0.031, 0.62}};
  return uv;
}

// The Catmull-Clark net of one midpoint split of a generated triangle mesh.
Net quadSplit(const structure::TriMesh& mesh) {
  spline::TriangleQuadSplit split = spline::splitTrianglesIntoQuads(mesh);
  return {split.points, split.quads};
}

Net cube() {
  Net net;
  net.points.resize(8, 3);
  for (int v = 0; v < 8; ++v) net.points.row(v) << (v & 1), (v >> 1) & 1, (v >> 2) & 1;
  net.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return net;
}

// The triangles of a generated mesh as a Catmull-Clark net (non-quad faces).
Net triangles(const structure::TriMesh& mesh) {
  Net net;
  net.points.resize(static_cast<int>(mesh.n_vertices()), 3);
  for (auto v : mesh.vertices())
    net.points.row(v.idx()) << mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2];
  for (auto f : mesh.faces()) {
    std::vector<int> face;
    for (auto v : mesh.fv_range(f)) face.push_back(v.idx());
    net.faces.push_back(face);
  }
  return net;
}

// Random (patch face, u, v) over every patch face of the net, with parameters away from the ends
// so that finite differences stay inside [0,1]^2.
std::vector<spline::FaceParameter> randomParameters(const CatmullClarkLimit& limit, int count,
                                                    unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, limit.numPatchFaces() - 1);
  std::uniform_real_distribution<double> uv(0.01, 0.99);
  std::vector<spline::FaceParameter> points;
  for (int i = 0; i < count; ++i) points.push_back({face(rng), uv(rng), uv(rng)});
  return points;
}

double netScale(const Eigen::MatrixXd& points) {
  return points.rowwise().norm().maxCoeff();
}

template <class Fn>
std::string messageOf(Fn fn) {
  try {
    fn();
  } catch (const structure::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST_CASE("catmull_clark_limit: inner faces of an open grid are the uniform bicubic B-spline",
          "[spline]") {
  const int nx = 8, ny = 7;
  const Net net = randomGrid(nx, ny, 11);
  CatmullClarkOptions options;
  options.boundary = BoundaryRule::None;
  const CatmullClarkLimit limit(net.points, net.faces, options);
  REQUIRE(limit.numPatchFaces() == (nx - 1) * (ny - 1));
  CHECK(limit.faceCounts().regular == (nx - 3) * (ny - 3));
  CHECK(limit.faceCounts().irregular == 0);
  CHECK(limit.faceCounts().withoutSurface == (nx - 1) * (ny - 1) - (nx - 3) * (ny - 3));

  const double scale = netScale(net.points);
  double worst = 0.0;
  int inner = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int face = j * (nx - 1) + i;
      const bool isInner = i >= 1 && j >= 1 && i + 2 < nx && j + 2 < ny;
      for (const auto& [u, v] : parameters()) {
        const auto point = limit.evaluate(face, u, v, true);
        REQUIRE(point.has_value() == isInner);
        if (!isInner) continue;
        // Face vertex 0 = grid point (i, j) is the patch's point 5 = (1, 1) of its 4 x 4 grid.
        const LimitPoint expected = bicubic(
            [&](int a, int b) {
              return Eigen::Vector3d(net.points.row((j - 1 + b) * nx + i - 1 + a).transpose());
            },
            u, v);
        worst = std::max(worst, maxError(*point, expected, scale, true));
      }
      inner += isInner;
    }
  CHECK(inner == (nx - 3) * (ny - 3));
  CHECK(worst <= 1e-12);

  // The batch gives the same values, and NaN with a flag off the surface.
  std::vector<spline::FaceParameter> batch;
  for (int face = 0; face < limit.numPatchFaces(); ++face) batch.push_back({face, 0.3, 0.6});
  spline::LimitPoints out;
  CHECK(limit.evaluate(batch, out) == std::size_t((nx - 3) * (ny - 3)));
  for (int face = 0; face < limit.numPatchFaces(); ++face) {
    const auto single = limit.evaluate(face, 0.3, 0.6);
    REQUIRE(bool(out.onSurface[face]) == single.has_value());
    if (!single) {
      CHECK(std::isnan(out.position(face, 0)));
      CHECK(std::isnan(out.du(face, 1)));
      continue;
    }
    CHECK(out.position.row(face).transpose() == single->position);
    CHECK(out.du.row(face).transpose() == single->du);
    CHECK(out.dv.row(face).transpose() == single->dv);
  }
}

TEST_CASE("catmull_clark_limit: a closed torus net is the periodic bicubic B-spline", "[spline]") {
  const int n = 9, m = 6;
  const Net net = randomTorus(n, m, 5);
  const CatmullClarkLimit limit(net.points, net.faces);
  CHECK(limit.faceCounts().regular == n * m);
  CHECK(limit.faceCounts().irregular == 0);
  CHECK(limit.faceCounts().withoutSurface == 0);
  const double scale = netScale(net.points);
  double worst = 0.0;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i)
      for (const auto& [u, v] : parameters()) {
        const auto point = limit.evaluate(j * n + i, u, v, true);
        REQUIRE(point);
        const LimitPoint expected = bicubic(
            [&](int a, int b) {
              const int pi = (i - 1 + a + n) % n, pj = (j - 1 + b + m) % m;
              return Eigen::Vector3d(net.points.row(pj * n + pi).transpose());
            },
            u, v);
        worst = std::max(worst, maxError(*point, expected, scale, true));
      }
  CHECK(worst <= 1e-12);
}

TEST_CASE("catmull_clark_limit: boundary rules on an open grid", "[spline]") {
  const int nx = 7, ny = 6;
  const Net net = randomGrid(nx, ny, 3);
  const Eigen::Vector3d corner = net.points.row(0).transpose();
  const double scale = netScale(net.points);
  for (BoundaryRule rule : {BoundaryRule::EdgeOnly, BoundaryRule::EdgeAndCorner}) {
    CatmullClarkOptions options;
    options.boundary = rule;
    const CatmullClarkLimit limit(net.points, net.faces, options);
    CHECK(limit.faceCounts().withoutSurface == 0);
    // Every face has a surface; along the bottom boundary (away from the corners) it is the
    // cubic B-spline of the boundary points.
    for (int i = 1; i + 2 < nx; ++i)
      for (double u : {0.0, 0.3, 0.8}) {
        double b[4], b1[4];
        spline::uniformCubicBasis(u, b, b1);
        Eigen::Vector3d expected = Eigen::Vector3d::Zero(), tangent = expected;
        for (int k = 0; k < 4; ++k) {
          expected += b[k] * net.points.row(i - 1 + k).transpose();
          tangent += b1[k] * net.points.row(i - 1 + k).transpose();
        }
        const auto point = limit.evaluate(i, u, 0.0);
        REQUIRE(point);
        CHECK(relativeError(point->position, expected, scale) <= 1e-12);
        CHECK(relativeError(point->du, tangent, scale) <= 1e-12);
      }
    const auto atCorner = limit.evaluate(0, 0.0, 0.0);
    REQUIRE(atCorner);
    if (rule == BoundaryRule::EdgeAndCorner) {
      CHECK((atCorner->position - corner).norm() <= 1e-12 * scale);
      CHECK(limit.faceCounts().regular == (nx - 1) * (ny - 1));
    } else {
      CHECK((atCorner->position - corner).norm() > 1e-3);
    }
  }
}

TEST_CASE("catmull_clark_limit: irregular nets are affine invariant and match finite differences",
          "[spline]") {
  struct Case {
    std::string name;
    Net net;
    int irregularFaces;
  };
  const structure::TriMesh sphere = test::icosphere(1);
  const std::vector<Case> cases = {
      {"cube (valence 3)", cube(), 6},
      {"split icosphere (valences 3, 5, 6)", quadSplit(sphere), 3 * int(sphere.n_faces())},
      {"icosahedron triangles (valence 5)", triangles(test::icosphere(0)), 20},
      {"split disk (open)", quadSplit(test::gridDisk(3)), -1},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    const CatmullClarkLimit limit(c.net.points, c.net.faces);
    if (c.irregularFaces >= 0) CHECK(limit.faceCounts().irregular == c.irregularFaces);
    CHECK(limit.faceCounts().withoutSurface == 0);
    CHECK(limit.faceCounts().regular + limit.faceCounts().irregular == limit.numBaseFaces());
    const auto params = randomParameters(limit, 200, 17);

    // Constant control points: the weights sum to 1 and the derivative weights to 0.
    const Eigen::RowVector3d c0(0.3, -1.7, 2.5);
    Eigen::MatrixXd constant = c0.replicate(c.net.points.rows(), 1);
    const CatmullClarkLimit flat(constant, c.net.faces);
    // Translated control points: the surface moves, its derivatives do not.
    const Eigen::RowVector3d shift(10.0, -3.0, 0.5);
    Eigen::MatrixXd moved = c.net.points.rowwise() + shift;
    const CatmullClarkLimit translated(moved, c.net.faces);

    double constantError = 0.0, translationError = 0.0, fdError = 0.0, fd2Error = 0.0;
    const double h = 1e-6;
    for (const auto& p : params) {
      const auto a = limit.evaluate(p.face, p.u, p.v, true);
      const auto k = flat.evaluate(p.face, p.u, p.v, true);
      const auto t = translated.evaluate(p.face, p.u, p.v, true);
      REQUIRE(a);
      REQUIRE(k);
      REQUIRE(t);
      constantError = std::max({constantError, (k->position - c0.transpose()).norm(), k->du.norm(),
                                k->dv.norm(), k->duu.norm(), k->duv.norm(), k->dvv.norm()});
      translationError =
          std::max({translationError, (t->position - a->position - shift.transpose()).norm(),
                    (t->du - a->du).norm(), (t->dv - a->dv).norm()});
      // Central differences (the points stay inside the face); relative to the derivative size.
      const auto up = limit.evaluate(p.face, p.u + h, p.v, true);
      const auto um = limit.evaluate(p.face, p.u - h, p.v, true);
      const auto vp = limit.evaluate(p.face, p.u, p.v + h, true);
      const auto vm = limit.evaluate(p.face, p.u, p.v - h, true);
      const double size = std::max({a->du.norm(), a->dv.norm(), 1e-3});
      fdError = std::max({fdError, ((up->position - um->position) / (2 * h) - a->du).norm() / size,
                          ((vp->position - vm->position) / (2 * h) - a->dv).norm() / size});
      const double size2 = std::max({a->duu.norm(), a->duv.norm(), a->dvv.norm(), size});
      fd2Error = std::max({fd2Error, ((up->du - um->du) / (2 * h) - a->duu).norm() / size2,
                           ((vp->du - vm->du) / (2 * h) - a->duv).norm() / size2,
                           ((up->dv - um->dv) / (2 * h) - a->duv).norm() / size2,
                           ((vp->dv - vm->dv) / (2 * h) - a->dvv).norm() / size2});
    }
    CHECK(constantError <= 1e-12);
    CHECK(translationError <= 1e-12);
    CHECK(fdError <= 1e-6);
    CHECK(fd2Error <= 1e-5);
  }
}

TEST_CASE("catmull_clark_limit: a planar irregular net has a planar limit surface", "[spline]") {
  // The split grid disk lies in z = 0; rotate it into a general plane.
  Net net = quadSplit(test::gridDisk(4));
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
                                    Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  const Eigen::Vector3d normal = rotation.col(2), origin(1.0, 2.0, -0.5);
  net.points = (net.points * rotation.transpose()).rowwise() + origin.transpose();
  for (BoundaryRule rule : {BoundaryRule::EdgeOnly, BoundaryRule::EdgeAndCorner}) {
    CatmullClarkOptions options;
    options.boundary = rule;
    const CatmullClarkLimit limit(net.points, net.faces, options);
    REQUIRE(limit.faceCounts().irregular > 0);
    double offPlane = 0.0;
    int evaluated = 0;
    for (int face = 0; face < limit.numPatchFaces(); ++face)
      for (const auto& [u, v] : parameters()) {
        const auto p = limit.evaluate(face, u, v, true);
        REQUIRE(p);
        offPlane = std::max({offPlane, std::abs(normal.dot(p->position - origin)),
                             std::abs(normal.dot(p->du)), std::abs(normal.dot(p->dv)),
                             std::abs(normal.dot(p->duu)), std::abs(normal.dot(p->duv)),
                             std::abs(normal.dot(p->dvv))});
        ++evaluated;
      }
    CHECK(evaluated == limit.numPatchFaces() * int(parameters().size()));
    CHECK(offPlane <= 1e-12);
  }
}

TEST_CASE("catmull_clark_limit: updating control points equals rebuilding", "[spline]") {
  const Net net = quadSplit(test::icosphere(1));
  CatmullClarkLimit limit(net.points, net.faces);
  std::mt19937 rng(23);
  std::normal_distribution<double> noise(0.0, 0.1);
  Eigen::MatrixXd moved = net.points;
  for (Eigen::Index i = 0; i < moved.size(); ++i) moved(i) += noise(rng);
  const auto params = randomParameters(limit, 300, 29);
  spline::LimitPoints before, updated, rebuilt;
  limit.evaluate(params, before);
  limit.updateControlPoints(moved);
  limit.evaluate(params, updated);
  CatmullClarkLimit(moved, net.faces).evaluate(params, rebuilt);
  CHECK((updated.position - rebuilt.position).cwiseAbs().maxCoeff() <= 1e-15);
  CHECK((updated.du - rebuilt.du).cwiseAbs().maxCoeff() <= 1e-15);
  CHECK((updated.dv - rebuilt.dv).cwiseAbs().maxCoeff() <= 1e-15);
  // And the update did change the surface.
  CHECK((updated.position - before.position).cwiseAbs().maxCoeff() > 1e-3);
}

TEST_CASE("catmull_clark_limit: patch faces of polygons meet along their shared edges",
          "[spline]") {
  // Triangles are 3 patch faces each: the k-th has (0,0) at vertex k, u towards vertex k+1, v
  // towards vertex k-1 and (1,1) at the centre, so its edge u = 1 is the next one's edge v = 1.
  const Net net = triangles(test::icosphere(0));
  const CatmullClarkLimit limit(net.points, net.faces);
  REQUIRE(limit.numPatchFaces() == 3 * limit.numBaseFaces());
  double gap = 0.0;
  for (int f = 0; f < limit.numBaseFaces(); ++f) {
    REQUIRE(limit.firstPatchFace(f + 1) - limit.firstPatchFace(f) == 3);
    for (int k = 0; k < 3; ++k) {
      const int face = limit.firstPatchFace(f) + k, next = limit.firstPatchFace(f) + (k + 1) % 3;
      for (double t : {0.0, 0.2, 0.5, 0.77, 1.0})
        gap = std::max(
            gap, (limit.evaluate(face, 1.0, t)->position - limit.evaluate(next, t, 1.0)->position)
                     .norm());
      // The corner (0,0) is the limit of vertex k: nearest to it among the triangle's vertices.
      const Eigen::Vector3d p = limit.evaluate(face, 0.0, 0.0)->position;
      const auto& tri = net.faces[std::size_t(f)];
      for (int other = 1; other < 3; ++other)
        CHECK((p - net.points.row(tri[k]).transpose()).norm() <
              (p - net.points.row(tri[(k + other) % 3]).transpose()).norm());
    }
  }
  CHECK(gap <= 1e-12);
}

TEST_CASE("catmull_clark_limit: unreferenced control points change nothing", "[spline]") {
  const Net net = cube();
  Eigen::MatrixXd extended(9, 3);
  extended << net.points, Eigen::RowVector3d(5.0, 5.0, 5.0);
  const CatmullClarkLimit plain(net.points, net.faces), withExtra(extended, net.faces);
  CHECK(withExtra.numControlPoints() == 9);
  for (int face = 0; face < 6; ++face)
    CHECK(plain.evaluate(face, 0.2, 0.7)->position == withExtra.evaluate(face, 0.2, 0.7)->position);
}

TEST_CASE("catmull_clark_limit: bad nets and queries are rejected with a clear message",
          "[spline]") {
  const Net grid = randomGrid(4, 4, 1);
  auto build = [](const Eigen::MatrixXd& points, const Faces& faces,
                  const CatmullClarkOptions& options = {}) {
    return messageOf([&] { CatmullClarkLimit(points, faces, options); });
  };
  using Catch::Matchers::Contains;
  Faces bad = grid.faces;
  bad[2][1] = 99;
  CHECK_THAT(build(grid.points, bad), Contains("out of range") && Contains("face 2"));
  bad = grid.faces;
  bad[3] = {0, 1};
  CHECK_THAT(build(grid.points, bad), Contains("fewer than 3"));
  bad = grid.faces;
  bad[4] = {0, 1, 1, 4};
  CHECK_THAT(build(grid.points, bad), Contains("face 4 repeats a vertex"));
  bad = grid.faces;
  bad.push_back(bad[0]);
  CHECK_THAT(build(grid.points, bad), Contains("duplicate"));
  bad = grid.faces;
  std::swap(bad[0][1], bad[0][3]);  // reversed orientation of face 0
  CHECK_THAT(build(grid.points, bad), Contains("orientation"));
  // A third face on the edge (1, 5) and a second fan at vertex 0.
  Eigen::MatrixXd more(grid.points.rows() + 2, 3);
  more << grid.points, Eigen::RowVector3d(0.5, -1.0, 1.0), Eigen::RowVector3d(-1.0, -1.0, 0.0);
  bad = grid.faces;
  bad.push_back({1, 5, 16});
  CHECK_THAT(build(more, bad), Contains("non-manifold edge"));
  bad = grid.faces;
  bad.push_back({0, 17, 16});
  CHECK_THAT(build(more, bad), Contains("non-manifold vertex"));
  CHECK_THAT(build(grid.points, {}), Contains("empty"));
  Eigen::MatrixXd nan = grid.points;
  nan(5, 1) = std::nan("");
  CHECK_THAT(build(nan, grid.faces), Contains("control point 5") && Contains("non-finite"));
  CHECK_THAT(build(grid.points.leftCols(2), grid.faces), Contains("n x 3"));
  CatmullClarkOptions options;
  options.isolationLevel = 0;
  CHECK_THAT(build(grid.points, grid.faces, options), Contains("isolation level 0"));
  options.isolationLevel = 11;
  CHECK_THAT(build(grid.points, grid.faces, options), Contains("isolation level 11"));

  CatmullClarkLimit limit(grid.points, grid.faces);
  CHECK_THAT(messageOf([&] { limit.evaluate(9, 0.5, 0.5); }), Contains("patch face 9"));
  CHECK_THAT(messageOf([&] { limit.evaluate(-1, 0.5, 0.5); }), Contains("out of range"));
  CHECK_THAT(messageOf([&] { limit.evaluate(0, 1.5, 0.5); }), Contains("outside [0,1]^2"));
  CHECK_THAT(messageOf([&] { limit.evaluate(0, 0.5, std::nan("")); }), Contains("outside"));
  spline::LimitPoints out;
  CHECK_THAT(messageOf([&] {
               limit.evaluate({{0, 0.5, 0.5}, {0, -0.1, 0.5}}, out);
             }),
             Contains("outside"));
  CHECK_THAT(messageOf([&] { limit.updateControlPoints(grid.points.topRows(10)); }),
             Contains("10 control points given where the net has 16"));
  CHECK_THAT(messageOf([&] { limit.firstPatchFace(10); }), Contains("base face 10"));
}
