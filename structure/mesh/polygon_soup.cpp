#include "mspline/structure/mesh/polygon_soup.h"

#include <OpenMesh/Core/System/omstream.hh>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

namespace {

// OpenMesh prints its own complaint about a face it rejects; the exception thrown instead names
// the source and the face, so OpenMesh's message would only be noise.
class QuietOpenMeshErrors {
 public:
  QuietOpenMeshErrors() : wasEnabled_(omerr().is_enabled()) { omerr().disable(); }
  ~QuietOpenMeshErrors() {
    if (wasEnabled_) omerr().enable();
  }
  QuietOpenMeshErrors(const QuietOpenMeshErrors&) = delete;
  QuietOpenMeshErrors& operator=(const QuietOpenMeshErrors&) = delete;

 private:
  bool wasEnabled_;
};

std::string describeFace(const PolygonSoup& soup, std::size_t f) {
  std::string text = soup.sourceName + ": face " + std::to_string(f) + " (vertices";
  for (std::int64_t index : soup.faces[f]) text += " " + std::to_string(index);
  return text + ")";
}

}  // namespace

std::vector<std::array<int, 3>> triangleIndices(const PolygonSoup& soup) {
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    if (face.size() != 3) throw InputError(describeFace(soup, f) + " is not a triangle");
    triangles.push_back({int(face[0]), int(face[1]), int(face[2])});
  }
  return triangles;
}

Eigen::MatrixX3d pointMatrix(const std::vector<std::array<double, 3>>& points) {
  Eigen::MatrixX3d rows(Eigen::Index(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    rows.row(Eigen::Index(i)) << points[i][0], points[i][1], points[i][2];
  return rows;
}

std::size_t triangulatePolygons(PolygonSoup& soup) {
  std::size_t polygons = 0;
  std::size_t triangles = 0;
  for (const auto& face : soup.faces) {
    if (face.size() > 3) {
      ++polygons;
      triangles += face.size() - 2;
    } else {
      ++triangles;
    }
  }
  if (polygons == 0) return 0;
  bool withUVs = !soup.cornerUVs.empty();
  MSPLINE_ASSERT(!withUVs || soup.cornerUVs.size() == soup.faces.size(),
                 "cornerUVs must be parallel to faces");

  std::vector<std::vector<std::int64_t>> faces;
  std::vector<std::vector<std::array<double, 2>>> cornerUVs;
  faces.reserve(triangles);
  if (withUVs) cornerUVs.reserve(triangles);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    std::vector<std::int64_t>& face = soup.faces[f];
    if (withUVs)
      MSPLINE_ASSERT(soup.cornerUVs[f].size() == face.size(), "cornerUVs must match each face");
    if (face.size() <= 3) {
      faces.push_back(std::move(face));
      if (withUVs) cornerUVs.push_back(std::move(soup.cornerUVs[f]));
      continue;
    }
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      faces.push_back({face[0], face[k], face[k + 1]});
      if (withUVs) {
        const auto& uvs = soup.cornerUVs[f];
        cornerUVs.push_back({uvs[0], uvs[k], uvs[k + 1]});
      }
    }
  }
  soup.faces = std::move(faces);
  soup.cornerUVs = std::move(cornerUVs);
  return polygons;
}

TriMesh toTriMesh(const PolygonSoup& soup) {
  const bool withUVs = !soup.cornerUVs.empty();
  if (withUVs && soup.cornerUVs.size() != soup.faces.size())
    throw InputError(soup.sourceName + ": the texture coordinates do not match the faces");
  TriMesh mesh;
  const std::size_t vertexCount = soup.positions.size();
  mesh.reserve(vertexCount, soup.faces.size() * 3 / 2 + 3, soup.faces.size());
  for (const auto& p : soup.positions) mesh.add_vertex(TriMesh::Point(p[0], p[1], p[2]));
  if (withUVs) mesh.request_halfedge_texcoords2D();

  QuietOpenMeshErrors quiet;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    if (face.size() != 3) throw InputError(describeFace(soup, f) + " is not a triangle");
    std::array<TriMesh::VertexHandle, 3> corners;
    for (std::size_t k = 0; k < 3; ++k) {
      if (face[k] < 0 || face[k] >= static_cast<std::int64_t>(vertexCount))
        throw InputError(describeFace(soup, f) + " refers to a vertex that does not exist");
      corners[k] = TriMesh::VertexHandle(static_cast<int>(face[k]));
    }
    if (corners[0] == corners[1] || corners[1] == corners[2] || corners[0] == corners[2])
      throw TopologyError(describeFace(soup, f) + " uses a vertex twice");
    TriMesh::FaceHandle added = mesh.add_face(corners[0], corners[1], corners[2]);
    if (!added.is_valid())
      throw TopologyError(describeFace(soup, f) +
                          " cannot be added: an edge or vertex would become non-manifold, or the "
                          "face is oriented against its neighbours");
    if (!withUVs) continue;
    const auto& uvs = soup.cornerUVs[f];
    if (uvs.size() != 3)
      throw InputError(describeFace(soup, f) + " has " + std::to_string(uvs.size()) +
                       " texture coordinates");
    // A halfedge's texture coordinate belongs to the corner at the vertex it points to.
    for (TriMesh::HalfedgeHandle h : mesh.fh_range(added)) {
      TriMesh::VertexHandle to = mesh.to_vertex_handle(h);
      std::size_t k = to == corners[0] ? 0 : to == corners[1] ? 1 : 2;
      mesh.set_texcoord2D(h, TriMesh::TexCoord2D(uvs[k][0], uvs[k][1]));
    }
  }
  return mesh;
}

PolygonSoup toSoup(const TriMesh& mesh, const std::string& sourceName) {
  PolygonSoup soup;
  soup.sourceName = sourceName;
  // Deleted elements (before garbage collection) are left out, so indices are renumbered.
  std::vector<std::int64_t> newIndex(mesh.n_vertices(), -1);
  soup.positions.reserve(mesh.n_vertices());
  for (TriMesh::VertexHandle v : mesh.vertices()) {
    newIndex[static_cast<std::size_t>(v.idx())] = static_cast<std::int64_t>(soup.positions.size());
    const TriMesh::Point& p = mesh.point(v);
    soup.positions.push_back({p[0], p[1], p[2]});
  }
  const bool withUVs = mesh.has_halfedge_texcoords2D();
  soup.faces.reserve(mesh.n_faces());
  if (withUVs) soup.cornerUVs.reserve(mesh.n_faces());
  for (TriMesh::FaceHandle f : mesh.faces()) {
    auto& face = soup.faces.emplace_back();
    face.reserve(3);
    std::vector<std::array<double, 2>>* uvs = withUVs ? &soup.cornerUVs.emplace_back() : nullptr;
    for (TriMesh::HalfedgeHandle h : mesh.fh_range(f)) {
      face.push_back(newIndex[static_cast<std::size_t>(mesh.to_vertex_handle(h).idx())]);
      if (uvs) {
        const TriMesh::TexCoord2D& uv = mesh.texcoord2D(h);
        uvs->push_back({uv[0], uv[1]});
      }
    }
  }
  return soup;
}

}  // namespace mspline::structure
