#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "mspline/spline/tspline/tspline.h"
#include "mspline/spline/tspline/tspline_bezier.h"
#include "mspline/spline/tspline/tspline_cap.h"
#include "mspline/spline/tspline/tspline_check.h"
#include "mspline/spline/tspline/tspline_cone_normals.h"
#include "mspline/spline/tspline/tspline_refine.h"
#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "support/test_tmeshes.h"

using namespace mspline;
using spline::TSplineSpace;

namespace {

constexpr int kSide = test::StarTMesh::kSide;
using test::starControl;
using test::StarTMesh;
using test::starTMesh;

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Normal jumps (radians) across the cap's sector edges (cone excluded) and across its outer
// sides, and the relative first-derivative jump across the outer sides.
struct Jumps {
  double sectorNormal = 0.0, outerNormal = 0.0, outerDerivative = 0.0;
};

Jumps capJumps(const StarTMesh& star, const TSplineSpace& space, const Eigen::MatrixXd& control) {
  Jumps jumps;
  const Eigen::VectorXd unit;
  for (int k = 0; k < star.n; ++k) {
    const int previous = (k + star.n - 1) % star.n;
    for (int s = 1; s < 20; ++s) {
      const double t = s / 20.0;
      // Sector edge k: (t, 0) of sector k is (0, t) of sector k - 1.
      const auto a = space.evaluate(control, unit, star.face(k, 0, 0), {t, 0.0});
      const auto b = space.evaluate(control, unit, star.face(previous, 0, 0), {0.0, t});
      REQUIRE((a.position - b.position).norm() < 1e-12);
      jumps.sectorNormal = std::max(jumps.sectorNormal, angleBetween(a.normal, b.normal));
      // Outer side x = 1 of the cap face against cell (1, 0).
      const auto c = space.evaluate(control, unit, star.face(k, 0, 0), {1.0, t});
      const auto d = space.evaluate(control, unit, star.face(k, 1, 0), {0.0, t});
      REQUIRE((c.position - d.position).norm() < 1e-12);
      jumps.outerNormal = std::max(jumps.outerNormal, angleBetween(c.normal, d.normal));
      jumps.outerDerivative = std::max({jumps.outerDerivative, (c.ds - d.ds).norm() / d.ds.norm(),
                                        (c.dt - d.dt).norm() / d.dt.norm()});
    }
  }
  return jumps;
}

}  // namespace

TEST_CASE("tspline caps: partition of unity, a point and a normal at the cone", "[spline]") {
  for (const int n : {2, 3, 5, 6}) {
    INFO("valence " << n);
    const StarTMesh star = starTMesh(n);
    const TSplineSpace space(star.mesh);
    CHECK(space.missingAnchors().empty());
    CHECK(int(space.capFaces().size()) == n);
    REQUIRE(space.anchorOfVertex()[0] >= 0);
    // Partition of unity (derivatives summing to 0) on every face.
    std::vector<spline::TSplineBasisValue> basis;
    double unity = 0.0, slope = 0.0;
    for (int f = 0; f < star.mesh.numFaces(); ++f)
      for (double y : {0.0, 0.3, 0.77})
        for (double x : {0.0, 0.45, 0.9}) {
          space.basisAt(f, {x, y}, basis, 2);
          double sum = 0.0, ds = 0.0, dt = 0.0, dss = 0.0;
          for (const auto& b : basis) sum += b.value, ds += b.ds, dt += b.dt, dss += b.dss;
          // Only the faces a cell away from the open boundary have all their functions.
          const bool inner = (f % (kSide * kSide)) % kSide < kSide - 1 &&
                             (f % (kSide * kSide)) / kSide < kSide - 1;
          if (!inner) continue;
          unity = std::max(unity, std::abs(sum - 1.0));
          slope = std::max({slope, std::abs(ds), std::abs(dt), std::abs(dss)});
        }
    CHECK(unity < 1e-12);
    CHECK(slope < 1e-10);

    // The cone point, the same from every face around it, is the limit point of the net.
    const Eigen::MatrixXd control = starControl(star, space, 0.1);
    const Eigen::VectorXd unit;
    const auto cone = space.evaluate(control, unit, star.face(0, 0, 0), {0.0, 0.0}, 1);
    REQUIRE(cone.position.allFinite());
    for (int k = 1; k < n; ++k)
      CHECK((space.evaluate(control, unit, star.face(k, 0, 0), {0.0, 0.0}).position - cone.position)
                .norm() < 1e-13);
    // Normals at 1e-3 of a cell from the cone, in 8 directions (angles of the characteristic
    // map), agree.
    std::vector<Eigen::Vector3d> normals;
    for (int m = 0; m < 8; ++m) {
      const double phi = 2.0 * kPi * (m + 0.5) / 8.0;
      const int k = std::min(n - 1, int(phi / (2.0 * kPi / n)));
      const double alpha = (phi - 2.0 * kPi * k / n) * n / 4.0;
      const auto p = space.evaluate(control, unit, star.face(k, 0, 0),
                                    1e-3 * Eigen::Vector2d(std::cos(alpha), std::sin(alpha)));
      normals.push_back(p.normal);
    }
    double spread = 0.0;
    for (const auto& a : normals)
      for (const auto& b : normals) spread = std::max(spread, angleBetween(a, b));
    CHECK(spread < 1e-3);
    if (n > 2) CHECK(angleBetween(cone.normal, normals[0]) < 1e-3);
  }
}

