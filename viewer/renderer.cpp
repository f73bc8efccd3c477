#include "mspline/viewer/renderer.h"

#include <algorithm>
#include <string>

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include "mspline/structure/core/errors.h"

namespace mspline::viewer {

namespace {

const char* const kMeshVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 chart;
layout(location = 3) in vec3 color;
uniform mat4 viewMatrix;
uniform mat4 projectionMatrix;
out vec3 eyeNormal;
out vec3 eyePosition;
out vec2 chartPosition;
out vec3 vertexColor;
void main() {
  vec4 e = viewMatrix * vec4(position, 1.0);
  eyePosition = e.xyz;
  eyeNormal = mat3(viewMatrix) * normal;
  chartPosition = chart;
  vertexColor = color;
  gl_Position = projectionMatrix * e;
}
)";

// A headlight: diffuse plus a little specular; both sides of the surface lit alike.
const char* const kMeshFragmentShader = R"(#version 330 core
in vec3 eyeNormal;
in vec3 eyePosition;
in vec2 chartPosition;
in vec3 vertexColor;
uniform int pattern;  // 0 none, 1 checkerboard, 2 parallel lines
uniform float patternScale;
uniform float alpha;
out vec4 fragColor;
void main() {
  vec3 n = normalize(eyeNormal);
  vec3 v = normalize(-eyePosition);
  if (dot(n, v) < 0.0) n = -n;
  vec3 base = vertexColor;
  vec2 c = chartPosition * patternScale;
  if (pattern == 1) {
    vec2 cell = floor(c);
    if (mod(cell.x + cell.y, 2.0) > 0.5) base *= 0.45;
  } else if (pattern == 2) {
    float s = fract(c.x);
    float w = max(fwidth(c.x), 1e-6);
    float line = 1.0 - smoothstep(0.5 * w, 1.5 * w, min(s, 1.0 - s));
    base = mix(base, vec3(0.1, 0.15, 0.45), line);
  }
  float diffuse = max(dot(n, v), 0.0);
  float specular = pow(diffuse, 48.0);
  fragColor = vec4(base * (0.22 + 0.78 * diffuse) + 0.25 * specular, alpha);
}
)";

const char* const kPointVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 color;
uniform mat4 viewMatrix;
uniform mat4 projectionMatrix;
uniform float pointSize;
out vec3 vertexColor;
void main() {
  vertexColor = color;
  gl_Position = projectionMatrix * (viewMatrix * vec4(position, 1.0));
  gl_PointSize = pointSize;
}
)";

// Points are round (a square sprite with its corners discarded); lines use the same shader.
const char* const kPointFragmentShader = R"(#version 330 core
in vec3 vertexColor;
uniform int roundPoints;
out vec4 fragColor;
void main() {
  if (roundPoints == 1 && length(gl_PointCoord - vec2(0.5)) > 0.5) discard;
  fragColor = vec4(vertexColor, 1.0);
}
)";

// Throws IoError with the driver's log (the object deleted) unless `object`'s `status` is set.
void requireStatus(GLuint object, GLenum status, void (*get)(GLuint, GLenum, GLint*),
                   void (*log)(GLuint, GLsizei, GLsizei*, GLchar*), void (*destroy)(GLuint),
                   const std::string& what) {
  GLint ok = 0;
  get(object, status, &ok);
  if (ok) return;
  char text[2048] = {};
  log(object, sizeof text, nullptr, text);
  destroy(object);
  throw structure::IoError("viewer: " + what + ": " + text);
}

GLuint compileShader(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  requireStatus(shader, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
                "a shader does not compile");
  return shader;
}

GLuint linkProgram(const char* vertex, const char* fragment) {
  const GLuint vs = compileShader(GL_VERTEX_SHADER, vertex);
  const GLuint fs = compileShader(GL_FRAGMENT_SHADER, fragment);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  requireStatus(program, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
                "the shaders do not link");
  return program;
}

// Column-major floats for glUniformMatrix4fv.
std::array<float, 16> toFloats(const Eigen::Matrix4d& m) {
  std::array<float, 16> out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[std::size_t(4 * c + r)] = float(m(r, c));
  return out;
}

