#include "mspline/io/write_labeled_mesh.h"

#include <algorithm>
#include <numeric>

#include "mspline/io/atomic_file.h"
#include "mspline/io/detail/output_buffer.h"
#include "mspline/io/read_mesh.h"
#include "mspline/structure/core/errors.h"

namespace mspline::io {

void writeLabeledObj(const std::string& path, const structure::TriMesh& mesh,
                     const std::vector<int>& faceLabels, const std::string& labelPrefix,
                     const std::vector<LabeledPolyline>& polylines) {
  using structure::InputError;
  if (meshFormatFromPath(path) != MeshFormat::Obj)
    throw InputError("cannot write '" + path + "': labeled meshes are written as OBJ");
  if (faceLabels.size() != mesh.n_faces() ||
      std::any_of(faceLabels.begin(), faceLabels.end(), [](int label) { return label < 0; }))
    throw InputError("cannot write '" + path + "': the face labels are not one per face, >= 0");
  for (const LabeledPolyline& line : polylines)
    if (line.points.size() < 2)
      throw InputError("cannot write '" + path + "': polyline '" + line.group +
                       "' has fewer than two points");

  std::vector<int> order(mesh.n_faces());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return faceLabels[a] < faceLabels[b]; });
  writeFileAtomically(path, [&](std::ostream& out) {
    detail::OutputBuffer buffer(out);
    for (auto v : mesh.vertices()) {
      const auto& p = mesh.point(v);
      buffer.text("v ");
      buffer.pointLine({p[0], p[1], p[2]});
    }
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int label = faceLabels[order[i]];
      if (i == 0 || label != faceLabels[order[i - 1]]) {
        buffer.text("g " + labelPrefix);
        buffer.integer(label);
        buffer.character('\n');
      }
      buffer.character('f');
      for (auto v : mesh.fv_range(structure::TriMesh::FaceHandle(order[i]))) {
        buffer.character(' ');
        buffer.integer(v.idx() + 1);
      }
      buffer.character('\n');
    }
    std::int64_t next = static_cast<std::int64_t>(mesh.n_vertices()) + 1;
    for (const LabeledPolyline& line : polylines) {
      const bool closed = line.points.back() == line.points.front();
      const std::size_t count = line.points.size() - (closed ? 1 : 0);
      buffer.text("g " + line.group + "\n");
      for (std::size_t k = 0; k < count; ++k) {
        buffer.text("v ");
        buffer.pointLine({line.points[k].x(), line.points[k].y(), line.points[k].z()});
      }
      buffer.character('l');
      for (std::size_t k = 0; k < line.points.size(); ++k) {
        buffer.character(' ');
        buffer.integer(next + static_cast<std::int64_t>(k % count));
      }
      buffer.character('\n');
      next += static_cast<std::int64_t>(count);
    }
    buffer.flush();
  });
}

}  // namespace mspline::io
