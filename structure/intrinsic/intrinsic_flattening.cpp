#include "mspline/structure/intrinsic/intrinsic_flattening.h"

#include <string>
#include <vector>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

using VH = OpenMesh::VertexHandle;

bool hasBoundary(const TriMesh& mesh) {
  for (const auto v : mesh.vertices())
    if (mesh.is_boundary(v)) return true;
  return false;
}

// The faces of `overlay` that lie in the first `faces` input faces, as a mesh of their own whose
// first `keep` vertices are the overlay's first `keep`.
IntrinsicOverlay restrictOverlay(const IntrinsicOverlay& overlay, int faces, int keep,
                                 int doubleVertices) {
  IntrinsicOverlay half;
  half.flips = overlay.flips;
  half.maxLengthMismatch = overlay.maxLengthMismatch;
  std::vector<int> newIndex(overlay.mesh.n_vertices(), -1);
  std::vector<int> oldIndex;
  for (int v = 0; v < keep; ++v) {
    newIndex[std::size_t(v)] = v;
    oldIndex.push_back(v);
    half.mesh.add_vertex(overlay.mesh.point(VH(v)));
  }
  for (const auto f : overlay.mesh.faces()) {
    if (overlay.inputFace[std::size_t(f.idx())] >= faces) continue;
    std::vector<VH> corners;
    for (const auto v : overlay.mesh.fv_range(f)) {
      int& index = newIndex[std::size_t(v.idx())];
      if (index < 0) {
        if (v.idx() < doubleVertices)
          throw InternalError("overlay: a cell of the input's half touches the mirror copy");
        index = int(oldIndex.size());
        oldIndex.push_back(v.idx());
        half.mesh.add_vertex(overlay.mesh.point(v));
        half.crossingInputEdge.push_back(
            overlay.crossingInputEdge[std::size_t(v.idx() - doubleVertices)]);
      }
      corners.push_back(VH(index));
    }
    if (!half.mesh.add_face(corners).is_valid())
      throw InternalError("overlay: the input's half is not a manifold");
    half.inputFace.push_back(overlay.inputFace[std::size_t(f.idx())]);
    half.intrinsicFace.push_back(overlay.intrinsicFace[std::size_t(f.idx())]);
  }
  half.edgeLengths.resize(Eigen::Index(half.mesh.n_edges()));
  for (const auto e : half.mesh.edges()) {
    const auto h = half.mesh.halfedge_handle(e, 0);
    const auto original =
        overlay.mesh.find_halfedge(VH(oldIndex[std::size_t(half.mesh.from_vertex_handle(h).idx())]),
                                   VH(oldIndex[std::size_t(half.mesh.to_vertex_handle(h).idx())]));
    half.edgeLengths[e.idx()] = overlay.edgeLengths[overlay.mesh.edge_handle(original).idx()];
  }
  return half;
}

}  // namespace

IntrinsicFlattening flattenWithFlips(const TriMesh& mesh, const CurvatureTarget& target,
                                     const RicciNewtonOptions& options) {
  IntrinsicFlattening out;
  const Eigen::Index inputVertices = Eigen::Index(mesh.n_vertices());
  if (!hasBoundary(mesh)) {
    out.solve = solveVertexScalingWithFlips(mesh, target, options);
    out.u = out.solve.ricci.u;
    if (out.solve.ricci.converged)
      out.overlay = intrinsicOverlay(mesh, out.solve.triangulation.flippedEdges(), out.u,
                                     out.solve.triangulation.lengths(out.u));
    return out;
  }
  out.doubled = true;

  // The half: the input with every interior edge between two boundary vertices split.
  TriMesh half = mesh;
  std::vector<TriMesh::EdgeHandle> chords;
  for (const auto e : half.edges()) {
    const auto h = half.halfedge_handle(e, 0);
    if (!half.is_boundary(e) && half.is_boundary(half.from_vertex_handle(h)) &&
        half.is_boundary(half.to_vertex_handle(h)))
      chords.push_back(e);
  }
  for (const auto e : chords) half.split(e, half.calc_edge_midpoint(e));
  out.splitEdges = int(chords.size());
  const int n = int(half.n_vertices());
  Eigen::VectorXd halfCurvature = Eigen::VectorXd::Zero(n);
  halfCurvature.head(inputVertices) = target.curvature;
  std::vector<char> halfFixed(std::size_t(n), 0);
  std::copy(target.fixed.begin(), target.fixed.end(), halfFixed.begin());

  // The double: interior vertices get a mirror copy, boundary vertices are shared, and the
  // mirrored faces are reversed. A boundary vertex carries twice its geodesic curvature.
  TriMesh twice;
  std::vector<int> mirror(half.n_vertices());
  for (const auto v : half.vertices()) twice.add_vertex(half.point(v));
  for (const auto v : half.vertices())
    mirror[std::size_t(v.idx())] =
        half.is_boundary(v) ? v.idx() : twice.add_vertex(half.point(v)).idx();
  const auto addFace = [&](int a, int b, int c) {
    if (!twice.add_face(VH(a), VH(b), VH(c)).is_valid())
      throw InternalError("doubling: the double is not a manifold");
  };
  for (const auto f : half.faces()) {
    std::vector<int> v;
    for (const auto w : half.fv_range(f)) v.push_back(w.idx());
    addFace(v[0], v[1], v[2]);
  }
  for (const auto f : half.faces()) {
    std::vector<int> v;
    for (const auto w : half.fv_range(f)) v.push_back(mirror[std::size_t(w.idx())]);
    addFace(v[0], v[2], v[1]);
  }
  CurvatureTarget doubled;
  doubled.curvature.resize(Eigen::Index(twice.n_vertices()));
  doubled.fixed.assign(twice.n_vertices(), 0);
  for (const auto v : half.vertices()) {
    const int i = v.idx(), m = mirror[std::size_t(i)];
    const bool boundary = half.is_boundary(v);
    doubled.curvature[i] = doubled.curvature[m] = (boundary ? 2.0 : 1.0) * halfCurvature[i];
    doubled.fixed[std::size_t(i)] = doubled.fixed[std::size_t(m)] = halfFixed[std::size_t(i)];
  }

  out.solve = solveVertexScalingWithFlips(twice, doubled, options);
  out.u = out.solve.ricci.u.head(inputVertices);
  if (!out.solve.ricci.converged) return out;
  const IntrinsicOverlay full =
      intrinsicOverlay(twice, out.solve.triangulation.flippedEdges(), out.solve.ricci.u,
                       out.solve.triangulation.lengths(out.solve.ricci.u));
  out.overlay = restrictOverlay(full, int(half.n_faces()), n, int(twice.n_vertices()));
  return out;
}

}  // namespace mspline::structure