// A vertex array with its buffers; count is the number of indices (or vertices).
struct Drawable {
  GLuint vao = 0;
  std::vector<GLuint> buffers;
  GLuint indices = 0;
  GLsizei count = 0;

  void create() {
    if (!vao) glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
  }
  GLuint buffer(std::size_t k) {
    while (buffers.size() <= k) {
      GLuint b = 0;
      glGenBuffers(1, &b);
      buffers.push_back(b);
    }
    return buffers[k];
  }
  void destroy() {
    if (!buffers.empty()) glDeleteBuffers(GLsizei(buffers.size()), buffers.data());
    if (indices) glDeleteBuffers(1, &indices);
    if (vao) glDeleteVertexArrays(1, &vao);
    *this = Drawable();
  }
};

void uploadArray(GLuint buffer, GLuint location, int components, const std::vector<float>& data,
                 GLenum usage) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(), usage);
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, 0, nullptr);
}

void uploadIndices(Drawable& d, const std::vector<GLuint>& indices) {
  if (!d.indices) glGenBuffers(1, &d.indices);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d.indices);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(GLuint)), indices.data(),
               GL_STATIC_DRAW);
  d.count = GLsizei(indices.size());
}

// Uploads the 3-float items `items` (ascending) of `data` to `buffer`, items close together in one
// call (a few calls of a few kilobytes cost less than many tiny ones or the whole buffer).
std::size_t uploadItems(GLuint buffer, const std::vector<float>& data, int floatsPerItem,
                        const std::vector<std::int64_t>& items) {
  constexpr std::int64_t kGap = 32;
  std::size_t bytes = 0;
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  for (std::size_t i = 0; i < items.size();) {
    std::size_t j = i;
    while (j + 1 < items.size() && items[j + 1] - items[j] <= kGap) ++j;
    const auto first = std::size_t(items[i]) * std::size_t(floatsPerItem);
    const auto size = (std::size_t(items[j] - items[i]) + 1) * std::size_t(floatsPerItem);
    glBufferSubData(GL_ARRAY_BUFFER, GLintptr(first * sizeof(float)),
                    GLsizeiptr(size * sizeof(float)), data.data() + first);
    bytes += size * sizeof(float);
    i = j + 1;
  }
  return bytes;
}

const std::array<float, 3> kSurfaceColor{0.80f, 0.74f, 0.62f};
const std::array<float, 3> kScanColor{0.45f, 0.55f, 0.70f};
const std::array<float, 3> kNetLineColor{0.15f, 0.15f, 0.18f};
const std::array<float, 3> kPointColor{0.05f, 0.05f, 0.05f};
const std::array<float, 3> kExtraordinaryColor{0.85f, 0.1f, 0.1f};
const std::array<float, 3> kTJunctionColor{0.1f, 0.6f, 0.15f};
const std::array<float, 3> kSelectedColor{1.0f, 0.75f, 0.0f};
const std::array<float, 3> kConeColor{0.75f, 0.0f, 0.75f};

}  // namespace

struct Renderer::Impl {
  GLuint meshProgram = 0, pointProgram = 0;
  Drawable surface, netLines, netPoints, cones, scan;
  // Surface: a drawn vertex per (tessellation vertex, chart coordinates) pair.
  std::vector<float> surfaceData;  // position, normal per drawn vertex
  std::vector<std::int64_t> drawnOffsets;
  std::vector<std::int64_t> drawnVertices;
  // Net: rows shown, in drawn order, and each row's drawn index (-1: not shown).
  std::vector<int> netRows;
  std::vector<int> netIndexOfRow;
  std::vector<float> netPositions;
  std::vector<int> extraordinary, tJunctions;
  GLsizei netLineCount = 0;
  std::vector<float> scanColorsGrey;

