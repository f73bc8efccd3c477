#include "mspline/spline/tribspline/tessellate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mspline/structure/core/errors.h"

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
  struct Sample {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // zero where du x dv vanishes
    SurfacePoint evaluated;                            // where the spline was evaluated
  };
  const auto sample = [&](const SurfacePoint& at) {
    // The normalized basis is non-negative and sums to 1; where its denominator is so small that
    // rounding breaks that (sum |N_k| / sum N_k well above 1), the point is moved a little
    // towards the face's centre, where the spline is the same up to that little move.
    double denominator = 0.0;
    SurfacePoint point = at;
    for (const double towardsCentre : {0.0, 1e-4, 1e-3, 1e-2, 0.05}) {
      point.barycentric =
          (1.0 - towardsCentre) * at.barycentric + Eigen::Vector3d::Constant(towardsCentre / 3.0);
      space.basisAt(point, basis, 1, &denominator);
      double absolute = 0.0;
      for (const double value : basis.value) absolute += std::abs(value);
      if (absolute <= 1.0 + 1e-6) break;
    }
    out.minDenominator = std::min(out.minDenominator, denominator);
    Sample s;
    s.evaluated = point;
    Eigen::Vector3d du = Eigen::Vector3d::Zero(), dv = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < basis.index.size(); ++k) {
      const Eigen::Vector3d c = control.row(basis.index[k]).transpose();
      s.position += basis.value[k] * c;
      du += basis.gradient[k].x() * c;
      dv += basis.gradient[k].y() * c;
    }
    const Eigen::Vector3d n = du.cross(dv);
    if (n.norm() > 0.0) s.normal = n.normalized();
    return s;
  };
  out.sampleOffsets.push_back(0);
  // A mesh vertex at `s`, which is the spline at `evaluated` (their mean), with the chart
  // coordinates of `point`.
  const auto add = [&](const Sample& s, const SurfacePoint& point,
                       const std::vector<SurfacePoint>& evaluated) {
    out.samplePoints.insert(out.samplePoints.end(), evaluated.begin(), evaluated.end());
    out.sampleOffsets.push_back(std::int64_t(out.samplePoints.size()));
    out.mesh.positions.push_back({s.position.x(), s.position.y(), s.position.z()});
    out.normals.push_back({s.normal.x(), s.normal.y(), s.normal.z()});
    const Eigen::Vector2d uv = space.framePosition(point);
    out.uvs.push_back({uv.x(), uv.y()});
    return std::int64_t(out.mesh.positions.size() - 1);
  };

  // Domain vertices: one sample each (at a cone, the mean just inside its faces).
  std::vector<std::int64_t> vertexSample(std::size_t(domain.vertexCount()), -1);
  std::vector<Sample> coneSum(std::size_t(domain.vertexCount()));
  std::vector<int> coneFaces(std::size_t(domain.vertexCount()), 0);
  std::vector<SurfacePoint> coneCorner(std::size_t(domain.vertexCount()));
  std::vector<std::vector<SurfacePoint>> coneEvaluated(std::size_t(domain.vertexCount()));
  for (int f = 0; f < domain.faceCount(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = domain.faces[std::size_t(f)][std::size_t(c)];
      SurfacePoint point{f, Eigen::Vector3d::Zero()};
      if (domain.cone[std::size_t(v)]) {
        const auto offCone = [&](double offset) {
          SurfacePoint inside{f, Eigen::Vector3d::Constant(offset / 2.0)};
          inside.barycentric[c] = 1.0 - offset;
          return sample(inside);
        };
        // The vanishing denominator amplifies rounding: a sample that does not follow the
        // surface's approach to the cone (closer to the sample 10 times farther out than that
        // one is to the sample 100 times farther) is replaced by the one 10 times farther.
        Sample s = offCone(kConeOffset);
        const Sample farther = offCone(10.0 * kConeOffset);
        const double step = (farther.position - offCone(100.0 * kConeOffset).position).norm();
        if (!((s.position - farther.position).norm() <= step)) s = farther;
        coneEvaluated[std::size_t(v)].push_back(s.evaluated);
        coneSum[std::size_t(v)].position += s.position;
        coneSum[std::size_t(v)].normal += s.normal;
        if (coneFaces[std::size_t(v)]++ == 0) {
          coneCorner[std::size_t(v)] = {f, Eigen::Vector3d::Zero()};
          coneCorner[std::size_t(v)].barycentric[c] = 1.0;
        }
      } else if (vertexSample[std::size_t(v)] < 0) {
        point.barycentric[c] = 1.0;
        const Sample s = sample(point);
        vertexSample[std::size_t(v)] = add(s, point, {s.evaluated});
      }
    }
  for (int v = 0; v < domain.vertexCount(); ++v)
    if (coneFaces[std::size_t(v)] > 0) {
      Sample mean = coneSum[std::size_t(v)];
      mean.position /= coneFaces[std::size_t(v)];
      if (mean.normal.norm() > 0.0) mean.normal.normalize();
      vertexSample[std::size_t(v)] =
          add(mean, coneCorner[std::size_t(v)], coneEvaluated[std::size_t(v)]);
      out.coneSamples.push_back(vertexSample[std::size_t(v)]);
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
      SurfacePoint point{f, Eigen::Vector3d::Zero()};
      point.barycentric[k] = double(r - i) / r;
      point.barycentric[(k + 1) % 3] = double(i) / r;
      const Sample s = sample(point);
      samples.push_back(add(s, point, {s.evaluated}));
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
        const SurfacePoint point{f, Eigen::Vector3d(double(r - a - b), double(a), double(b)) / r};
        const Sample s = sample(point);
        grid[at(a, b)] = add(s, point, {s.evaluated});
      }
    for (int b = 0; b < r; ++b)
      for (int a = 0; a + b < r; ++a) {
        out.mesh.faces.push_back({grid[at(a, b)], grid[at(a + 1, b)], grid[at(a, b + 1)]});
        if (a + b + 2 <= r)
          out.mesh.faces.push_back(
              {grid[at(a + 1, b)], grid[at(a + 1, b + 1)], grid[at(a, b + 1)]});
      }
  }
  fillMissingNormals(out.mesh, out.normals);
  return out;
}

