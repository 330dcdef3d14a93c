// Random values that follow a vertex's position, not its index: the noise probes of the noise
// estimate and the band shrinkage read the same values whatever the vertex order.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace vcg_ext {

namespace detail {

// A standard normal value from a vertex's position: the same vertex gets the same value whatever
// its index (SplitMix64 over the coordinates' bits, then Box-Muller); `stream` gives independent
// values for the same position.
inline Vec3 positionHashedGaussian(const Vec3 &p, std::uint64_t stream = 0) {
  std::uint64_t h = 0x9E3779B97F4A7C15ull * (stream + 1);
  auto mix = [](std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  for (int k = 0; k < 3; ++k) {
    std::uint64_t bits;
    std::memcpy(&bits, &p[k], sizeof bits);
    h = mix(h ^ bits) + 0x9E3779B97F4A7C15ull;
  }
  auto uniform = [&](std::uint64_t &state) {
    state = mix(state + 0x9E3779B97F4A7C15ull);
    return (double(state >> 11) + 0.5) * (1.0 / 9007199254740992.0); // (0, 1)
  };
  std::uint64_t state = h;
  Vec3 out;
  for (int k = 0; k < 3; ++k) {
    const double u1 = uniform(state), u2 = uniform(state);
    out[k] = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  return out;
}

} // namespace detail

} // namespace vcg_ext