  void setMatrices(GLuint program, const Camera& camera) const {
    glUseProgram(program);
    const auto view = toFloats(camera.view());
    const auto projection = toFloats(camera.projection());
    glUniformMatrix4fv(glGetUniformLocation(program, "viewMatrix"), 1, GL_FALSE, view.data());
    glUniformMatrix4fv(glGetUniformLocation(program, "projectionMatrix"), 1, GL_FALSE,
                       projection.data());
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  impl_->meshProgram = linkProgram(kMeshVertexShader, kMeshFragmentShader);
  impl_->pointProgram = linkProgram(kPointVertexShader, kPointFragmentShader);
}

Renderer::~Renderer() {
  for (Drawable* d :
       {&impl_->surface, &impl_->netLines, &impl_->netPoints, &impl_->cones, &impl_->scan})
    d->destroy();
  glDeleteProgram(impl_->meshProgram);
  glDeleteProgram(impl_->pointProgram);
}

void Renderer::setSurface(const MeshGeometry& mesh) {
  Impl& m = *impl_;
  const auto vertices = std::size_t(mesh.positions.rows());
  // Drawn vertices: corners of one vertex share one when their chart coordinates agree.
  std::vector<std::vector<std::pair<std::array<double, 2>, GLuint>>> drawnOf(vertices);
  std::vector<GLuint> indices;
  std::vector<float> uvs;
  std::vector<int> sourceOf;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = std::size_t(mesh.triangles[t][k]);
      const std::array<double, 2> uv =
          mesh.cornerUVs.empty() ? std::array<double, 2>{0.0, 0.0} : mesh.cornerUVs[t][k];
      auto& list = drawnOf[v];
      auto found =
          std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == uv; });
      if (found == list.end()) {
        list.push_back({uv, GLuint(sourceOf.size())});
        sourceOf.push_back(int(v));
        uvs.push_back(float(uv[0]));
        uvs.push_back(float(uv[1]));
        found = list.end() - 1;
      }
      indices.push_back(found->second);
    }
  m.drawnOffsets.assign(vertices + 1, 0);
  m.drawnVertices.clear();
  for (std::size_t v = 0; v < vertices; ++v) {
    for (const auto& e : drawnOf[v]) m.drawnVertices.push_back(std::int64_t(e.second));
    m.drawnOffsets[v + 1] = std::int64_t(m.drawnVertices.size());
  }
  m.surfaceData.assign(sourceOf.size() * 6, 0.0f);
  for (std::size_t d = 0; d < sourceOf.size(); ++d)
    for (int c = 0; c < 3; ++c) {
      m.surfaceData[6 * d + std::size_t(c)] = float(mesh.positions(sourceOf[d], c));
      m.surfaceData[6 * d + 3 + std::size_t(c)] = float(mesh.normals(sourceOf[d], c));
    }
  m.surface.create();
  glBindBuffer(GL_ARRAY_BUFFER, m.surface.buffer(0));
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m.surfaceData.size() * sizeof(float)),
               m.surfaceData.data(), GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  uploadArray(m.surface.buffer(1), 2, 2, uvs, GL_STATIC_DRAW);
  uploadIndices(m.surface, indices);
  glBindVertexArray(0);
}

std::size_t Renderer::updateSurface(const std::vector<int>& vertices,
                                    const Eigen::MatrixX3d& positions,
                                    const Eigen::MatrixX3d& normals) {
  Impl& m = *impl_;
  if (!m.surface.vao || vertices.empty()) return 0;
  std::vector<std::int64_t> drawn;
  for (int v : vertices)
    for (auto k = m.drawnOffsets[std::size_t(v)]; k < m.drawnOffsets[std::size_t(v) + 1]; ++k) {
      const auto d = std::size_t(m.drawnVertices[std::size_t(k)]);
      for (int c = 0; c < 3; ++c) {
        m.surfaceData[6 * d + std::size_t(c)] = float(positions(v, c));
        m.surfaceData[6 * d + 3 + std::size_t(c)] = float(normals(v, c));
      }
      drawn.push_back(std::int64_t(d));
    }
  std::sort(drawn.begin(), drawn.end());
  return uploadItems(m.surface.buffer(0), m.surfaceData, 6, drawn);
}

