#include "spline/tessellate.h"

#include <algorithm>
#include <limits>
#include <string>

#include "structure/errors.h"

namespace mspline::spline {

namespace {

// Off a cone into its faces, barycentrically: close enough to stand for the cone point, far
// enough for the denominator (which vanishes at the cone) to keep rounding small.
constexpr double kConeOffset = 1e-3;

}  // namespace

Tessellation tessellate(const TriBSplineSpace& space, const Eigen::MatrixXd& control,
                        int resolution) {
  if (resolution < 1)
    throw structure::InputError("tessellation: resolution " + std::to_string(resolution) +
                                " is below 1");
  if (control.cols() != 3 || control.rows() != space.numBasis())
    throw structure::InputError("tessellation: the control points do not fit the spline");
  const SplineDomain& domain = space.domain();
  const int r = resolution;
  Tessellation out;
  out.mesh.sourceName = "tessellation";
  out.coneOffset = kConeOffset;
  out.minDenominator = std::numeric_limits<double>::infinity();
  BasisValues basis;
  const auto sample = [&](const DomainPoint& point) {
    double denominator = 0.0;
    space.basisAt(point, basis, 0, &denominator);
    out.minDenominator = std::min(out.minDenominator, denominator);
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < basis.index.size(); ++k)
      position += basis.value[k] * control.row(basis.index[k]).transpose();
    return position;
  };
  const auto add = [&](const Eigen::Vector3d& p) {
    out.mesh.positions.push_back({p.x(), p.y(), p.z()});
    return std::int64_t(out.mesh.positions.size() - 1);
  };

  // Domain vertices: one sample each (at a cone, the mean just inside its faces).
  std::vector<std::int64_t> vertexSample(std::size_t(domain.vertexCount()), -1);
  std::vector<Eigen::Vector3d> coneSum(std::size_t(domain.vertexCount()), Eigen::Vector3d::Zero());
  std::vector<int> coneFaces(std::size_t(domain.vertexCount()), 0);
  for (int f = 0; f < domain.faceCount(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = domain.faces[std::size_t(f)][std::size_t(c)];
      DomainPoint point{f, Eigen::Vector3d::Zero()};
      if (domain.cone[std::size_t(v)]) {
        point.barycentric.setConstant(kConeOffset / 2.0);
        point.barycentric[c] = 1.0 - kConeOffset;
        coneSum[std::size_t(v)] += sample(point);
        ++coneFaces[std::size_t(v)];
      } else if (vertexSample[std::size_t(v)] < 0) {
        point.barycentric[c] = 1.0;
        vertexSample[std::size_t(v)] = add(sample(point));
      }
    }
  for (int v = 0; v < domain.vertexCount(); ++v)
    if (coneFaces[std::size_t(v)] > 0) {
      vertexSample[std::size_t(v)] = add(coneSum[std::size_t(v)] / coneFaces[std::size_t(v)]);
      ++out.coneVertices;
    }

  // Side samples 1 .. r-1 from corner k to corner k+1, made by whichever face comes first.
  std::vector<std::vector<std::int64_t>> sideSamples(std::size_t(3 * domain.faceCount()));
  const auto side = [&](int f, int k) -> const std::vector<std::int64_t>& {
    auto& samples = sideSamples[std::size_t(3 * f + k)];
    if (!samples.empty() || r == 1) return samples;
    const int g = domain.neighbour[std::size_t(f)][std::size_t(k)];
    const int gk = domain.neighbourSide[std::size_t(f)][std::size_t(k)];
    const auto& across = sideSamples[std::size_t(3 * g + gk)];
    if (!across.empty()) {
      samples.assign(across.rbegin(), across.rend());
      return samples;
    }
    for (int i = 1; i < r; ++i) {
      DomainPoint point{f, Eigen::Vector3d::Zero()};
      point.barycentric[k] = double(r - i) / r;
      point.barycentric[(k + 1) % 3] = double(i) / r;
      samples.push_back(add(sample(point)));
    }
    return samples;
  };

  std::vector<std::int64_t> grid;
  for (int f = 0; f < domain.faceCount(); ++f) {
    // Grid point (a, b), a + b <= r, has barycentric coordinates ((r - a - b), a, b) / r.
    const auto at = [r](int a, int b) { return std::size_t(b * (r + 1) + a); };
    grid.assign(std::size_t((r + 1) * (r + 1)), -1);
    const auto& corners = domain.faces[std::size_t(f)];
    grid[at(0, 0)] = vertexSample[std::size_t(corners[0])];
    grid[at(r, 0)] = vertexSample[std::size_t(corners[1])];
    grid[at(0, r)] = vertexSample[std::size_t(corners[2])];
    const auto& s0 = side(f, 0);
    const auto& s1 = side(f, 1);
    const auto& s2 = side(f, 2);
    for (int i = 1; i < r; ++i) {
      grid[at(i, 0)] = s0[std::size_t(i - 1)];
      grid[at(r - i, i)] = s1[std::size_t(i - 1)];
      grid[at(0, r - i)] = s2[std::size_t(i - 1)];
    }
    for (int b = 1; b < r; ++b)
      for (int a = 1; a + b < r; ++a) {
        const DomainPoint point{f, Eigen::Vector3d(double(r - a - b), double(a), double(b)) / r};
        grid[at(a, b)] = add(sample(point));
      }
    for (int b = 0; b < r; ++b)
      for (int a = 0; a + b < r; ++a) {
        out.mesh.faces.push_back({grid[at(a, b)], grid[at(a + 1, b)], grid[at(a, b + 1)]});
        if (a + b + 2 <= r)
          out.mesh.faces.push_back(
              {grid[at(a + 1, b)], grid[at(a + 1, b + 1)], grid[at(a, b + 1)]});
      }
  }
  return out;
}

}  // namespace mspline::spline
