#include "mspline/spline/tspline/tspline_fit_space.h"

#include <algorithm>
#include <array>

#include "mspline/spline/tspline/tmesh_walk.h"

namespace mspline::spline {

TSplineFitSpace::TSplineFitSpace(const TSplineSpace& space, const Eigen::VectorXd& weights)
    : space_(space), weights_(weights) {}

void TSplineFitSpace::basisAt(const FacePoint& p, std::vector<FitBasisTerm>& out,
                              int derivatives) const {
  thread_local std::vector<TSplineBasisValue> raw;
  out.clear();
  space_.basisAt(p.face, p.position, raw, derivatives);
  // The denominator W = sum w N and its derivatives; R = w N / W by the quotient rule.
  double w = 0.0, ws = 0.0, wt = 0.0, wss = 0.0, wst = 0.0, wtt = 0.0;
  const auto weightOf = [&](int anchor) { return weights_.size() > 0 ? weights_[anchor] : 1.0; };
  for (const auto& b : raw) {
    const double c = weightOf(b.anchor);
    w += c * b.value;
    ws += c * b.ds;
    wt += c * b.dt;
    wss += c * b.dss;
    wst += c * b.dst;
    wtt += c * b.dtt;
  }
  if (!(w > 0.0)) return;
  for (const auto& b : raw) {
    const double c = weightOf(b.anchor);
    FitBasisTerm term;
    term.index = b.anchor;
    term.value = c * b.value / w;
    if (derivatives >= 1) {
      term.ds = (c * b.ds - term.value * ws) / w;
      term.dt = (c * b.dt - term.value * wt) / w;
    }
    if (derivatives >= 2) {
      term.dss = (c * b.dss - 2.0 * term.ds * ws - term.value * wss) / w;
      term.dtt = (c * b.dtt - 2.0 * term.dt * wt - term.value * wtt) / w;
      term.dst = (c * b.dst - term.ds * wt - term.dt * ws - term.value * wst) / w;
    }
    out.push_back(term);
  }
}

FacePoint TSplineFitSpace::walk(const FacePoint& p, const Eigen::Vector2d& step) const {
  const FacePoint end = walkTMesh(space_.mesh(), FacePoint{p.face, p.position}, step);
  return {end.face, end.position};
}

double tmeshFaceSize(const TMesh& mesh, int face) {
  const TMeshFace& f = mesh.faces.at(std::size_t(face));
  return std::max(f.width, f.height);
}

void tmeshQuadrature(const TMesh& mesh, std::vector<FacePoint>& nodes,
                     std::vector<double>& weights) {
  // Gauss-Legendre, 4 points on [0, 1].
  const std::array<double, 4> x{0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                                0.9305681557970263};
  const std::array<double, 4> w{0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                                0.1739274225687269};
  nodes.clear();
  weights.clear();
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const double width = mesh.faces[std::size_t(f)].width,
                 height = mesh.faces[std::size_t(f)].height;
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) {
        nodes.push_back({f, Eigen::Vector2d(x[i] * width, x[j] * height)});
        weights.push_back(w[i] * w[j] * width * height);
      }
  }
}

double TSplineFitSpace::faceSize(int face) const {
  return tmeshFaceSize(space_.mesh(), face);
}

void TSplineFitSpace::quadrature(std::vector<FacePoint>& nodes,
                                 std::vector<double>& weights) const {
  tmeshQuadrature(space_.mesh(), nodes, weights);
}

}  // namespace mspline::spline
