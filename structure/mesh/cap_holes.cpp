#include "mspline/structure/mesh/cap_holes.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/SparseCore>

#include "mspline/structure/core/constants.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/sparse_cholesky.h"
#include "mspline/structure/mesh/boundary_loops.h"
#include "mspline/structure/mesh/subdivide.h"

namespace mspline::structure {

namespace {

// The boundary loops in the direction of their boundary halfedges (vertex k to k + 1), which is
// the direction the cap faces must traverse them in to keep the input's orientation.
std::vector<std::vector<TriMesh::VertexHandle>> loopsToCap(const TriMesh& mesh) {
  // OpenMesh keeps a vertex where two boundary fans touch; its loops cannot get disjoint caps.
  std::vector<int> outgoing(mesh.n_vertices(), 0);
  for (auto h : mesh.halfedges())
    if (mesh.is_boundary(h) && ++outgoing[mesh.from_vertex_handle(h).idx()] == 2)
      throw TopologyError("capping holes: boundary vertex " +
                          std::to_string(mesh.from_vertex_handle(h).idx()) +
                          " lies on two boundary loops (or twice on one); repair the mesh first");
  auto loops = boundaryLoops(mesh);
  for (const auto& loop : loops)
    if (loop.size() < 3)
      throw TopologyError("capping holes: the boundary loop through vertex " +
                          std::to_string(loop.front().idx()) + " has " +
                          std::to_string(loop.size()) + " edges; a cap needs at least 3");
  return loops;
}

// A ring of the cap: its vertices in loop direction and their positions along the loop as
// fractions of its length, increasing from ring vertex 0.
struct Ring {
  std::vector<TriMesh::VertexHandle> vertices;
  std::vector<double> parameters;
};

// Triangulates the band between `outer` and the smaller `inner` ring, starting at the segment
// from vertex 0 to vertex 0 and always advancing on the ring whose next vertex stays closer
// along the loop, so that the band's diagonals do not cross. The faces traverse `outer` in its
// direction and `inner` against it.
void zipRings(TriMesh& mesh, const Ring& outer, const Ring& inner) {
  const std::size_t na = outer.vertices.size(), nb = inner.vertices.size();
  auto param = [](const Ring& ring, std::size_t k) {
    const std::size_t n = ring.vertices.size();
    return ring.parameters[k % n] + static_cast<double>(k / n);
  };
  for (std::size_t i = 0, j = 0; i < na || j < nb;) {
    const bool advanceOuter = j == nb || (i < na && param(outer, i) + param(outer, i + 1) <=
                                                        param(inner, j) + param(inner, j + 1));
    const auto o = outer.vertices[i % na], b = inner.vertices[j % nb];
    const auto face = advanceOuter ? mesh.add_face(o, outer.vertices[(i + 1) % na], b)
                                   : mesh.add_face(o, inner.vertices[(j + 1) % nb], b);
    MSPLINE_ASSERT(face.is_valid(), "capping holes: OpenMesh refused a cap face");
    (advanceOuter ? i : j) += 1;
  }
}

// Adds the rings and faces of the cap of one loop, the new vertices placed at its centroid; the
// number of rings (1: the centre alone).
int buildCap(TriMesh& mesh, const std::vector<TriMesh::VertexHandle>& loop,
             double edgeLengthFactor) {
  Ring outer{loop, {}};
  double length = 0.0;
  OpenMesh::Vec3d centroid(0.0, 0.0, 0.0);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    outer.parameters.push_back(length);
    length += (mesh.point(loop[(k + 1) % loop.size()]) - mesh.point(loop[k])).norm();
    centroid += mesh.point(loop[k]);
  }
  centroid /= static_cast<double>(loop.size());
  for (double& t : outer.parameters) t /= length;

