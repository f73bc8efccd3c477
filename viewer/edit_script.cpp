#include "mspline/viewer/edit_script.h"

#include <chrono>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "mspline/structure/core/errors.h"

namespace mspline::viewer {

namespace {

using Json = nlohmann::json;

Eigen::Vector3d vectorOf(const Json& value, std::size_t size, const std::string& what) {
  if (!value.is_array() || value.size() != size)
    throw structure::InputError(what + " must be an array of " + std::to_string(size) + " numbers");
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < size; ++k) {
    if (!value[k].is_number()) throw structure::InputError(what + " must hold numbers");
    out[Eigen::Index(k)] = value[k].get<double>();
  }
  if (!out.allFinite()) throw structure::InputError(what + " must be finite");
  return out;
}

}  // namespace

std::vector<ScriptedEdit> readEditScript(const std::string& path, int numControlPoints) {
  std::ifstream in(path);
  if (!in) throw structure::IoError(path + ": cannot open the edit script");
  Json document;
  try {
    in >> document;
  } catch (const Json::exception& e) {
    throw structure::InputError(path + ": not JSON: " + e.what());
  }
  if (!document.is_object() || !document.contains("edits") || !document["edits"].is_array())
    throw structure::InputError(path + ": expected an object with an array \"edits\"");
  std::vector<ScriptedEdit> edits;
  for (std::size_t i = 0; i < document["edits"].size(); ++i) {
    const Json& e = document["edits"][i];
    const std::string where = path + ": edit " + std::to_string(i + 1);
    if (!e.is_object()) throw structure::InputError(where + ": expected an object");
    ScriptedEdit edit;
    try {
      if (e.contains("points")) {
        if (!e["points"].is_array() || e["points"].empty())
          throw structure::InputError("\"points\" must be a non-empty array");
        for (const Json& p : e["points"]) {
          if (!p.is_number_integer() || p.get<long long>() < 0 ||
              p.get<long long>() >= numControlPoints)
            throw structure::InputError("control point " + p.dump() + " is not one of the " +
                                        std::to_string(numControlPoints));
          edit.points.push_back(p.get<int>());
        }
      }
      if (e.contains("steps")) {
        if (!e["steps"].is_number_integer() || e["steps"].get<int>() < 1)
          throw structure::InputError("\"steps\" must be a positive integer");
        edit.steps = e["steps"].get<int>();
      }
      const auto countOf = [&](const char* key) {
        if (!e[key].is_number_integer() || e[key].get<int>() < 1)
          throw structure::InputError(std::string("\"") + key + "\" must be a positive integer");
        return e[key].get<int>();
      };
      if (e.contains("pixels")) {
        edit.kind = ScriptedEdit::Kind::Pixels;
        edit.vector.head<2>() = vectorOf(e["pixels"], 2, "\"pixels\"").head<2>();
      } else if (e.contains("offset")) {
        edit.kind = ScriptedEdit::Kind::Offset;
        edit.vector = vectorOf(e["offset"], 3, "\"offset\"");
      } else if (e.contains("normal")) {
        edit.kind = ScriptedEdit::Kind::Normal;
        if (!e["normal"].is_number()) throw structure::InputError("\"normal\" must be a number");
        edit.amount = e["normal"].get<double>();
      } else if (e.contains("undo")) {
        edit.kind = ScriptedEdit::Kind::Undo;
        edit.count = countOf("undo");
      } else if (e.contains("redo")) {
        edit.kind = ScriptedEdit::Kind::Redo;
        edit.count = countOf("redo");
      } else if (e.contains("save")) {
        edit.kind = ScriptedEdit::Kind::Save;
      } else if (e.contains("wait")) {
        edit.kind = ScriptedEdit::Kind::Wait;
        if (!e["wait"].is_number() || e["wait"].get<double>() < 0.0)
          throw structure::InputError("\"wait\" must be a number of seconds");
        edit.amount = e["wait"].get<double>();
      } else {
        throw structure::InputError(
            "expected one of pixels, offset, normal, undo, redo, save, wait");
      }
      const bool isMove = edit.kind == ScriptedEdit::Kind::Pixels ||
                          edit.kind == ScriptedEdit::Kind::Offset ||
                          edit.kind == ScriptedEdit::Kind::Normal;
      if (isMove && edit.points.empty()) throw structure::InputError("a move needs \"points\"");
    } catch (const structure::InputError& error) {
      throw structure::InputError(where + ": " + error.what());
    }
    edits.push_back(std::move(edit));
  }
  return edits;
}

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