void Renderer::setNet(const Eigen::MatrixXd& control, const spline::ModelControlNet& net,
                      const std::vector<int>& selection) {
  Impl& m = *impl_;
  m.netRows = net.points;
  m.netIndexOfRow.assign(std::size_t(control.rows()), -1);
  m.netPositions.clear();
  for (std::size_t i = 0; i < m.netRows.size(); ++i) {
    m.netIndexOfRow[std::size_t(m.netRows[i])] = int(i);
    for (int c = 0; c < 3; ++c) m.netPositions.push_back(float(control(m.netRows[i], c)));
  }
  m.extraordinary = net.extraordinary;
  m.tJunctions = net.tJunctions;
  std::vector<GLuint> lines;
  for (const auto& line : net.lines) {
    const int a = m.netIndexOfRow[std::size_t(line[0])], b = m.netIndexOfRow[std::size_t(line[1])];
    if (a < 0 || b < 0) continue;
    lines.push_back(GLuint(a));
    lines.push_back(GLuint(b));
  }
  // Lines and points share the positions buffer.
  m.netPoints.create();
  uploadArray(m.netPoints.buffer(0), 0, 3, m.netPositions, GL_DYNAMIC_DRAW);
  m.netPoints.count = GLsizei(m.netRows.size());
  m.netLines.create();
  glBindBuffer(GL_ARRAY_BUFFER, m.netPoints.buffer(0));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glDisableVertexAttribArray(1);
  uploadIndices(m.netLines, lines);
  glBindVertexArray(0);
  setSelection(selection);
}

std::size_t Renderer::updateNetPoints(const std::vector<int>& rows,
                                      const Eigen::MatrixXd& control) {
  Impl& m = *impl_;
  if (!m.netPoints.vao || rows.empty()) return 0;
  std::vector<std::int64_t> drawn;
  for (int row : rows) {
    const int i = m.netIndexOfRow[std::size_t(row)];
    if (i < 0) continue;
    for (int c = 0; c < 3; ++c)
      m.netPositions[3 * std::size_t(i) + std::size_t(c)] = float(control(row, c));
    drawn.push_back(i);
  }
  std::sort(drawn.begin(), drawn.end());
  return uploadItems(m.netPoints.buffer(0), m.netPositions, 3, drawn);
}

void Renderer::setSelection(const std::vector<int>& selection) {
  Impl& m = *impl_;
  if (!m.netPoints.vao) return;
  std::vector<std::array<float, 3>> colors(m.netRows.size(), kPointColor);
  const auto paint = [&](const std::vector<int>& rows, const std::array<float, 3>& color) {
    for (int row : rows) {
      const int i = m.netIndexOfRow[std::size_t(row)];
      if (i >= 0) colors[std::size_t(i)] = color;
    }
  };
  paint(m.extraordinary, kExtraordinaryColor);
  paint(m.tJunctions, kTJunctionColor);
  paint(selection, kSelectedColor);
  std::vector<float> flat;
  for (const auto& c : colors) flat.insert(flat.end(), c.begin(), c.end());
  glBindVertexArray(m.netPoints.vao);
  uploadArray(m.netPoints.buffer(1), 1, 3, flat, GL_DYNAMIC_DRAW);
  glBindVertexArray(0);
}

void Renderer::setCones(const Eigen::MatrixX3d& points) {
  Impl& m = *impl_;
  std::vector<float> flat;
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    for (int c = 0; c < 3; ++c) flat.push_back(float(points(i, c)));
  m.cones.create();
  uploadArray(m.cones.buffer(0), 0, 3, flat, GL_DYNAMIC_DRAW);
  glDisableVertexAttribArray(1);
  m.cones.count = GLsizei(points.rows());
  glBindVertexArray(0);
}

void Renderer::setScan(const MeshGeometry& scan) {
  Impl& m = *impl_;
  std::vector<float> positions, normals;
  for (Eigen::Index v = 0; v < scan.positions.rows(); ++v)
    for (int c = 0; c < 3; ++c) {
      positions.push_back(float(scan.positions(v, c)));
      normals.push_back(float(scan.normals(v, c)));
    }
  std::vector<GLuint> indices;
  for (const auto& t : scan.triangles)
    for (int v : t) indices.push_back(GLuint(v));
  m.scan.create();
  uploadArray(m.scan.buffer(0), 0, 3, positions, GL_STATIC_DRAW);
  uploadArray(m.scan.buffer(1), 1, 3, normals, GL_STATIC_DRAW);
  glDisableVertexAttribArray(2);
  m.scanColorsGrey.clear();
  for (Eigen::Index v = 0; v < scan.positions.rows(); ++v)
    m.scanColorsGrey.insert(m.scanColorsGrey.end(), kScanColor.begin(), kScanColor.end());
  uploadArray(m.scan.buffer(2), 3, 3, m.scanColorsGrey, GL_DYNAMIC_DRAW);
  uploadIndices(m.scan, indices);
  glBindVertexArray(0);
}