TEST_CASE("tspline caps: check measures the normals around each cone", "[spline]") {
  for (const int n : {2, 3, 5, 6}) {
    INFO("valence " << n);
    const StarTMesh star = starTMesh(n);
    const TSplineSpace space(star.mesh);
    const Eigen::MatrixXd control = starControl(star, space, 0.1);
    spline::TSplineCheckOptions options;
    options.samples = 100;
    const auto smooth = spline::checkTSpline(space, control, {}, options);
    CHECK(smooth.cones == 1);
    CHECK(smooth.worstCone == 0);
    CHECK(smooth.maxConeNormalSpread < 1e-3);
    CHECK(smooth.conesSpreadOver1e3 == 0);
    // A unique normal at the cone: the spread vanishes like the distance to it.
    const auto near = spline::coneNormalSpreads(space, control, {}, 1e-4);
    const auto far = spline::coneNormalSpreads(space, control, {}, 1e-3);
    REQUIRE(near.size() == 1);
    REQUIRE(far.size() == 1);
    CHECK(near[0].valence == n);
    CHECK(near[0].spread / far[0].spread == Approx(0.1).epsilon(0.05));
    // The surface turns faster on a coarser net: there the spread passes 1e-3, and it doubles
    // with h.
    const auto half = spline::checkTSpline(space, starControl(star, space, 0.5), {}, options);
    const auto coarse = spline::checkTSpline(space, starControl(star, space, 1.0), {}, options);
    CHECK(coarse.maxConeNormalSpread > 2e-3);
    CHECK(coarse.conesSpreadOver1e3 == 1);
    CHECK(coarse.maxConeNormalSpread / half.maxConeNormalSpread > 1.7);
  }
}

