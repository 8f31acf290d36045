#pragma once
/// \file
/// Elapsed time, for the timings that reports and statistics give.

#include <chrono>

namespace rgbmesh {

/// Seconds of the steady clock since `start`.
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace rgbmesh
