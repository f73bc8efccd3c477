#pragma once
// A spline model being edited: its control points, the evaluated surface shown for it, and the
// edit history. Moving control points re-evaluates only the tessellation vertices in their
// supports (spline::SurfaceSamples); every edit is one undo step that restores the control points
// bit for bit. Saving is atomic and keeps a backup of the file it replaces; an autosave file
// beside the model holds unsaved edits. No OpenGL here: the renderer reads the state, tests drive
// it directly.
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mspline/spline/core/spline_model.h"
#include "mspline/spline/model/model_surface.h"

namespace mspline::viewer {

struct EditSessionOptions {
  /// Samples along every side of every face of the shown surface (as `mspline export
  /// --resolution`).
  int resolution = 6;
  /// Undo steps kept; the oldest are dropped beyond this.
  int undoLimit = 1000;
};

/// One undo step: control point rows and their coordinates before and after.
struct ControlPointEdit {
  std::vector<int> rows;
  Eigen::MatrixX3d before, after;
  /// Identify the model states before and after this edit (for modified()).
  std::uint64_t stateBefore = 0, stateAfter = 0;
};

class EditSession {
 public:
  /// `path`: where save() writes (the file the model came from). Throws InputError (naming the
  /// path) when the model's control points do not fit its space.
  EditSession(spline::SplineModel model, std::string path, const EditSessionOptions& options = {});

  const spline::SplineModel& model() const { return model_; }
  const std::string& path() const { return path_; }
  const spline::ModelSurface& surface() const { return *surface_; }
  /// The shown surface's mesh, chart coordinates and cone vertices (its positions and normals are
  /// those of the model as loaded: the current ones are positions() and normals()).
  const spline::ModelTessellation& tessellation() const { return tessellation_; }
  const spline::SurfaceSamples& samples() const { return samples_; }
  const spline::ModelControlNet& net() const { return net_; }
  /// Current surface positions and unit normals, one row per tessellation vertex.
  const Eigen::MatrixX3d& positions() const { return positions_; }
  const Eigen::MatrixX3d& normals() const { return normals_; }
  /// The direction a control point moves "along the normal": the mean of the surface normals
  /// where its basis function is non-zero, weighted by the function's values (unit length).
  Eigen::Vector3d controlNormal(int row) const;
  /// Tessellation vertices whose position depends on control point `row`.
  std::vector<int> support(int row) const;

  /// Starts moving `rows` (distinct control point rows).
  void beginDrag(std::vector<int> rows);
  /// Puts every dragged control point at its position at beginDrag plus its offset (one offset
  /// per row, or one for all) and re-evaluates the surface where they act.
  void dragTo(const std::vector<Eigen::Vector3d>& offsets);
  /// Ends the move: one undo step when a control point moved.
  void endDrag();
  bool dragging() const { return dragging_; }
  const std::vector<int>& draggedRows() const { return dragRows_; }

  bool canUndo() const { return !undo_.empty(); }
  bool canRedo() const { return !redo_.empty(); }
  void undo();
  void redo();
  int undoSteps() const { return int(undo_.size()); }
  int redoSteps() const { return int(redo_.size()); }

  /// Vertices re-evaluated by the last change (drag step, undo, redo), ascending (the moved
  /// control points' supports, and vertices around them whose normals come from triangles), and
  /// the control point rows it moved.
  const std::vector<int>& changedVertices() const { return changedVertices_; }
  const std::vector<int>& changedRows() const { return changedRows_; }
  /// Counts re-evaluations (a change of changeCount() means the surface changed).
  std::uint64_t changeCount() const { return changes_; }
  /// Seconds the last re-evaluation took.
  double lastEvaluationSeconds() const { return lastEvaluationSeconds_; }

  /// Edits since the last save (or the load).
  bool modified() const { return state_ != savedState_; }
  /// Identifies the control points' state: equal ids, equal control points.
  std::uint64_t state() const { return state_; }
  /// Changes where save() writes (as "save as").
  void setPath(std::string path) {
    path_ = std::move(path);
    savedState_ = ~std::uint64_t(0);
  }
  /// Writes the model to path() atomically; an existing file there is first copied to
  /// path() + ".bak". Removes the autosave file, which is older than the saved state.
  void save();
  /// The autosave file of a model path: "<stem>.autosave.msp" beside it.
  static std::string autosavePath(const std::string& modelPath);
  /// Writes the model to autosavePath(path()) atomically when it changed since the last save or
  /// autosave; returns whether it wrote.
  bool autosave();

 private:
  void setRows(const std::vector<int>& rows, const Eigen::MatrixX3d& coordinates);
  void reevaluate(const std::vector<int>& rows);
  void pushEdit(ControlPointEdit edit);

  spline::SplineModel model_;
  std::string path_;
  EditSessionOptions options_;
  std::unique_ptr<spline::ModelSurface> surface_;
  spline::ModelTessellation tessellation_;
  spline::SurfaceSamples samples_;
  // value_ by columns: the vertices each control point acts on.
  Eigen::SparseMatrix<double> valueByColumn_;
  spline::ModelControlNet net_;
  Eigen::MatrixX3d positions_, normals_;
  // Triangles around each vertex (CSR), for normals from triangles.
  std::vector<std::int64_t> vertexTriangleOffsets_;
  std::vector<int> vertexTriangles_;
  std::vector<char> normalFromTriangles_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t stampValue_ = 0;

  bool dragging_ = false;
  std::vector<int> dragRows_;
  Eigen::MatrixX3d dragStart_;

  std::deque<ControlPointEdit> undo_;
  std::vector<ControlPointEdit> redo_;
  std::uint64_t nextState_ = 1, state_ = 0, savedState_ = 0, autosavedState_ = 0;

  std::vector<int> changedVertices_, changedRows_;
  double lastEvaluationSeconds_ = 0.0;
  std::uint64_t changes_ = 0;
};

}  // namespace mspline::viewer