TEST_CASE("tspline caps: C1 across the outer sides, normal jumps O(h) across sector edges",
          "[spline]") {
  for (const int n : {2, 3, 5, 6}) {
    INFO("valence " << n);
    const StarTMesh star = starTMesh(n);
    const TSplineSpace space(star.mesh);
    const Jumps coarse = capJumps(star, space, starControl(star, space, 0.2));
    const Jumps fine = capJumps(star, space, starControl(star, space, 0.1));
    INFO("sector edge normal jumps " << coarse.sectorNormal << " -> " << fine.sectorNormal);
    CHECK(coarse.sectorNormal / fine.sectorNormal > 1.7);
    CHECK(fine.sectorNormal < 0.05);
    // The patches share the tangent plane at the cone (at valence 2 through the second-order
    // coefficients, projected into one plane), so the jump vanishes there like the distance to it:
    // a tenth as far, a tenth as large.
    const Eigen::MatrixXd control = starControl(star, space, 0.2);
    std::array<double, 2> nearCone{};
    for (int m = 0; m < 2; ++m) {
      const double t = m == 0 ? 1e-3 : 1e-4;
      const auto a = space.evaluate(control, {}, star.face(1, 0, 0), {t, 0.0});
      const auto b = space.evaluate(control, {}, star.face(0, 0, 0), {0.0, t});
      nearCone[std::size_t(m)] = angleBetween(a.normal, b.normal);
    }
    INFO("sector edge normal jumps 1e-3 and 1e-4 from the cone " << nearCone[0] << ", "
                                                                 << nearCone[1]);
    CHECK(nearCone[0] < 1e-3);
    CHECK(nearCone[0] / nearCone[1] == Approx(10.0).epsilon(0.05));
    INFO("outer side normal jumps " << coarse.outerNormal << " -> " << fine.outerNormal);
    if (n == 2) {
      // The second-order corner coefficients moved: across the outer sides too, O(h).
      CHECK(coarse.outerNormal / fine.outerNormal > 1.7);
    } else {
      CHECK(coarse.outerDerivative < 1e-12);
      CHECK(fine.outerNormal < 1e-10);
    }
  }
}

TEST_CASE("tspline caps: valence 4 is the uniform B-spline", "[spline]") {
  // A regular vertex of a grid, capped anyway: the patch is the B-spline's Bezier form.
  const StarTMesh star = starTMesh(4);
  const TSplineSpace space(star.mesh);  // no cone: ordinary B-splines everywhere
  CHECK(space.capFaces().empty());
  spline::TSplineCapRegion region;
  spline::FaceDeveloper developer(star.mesh);
  REQUIRE(spline::findCapRegion(star.mesh, 0, region, developer).empty());
  REQUIRE(region.valence == 4);
  const Eigen::MatrixXd control = starControl(star, space, 0.3);
  std::vector<spline::TSplineBasisValue> basis;
  for (int k = 0; k < 4; ++k) {
    const spline::TSplineCapPatch patch = spline::capPatch(region, k);
    REQUIRE(patch.face == star.face(k, 0, 0));
    Eigen::MatrixXd net(patch.vertices.size(), 3);
    for (std::size_t c = 0; c < patch.vertices.size(); ++c)
      net.row(Eigen::Index(c)) =
          control.row(space.anchorOfVertex()[std::size_t(patch.vertices[c])]);
    const Eigen::MatrixXd bezier = patch.coefficients * net;
    for (double y : {0.0, 0.2, 0.7, 1.0})
      for (double x : {0.0, 0.5, 0.9}) {
        double bx[4], by[4];
        spline::cubicBernstein(x, bx);
        spline::cubicBernstein(y, by);
        Eigen::Vector3d patchPoint = Eigen::Vector3d::Zero();
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i)
            patchPoint += bx[i] * by[j] * bezier.row(4 * j + i).transpose();
        const auto p = space.evaluate(control, {}, patch.face, {x, y}, 0);
        CHECK((patchPoint - p.position).norm() < 1e-13);
      }
  }
}

TEST_CASE("tspline caps: Bezier extraction and moved knots agree with evaluation", "[spline]") {
  const StarTMesh star = starTMesh(5);
  const TSplineSpace space(star.mesh);
  const Eigen::MatrixXd control = starControl(star, space, 0.25);
  const spline::TSplineBezier bezier(space, control);
  double worst = 0.0;
  for (int f = 0; f < star.mesh.numFaces(); ++f)
    for (double y : {0.0, 0.4, 0.8})
      for (double x : {0.1, 0.6}) {
        const auto p = space.evaluate(control, {}, f, {x, y});
        Eigen::Vector3d position, ds, dt;
        bezier.evaluate(f, {x, y}, position, &ds, &dt);
        worst = std::max(
            {worst, (position - p.position).norm(), (ds - p.ds).norm(), (dt - p.dt).norm(),
             (space.evaluateMovingKnots(control, {}, f, {x, y}).position - p.position).norm()});
      }
  CHECK(worst < 1e-12);
}

