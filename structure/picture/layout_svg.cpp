#include "mspline/structure/picture/layout_svg.h"

#include <algorithm>
#include <limits>
#include <sstream>
#include <vector>

#include <Eigen/Core>

#include "mspline/structure/core/errors.h"

namespace mspline::structure {

SvgFrame SvgFrame::fit(const Eigen::Vector2d& low, const Eigen::Vector2d& high,
                       double drawingWidth) {
  SvgFrame frame;
  frame.low = low;
  frame.top = high.y();
  const Eigen::Vector2d extent = (high - low).cwiseMax(1e-300);
  frame.scale = drawingWidth / extent.x();
  frame.width = drawingWidth + 2 * frame.margin;
  frame.height = extent.y() * frame.scale + 2 * frame.margin;
  return frame;
}

std::vector<Eigen::Vector2d> coverShifts(const FlatLayout& layout, int radius) {
  std::vector<Eigen::Vector2d> shifts;
  for (int i = -radius; i <= radius; ++i)
    for (int j = -radius; j <= radius; ++j)
      shifts.push_back(i * layout.periods[0] + j * layout.periods[1]);
  return shifts;
}

std::array<Eigen::Vector2d, 2> shiftedBounds(const FlatLayout& layout,
                                             const std::vector<Eigen::Vector2d>& shifts) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  for (const Eigen::Vector2d& s : shifts)
    for (Eigen::Index k = 0; k < layout.cornerUV.rows(); ++k) {
      const Eigen::Vector2d p = layout.cornerUV.row(k).transpose() + s;
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  return {low, high};
}

std::string layoutSvg(const TriMesh& mesh, const FlatLayout& layout,
                      const LayoutSvgOptions& options) {
  if (options.coverRadius < 0) throw InputError("svg: negative cover radius");
  if (options.coverRadius > 0 && !layout.hasPeriods)
    throw InputError("svg: the universal cover needs a layout with periods (flat torus)");
  MSPLINE_ASSERT(layout.cornerUV.rows() == static_cast<Eigen::Index>(3 * mesh.n_faces()),
                 "layout does not belong to this mesh");

  const std::vector<Eigen::Vector2d> shifts = coverShifts(layout, options.coverRadius);
  auto [low, high] = shiftedBounds(layout, shifts);
  const SvgFrame frame = SvgFrame::fit(low, high, options.width);
  const double width = frame.width, height = frame.height;

  std::ostringstream svg;
  svg.precision(7);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << ' ' << height << "\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  auto corner = [&](int f, int k, const Eigen::Vector2d& s) {
    return frame(layout.cornerUV.row(3 * f + k).transpose() + s);
  };
  for (const Eigen::Vector2d& s : shifts) {
    const bool home = s.isZero(0.0);
    svg << "<g fill=\"" << (home ? "#b8d4f0" : "#e8eef5")
        << "\" stroke=\"#4a5a6a\" stroke-width=\"0.3\">\n";
    for (auto f : mesh.faces()) {
      svg << "<polygon points=\"";
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d p = corner(f.idx(), k, s);
        svg << (k ? " " : "") << p.x() << ',' << p.y();
      }
      svg << "\"/>\n";
    }
    svg << "</g>\n";
  }

  // Seams (both sides) and the surface boundary, on the layout's own copy.
  auto edgeLine = [&](TriMesh::HalfedgeHandle h, const char* colour, double strokeWidth) {
    const int f = mesh.face_handle(h).idx();
    int k = 0;
    for (auto g = mesh.halfedge_handle(mesh.face_handle(h)); g != h;
         g = mesh.next_halfedge_handle(g))
      ++k;
    const Eigen::Vector2d a = corner(f, (k + 2) % 3, Eigen::Vector2d::Zero());
    const Eigen::Vector2d b = corner(f, k, Eigen::Vector2d::Zero());
    svg << "<line x1=\"" << a.x() << "\" y1=\"" << a.y() << "\" x2=\"" << b.x() << "\" y2=\""
        << b.y() << "\" stroke=\"" << colour << "\" stroke-width=\"" << strokeWidth << "\"/>\n";
  };
  for (int e : layout.cutEdges)
    for (int side = 0; side < 2; ++side)
      edgeLine(mesh.halfedge_handle(TriMesh::EdgeHandle(e), side), "#d62728", 1.5);
  for (auto h : mesh.halfedges())
    if (mesh.is_boundary(h)) edgeLine(mesh.opposite_halfedge_handle(h), "black", 1.5);

  if (layout.hasPeriods) {
    svg << "<path fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"2\" d=\"";
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d p = frame(layout.fundamentalParallelogram[k]);
      svg << (k ? " L " : "M ") << p.x() << ' ' << p.y();
    }
    svg << " Z\"/>\n";
  }

  std::vector<char> isCone(mesh.n_vertices(), 0);
  for (const Cone& c : layout.cones) isCone[c.vertex] = 1;
  for (Eigen::Index k = 0; k < layout.chartPositions.rows(); ++k) {
    if (!isCone[layout.chartSourceVertex[k]]) continue;
    const Eigen::Vector2d p = frame(layout.chartPositions.row(k).transpose());
    svg << "<circle cx=\"" << p.x() << "\" cy=\"" << p.y() << "\" r=\"4\" fill=\"#1f3fbf\"/>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace mspline::structure
