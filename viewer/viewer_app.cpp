#include "mspline/viewer/viewer_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#define GL_GLEXT_PROTOTYPES
#define GLFW_INCLUDE_GLCOREARB
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "mspline/io/error_map.h"
#include "mspline/io/export_model.h"
#include "mspline/io/raster_image.h"
#include "mspline/io/read_mesh.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/spline/model/filled_faces.h"
#include "mspline/spline/tribspline/tessellate.h"
#include "mspline/structure/core/errors.h"
#include "mspline/structure/mesh/closest_point.h"
#include "mspline/structure/mesh/polygon_soup.h"
#include "mspline/viewer/controller.h"
#include "mspline/viewer/edit_script.h"
#include "mspline/viewer/edit_session.h"

namespace mspline::viewer {

namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bool isModelPath(const std::string& path) {
  return std::filesystem::path(path).extension() == ".msp";
}

// A mesh shown as it is (the scan, or a mesh without a model).
struct PlainMesh {
  std::string path;
  MeshGeometry geometry;
};

PlainMesh readPlainMesh(const std::string& path) {
  io::MeshReadResult read = io::readMesh(path);
  structure::triangulatePolygons(read.soup);
  if (read.soup.faces.empty()) throw structure::InputError(path + ": the mesh has no faces");
  PlainMesh out{path, {}};
  MeshGeometry& g = out.geometry;
  g.positions = structure::pointMatrix(read.soup.positions);
  g.normals = structure::pointMatrix(spline::vertexNormalsOfMesh(read.soup));
  g.triangles = structure::triangleIndices(read.soup);
  if (read.soup.cornerUVs.size() == read.soup.faces.size())
    for (const auto& uv : read.soup.cornerUVs) g.cornerUVs.push_back({uv[0], uv[1], uv[2]});
  return out;
}

MeshGeometry surfaceGeometry(const EditSession& session) {
  MeshGeometry g;
  const spline::ModelTessellation& t = session.tessellation();
  g.positions = session.positions();
  g.normals = session.normals();
  g.triangles = structure::triangleIndices(t.mesh);
  const bool corners = t.mesh.cornerUVs.size() == t.mesh.faces.size();
  for (std::size_t f = 0; f < g.triangles.size(); ++f) {
    std::array<std::array<double, 2>, 3> uv{};
    for (std::size_t k = 0; k < 3; ++k)
      uv[k] = corners ? t.mesh.cornerUVs[f][k] : t.uvs[std::size_t(g.triangles[f][k])];
    g.cornerUVs.push_back(uv);
  }
  return g;
}

// Checker squares per chart unit: 2 x 2 on a typical face (every face has a frame of its own).
double patternScaleOf(const MeshGeometry& g, int resolution) {
  std::vector<double> lengths;
  for (const auto& uv : g.cornerUVs)
    lengths.push_back(std::hypot(uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]));
  if (lengths.empty()) return 1.0;
  std::nth_element(lengths.begin(), lengths.begin() + std::ptrdiff_t(lengths.size() / 2),
                   lengths.end());
  const double faceSide = lengths[lengths.size() / 2] * resolution;
  return faceSide > 0.0 ? 2.0 / faceSide : 1.0;
}

struct Timings {
  std::vector<double> evaluate, upload, render, vertices;
  static Json summary(std::vector<double> values, double scale) {
    if (values.empty()) return nullptr;
    double sum = 0.0, largest = 0.0;
    for (double v : values) {
      sum += v * scale;
      largest = std::max(largest, v * scale);
    }
    std::sort(values.begin(), values.end());
    return {{"mean", sum / double(values.size())},
            {"median", values[values.size() / 2] * scale},
            {"max", largest}};
  }
};

