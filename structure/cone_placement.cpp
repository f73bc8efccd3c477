#include "structure/cone_placement.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <sstream>

#include "structure/errors.h"
#include "structure/sparse_cholesky.h"
#include "structure/topology.h"
#include "structure/vertex_scaling_energy.h"

namespace mspline::structure {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kQuarter = kPi / 2.0;

// The input's cotangent Laplacian with a fixed pattern; any set of vertices can be held at u = 0 by
// turning their rows and columns into identity ones, so one symbolic analysis serves every solve.
class PinnedLaplacian {
 public:
  explicit PinnedLaplacian(const TriMesh& mesh)
      : laplacian_(vertexScalingHessian(
            mesh, edgeLengths(mesh),
            Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices())))),
        system_(laplacian_) {
    solver_.analyze(system_);
  }

  const Eigen::SparseMatrix<double>& laplacian() const { return laplacian_; }

  // Solves L u = rhs on the vertices with pinned[v] == 0 and u = 0 on the others.
  Eigen::VectorXd solve(const std::vector<char>& pinned, Eigen::VectorXd rhs) {
    for (int col = 0; col < system_.outerSize(); ++col) {
      Eigen::SparseMatrix<double>::InnerIterator base(laplacian_, col);
      for (Eigen::SparseMatrix<double>::InnerIterator it(system_, col); it; ++it, ++base) {
        const auto row = it.row();
        it.valueRef() = pinned[row] || pinned[col] ? (row == col ? 1.0 : 0.0) : base.value();
      }
    }
    for (std::size_t v = 0; v < pinned.size(); ++v)
      if (pinned[v]) rhs[static_cast<Eigen::Index>(v)] = 0.0;
    try {
      solver_.factorize(system_);
    } catch (const SolverError& e) {
      throw SolverError(std::string("cone placement: the cotangent Laplacian of the input could "
                                    "not be factorized (degenerate faces?): ") +
                        e.what());
    }
    return solver_.solve(rhs);
  }

 private:
  Eigen::SparseMatrix<double> laplacian_;
  Eigen::SparseMatrix<double> system_;
  SparseCholesky solver_;
};

// One third of the area of every face around each vertex.
Eigen::VectorXd vertexAreas(const TriMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.n_vertices()));
  for (const auto f : mesh.faces()) {
    auto v = mesh.cfv_begin(f);
    const auto a = *v++, b = *v++, c = *v;
    const double third =
        ((mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a))).norm() / 6.0;
    area[a.idx()] += third;
    area[b.idx()] += third;
    area[c.idx()] += third;
  }
  return area;
}

// Hop distance of every vertex from the sources (large where unreachable).
std::vector<int> hopDistance(const TriMesh& mesh, const std::vector<int>& sources) {
  std::vector<int> distance(mesh.n_vertices(), std::numeric_limits<int>::max());
  std::deque<int> queue;
  for (int s : sources) {
    distance[s] = 0;
    queue.push_back(s);
  }
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    for (const auto w : mesh.vv_range(OpenMesh::VertexHandle(v))) {
      if (distance[w.idx()] > distance[v] + 1) {
        distance[w.idx()] = distance[v] + 1;
        queue.push_back(w.idx());
      }
    }
  }
  return distance;
}

double distortionOf(const Eigen::VectorXd& u, bool closed) {
  return closed ? (u.maxCoeff() - u.minCoeff()) / 2.0 : u.cwiseAbs().maxCoeff();
}

