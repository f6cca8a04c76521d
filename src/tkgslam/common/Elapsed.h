#pragma once
// Wall-clock time for the per-stage timings.
#include <chrono>

namespace tkgslam {

/// Milliseconds elapsed since t0 (steady clock).
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace tkgslam