// An off-screen framebuffer (4x multisampled, resolved into a plain one for reading).
class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height) : width_(width), height_(height) {
    glGenFramebuffers(2, framebuffers_);
    glGenRenderbuffers(3, renderbuffers_);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[0]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[1]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_DEPTH_COMPONENT24, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              renderbuffers_[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              renderbuffers_[1]);
    const GLenum multisampled = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[2]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[1]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              renderbuffers_[2]);
    const GLenum resolved = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (multisampled != GL_FRAMEBUFFER_COMPLETE || resolved != GL_FRAMEBUFFER_COMPLETE)
      throw structure::IoError("viewer: cannot make an off-screen framebuffer of " +
                               std::to_string(width) + " x " + std::to_string(height));
  }
  ~OffscreenTarget() {
    glDeleteFramebuffers(2, framebuffers_);
    glDeleteRenderbuffers(3, renderbuffers_);
  }
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  void bind() const { glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[0]); }
  std::vector<std::uint8_t> read() const {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffers_[0]);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffers_[1]);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffers_[1]);
    std::vector<std::uint8_t> pixels = readPixels(width_, height_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return pixels;
  }

 private:
  int width_, height_;
  GLuint framebuffers_[2] = {0, 0};
  GLuint renderbuffers_[3] = {0, 0, 0};
};

std::string glfwErrorMessage;

class Viewer {
 public:
  explicit Viewer(const ViewerOptions& options) : options_(options) {
    load();
    if (options_.display)
      display_ = *options_.display;
    else
      display_.scan = scan_.has_value();
    openWindow();
    renderer_ = std::make_unique<Renderer>();
    uploadScene();
    camera_.width = options_.width;
    camera_.height = options_.height;
    camera_.fitTo(low_, high_);
    if (options_.camera) {
      camera_.azimuth = (*options_.camera)[0];
      camera_.elevation = (*options_.camera)[1];
      camera_.distance *= (*options_.camera)[2];
    }
    controller_ = std::make_unique<Controller>(camera_, session_.get());
    lastAutosave_ = Clock::now();
  }

