#pragma once
// Wall-clock stage timing: milliseconds since `start`, which then restarts at now.

#include <chrono>

namespace vocal {

inline double lapMilliseconds(std::chrono::steady_clock::time_point* start) {
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - *start).count();
  *start = now;
  return ms;
}

}  // namespace vocal
