#include "mspline/structure/mesh/subdivide.h"

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

TriMesh subdivideMidpoint(const TriMesh& mesh) {
  const std::size_t nV = mesh.n_vertices();
  const std::size_t nE = mesh.n_edges();
  const std::size_t nF = mesh.n_faces();

  TriMesh out;
  // Euler: each old edge becomes two, each face adds three interior edges.
  out.reserve(nV + nE, 2 * nE + 3 * nF, 4 * nF);
  for (std::size_t v = 0; v < nV; ++v) out.add_vertex(mesh.point(TriMesh::VertexHandle(int(v))));
  for (std::size_t e = 0; e < nE; ++e) {
    const auto h = mesh.halfedge_handle(TriMesh::EdgeHandle(int(e)), 0);
    out.add_vertex(0.5 *
                   (mesh.point(mesh.from_vertex_handle(h)) + mesh.point(mesh.to_vertex_handle(h))));
  }

  const auto midpoint = [&](TriMesh::HalfedgeHandle h) {
    return TriMesh::VertexHandle(int(nV) + mesh.edge_handle(h).idx());
  };
  for (const auto f : mesh.faces()) {
    // h0 runs v0 -> v1, h1 runs v1 -> v2, h2 runs v2 -> v0; m_i is the midpoint of h_i.
    const auto h0 = mesh.halfedge_handle(f);
    const auto h1 = mesh.next_halfedge_handle(h0);
    const auto h2 = mesh.next_halfedge_handle(h1);
    const auto v0 = mesh.from_vertex_handle(h0);
    const auto v1 = mesh.from_vertex_handle(h1);
    const auto v2 = mesh.from_vertex_handle(h2);
    const auto m0 = midpoint(h0), m1 = midpoint(h1), m2 = midpoint(h2);
    // Corner triangles first, then the centre one; all keep the parent's orientation.
    const bool ok = out.add_face(v0, m0, m2).is_valid() && out.add_face(v1, m1, m0).is_valid() &&
                    out.add_face(v2, m2, m1).is_valid() && out.add_face(m0, m1, m2).is_valid();
    MSPLINE_ASSERT(
        ok, "subdivideMidpoint: OpenMesh rejected a child face of face " + std::to_string(f.idx()));
  }
  return out;
}

TriMesh subdivideToAtLeast(const TriMesh& mesh, std::size_t minFaces) {
  if (mesh.n_faces() >= minFaces) return mesh;
  if (mesh.n_faces() == 0)
    throw InputError("subdivideToAtLeast: the mesh has no faces, so it cannot reach " +
                     std::to_string(minFaces) + " faces");
  TriMesh result = subdivideMidpoint(mesh);
  while (result.n_faces() < minFaces) result = subdivideMidpoint(result);
  return result;
}

}  // namespace mspline::structure
