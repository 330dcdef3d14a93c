// Taubin's λ|μ smoothing (Taubin 1995) with uniform weights, on one field: the low-pass filter the
// feature mode's pre-pass, the noise estimate and the automatic mode's evidence run.
#pragma once

#include "vcg_ext/core/rings.h"

#include <array>
#include <cstdint>
#include <vector>

namespace vcg_ext {

// Taubin λ|μ smoothing with uniform weights: `pairs` shrink/inflate steps. Vertices with
// `fixed[v]` != 0 stay (frozen, unselected); they still pull on their neighbours. A boundary vertex
// is smoothed along its boundary curve only, from its two boundary neighbours (`curve[v]`, −1 where
// absent: then it stays), so an open boundary is denoised without being pulled inward.
// (Several fields at once, or long runs on large meshes: SpatialTaubin, the same bits.)
inline void taubinSmooth(std::vector<Vec3> &points, const Rings &rings,
                         const std::vector<std::uint8_t> &fixed,
                         const std::vector<std::array<int, 2>> &curve, int pairs,
                         double lambda = 0.5, double mu = -0.53) {
  const int n = rings.vertex_count;
  if (pairs <= 0) return;
  std::vector<Vec3> next(n);
  for (int step = 0; step < 2 * pairs; ++step) {
    const double factor = step % 2 == 0 ? lambda : mu;
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) {
      const bool still = fixed[v] || rings.ring1Size(v) == 0 ||
                         (rings.boundary[v] && (curve[v][0] < 0 || curve[v][1] < 0));
      if (still) {
        next[v] = points[v];
        continue;
      }
      Vec3 centre = Vec3::Zero();
      if (rings.boundary[v]) {
        centre = 0.5 * (points[curve[v][0]] + points[curve[v][1]]);
      } else {
        for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) centre += points[*w];
        centre /= rings.ring1Size(v);
      }
      next[v] = points[v] + factor * (centre - points[v]);
    }
    points.swap(next);
  }
}

} // namespace vcg_ext
