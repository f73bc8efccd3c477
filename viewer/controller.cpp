#include "mspline/viewer/controller.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mspline::viewer {

namespace {

// Degrees of orbit per pixel of mouse motion.
constexpr double kOrbitSpeed = 0.4;
// Zoom factor per scroll step.
constexpr double kZoomStep = 0.9;

}  // namespace

Controller::Controller(Camera& camera, EditSession* session) : camera_(camera), session_(session) {}

int Controller::pick(double x, double y) const {
  if (!session_) return -1;
  const Ray ray = camera_.ray(x, y);
  struct Candidate {
    int row;
    double pixels, depth;
  };
  std::vector<Candidate> candidates;
  const Eigen::MatrixXd& c = session_->model().controlPoints;
  for (int row : session_->net().points) {
    const Eigen::Vector3d p = c.row(row).transpose();
    const double depth = (p - ray.origin).dot(ray.direction);
    if (depth <= 0.0) continue;
    const double pixels =
        (p - ray.origin - depth * ray.direction).norm() / camera_.pixelSize(depth);
    if (pixels <= pickRadius) candidates.push_back({row, pixels, depth});
  }
  if (candidates.empty()) return -1;
  double closest = std::numeric_limits<double>::infinity();
  for (const Candidate& k : candidates) closest = std::min(closest, k.pixels);
  // Within half a pixel of the closest counts as equally close: then the nearest to the eye.
  int best = -1;
  double bestDepth = std::numeric_limits<double>::infinity();
  for (const Candidate& k : candidates)
    if (k.pixels <= closest + 0.5 && k.depth < bestDepth) {
      best = k.row;
      bestDepth = k.depth;
    }
  return best;
}

std::vector<int> Controller::pointsInBox(double x0, double y0, double x1, double y1) const {
  std::vector<int> out;
  if (!session_) return out;
  const double left = std::min(x0, x1), right = std::max(x0, x1);
  const double top = std::min(y0, y1), bottom = std::max(y0, y1);
  const Eigen::MatrixXd& c = session_->model().controlPoints;
  for (int row : session_->net().points) {
    const Eigen::Vector3d s = camera_.project(c.row(row).transpose());
    if (s.z() > 0.0 && s.x() >= left && s.x() <= right && s.y() >= top && s.y() <= bottom)
      out.push_back(row);
  }
  return out;
}

void Controller::setSelection(std::vector<int> rows) {
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  selection_ = std::move(rows);
}

void Controller::press(double x, double y, MouseButton button, const Modifiers& modifiers) {
  if (state_ != State::Idle) return;
  pressX_ = lastX_ = x;
  pressY_ = lastY_ = y;
  if (button != MouseButton::Left) {
    state_ = State::Pan;
    return;
  }
  const int hit = pick(x, y);
  if (hit >= 0) {
    const bool selected = std::binary_search(selection_.begin(), selection_.end(), hit);
    if (modifiers.shift && !selected) {
      std::vector<int> rows = selection_;
      rows.push_back(hit);
      setSelection(std::move(rows));
    } else if (!selected) {
      selection_ = {hit};
    }
    const DragMode other = dragMode == DragMode::ViewPlane ? DragMode::Normal : DragMode::ViewPlane;
    startMoving(session_->model().controlPoints.row(hit).transpose(),
                modifiers.alt ? other : dragMode);
    return;
  }
  if (modifiers.shift && session_) {
    state_ = State::Box;
    boxAdds_ = true;
    return;
  }
  state_ = State::Orbit;
}

void Controller::move(double x, double y) {
  const double dx = x - lastX_, dy = y - lastY_;
  lastX_ = x;
  lastY_ = y;
  switch (state_) {
    case State::Orbit:
      camera_.orbit(dx * kOrbitSpeed, dy * kOrbitSpeed);
      break;
    case State::Pan:
      camera_.pan(dx, dy);
      break;
    case State::Moving:
      moveByPixels(x - pressX_, y - pressY_);
      break;
    case State::Box:
    case State::Idle:
      break;
  }
}

void Controller::release(double x, double y) {
  if (state_ == State::Moving) {
    move(x, y);
    finishMoving();
    return;
  }
  if (state_ == State::Box) {
    std::vector<int> rows = pointsInBox(pressX_, pressY_, x, y);
    if (boxAdds_) rows.insert(rows.end(), selection_.begin(), selection_.end());
    setSelection(std::move(rows));
  } else if (state_ == State::Orbit && std::hypot(x - pressX_, y - pressY_) < 2.0) {
    selection_.clear();  // a click on empty space
  }
  state_ = State::Idle;
}

void Controller::scroll(double steps) {
  camera_.zoom(std::pow(kZoomStep, steps));
}

void Controller::startMoving(const Eigen::Vector3d& anchor, DragMode mode) {
  if (!session_ || selection_.empty()) return;
  activeMode_ = mode;
  anchorDepth_ = std::max(camera_.project(anchor).z(), 1e-12);
  normals_.clear();
  for (int row : selection_) normals_.push_back(session_->controlNormal(row));
  session_->beginDrag(selection_);
  state_ = State::Moving;
}

void Controller::moveByPixels(double dx, double dy) {
  if (activeMode_ == DragMode::ViewPlane)
    moveByOffset(camera_.screenOffset(dx, dy, anchorDepth_));
  else  // up the screen is out along the normal
    moveAlongNormal(-dy * camera_.pixelSize(anchorDepth_));
}

void Controller::moveByOffset(const Eigen::Vector3d& offset) {
  if (state_ != State::Moving) return;
  session_->dragTo({offset});
}

void Controller::moveAlongNormal(double distance) {
  if (state_ != State::Moving) return;
  std::vector<Eigen::Vector3d> offsets;
  for (const Eigen::Vector3d& n : normals_) offsets.push_back(distance * n);
  session_->dragTo(offsets);
}

void Controller::finishMoving() {
  if (state_ != State::Moving) return;
  session_->endDrag();
  state_ = State::Idle;
}

}  // namespace mspline::viewer