void Renderer::setScanColors(const std::vector<std::array<std::uint8_t, 3>>& colors) {
  Impl& m = *impl_;
  if (!m.scan.vao) return;
  std::vector<float> flat = m.scanColorsGrey;
  if (colors.size() * 3 == flat.size())
    for (std::size_t v = 0; v < colors.size(); ++v)
      for (std::size_t c = 0; c < 3; ++c) flat[3 * v + c] = float(colors[v][c]) / 255.0f;
  glBindVertexArray(m.scan.vao);
  uploadArray(m.scan.buffer(2), 3, 3, flat, GL_DYNAMIC_DRAW);
  glBindVertexArray(0);
}

void Renderer::draw(const Camera& camera, const DisplayOptions& options) {
  Impl& m = *impl_;
  glViewport(0, 0, camera.width, camera.height);
  glClearColor(options.background[0], options.background[1], options.background[2], 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);

  m.setMatrices(m.meshProgram, camera);
  const GLint pattern = glGetUniformLocation(m.meshProgram, "pattern");
  const GLint alpha = glGetUniformLocation(m.meshProgram, "alpha");
  glUniform1f(glGetUniformLocation(m.meshProgram, "patternScale"), float(options.patternScale));
  if (options.surface && m.surface.vao) {
    // Pushed back a little so that net lines lying on the surface stay visible.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    glUniform1i(pattern, options.checker ? 1 : options.lines ? 2 : 0);
    glUniform1f(alpha, 1.0f);
    glBindVertexArray(m.surface.vao);
    glVertexAttrib3f(3, kSurfaceColor[0], kSurfaceColor[1], kSurfaceColor[2]);
    glDrawElements(GL_TRIANGLES, m.surface.count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }

  m.setMatrices(m.pointProgram, camera);
  const GLint round = glGetUniformLocation(m.pointProgram, "roundPoints");
  const GLint size = glGetUniformLocation(m.pointProgram, "pointSize");
  glEnable(GL_PROGRAM_POINT_SIZE);
  if (options.net && m.netLines.vao) {
    glUniform1i(round, 0);
    glUniform1f(size, 1.0f);
    glBindVertexArray(m.netLines.vao);
    glVertexAttrib3f(1, kNetLineColor[0], kNetLineColor[1], kNetLineColor[2]);
    glDrawElements(GL_LINES, m.netLines.count, GL_UNSIGNED_INT, nullptr);
    glUniform1i(round, 1);
    glUniform1f(size, 6.0f);
    glBindVertexArray(m.netPoints.vao);
    glDrawArrays(GL_POINTS, 0, m.netPoints.count);
  }
  if (options.cones && m.cones.vao && m.cones.count > 0) {
    glUniform1i(round, 1);
    glUniform1f(size, 11.0f);
    glBindVertexArray(m.cones.vao);
    glVertexAttrib3f(1, kConeColor[0], kConeColor[1], kConeColor[2]);
    glDrawArrays(GL_POINTS, 0, m.cones.count);
  }

  if (options.scan && m.scan.vao) {
    m.setMatrices(m.meshProgram, camera);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glUniform1i(pattern, 0);
    glUniform1f(alpha, options.errors ? std::max(options.scanAlpha, 0.85f) : options.scanAlpha);
    glBindVertexArray(m.scan.vao);
    glDrawElements(GL_TRIANGLES, m.scan.count, GL_UNSIGNED_INT, nullptr);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
}

std::vector<std::uint8_t> readPixels(int width, int height) {
  std::vector<std::uint8_t> rgb(std::size_t(width) * std::size_t(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  // OpenGL's rows run bottom to top.
  std::vector<std::uint8_t> flipped(rgb.size());
  const std::size_t row = std::size_t(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(rgb.data() + std::size_t(height - 1 - y) * row, row,
                flipped.data() + std::size_t(y) * row);
  return flipped;
}

}  // namespace mspline::viewer