  // A disk of perimeter L has radius L / (2 pi): that many target edge lengths fit from the loop
  // to the centre, and ring k keeps the fraction (K - k) / K of the loop's vertex count.
  const double edgesAround = static_cast<double>(loop.size()) / edgeLengthFactor;
  const int rings = std::max(1, static_cast<int>(std::lround(edgesAround / (2.0 * kPi))));
  for (int k = 1; k < rings; ++k) {
    const auto count = std::max<long>(3, std::lround(edgesAround * (rings - k) / rings));
    Ring inner;
    for (long j = 0; j < count; ++j) {
      // Placed at the centroid for now: fairing gives every cap vertex its position.
      inner.vertices.push_back(mesh.add_vertex(centroid));
      inner.parameters.push_back(static_cast<double>(j) / static_cast<double>(count));
    }
    zipRings(mesh, outer, inner);
    outer = std::move(inner);
  }
  const auto centre = mesh.add_vertex(centroid);
  for (std::size_t i = 0; i < outer.vertices.size(); ++i) {
    const auto face =
        mesh.add_face(outer.vertices[i], outer.vertices[(i + 1) % outer.vertices.size()], centre);
    MSPLINE_ASSERT(face.is_valid(), "capping holes: OpenMesh refused a cap face");
  }
  return rings;
}

// Positions the cap vertices (indices from `firstCap` on) minimizing sum_r |(M x)_r|^2, M the
// umbrella operator x_r - mean of its neighbours, over the rows r of the cap vertices (order 1:
// M x = 0 there, a membrane) or of the cap and loop vertices (order 2: the bi-Laplace equation
// M^T M x = 0 at the cap vertices, which also asks the loop vertices to be the mean of their
// neighbours, so the cap continues the surface's tangent plane). The scan's vertices are fixed.
// The sum of the angles of the faces around interior vertex v.
double angleSum(const TriMesh& mesh, TriMesh::VertexHandle v) {
  double sum = 0.0;
  for (const auto h : mesh.voh_range(v)) {
    const OpenMesh::Vec3d a = mesh.point(h.to()) - mesh.point(v);
    const OpenMesh::Vec3d b = mesh.point(h.prev().from()) - mesh.point(v);
    sum += std::atan2(OpenMesh::cross(a, b).norm(), OpenMesh::dot(a, b));
  }
  return sum;
}

void fairCaps(TriMesh& mesh, int firstCap, int order) {
  const int unknowns = static_cast<int>(mesh.n_vertices()) - firstCap;
  std::vector<int> rows;
  for (auto v : mesh.vertices()) {
    bool row = v.idx() >= firstCap;
    if (order == 2)
      for (auto w : mesh.vv_range(v)) row = row || w.idx() >= firstCap;
    if (row) rows.push_back(v.idx());
  }

  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd fixedPart = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), 3);
  auto add = [&](int row, int vertex, double weight) {
    if (vertex >= firstCap) {
      triplets.emplace_back(row, vertex - firstCap, weight);
      return;
    }
    const auto& p = mesh.point(TriMesh::VertexHandle(vertex));
    for (int c = 0; c < 3; ++c) fixedPart(row, c) += weight * p[c];
  };
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const TriMesh::VertexHandle v(rows[r]);
    const double weight = -1.0 / static_cast<double>(mesh.valence(v));
    add(r, v.idx(), 1.0);
    for (auto w : mesh.vv_range(v)) add(r, w.idx(), weight);
  }
  Eigen::SparseMatrix<double> umbrella(static_cast<Eigen::Index>(rows.size()), unknowns);
  umbrella.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double> normal = umbrella.transpose() * umbrella;
  SparseCholesky cholesky;
  cholesky.compute(normal);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd x = cholesky.solve(-(umbrella.transpose() * fixedPart.col(c)));
    for (int k = 0; k < unknowns; ++k) mesh.point(TriMesh::VertexHandle(firstCap + k))[c] = x[k];
  }
}

}  // namespace

CappedSurface capHoles(const TriMesh& mesh, const CapOptions& options) {
  if (!(options.edgeLengthFactor > 0.0) || !std::isfinite(options.edgeLengthFactor))
    throw InputError("capping holes: the cap edge length factor must be positive, not " +
                     std::to_string(options.edgeLengthFactor));
  if (options.fairingOrder != 1 && options.fairingOrder != 2)
    throw InputError("capping holes: the fairing order must be 1 or 2, not " +
                     std::to_string(options.fairingOrder));

  const auto loops = loopsToCap(mesh);
  CappedSurface result{mesh, {}, {}, loops.size(), {}};
  const int firstCap = static_cast<int>(mesh.n_vertices());
  std::vector<TriMesh::VertexHandle> loneCentres;
  for (const auto& loop : loops) {
    result.loopLengths.push_back(loop.size());
    if (buildCap(result.mesh, loop, options.edgeLengthFactor) == 1)
      loneCentres.emplace_back(static_cast<int>(result.mesh.n_vertices()) - 1);
  }
  if (!loops.empty()) fairCaps(result.mesh, firstCap, options.fairingOrder);
  // A cap whose centre is its only vertex cannot bulge: on a rough scan the bi-Laplacian asks that
  // one vertex to make every loop vertex the mean of its neighbours, and it goes far off
  // (ChineseDragon-10kv: 3-edge holes whose centres had angle sums of 1.05 and 0.09, spikes no cone
  // placement can flatten). Where its angle sum is below pi it is the mean of its loop instead.
  for (const auto centre : loneCentres)
    if (angleSum(result.mesh, centre) < kPi) {
      OpenMesh::Vec3d mean(0.0, 0.0, 0.0);
      for (const auto w : result.mesh.vv_range(centre)) mean += result.mesh.point(w);
      result.mesh.point(centre) = mean / static_cast<double>(result.mesh.valence(centre));
    }

  result.capVertex.assign(result.mesh.n_vertices(), 0);
  std::fill(result.capVertex.begin() + firstCap, result.capVertex.end(), 1);
  result.capFace.assign(result.mesh.n_faces(), 0);
  std::fill(result.capFace.begin() + static_cast<std::ptrdiff_t>(mesh.n_faces()),
            result.capFace.end(), 1);
  return result;
}

CappedSurface subdivideMidpoint(const CappedSurface& capped) {
  const TriMesh& mesh = capped.mesh;
  CappedSurface out;
  out.mesh = subdivideMidpoint(mesh);
  out.caps = capped.caps;
  for (const std::size_t length : capped.loopLengths) out.loopLengths.push_back(2 * length);
  out.capVertex = capped.capVertex;
  for (const auto e : mesh.edges()) {
    bool cap = true;
    for (int side = 0; side < 2; ++side) {
      const auto face = mesh.face_handle(mesh.halfedge_handle(e, side));
      cap = cap && face.is_valid() && capped.capFace[std::size_t(face.idx())];
    }
    out.capVertex.push_back(cap);
  }
  out.capFace.reserve(4 * capped.capFace.size());
  for (const char cap : capped.capFace) out.capFace.insert(out.capFace.end(), 4, cap);
  return out;
}

}  // namespace mspline::structure
