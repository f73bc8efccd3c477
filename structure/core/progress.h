#pragma once
// How long-running pipelines report progress: a stage name and the fraction of it done, in [0, 1]
// (a new stage starts at 0; a one-line message is a stage reported once, at fraction 1).
#include <functional>
#include <string>

namespace mspline::structure {

using Progress = std::function<void(const std::string& stage, double fraction)>;

/// Calls `progress` when it is set.
inline void report(const Progress& progress, const std::string& stage, double fraction = 1.0) {
  if (progress) progress(stage, fraction);
}

}  // namespace mspline::structure
