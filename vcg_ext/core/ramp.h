// A linear ramp between two readings: how far a measured quantity is into the range where a rule
// comes in. The measured modes' factors and thresholds read their figures through it.
#pragma once

#include <algorithm>

namespace vcg_ext {

// 0 up to `from`, 1 from `full`, linear between (a step at `from` when full <= from).
inline double rampBetween(double x, double from, double full) {
  return full > from ? std::clamp((x - from) / (full - from), 0.0, 1.0) : double(x >= from);
}

} // namespace vcg_ext
