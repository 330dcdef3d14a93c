// The stage timings the methods' logs report (seconds of wall time on a steady clock).
#pragma once

#include <chrono>

namespace vcg_ext {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

} // namespace vcg_ext
