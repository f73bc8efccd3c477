#include "mspline/viewer/edit_session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include "mspline/io/atomic_file.h"
#include "mspline/io/spline_model_file.h"
#include "mspline/structure/core/errors.h"

namespace mspline::viewer {

namespace {

Eigen::Vector3d rowVector(const Eigen::MatrixX3d& m, Eigen::Index row) {
  return m.row(row).transpose();
}

}  // namespace

EditSession::EditSession(spline::SplineModel model, std::string path,
                         const EditSessionOptions& options)
    : model_(std::move(model)), path_(std::move(path)), options_(options) {
  surface_ = std::make_unique<spline::ModelSurface>(model_, path_);
  tessellation_ = surface_->tessellate(model_.controlPoints, options_.resolution);
  samples_ = surface_->samples(tessellation_);
  valueByColumn_ = samples_.value;
  net_ = surface_->controlNet();
  const auto vertices = Eigen::Index(tessellation_.mesh.positions.size());
  positions_.resize(vertices, 3);
  normals_.resize(vertices, 3);
  for (Eigen::Index v = 0; v < vertices; ++v) {
    const auto& p = tessellation_.mesh.positions[std::size_t(v)];
    const auto& n = tessellation_.normals[std::size_t(v)];
    positions_.row(v) << p[0], p[1], p[2];
    normals_.row(v) << n[0], n[1], n[2];
  }
  vertexTriangleOffsets_.assign(std::size_t(vertices) + 1, 0);
  for (const auto& face : tessellation_.mesh.faces)
    for (std::int64_t v : face) ++vertexTriangleOffsets_[std::size_t(v) + 1];
  for (std::size_t v = 0; v < std::size_t(vertices); ++v)
    vertexTriangleOffsets_[v + 1] += vertexTriangleOffsets_[v];
  vertexTriangles_.resize(std::size_t(vertexTriangleOffsets_.back()));
  std::vector<std::int64_t> next(vertexTriangleOffsets_.begin(), vertexTriangleOffsets_.end() - 1);
  for (std::size_t f = 0; f < tessellation_.mesh.faces.size(); ++f)
    for (std::int64_t v : tessellation_.mesh.faces[f])
      vertexTriangles_[std::size_t(next[std::size_t(v)]++)] = int(f);
  stamp_.assign(std::size_t(vertices), 0);
  // As the tessellation decides: normals from the triangles for means and where ds x dt
  // vanishes.
  normalFromTriangles_.assign(std::size_t(vertices), 0);
  const Eigen::MatrixX3d ds = samples_.ds * model_.controlPoints;
  const Eigen::MatrixX3d dt = samples_.dt * model_.controlPoints;
  for (Eigen::Index v = 0; v < vertices; ++v) {
    const double length = rowVector(ds, v).cross(rowVector(dt, v)).norm();
    normalFromTriangles_[std::size_t(v)] =
        samples_.isMean[std::size_t(v)] || !(length > 0.0 && std::isfinite(length));
  }
}

std::vector<int> EditSession::support(int row) const {
  std::vector<int> out;
  for (Eigen::SparseMatrix<double>::InnerIterator it(valueByColumn_, row); it; ++it)
    out.push_back(int(it.row()));
  return out;
}

Eigen::Vector3d EditSession::controlNormal(int row) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::SparseMatrix<double>::InnerIterator it(valueByColumn_, row); it; ++it)
    sum += it.value() * rowVector(normals_, it.row());
  return sum.norm() > 0.0 ? Eigen::Vector3d(sum.normalized()) : Eigen::Vector3d::UnitZ();
}

void EditSession::beginDrag(std::vector<int> rows) {
  MSPLINE_ASSERT(!dragging_, "a drag is already under way");
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  for (int row : rows)
    MSPLINE_ASSERT(row >= 0 && row < model_.controlPoints.rows(), "control point out of range");
  dragRows_ = std::move(rows);
  dragStart_.resize(Eigen::Index(dragRows_.size()), 3);
  for (std::size_t i = 0; i < dragRows_.size(); ++i)
    dragStart_.row(Eigen::Index(i)) = model_.controlPoints.row(dragRows_[i]);
  dragging_ = true;
}

void EditSession::dragTo(const std::vector<Eigen::Vector3d>& offsets) {
  MSPLINE_ASSERT(dragging_, "dragTo without beginDrag");
  MSPLINE_ASSERT(offsets.size() == 1 || offsets.size() == dragRows_.size(),
                 "one offset, or one per dragged control point");
  Eigen::MatrixX3d moved = dragStart_;
  for (Eigen::Index i = 0; i < moved.rows(); ++i)
    moved.row(i) += offsets[offsets.size() == 1 ? 0 : std::size_t(i)].transpose();
  setRows(dragRows_, moved);
}

void EditSession::endDrag() {
  MSPLINE_ASSERT(dragging_, "endDrag without beginDrag");
  dragging_ = false;
  ControlPointEdit edit;
  edit.rows = dragRows_;
  edit.before = dragStart_;
  edit.after.resize(dragStart_.rows(), 3);
  for (std::size_t i = 0; i < dragRows_.size(); ++i)
    edit.after.row(Eigen::Index(i)) = model_.controlPoints.row(dragRows_[i]);
  if (!dragRows_.empty() && edit.after != edit.before) pushEdit(std::move(edit));
  dragRows_.clear();
}