TEST_CASE("tspline caps: a T-junction in a cone's cap region is refused", "[spline]") {
  spline::TSplineCapRegion region;
  const StarTMesh star = starTMesh(3);
  // Cut the cell (2, 1) of sector 0: a T-junction inside the cap region.
  spline::TMesh cut = star.mesh;
  {
    spline::TMeshFace& face = cut.faces[std::size_t(star.face(0, 2, 1))];
    face.vertices.insert(face.vertices.begin() + 1, cut.numVertices);
    face.positions.insert(face.positions.begin() + 1, Eigen::Vector2d(0.5, 0.0));
    spline::TMeshFace& below = cut.faces[std::size_t(star.face(0, 2, 0))];
    below.vertices.insert(below.vertices.begin() + 3, cut.numVertices);
    below.positions.insert(below.positions.begin() + 3, Eigen::Vector2d(0.5, 1.0));
  }
  std::vector<spline::TMeshFace> faces;
  for (const auto& face : cut.faces)
    faces.push_back({0.0, 0.0, face.vertices, face.positions, {}, {}});
  const spline::TMesh withJunction = spline::buildTMesh(cut.numVertices + 1, faces);
  spline::FaceDeveloper junctionDeveloper(withJunction);
  CHECK_FALSE(spline::findCapRegion(withJunction, 0, region, junctionDeveloper).empty());
  CHECK_THROWS_AS(TSplineSpace(withJunction), structure::SolverError);
  CHECK_THROWS_WITH(TSplineSpace(withJunction), Catch::Contains("extraordinary vertex 0"));
}

TEST_CASE("tspline caps: refinement keeps caps, or makes them where cones are close", "[spline]") {
  // A face in a cap region: the cells within 2 of the cone (4 a sector) are split with it.
  const StarTMesh star = starTMesh(3);
  const std::vector<int> faces = spline::withTouchedCapsSplit(
      star.mesh, spline::capRegions(star.mesh), {star.face(1, 2, 1), star.face(2, 5, 5)});
  CHECK(faces.size() == 2 + 3 * 4);
  spline::TMesh mesh = star.mesh;
  std::vector<spline::FacePoint> points{{star.face(0, 0, 0), {0.75, 0.25}}};
  spline::splitIntoFour(mesh, faces, points);
  const TSplineSpace refined(mesh);
  REQUIRE(refined.capFaces().size() == 3);
  CHECK(refined.capFaces()[0].face == star.face(0, 0, 0));
  CHECK(mesh.faces[std::size_t(star.face(0, 0, 0))].width == 0.5);
  // The point moved to the part holding it, in that part's frame.
  CHECK(points[0].face != star.face(0, 0, 0));
  CHECK(points[0].position.isApprox(Eigen::Vector2d(0.25, 0.25)));
  // Splitting only a face next to the region would put a T-junction into it; with the cells
  // around the cone the cap comes back at half the size.
  spline::TMesh broken = star.mesh;
  spline::splitIntoFour(broken, {star.face(0, 3, 0)}, points);
  CHECK_THROWS_AS(TSplineSpace(broken), structure::SolverError);
  spline::TMesh closed = star.mesh;
  const std::vector<int> next =
      spline::withTouchedCapsSplit(closed, spline::capRegions(closed), {star.face(0, 3, 0)});
  CHECK(next.size() == 1 + 3 * 4);
  spline::splitIntoFour(closed, next, points);
  CHECK(TSplineSpace(closed).capFaces().size() == 3);

  // A cube of 2 x 2 cells a side: its corners 2 cells apart, then 4 half cells: capped.
  const test::CubeTMesh cube = test::cubeTMesh(2);
  spline::TMesh cubeMesh = cube.mesh;
  std::vector<spline::FacePoint> centres;
  for (int f = 0; f < cubeMesh.numFaces(); ++f) centres.push_back({f, {0.5, 0.5}});
  CHECK_THROWS_AS(TSplineSpace(cubeMesh), structure::SolverError);
  CHECK(spline::refineAroundCones(cubeMesh, centres) == 24);
  const TSplineSpace capped(cubeMesh);
  CHECK(capped.capFaces().size() == 8 * 3);
  for (const auto& p : centres) {
    const auto& face = cubeMesh.faces[std::size_t(p.face)];
    CHECK(face.width == 0.5);
    // Each old centre is a corner of the quarter cells now.
    CHECK((p.position.array() == 0.0).all());
  }
}