std::vector<std::array<double, 3>> vertexNormalsOfMesh(const structure::PolygonSoup& soup) {
  std::vector<Eigen::Vector3d> sum(soup.positions.size(), Eigen::Vector3d::Zero());
  const auto at = [&](std::int64_t v) {
    const auto& p = soup.positions[std::size_t(v)];
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  for (const auto& face : soup.faces) {
    // Fan around the first corner: twice the area times the unit normal, summed.
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (std::size_t k = 1; k + 1 < face.size(); ++k)
      n += (at(face[k]) - at(face[0])).cross(at(face[k + 1]) - at(face[0]));
    for (std::int64_t v : face) sum[std::size_t(v)] += n;
  }
  std::vector<std::array<double, 3>> out(soup.positions.size(), {0.0, 0.0, 0.0});
  for (std::size_t v = 0; v < sum.size(); ++v)
    if (sum[v].norm() > 0.0) {
      const Eigen::Vector3d n = sum[v].normalized();
      out[v] = {n.x(), n.y(), n.z()};
    }
  return out;
}

void fillMissingNormals(const structure::PolygonSoup& soup,
                        std::vector<std::array<double, 3>>& normals) {
  MSPLINE_ASSERT(normals.size() == soup.positions.size(), "one normal per vertex");
  std::vector<std::array<double, 3>> fallback;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const auto& n = normals[v];
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (std::isfinite(length) && std::abs(length - 1.0) <= 1e-6) continue;
    if (fallback.empty()) fallback = vertexNormalsOfMesh(soup);
    normals[v] = fallback[v];
  }
}

}  // namespace mspline::spline
