#pragma once
// What the mouse and keys do to the camera, the selection and the control points. No OpenGL: the
// window forwards its events here, and scripted edits (edit_script.h) call the same methods, so a
// scripted move runs the code of a mouse drag.
#include <vector>

#include <Eigen/Core>

#include "mspline/viewer/camera.h"
#include "mspline/viewer/edit_session.h"

namespace mspline::viewer {

enum class MouseButton { Left, Right, Middle };

struct Modifiers {
  bool shift = false;
  bool control = false;
  bool alt = false;
};

/// How a drag moves control points: in the view plane, or each along its own normal
/// (EditSession::controlNormal).
enum class DragMode { ViewPlane, Normal };

class Controller {
 public:
  /// `session` may be null (a mesh without a model: camera only).
  Controller(Camera& camera, EditSession* session);

  /// A control point is picked when the ray through the mouse passes within this many pixels.
  double pickRadius = 8.0;
  /// Used for drags that start without Alt (Alt switches to the other mode).
  DragMode dragMode = DragMode::ViewPlane;

  /// Left button: on a control point, selects it (Shift: adds it) and starts moving the selection;
  /// elsewhere with Shift, starts a selection box; elsewhere, orbits. Right or middle: pans.
  void press(double x, double y, MouseButton button, const Modifiers& modifiers);
  void move(double x, double y);
  void release(double x, double y);
  void scroll(double steps);

  /// The shown control point nearest to the ray through pixel (x, y) within pickRadius (nearest
  /// to the eye among equally close ones), or -1.
  int pick(double x, double y) const;
  /// Shown control points whose projection lies in the pixel rectangle.
  std::vector<int> pointsInBox(double x0, double y0, double x1, double y1) const;

  const std::vector<int>& selection() const { return selection_; }
  void setSelection(std::vector<int> rows);
  bool boxSelecting() const { return state_ == State::Box; }
  /// The selection box's corners (pixels) while boxSelecting().
  Eigen::Vector4d box() const { return {pressX_, pressY_, lastX_, lastY_}; }

  /// The moves a mouse drag makes: start moving the selection with the pointer's depth at
  /// `anchor` (a world point), then by pixels, by a world offset, or along the normals.
  void startMoving(const Eigen::Vector3d& anchor, DragMode mode);
  void moveByPixels(double dx, double dy);
  void moveByOffset(const Eigen::Vector3d& offset);
  void moveAlongNormal(double distance);
  void finishMoving();
  bool moving() const { return state_ == State::Moving; }

 private:
  enum class State { Idle, Orbit, Pan, Box, Moving };
  Camera& camera_;
  EditSession* session_;
  std::vector<int> selection_;
  State state_ = State::Idle;
  DragMode activeMode_ = DragMode::ViewPlane;
  double pressX_ = 0, pressY_ = 0, lastX_ = 0, lastY_ = 0;
  bool boxAdds_ = false;
  double anchorDepth_ = 1.0;
  std::vector<Eigen::Vector3d> normals_;
};

}  // namespace mspline::viewer