  ~Viewer() {
    if (imgui_) {
      ImGui_ImplOpenGL3_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
    target_.reset();
    renderer_.reset();
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
  }

  Json run() {
    Json report;
    report["files"] = options_.files;
    describeScene(report);
    if (!options_.apply.empty()) report["edits"] = runScript();
    if (!options_.screenshot.empty()) report["screenshot"] = screenshot();
    if (options_.apply.empty() && options_.screenshot.empty()) interactive();
    if (session_) report["autosaves"] = autosaves_;
    return report;
  }

 private:
  void load() {
    if (options_.files.empty() || options_.files.size() > 2)
      throw structure::InputError("view: give one or two files (a mesh, a .msp model, or both)");
    for (const std::string& path : options_.files) {
      if (isModelPath(path)) {
        if (session_)
          throw structure::InputError(path + ": a second model (give a scan and one model)");
        EditSessionOptions sessionOptions;
        sessionOptions.resolution = options_.resolution;
        session_ = std::make_unique<EditSession>(io::readSplineModel(path), path, sessionOptions);
        if (!options_.output.empty()) session_->setPath(options_.output);
        const std::string autosave = EditSession::autosavePath(session_->path());
        std::error_code error;
        if (std::filesystem::exists(autosave, error) && !options_.quiet)
          std::cerr << "view: note: " << autosave
                    << " holds edits that were not saved (open it to recover them)\n";
      } else {
        if (scan_) throw structure::InputError(path + ": a second mesh (give a mesh and a model)");
        scan_ = readPlainMesh(path);
      }
    }
    if (!options_.output.empty() && !session_)
      throw structure::InputError("view: -o needs a .msp model to save");
    if (!options_.apply.empty() && !session_)
      throw structure::InputError("view: --apply needs a .msp model to edit");
    if (session_ && scan_)
      keptFaces_ = spline::facesToKeep(session_->tessellation().mesh, session_->model());
    if (!options_.apply.empty())
      script_ = readEditScript(options_.apply, int(session_->model().controlPoints.rows()));
    const Eigen::MatrixX3d& shown = session_ ? session_->positions() : scan_->geometry.positions;
    low_ = shown.colwise().minCoeff().transpose();
    high_ = shown.colwise().maxCoeff().transpose();
  }

  void openWindow() {
    glfwSetErrorCallback([](int, const char* message) { glfwErrorMessage = message; });
    if (!glfwInit())
      throw structure::IoError("view: cannot start GLFW (" + glfwErrorMessage +
                               "); is there a display? Headless: run under xvfb-run");
    const bool headless = !options_.apply.empty() || !options_.screenshot.empty();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_VISIBLE, headless ? GLFW_FALSE : GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    const std::string title = "mspline view " + options_.files.front();
    window_ = glfwCreateWindow(headless ? 64 : options_.width, headless ? 64 : options_.height,
                               title.c_str(), nullptr, nullptr);
    if (!window_)
      throw structure::IoError("view: cannot open an OpenGL 3.3 window (" + glfwErrorMessage + ")");
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(1);
    if (headless) target_ = std::make_unique<OffscreenTarget>(options_.width, options_.height);
  }

  void uploadScene() {
    if (session_) {
      const MeshGeometry surface = surfaceGeometry(*session_);
      display_.patternScale = patternScaleOf(surface, options_.resolution);
      renderer_->setSurface(surface);
      renderer_->setNet(session_->model().controlPoints, session_->net(), {});
      updateCones();
    } else if (scan_) {
      // A mesh without a model is shown as the surface.
      display_.patternScale = patternScaleOf(scan_->geometry, 1);
      renderer_->setSurface(scan_->geometry);
      display_.scan = false;
      display_.net = false;
    }
    if (session_ && scan_) renderer_->setScan(scan_->geometry);
  }

  void updateCones() {
    const auto& cones = session_->tessellation().coneVertices;
    Eigen::MatrixX3d points(Eigen::Index(cones.size()), 3);
    for (std::size_t i = 0; i < cones.size(); ++i)
      points.row(Eigen::Index(i)) = session_->positions().row(Eigen::Index(cones[i]));
    renderer_->setCones(points);
  }

  void describeScene(Json& report) const {
    if (session_) {
      const spline::SplineModel& model = session_->model();
      const spline::ModelControlNet& net = session_->net();
      report["model"] = {{"path", session_->path()},
                         {"kind", session_->surface().kindName()},
                         {"control_points", model.controlPoints.rows()},
                         {"net_points", net.points.size()},
                         {"net_lines", net.lines.size()},
                         {"extraordinary_points", net.extraordinary.size()},
                         {"t_junctions", net.tJunctions.size()},
                         {"surface_vertices", session_->positions().rows()},
                         {"surface_triangles", session_->tessellation().mesh.faces.size()},
                         {"cone_points", session_->tessellation().coneVertices.size()},
                         {"resolution", options_.resolution}};
    }
    if (scan_)
      report["mesh"] = {{"path", scan_->path},
                        {"vertices", scan_->geometry.positions.rows()},
                        {"triangles", scan_->geometry.triangles.size()}};
  }

  // Sends what the last change moved to the GPU; returns the seconds it took (0 when nothing
  // changed since the last upload).
  double uploadChanges() {
    if (!session_ || session_->changeCount() == uploadedChanges_) return 0.0;
    uploadedChanges_ = session_->changeCount();
    const auto start = Clock::now();
    renderer_->updateSurface(session_->changedVertices(), session_->positions(),
                             session_->normals());
    renderer_->updateNetPoints(session_->changedRows(), session_->model().controlPoints);
    if (!session_->tessellation().coneVertices.empty()) updateCones();
    return secondsSince(start);
  }

  void syncSelection() {
    if (!session_ || controller_->selection() == shownSelection_) return;
    shownSelection_ = controller_->selection();
    renderer_->setSelection(shownSelection_);
  }

  void updateErrorMap() {
    if (!scan_ || !session_ || !display_.errors || session_->dragging()) return;
    if (errorState_ == session_->state() && !errorColors_.empty()) return;
    // As `mspline export --error-map`: against the surface over the scan, the fills trimmed.
    const std::vector<std::array<int, 3>> all =
        structure::triangleIndices(session_->tessellation().mesh);
    std::vector<std::array<int, 3>> triangles;
    for (std::size_t f = 0; f < all.size(); ++f)
      if (keptFaces_[f]) triangles.push_back(all[f]);
    const structure::TriangleMeshDistance distance(session_->positions(), std::move(triangles));
    const io::ErrorMap map = io::errorMap(scan_->geometry.positions, distance);
    errorColors_ = map.colors;
    errorRms_ = map.rms;
    errorMax_ = map.max;
    errorState_ = session_->state();
    renderer_->setScanColors(errorColors_);
  }

  void autosaveTick() {
    if (!session_ || session_->dragging()) return;
    if (secondsSince(lastAutosave_) < options_.autosaveSeconds) return;
    lastAutosave_ = Clock::now();
    if (session_->autosave()) {
      ++autosaves_;
      if (!options_.quiet)
        std::cerr << "view: autosaved " << EditSession::autosavePath(session_->path()) << "\n";
    }
  }

  // One off-screen frame: the scene drawn and finished (so its time is the renderer's).
  void drawOffscreen() {
    target_->bind();
    renderer_->draw(camera_, display_);
    glFinish();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  Json runScript() {
    Timings timings;
    int frames = 0;
    const auto frame = [&] {
      ++frames;
      const double upload = uploadChanges();
      syncSelection();
      const auto start = Clock::now();
      drawOffscreen();
      if (session_->dragging()) {
        timings.evaluate.push_back(session_->lastEvaluationSeconds());
        timings.upload.push_back(upload);
        timings.render.push_back(secondsSince(start));
        timings.vertices.push_back(double(session_->changedVertices().size()));
      }
      autosaveTick();
    };
    const auto start = Clock::now();
    for (std::size_t i = 0; i < script_.size(); ++i) {
      if (!options_.quiet) std::cerr << "view: edit " << i + 1 << " of " << script_.size() << "\n";
      runScriptedEdit(script_[i], i + 1, *controller_, *session_, camera_, frame);
    }
    session_->save();
    if (!options_.quiet) std::cerr << "view: saved " << session_->path() << "\n";
    return {{"applied", script_.size()},
            {"frames", frames},
            {"seconds", secondsSince(start)},
            {"undo_steps", session_->undoSteps()},
            {"saved", session_->path()},
            {"backup", session_->path() + ".bak"},
            {"drag_frames", timings.evaluate.size()},
            {"evaluate_ms", Timings::summary(timings.evaluate, 1e3)},
            {"upload_ms", Timings::summary(timings.upload, 1e3)},
            {"render_ms", Timings::summary(timings.render, 1e3)},
            {"vertices_per_frame", Timings::summary(timings.vertices, 1.0)},
            {"note",
             "per drag frame: evaluate = re-evaluating the moved control points' supports (CPU), "
             "upload = writing them into the OpenGL buffers, render = drawing the frame and "
             "glFinish (Mesa)"}};
  }

  Json screenshot() {
    updateErrorMap();
    syncSelection();
    drawOffscreen();
    const std::vector<std::uint8_t> pixels = target_->read();
    io::RasterImage image(options_.width, options_.height, io::Rgb{});
    std::size_t background = 0;
    const auto bg = [&](float c) { return std::uint8_t(std::lround(c * 255.0f)); };
    const io::Rgb backgroundColor{bg(display_.background[0]), bg(display_.background[1]),
                                  bg(display_.background[2])};
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      image.pixels[i] = {pixels[3 * i], pixels[3 * i + 1], pixels[3 * i + 2]};
      if (image.pixels[i] == backgroundColor) ++background;
    }
    io::writePng(options_.screenshot, image);
    if (!options_.quiet) std::cerr << "view: wrote " << options_.screenshot << "\n";
    Json out = {{"path", options_.screenshot},
                {"width", options_.width},
                {"height", options_.height},
                {"covered", 1.0 - double(background) / double(image.pixels.size())},
                {"camera",
                 {{"azimuth", camera_.azimuth},
                  {"elevation", camera_.elevation},
                  {"distance", camera_.distance}}}};
    if (display_.errors && scan_ && session_)
      out["error_map"] = {{"rms", errorRms_}, {"max", errorMax_}};
    return out;
  }

  // --- interactive ---

  static Viewer& of(GLFWwindow* window) {
    return *static_cast<Viewer*>(glfwGetWindowUserPointer(window));
  }

  void interactive() {
    glfwSetWindowUserPointer(window_, this);
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
      Viewer& v = of(w);
      if (ImGui::GetIO().WantCaptureMouse && action == GLFW_PRESS) return;
      double x, y;
      glfwGetCursorPos(w, &x, &y);
      v.toFramebuffer(x, y);
      if (action == GLFW_PRESS) {
        const MouseButton b = button == GLFW_MOUSE_BUTTON_LEFT    ? MouseButton::Left
                              : button == GLFW_MOUSE_BUTTON_RIGHT ? MouseButton::Right
                                                                  : MouseButton::Middle;
        v.controller_->press(x, y, b,
                             {(mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_CONTROL) != 0,
                              (mods & GLFW_MOD_ALT) != 0});
      } else {
        v.controller_->release(x, y);
      }
      v.lastUpload_ = v.uploadChanges() * 1e3;
    });
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
      Viewer& v = of(w);
      v.toFramebuffer(x, y);
      v.controller_->move(x, y);
      if (v.session_ && v.session_->dragging()) v.lastUpload_ = v.uploadChanges() * 1e3;
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
      if (ImGui::GetIO().WantCaptureMouse) return;
      of(w).controller_->scroll(dy);
    });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
      if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
      of(w).key(key, mods);
    });
    glfwSetWindowCloseCallback(window_, [](GLFWwindow* w) {
      Viewer& v = of(w);
      if (v.session_ && v.session_->modified()) {
        glfwSetWindowShouldClose(w, GLFW_FALSE);
        v.askOnClose_ = true;
      }
    });
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330");
    imgui_ = true;
    if (!options_.quiet)
      std::cerr << "view: drag control points with the left button (Alt: along the normal), "
                   "Shift+drag selects a box; left drag orbits, right drag pans, wheel zooms; "
                   "Ctrl+Z/Ctrl+Y undo/redo, Ctrl+S saves, F fits the view\n";
    while (!glfwWindowShouldClose(window_)) {
      glfwPollEvents();
      int width, height;
      glfwGetFramebufferSize(window_, &width, &height);
      camera_.width = std::max(width, 1);
      camera_.height = std::max(height, 1);
      const auto frameStart = Clock::now();
      if (session_) {
        syncSelection();
        updateErrorMap();
        autosaveTick();
      }
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      panel();
      ImGui::Render();
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      renderer_->draw(camera_, display_);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      glfwSwapBuffers(window_);
      lastFrame_ = secondsSince(frameStart) * 1e3;
    }
  }

  // Window coordinates to framebuffer pixels (they differ on high-density screens).
  void toFramebuffer(double& x, double& y) const {
    int ww, wh;
    glfwGetWindowSize(window_, &ww, &wh);
    if (ww > 0 && wh > 0) {
      x *= double(camera_.width) / ww;
      y *= double(camera_.height) / wh;
    }
  }

  void key(int key, int mods) {
    const bool control = (mods & GLFW_MOD_CONTROL) != 0;
    if (session_ && control && key == GLFW_KEY_Z && (mods & GLFW_MOD_SHIFT))
      session_->redo();
    else if (session_ && control && key == GLFW_KEY_Z)
      session_->undo();
    else if (session_ && control && key == GLFW_KEY_Y)
      session_->redo();
    else if (session_ && control && key == GLFW_KEY_S)
      save();
    else if (key == GLFW_KEY_F)
      camera_.fitTo(low_, high_);
    else if (key == GLFW_KEY_ESCAPE)
      controller_->setSelection({});
    else if (key == GLFW_KEY_N)
      display_.net = !display_.net;
    else if (key == GLFW_KEY_C)
      display_.checker = !display_.checker;
    if (session_) lastUpload_ = uploadChanges() * 1e3;
  }

  void save() {
    try {
      session_->save();
      status_ = "saved " + session_->path();
    } catch (const std::exception& e) {
      status_ = std::string("save failed: ") + e.what();
    }
  }

  // As `mspline export`: the edited model at the shown resolution or the one the tolerance asks
  // for, the fills trimmed.
  void exportSurface() {
    try {
      io::ExportFileOptions options;
      options.output = exportPath_;
      options.surface.resolution = options_.resolution;
      options.surface.tolerance = std::max(0.0, exportTolerance_);
      const spline::ExportResult exported =
          io::exportModel(session_->model(), session_->path(), options).surface;
      status_ = std::string("exported ") + exportPath_ + " (resolution " +
                std::to_string(exported.resolution) + ", " +
                std::to_string(exported.surface.mesh.faces.size()) + " triangles, " +
                std::to_string(exported.trimmedFaces) + " over fills trimmed)";
    } catch (const std::exception& e) {
      status_ = std::string("export failed: ") + e.what();
    }
  }

  void panel() {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(300, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("mspline");
    bool errorsBefore = display_.errors;
    ImGui::Checkbox("surface", &display_.surface);
    ImGui::SameLine();
    ImGui::Checkbox("net", &display_.net);
    ImGui::SameLine();
    ImGui::Checkbox("cones", &display_.cones);
    if (ImGui::Checkbox("checker", &display_.checker) && display_.checker) display_.lines = false;
    ImGui::SameLine();
    if (ImGui::Checkbox("lines", &display_.lines) && display_.lines) display_.checker = false;
    if (scan_ && session_) {
      ImGui::Checkbox("scan", &display_.scan);
      ImGui::SameLine();
      ImGui::Checkbox("error map", &display_.errors);
      ImGui::SliderFloat("scan alpha", &display_.scanAlpha, 0.0f, 1.0f);
      if (display_.errors && !errorColors_.empty())
        ImGui::Text("scan to surface: rms %.3g, max %.3g", errorRms_, errorMax_);
    }
    if (errorsBefore && !display_.errors) renderer_->setScanColors({});
    if (errorsBefore != display_.errors && display_.errors) errorState_ = ~std::uint64_t(0);
    if (ImGui::Button("fit view")) camera_.fitTo(low_, high_);
    if (session_) {
      const spline::ModelControlNet& net = session_->net();
      ImGui::Separator();
      ImGui::Text("%s, %d control points", session_->surface().kindName().c_str(),
                  int(session_->model().controlPoints.rows()));
      ImGui::Text("%d cones, %d extraordinary net points, %d T-junctions",
                  int(session_->tessellation().coneVertices.size()), int(net.extraordinary.size()),
                  int(net.tJunctions.size()));
      ImGui::Text("surface: %d vertices, %d triangles", int(session_->positions().rows()),
                  int(session_->tessellation().mesh.faces.size()));
      ImGui::Text("selected: %d", int(controller_->selection().size()));
      int mode = controller_->dragMode == DragMode::ViewPlane ? 0 : 1;
      ImGui::RadioButton("drag in view plane", &mode, 0);
      ImGui::SameLine();
      ImGui::RadioButton("along normal", &mode, 1);
      controller_->dragMode = mode == 0 ? DragMode::ViewPlane : DragMode::Normal;
      ImGui::Text("last re-evaluation %.2f ms (%d vertices), upload %.2f ms",
                  session_->lastEvaluationSeconds() * 1e3, int(session_->changedVertices().size()),
                  lastUpload_);
      ImGui::Text("frame %.1f ms", lastFrame_);
      if (ImGui::Button("undo")) session_->undo();
      ImGui::SameLine();
      if (ImGui::Button("redo")) session_->redo();
      uploadChanges();
      ImGui::SameLine();
      ImGui::Text("%d / %d steps", session_->undoSteps(), session_->redoSteps());
      if (ImGui::Button(session_->modified() ? "save *" : "save")) save();
      ImGui::InputText("##export", exportPath_, sizeof exportPath_);
      ImGui::SameLine();
      if (ImGui::Button("export")) exportSurface();
      ImGui::InputDouble("export tolerance", &exportTolerance_, 0.0, 0.0, "%.1e");
      if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
    }
    ImGui::End();
    if (controller_->boxSelecting()) {
      const Eigen::Vector4d b = controller_->box();
      const double sx = double(ImGui::GetIO().DisplaySize.x) / camera_.width;
      const double sy = double(ImGui::GetIO().DisplaySize.y) / camera_.height;
      ImGui::GetForegroundDrawList()->AddRect(ImVec2(float(b[0] * sx), float(b[1] * sy)),
                                              ImVec2(float(b[2] * sx), float(b[3] * sy)),
                                              IM_COL32(230, 160, 0, 255));
    }
    if (askOnClose_) {
      ImGui::OpenPopup("Unsaved changes");
      askOnClose_ = false;
    }
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::Text("%s has unsaved edits.", session_->path().c_str());
      if (ImGui::Button("save and quit")) {
        save();
        if (!session_->modified()) glfwSetWindowShouldClose(window_, GLFW_TRUE);
        ImGui::CloseCurrentPopup();
      }
      ImGui::SameLine();
      if (ImGui::Button("quit without saving")) {
        glfwSetWindowShouldClose(window_, GLFW_TRUE);
        ImGui::CloseCurrentPopup();
      }
      ImGui::SameLine();
      if (ImGui::Button("cancel")) ImGui::CloseCurrentPopup();
      ImGui::EndPopup();
    }
  }

  ViewerOptions options_;
  std::unique_ptr<EditSession> session_;
  std::optional<PlainMesh> scan_;
  std::vector<ScriptedEdit> script_;
  Eigen::Vector3d low_, high_;
  GLFWwindow* window_ = nullptr;
  bool imgui_ = false;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<OffscreenTarget> target_;
  Camera camera_;
  std::unique_ptr<Controller> controller_;
  DisplayOptions display_;
  std::vector<int> shownSelection_;
  std::vector<std::array<std::uint8_t, 3>> errorColors_;
  double errorRms_ = 0.0, errorMax_ = 0.0;
  std::uint64_t errorState_ = ~std::uint64_t(0);
  std::uint64_t uploadedChanges_ = 0;
  Clock::time_point lastAutosave_;
  int autosaves_ = 0;
  double lastUpload_ = 0.0, lastFrame_ = 0.0;
  bool askOnClose_ = false;
  std::string status_;
  char exportPath_[512] = "surface.obj";
  // Chord tolerance of the export, relative to the model's diagonal; 0: the shown resolution.
  double exportTolerance_ = 0.0;
  // Per tessellation face, 1 when it lies over the scan (not over a fill), as first shown: the
  // error map's.
  std::vector<char> keptFaces_;
};

}  // namespace

DisplayOptions parseShowList(const std::string& list) {
  DisplayOptions d;
  d.surface = d.net = d.scan = d.checker = d.lines = d.cones = d.errors = false;
  std::stringstream stream(list);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (item == "surface")
      d.surface = true;
    else if (item == "net")
      d.net = true;
    else if (item == "scan")
      d.scan = true;
    else if (item == "checker")
      d.checker = true;
    else if (item == "lines")
      d.lines = true;
    else if (item == "cones")
      d.cones = true;
    else if (item == "errors")
      d.errors = d.scan = true;
    else
      throw structure::InputError("--show: unknown entry '" + item +
                                  "' (surface, net, scan, checker, lines, cones, errors)");
  }
  return d;
}

nlohmann::ordered_json runViewer(const ViewerOptions& options) {
  Viewer viewer(options);
  return viewer.run();
}

}  // namespace mspline::viewer
