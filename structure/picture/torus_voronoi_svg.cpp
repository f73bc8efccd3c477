#include "mspline/structure/picture/torus_voronoi_svg.h"

#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Core>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/picture/layout_svg.h"

namespace mspline::structure {

namespace {

// Hues a golden angle apart, so that neighbouring labels differ.
std::string cellColour(int label, bool home) {
  std::ostringstream colour;
  colour << "hsl(" << std::fmod(label * 137.508, 360.0) << ",60%," << (home ? 60 : 82) << "%)";
  return colour.str();
}

}  // namespace

std::string torusVoronoiSvg(const TriMesh& mesh, const FlatLayout& layout,
                            const std::vector<SurfacePoint>& sites, const TorusVoronoi& voronoi,
                            const TorusVoronoiSvgOptions& options) {
  if (options.coverRadius < 0) throw InputError("svg: negative cover radius");
  if (!layout.hasPeriods) throw InputError("svg: a flat torus needs a layout with periods");
  MSPLINE_ASSERT(layout.cornerUV.rows() == static_cast<Eigen::Index>(3 * mesh.n_faces()) &&
                     voronoi.faceLabel.size() == mesh.n_faces(),
                 "layout or diagram does not belong to this mesh");

  const std::vector<Eigen::Vector2d> shifts = coverShifts(layout, options.coverRadius);
  auto [low, high] = shiftedBounds(layout, shifts);
  for (const Eigen::Vector2d& corner : layout.fundamentalParallelogram) {
    low = low.cwiseMin(corner);
    high = high.cwiseMax(corner);
  }
  const SvgFrame frame = SvgFrame::fit(low, high, options.width);
  const double width = frame.width, height = frame.height;
  auto at = [&](const SurfacePoint& p, const Eigen::Vector2d& shift) {
    return frame(layout.cornerUV.middleRows(3 * p.face, 3).transpose() * p.barycentric + shift);
  };

  std::ostringstream svg;
  svg.precision(7);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << ' ' << height << "\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const Eigen::Vector2d& s : shifts) {
    const bool home = s.isZero(0.0);
    svg << "<g stroke-width=\"0.4\">\n";
    for (auto f : mesh.faces()) {
      const std::string colour = cellColour(voronoi.faceLabel[f.idx()], home);
      svg << "<polygon fill=\"" << colour << "\" stroke=\"" << colour << "\" points=\"";
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d p = frame(layout.cornerUV.row(3 * f.idx() + k).transpose() + s);
        svg << (k ? " " : "") << p.x() << ',' << p.y();
      }
      svg << "\"/>\n";
    }
    svg << "</g>\n<g stroke=\"black\" stroke-width=\"1.2\">\n";
    for (const VoronoiSegment& segment : voronoi.segments) {
      const Eigen::Vector2d a = at(segment.ends[0], s), b = at(segment.ends[1], s);
      svg << "<line x1=\"" << a.x() << "\" y1=\"" << a.y() << "\" x2=\"" << b.x() << "\" y2=\""
          << b.y() << "\"/>\n";
    }
    svg << "</g>\n";
  }
  svg << "<path fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"2\" d=\"";
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d p = frame(layout.fundamentalParallelogram[k]);
    svg << (k ? " L " : "M ") << p.x() << ' ' << p.y();
  }
  svg << " Z\"/>\n";
  for (const Eigen::Vector2d& s : shifts)
    for (const SurfacePoint& site : sites) {
      const Eigen::Vector2d p = at(site, s);
      svg << "<circle cx=\"" << p.x() << "\" cy=\"" << p.y()
          << "\" r=\"3.5\" fill=\"black\" stroke=\"white\"/>\n";
    }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace mspline::structure
