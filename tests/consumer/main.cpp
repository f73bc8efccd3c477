// Uses the installed library: loads a model, evaluates it, fits a scan. Exits 1 on any failure.
// Usage: consumer MODEL.msp SCAN.off
#include <cmath>
#include <iostream>
#include <stdexcept>

#include <mspline/io/load_mesh.h>
#include <mspline/io/spline_model_file.h>
#include <mspline/spline/model/fit_scan.h>
#include <mspline/spline/model/model_surface.h>

using namespace mspline;

int main(int argc, char** argv) try {
  if (argc != 3) throw std::invalid_argument("usage: consumer MODEL.msp SCAN.off");
  const spline::SplineModel model = io::readSplineModel(argv[1]);
  const spline::ModelSurface surface(model, argv[1]);
  const auto points = surface.tessellate(model.controlPoints, 2).mesh.positions;
  for (const auto& p : points)
    if (!std::isfinite(p[0] + p[1] + p[2])) throw std::runtime_error("non-finite surface point");
  std::cout << surface.kindName() << " surface: " << points.size() << " vertices, the first at ("
            << points.at(0)[0] << ", " << points[0][1] << ", " << points[0][2] << ")\n";

  spline::FitOptions options;
  options.maxControl = 400;
  options.flatten.name = argv[2];
  const spline::FitResult fit = spline::fitScan(*io::loadMesh(argv[2]).mesh, options);
  if (!fit.model.controlPoints.allFinite()) throw std::runtime_error("non-finite control point");
  std::cout << "fit: " << fit.model.controlPoints.rows() << " control points\n";
  return 0;
} catch (const std::exception& e) {
  std::cerr << "consumer: " << e.what() << '\n';
  return 1;
}
