// The edit script's reader, apart from runScriptedEdit so that it builds without OpenGL (the fuzz
// target links it alone).
#include <cstdint>

#include <nlohmann/json.hpp>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/core/whole_file.h"
#include "mspline/viewer/edit_script.h"

namespace mspline::viewer {

namespace {

using Json = nlohmann::json;
using structure::InputError;

// Bounds that keep a script from running for ever: frames per move, undo/redo steps, seconds.
constexpr std::int64_t kMaxSteps = 10000;
constexpr double kMaxWait = 600.0;

// JSON numbers are finite: the parser refuses "1e999".
double number(const Json& value, const std::string& what) {
  if (!value.is_number()) throw InputError(what + " must hold numbers");
  return value.get<double>();
}

Eigen::Vector3d vectorOf(const Json& value, std::size_t size, const std::string& what) {
  if (!value.is_array() || value.size() != size)
    throw InputError(what + " must be an array of " + std::to_string(size) + " numbers");
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < size; ++k) out[Eigen::Index(k)] = number(value[k], what);
  return out;
}

// An integer in [low, high] (0 <= low); JSON may hold a fraction, a string or a number beyond int
// there.
bool integerIn(const Json& value, std::int64_t low, std::int64_t high) {
  if (value.is_number_unsigned())
    return high >= low && value.get<std::uint64_t>() >= std::uint64_t(low) &&
           value.get<std::uint64_t>() <= std::uint64_t(high);
  return value.is_number_integer() && value.get<std::int64_t>() >= low &&
         value.get<std::int64_t>() <= high;
}

int stepCount(const Json& value, const char* key) {
  if (!integerIn(value, 1, kMaxSteps))
    throw InputError(std::string("\"") + key + "\" must be an integer from 1 to " +
                     std::to_string(kMaxSteps));
  return value.get<int>();
}

ScriptedEdit parseEdit(const Json& e, int numControlPoints) {
  if (!e.is_object()) throw InputError("expected an object");
  ScriptedEdit edit;
  if (e.contains("points")) {
    if (!e["points"].is_array() || e["points"].empty())
      throw InputError("\"points\" must be a non-empty array");
    for (const Json& p : e["points"]) {
      if (!integerIn(p, 0, std::int64_t(numControlPoints) - 1))
        throw InputError("control point " + p.dump() + " is not one of the " +
                         std::to_string(numControlPoints));
      edit.points.push_back(p.get<int>());
    }
  }
  if (e.contains("steps")) edit.steps = stepCount(e["steps"], "steps");
  if (e.contains("pixels")) {
    edit.kind = ScriptedEdit::Kind::Pixels;
    edit.vector.head<2>() = vectorOf(e["pixels"], 2, "\"pixels\"").head<2>();
  } else if (e.contains("offset")) {
    edit.kind = ScriptedEdit::Kind::Offset;
    edit.vector = vectorOf(e["offset"], 3, "\"offset\"");
  } else if (e.contains("normal")) {
    edit.kind = ScriptedEdit::Kind::Normal;
    edit.amount = number(e["normal"], "\"normal\"");
  } else if (e.contains("undo")) {
    edit.kind = ScriptedEdit::Kind::Undo;
    edit.count = stepCount(e["undo"], "undo");
  } else if (e.contains("redo")) {
    edit.kind = ScriptedEdit::Kind::Redo;
    edit.count = stepCount(e["redo"], "redo");
  } else if (e.contains("save")) {
    edit.kind = ScriptedEdit::Kind::Save;
  } else if (e.contains("wait")) {
    edit.kind = ScriptedEdit::Kind::Wait;
    const Json& wait = e["wait"];
    if (!wait.is_number() || !(wait.get<double>() >= 0.0 && wait.get<double>() <= kMaxWait))
      throw InputError("\"wait\" must be a number of seconds from 0 to " +
                       std::to_string(int(kMaxWait)));
    edit.amount = wait.get<double>();
  } else {
    throw InputError("expected one of pixels, offset, normal, undo, redo, save, wait");
  }
  const bool isMove = edit.kind == ScriptedEdit::Kind::Pixels ||
                      edit.kind == ScriptedEdit::Kind::Offset ||
                      edit.kind == ScriptedEdit::Kind::Normal;
  if (isMove && edit.points.empty()) throw InputError("a move needs \"points\"");
  return edit;
}

}  // namespace

std::vector<ScriptedEdit> readEditScript(const std::string& path, int numControlPoints) {
  return parseEditScript(structure::readWholeFile(path), path, numControlPoints);
}

std::vector<ScriptedEdit> parseEditScript(std::string_view text, const std::string& sourceName,
                                          int numControlPoints) {
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(sourceName + ": not JSON: " + e.what());
  }
  if (!document.is_object() || !document.contains("edits") || !document["edits"].is_array())
    throw InputError(sourceName + ": expected an object with an array \"edits\"");
  std::vector<ScriptedEdit> edits;
  for (std::size_t i = 0; i < document["edits"].size(); ++i) {
    try {
      edits.push_back(parseEdit(document["edits"][i], numControlPoints));
    } catch (const InputError& error) {
      throw InputError(sourceName + ": edit " + std::to_string(i + 1) + ": " + error.what());
    }
  }
  return edits;
}

}  // namespace mspline::viewer
