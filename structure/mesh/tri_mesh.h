#pragma once
// The project's triangle mesh: OpenMesh with double precision and the attributes algorithms need.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace mspline::structure {

struct TriMeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<TriMeshTraits>;

}  // namespace mspline::structure
