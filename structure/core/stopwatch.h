#pragma once
// Wall-clock seconds for the per-stage timings pipelines report.
#include <chrono>

namespace mspline::structure {

/// Seconds since the previous lap (or construction).
class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace mspline::structure