TEST_CASE("tspline caps: T-junctions just beyond the 3 x 3 cells keep the patches exact",
          "[spline]") {
  // As refineAroundCones leaves a cone: its 2 x 2 cells a sector split, so the cap has 3 x 3 half
  // cells and the T-junctions sit at 4 half cells. On the cap faces and the half cells next to
  // them every function has its knots within 3 half cells of the cone, all uniform: the basis is
  // a partition of unity there, and the patches meet the T-spline around them C1. (Farther out,
  // at the corners of the split block, T-junctions cost the raw basis its partition of unity, as
  // anywhere on a refined T-mesh; the rational normalization covers that.)
  for (const int n : {3, 5}) {
    INFO("valence " << n);
    const StarTMesh star = starTMesh(n);
    std::vector<int> split;
    for (int k = 0; k < n; ++k)
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) split.push_back(star.face(k, a, b));
    // Points on the cap faces' outer sides x = 1/2 (seen from beyond them) and over the unsplit
    // cell at the cone, given in the unsplit cells' frames and carried to their quarters.
    std::vector<spline::FacePoint> points;
    for (int k = 0; k < n; ++k)
      for (int m = 1; m < 5; ++m) points.push_back({star.face(k, 0, 0), {0.5, 0.1 * m}});
    const std::size_t sides = points.size();
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i)
          points.push_back({star.face(k, 0, 0), {0.1 * i + 0.03, 0.1 * j + 0.07}});
    spline::TMesh mesh = star.mesh;
    spline::splitIntoFour(mesh, split, points);
    const TSplineSpace space(mesh);
    REQUIRE(int(space.capFaces().size()) == n);
    CHECK(space.missingAnchors().empty());
    std::vector<spline::TSplineBasisValue> basis, across;
    double unity = 0.0, jump = 0.0;
    for (std::size_t q = 0; q < points.size(); ++q) {
      space.basisAt(points[q].face, points[q].position, basis, 1);
      double sum = 0.0;
      for (const auto& b : basis) sum += b.value;
      unity = std::max(unity, std::abs(sum - 1.0));
      if (q >= sides) continue;
      // The same point seen from the cap face F_k (x = 1/2 in its frame): every function's value
      // and first derivatives agree.
      const int k = int(q / 4);
      REQUIRE(points[q].face != star.face(k, 0, 0));
      space.basisAt(star.face(k, 0, 0), {0.5, points[q].position.y()}, across, 1);
      std::map<int, Eigen::Vector3d> difference;
      const auto at = [&](int anchor) -> Eigen::Vector3d& {
        return difference.try_emplace(anchor, Eigen::Vector3d::Zero()).first->second;
      };
      for (const auto& a : across) at(a.anchor) += Eigen::Vector3d(a.value, a.ds, a.dt);
      for (const auto& b : basis) at(b.anchor) -= Eigen::Vector3d(b.value, b.ds, b.dt);
      for (const auto& [anchor, d] : difference) jump = std::max(jump, d.cwiseAbs().maxCoeff());
    }
    CHECK(unity < 1e-12);
    CHECK(jump < 1e-10);
  }
}
