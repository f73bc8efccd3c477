#pragma once
// Draws the scene with OpenGL 3.3 core: the shaded surface (optionally a checkerboard or parallel
// lines of its chart coordinates), the control net's points and lines, cone points, and the scan
// (transparent, optionally colored by its error). Needs a current context; buffers are updated in
// place where control points moved.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/model/model_surface.h"
#include "mspline/viewer/camera.h"

namespace mspline::viewer {

struct DisplayOptions {
  bool surface = true;
  bool net = true;
  bool scan = true;
  bool checker = false;
  bool lines = false;
  bool cones = true;
  /// Scan vertex colors from the error map instead of plain grey.
  bool errors = false;
  float scanAlpha = 0.35f;
  /// Checker squares (and lines) per unit of chart coordinates.
  double patternScale = 1.0;
  std::array<float, 3> background{1.0f, 1.0f, 1.0f};
};

/// A triangle mesh to show: per-vertex positions and normals, triangles, and per corner of every
/// triangle its chart coordinates (or none).
struct MeshGeometry {
  Eigen::MatrixX3d positions, normals;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::array<double, 2>, 3>> cornerUVs;
};

class Renderer {
 public:
  /// Compiles the shaders; throws IoError with the compiler's log when that fails.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void setSurface(const MeshGeometry& surface);
  /// Uploads the positions and normals of `vertices` (ascending); returns the bytes sent.
  std::size_t updateSurface(const std::vector<int>& vertices, const Eigen::MatrixX3d& positions,
                            const Eigen::MatrixX3d& normals);
  void setNet(const Eigen::MatrixXd& control, const spline::ModelControlNet& net,
              const std::vector<int>& selection);
  /// Uploads the moved control points `rows`; returns the bytes sent.
  std::size_t updateNetPoints(const std::vector<int>& rows, const Eigen::MatrixXd& control);
  void setSelection(const std::vector<int>& selection);
  void setCones(const Eigen::MatrixX3d& points);
  void setScan(const MeshGeometry& scan);
  /// Per scan vertex, its error color (empty: none).
  void setScanColors(const std::vector<std::array<std::uint8_t, 3>>& colors);

  /// Draws into the bound framebuffer (camera.width x camera.height pixels).
  void draw(const Camera& camera, const DisplayOptions& options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads the bound framebuffer's pixels (RGB, top row first).
std::vector<std::uint8_t> readPixels(int width, int height);

}  // namespace mspline::viewer
