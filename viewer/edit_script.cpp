#include "mspline/viewer/edit_script.h"

#include <chrono>
#include <thread>

#include "mspline/structure/core/errors.h"

namespace mspline::viewer {

void runScriptedEdit(const ScriptedEdit& edit, std::size_t number, Controller& controller,
                     EditSession& session, const Camera& camera,
                     const std::function<void()>& frame) {
  using Kind = ScriptedEdit::Kind;
  const Eigen::MatrixXd& c = session.model().controlPoints;
  switch (edit.kind) {
    case Kind::Pixels: {
      controller.setSelection(edit.points);
      const Eigen::Vector3d start = camera.project(c.row(edit.points.front()).transpose());
      if (controller.pick(start.x(), start.y()) != edit.points.front())
        throw structure::InputError(
            "edit " + std::to_string(number) + ": control point " +
            std::to_string(edit.points.front()) +
            " is not the one under the pointer at its place on the screen (hidden or off screen);"
            " use \"offset\"");
      controller.press(start.x(), start.y(), MouseButton::Left, {});
      for (int s = 1; s <= edit.steps; ++s) {
        const double t = double(s) / edit.steps;
        controller.move(start.x() + t * edit.vector.x(), start.y() + t * edit.vector.y());
        frame();
      }
      controller.release(start.x() + edit.vector.x(), start.y() + edit.vector.y());
      frame();
      break;
    }
    case Kind::Offset:
    case Kind::Normal: {
      controller.setSelection(edit.points);
      controller.startMoving(c.row(edit.points.front()).transpose(),
                             edit.kind == Kind::Offset ? DragMode::ViewPlane : DragMode::Normal);
      for (int s = 1; s <= edit.steps; ++s) {
        const double t = double(s) / edit.steps;
        if (edit.kind == Kind::Offset)
          controller.moveByOffset(t * edit.vector);
        else
          controller.moveAlongNormal(t * edit.amount);
        frame();
      }
      controller.finishMoving();
      frame();
      break;
    }
    case Kind::Undo:
    case Kind::Redo:
      for (int k = 0; k < edit.count; ++k) {
        edit.kind == Kind::Undo ? session.undo() : session.redo();
        frame();
      }
      break;
    case Kind::Save:
      session.save();
      break;
    case Kind::Wait: {
      const auto end =
          std::chrono::steady_clock::now() + std::chrono::duration<double>(edit.amount);
      do {
        frame();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      } while (std::chrono::steady_clock::now() < end);
      break;
    }
  }
}

}  // namespace mspline::viewer