// Largest-remainder rounding of the cone curvatures to multiples of pi/2 summing to `total`
// quarter turns, no multiple above 3 (the cone angle stays positive).
std::vector<int> roundToQuarterTurns(const std::vector<Cone>& cones, long total) {
  std::vector<int> k(cones.size());
  std::vector<double> remainder(cones.size());
  long sum = 0;
  for (std::size_t i = 0; i < cones.size(); ++i) {
    const double q = cones[i].curvature / kQuarter;
    k[i] = std::min(3, static_cast<int>(std::floor(q)));
    remainder[i] = q - k[i];
    sum += k[i];
  }
  std::vector<std::size_t> order(cones.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  for (std::size_t i : order) {
    if (sum >= total) break;
    if (k[i] < 3) {
      ++k[i];
      ++sum;
    }
  }
  if (sum != total) {
    throw InputError("cone placement: " + std::to_string(cones.size()) +
                     " cones cannot be quantized to multiples of pi/2 with positive angles "
                     "summing to 2 pi chi; place more cones");
  }
  return k;
}

}  // namespace

ConePlacementResult placeCones(const TriMesh& mesh, const ConePlacementOptions& options) {
  const auto topology = analyzeTopology(mesh);
  if (mesh.n_faces() == 0 || topology.components != 1) {
    throw TopologyError("cone placement needs a connected mesh with faces; this one has " +
                        std::to_string(topology.components) + " components and " +
                        std::to_string(mesh.n_faces()) + " faces");
  }
  const bool closed = topology.closed;
  const long chi = topology.euler;
  if (options.singleCone && !(closed && topology.genus >= 2)) {
    throw TopologyError("a single cone needs a closed surface of genus >= 2; this one has genus " +
                        std::to_string(topology.genus) + " and " +
                        std::to_string(topology.boundaryLoops) + " boundary loops");
  }
  if (options.targetCount < -1) {
    throw InputError("cone placement: the target count must be -1 (automatic) or >= 0, not " +
                     std::to_string(options.targetCount));
  }

  const auto n = static_cast<Eigen::Index>(mesh.n_vertices());
  std::vector<int> boundary;
  for (const auto v : mesh.vertices())
    if (mesh.is_boundary(v)) boundary.push_back(v.idx());
  if (boundary.size() == mesh.n_vertices())
    throw TopologyError("cone placement: the mesh has no interior vertex");

  const Eigen::VectorXd inputCurvature = vertexCurvatures(mesh, edgeLengths(mesh));
  PinnedLaplacian system(mesh);
  std::vector<char> pinned(mesh.n_vertices(), 0);
  for (int v : boundary) pinned[v] = 1;

  // Round 0. Closed: the conformal factor to constant curvature (2 pi chi spread by area), gauge
  // fixed at vertex 0 and then by mean zero; it is the flat metric itself on a torus. With a
  // boundary: flat with u = 0 on the boundary.
  Eigen::VectorXd u;
  if (closed) {
    const Eigen::VectorXd area = vertexAreas(mesh);
    const Eigen::VectorXd uniform = area * (2.0 * kPi * static_cast<double>(chi) / area.sum());
    std::vector<char> gauge(mesh.n_vertices(), 0);
    gauge[0] = 1;
    u = system.solve(gauge, uniform - inputCurvature);
    u.array() -= u.mean();
  } else {
    u = system.solve(pinned, -inputCurvature);
  }

  ConePlacementResult result;
  result.distortionPerRound.push_back(distortionOf(u, closed));
  std::ostringstream message;

  if (options.singleCone) {
    Eigen::Index best = 0;
    u.cwiseAbs().maxCoeff(&best);
    const int k = static_cast<int>(4 * chi);
    result.cones.push_back({static_cast<int>(best), k * kQuarter});
    result.quarterTurns.push_back(k);
    message << "single cone at vertex " << best << " (curvature " << k << " pi/2)";
  } else {
    const double minAngle = options.minConeAngle;
    std::vector<Cone>& cones = result.cones;
    const auto valid = [&] {
      if (closed && chi != 0 && cones.empty()) return false;
      for (const Cone& c : cones)
        if (2.0 * kPi - c.curvature < minAngle) return false;
      return true;
    };
    std::string stop;
    for (;;) {
      const double distortion = result.distortionPerRound.back();
      if (options.targetCount >= 0) {
        if (static_cast<int>(cones.size()) == options.targetCount) {
          stop = "reached the requested count";
          break;
        }
      } else if (valid() && distortion <= options.maxDistortion) {
        stop = "distortion below the threshold";
        break;
      } else if (static_cast<int>(cones.size()) >= options.maxCones) {
        stop = "reached the maximum number of cones";
        break;
      }

      std::vector<int> sources = boundary;
      for (const Cone& c : cones) sources.push_back(c.vertex);
      const std::vector<int> hops = hopDistance(mesh, sources);
      int best = -1;
      for (Eigen::Index v = 0; v < n; ++v) {
        if (hops[v] < options.minSeparation || pinned[v]) continue;
        if (best < 0 || std::abs(u[v]) > std::abs(u[best])) best = static_cast<int>(v);
      }
      if (best < 0) {
        stop = "no vertex is far enough from the cones and the boundary";
        break;
      }
      cones.push_back({best, 0.0});
      pinned[best] = 1;

      // Flat at every free vertex, u = 0 at the cones and on the boundary; each cone keeps the
      // curvature the linearized metric leaves there.
      u = system.solve(pinned, -inputCurvature);
      const Eigen::VectorXd linearCurvature = inputCurvature + system.laplacian() * u;
      double sum = 0.0;
      for (Cone& c : cones) {
        c.curvature = linearCurvature[c.vertex];
        sum += c.curvature;
      }
      if (closed) {
        // Gauss-Bonnet holds up to rounding; make it exact.
        const double excess =
            (sum - 2.0 * kPi * static_cast<double>(chi)) / static_cast<double>(cones.size());
        for (Cone& c : cones) c.curvature -= excess;
      }
      result.distortionPerRound.push_back(distortionOf(u, closed));
    }
    if (!valid()) {
      std::ostringstream msg;
      msg << "cone placement: " << cones.size() << " cones (" << stop
          << ") cannot flatten this surface: ";
      if (cones.empty()) {
        msg << "Gauss-Bonnet needs total curvature 2 pi chi = " << 2.0 * kPi * chi;
      } else {
        const auto worst = std::max_element(
            cones.begin(), cones.end(), [](auto& a, auto& b) { return a.curvature < b.curvature; });
        msg << "the cone at vertex " << worst->vertex << " would have angle "
            << 2.0 * kPi - worst->curvature << " (below " << minAngle << ")";
      }
      throw InputError(msg.str());
    }
    message << cones.size() << " cones after " << result.distortionPerRound.size() - 1
            << " rounds (" << stop << ")";

    if (options.quantize && !cones.empty()) {
      std::vector<int> k;
      if (closed) {
        k = roundToQuarterTurns(cones, 4 * chi);
      } else {
        for (const Cone& c : cones)
          k.push_back(std::min(3, static_cast<int>(std::lround(c.curvature / kQuarter))));
      }
      std::vector<Cone> kept;
      for (std::size_t i = 0; i < cones.size(); ++i) {
        if (k[i] == 0) continue;
        kept.push_back({cones[i].vertex, k[i] * kQuarter});
        result.quarterTurns.push_back(k[i]);
      }
      message << ", " << kept.size() << " after quantization";
      cones = std::move(kept);
    }
  }

  // The linear solve for the returned cones as curvature targets.
  Eigen::VectorXd target = Eigen::VectorXd::Zero(n);
  for (const Cone& c : result.cones) target[c.vertex] = c.curvature;
  std::vector<char> held(mesh.n_vertices(), 0);
  for (int v : boundary) held[v] = 1;
  if (closed) held[0] = 1;
  result.u = system.solve(held, target - inputCurvature);
  if (closed) result.u.array() -= result.u.mean();
  result.distortion = distortionOf(result.u, closed);
  message << "; linearized distortion " << result.distortion;
  result.message = message.str();
  return result;
}

}  // namespace mspline::structure