void EditSession::pushEdit(ControlPointEdit edit) {
  edit.stateBefore = state_;
  edit.stateAfter = state_ = nextState_++;
  undo_.push_back(std::move(edit));
  if (int(undo_.size()) > options_.undoLimit) undo_.pop_front();
  redo_.clear();
}

void EditSession::undo() {
  if (undo_.empty() || dragging_) return;
  ControlPointEdit edit = std::move(undo_.back());
  undo_.pop_back();
  setRows(edit.rows, edit.before);
  state_ = edit.stateBefore;
  redo_.push_back(std::move(edit));
}

void EditSession::redo() {
  if (redo_.empty() || dragging_) return;
  ControlPointEdit edit = std::move(redo_.back());
  redo_.pop_back();
  setRows(edit.rows, edit.after);
  state_ = edit.stateAfter;
  undo_.push_back(std::move(edit));
}

void EditSession::setRows(const std::vector<int>& rows, const Eigen::MatrixX3d& coordinates) {
  for (std::size_t i = 0; i < rows.size(); ++i)
    model_.controlPoints.row(rows[i]) = coordinates.row(Eigen::Index(i));
  reevaluate(rows);
}

void EditSession::reevaluate(const std::vector<int>& rows) {
  const auto start = std::chrono::steady_clock::now();
  ++changes_;
  changedRows_ = rows;
  changedVertices_.clear();
  // Two stamp values a call (changed, and normal from triangles queued).
  if (stampValue_ >= std::numeric_limits<std::uint32_t>::max() - 2) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    stampValue_ = 0;
  }
  ++stampValue_;
  std::vector<int> extraVertices;
  for (int row : rows)
    for (Eigen::SparseMatrix<double>::InnerIterator it(valueByColumn_, row); it; ++it) {
      auto& s = stamp_[std::size_t(it.row())];
      if (s == stampValue_) continue;
      s = stampValue_;
      changedVertices_.push_back(int(it.row()));
    }
  std::sort(changedVertices_.begin(), changedVertices_.end());
  const Eigen::MatrixXd& c = model_.controlPoints;
  const auto combine = [&](const Eigen::SparseMatrix<double, Eigen::RowMajor>& m, int v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m, v); it; ++it)
      sum += it.value() * c.row(it.col()).transpose();
    return sum;
  };
  for (int v : changedVertices_) {
    positions_.row(v) = combine(samples_.value, v).transpose();
    if (normalFromTriangles_[std::size_t(v)]) continue;
    const Eigen::Vector3d n = combine(samples_.ds, v).cross(combine(samples_.dt, v));
    normals_.row(v) = n.normalized().transpose();
  }
  // Normals from triangles (as spline::vertexNormalsOfMesh: area-weighted) change with any
  // corner of the triangles around them.
  const auto& faces = tessellation_.mesh.faces;
  const auto trianglesAround = [&](int v) {
    return std::make_pair(vertexTriangleOffsets_[std::size_t(v)],
                          vertexTriangleOffsets_[std::size_t(v) + 1]);
  };
  std::vector<int> fromTriangles;
  for (int v : changedVertices_) {
    const auto [begin, end] = trianglesAround(v);
    for (auto k = begin; k < end; ++k)
      for (std::int64_t w : faces[std::size_t(vertexTriangles_[std::size_t(k)])]) {
        if (!normalFromTriangles_[std::size_t(w)] || stamp_[std::size_t(w)] == stampValue_ + 1)
          continue;
        stamp_[std::size_t(w)] = stampValue_ + 1;
        fromTriangles.push_back(int(w));
      }
  }
  ++stampValue_;
  for (int v : fromTriangles) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const auto [begin, end] = trianglesAround(v);
    for (auto k = begin; k < end; ++k) {
      const auto& face = faces[std::size_t(vertexTriangles_[std::size_t(k)])];
      const Eigen::Vector3d a = rowVector(positions_, face[0]);
      sum += (rowVector(positions_, face[1]) - a).cross(rowVector(positions_, face[2]) - a);
    }
    normals_.row(v) = sum.norm() > 0.0 ? Eigen::RowVector3d(sum.normalized().transpose())
                                       : Eigen::RowVector3d::Zero();
    if (!std::binary_search(changedVertices_.begin(), changedVertices_.end(), v))
      extraVertices.push_back(v);
  }
  if (!extraVertices.empty()) {
    changedVertices_.insert(changedVertices_.end(), extraVertices.begin(), extraVertices.end());
    std::sort(changedVertices_.begin(), changedVertices_.end());
  }
  lastEvaluationSeconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void EditSession::save() {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(path_, error)) {
    std::ifstream in(path_, std::ios::binary);
    if (!in) throw structure::IoError(path_ + ": cannot read the file to back it up");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    io::writeFileAtomically(path_ + ".bak", [&](std::ostream& out) { out << bytes; });
  }
  io::writeSplineModel(path_, model_);
  savedState_ = autosavedState_ = state_;
  fs::remove(autosavePath(path_), error);
}

std::string EditSession::autosavePath(const std::string& modelPath) {
  std::filesystem::path p(modelPath);
  p.replace_extension(".autosave.msp");
  return p.string();
}

bool EditSession::autosave() {
  if (state_ == autosavedState_) return false;
  io::writeSplineModel(autosavePath(path_), model_);
  autosavedState_ = state_;
  return true;
}

}  // namespace mspline::viewer
