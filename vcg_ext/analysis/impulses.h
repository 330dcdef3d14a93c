// Impulses: single vertices far off the surface their neighbours describe, found and put back.
//
// Inputs: positions, faces, Rings, the vertices that may not move (`fixed`: boundary, frozen or
// unselected ones are never read as impulses), the mean edge length. Output: Impulses (the share
// of the movable vertices read as impulses, their median size in mean edge lengths, which ones)
// and, for repairImpulses, the positions with the impulses moved back.
//
// How: a vertex's offset is its distance from its 1-ring's mean along its normal; on a smooth
// surface it follows the curvature, the same for neighbours. Its deviation is that offset minus
// the median of its neighbours' offsets (which carries the local curvature, so fine relief is not
// read as an impulse). An impulse is a vertex whose deviation exceeds `min_size` mean edge lengths
// and `relative_size` times the deviations' robust std, and `isolation` times every neighbour's: an impulse drags each neighbour's ring mean by about a
// sixth of itself, while a crease or a corner has neighbours along it that deviate as much as it
// does (clean CAD meshes read no impulse). That reading decides: below `min_share` of the
// vertices (Gaussian noise's own tail) nothing moves. Above, repair moves each impulse back along
// its normal by its deviation less its neighbours' pull, for `rounds` rounds, and from then on a vertex needs only to exceed
// every neighbour but one, so that two impulses side by side are both put back (a crease or a
// corner still has two neighbours along it; the looser rule alone reads 1 % of Gaussian noise as
// impulses).
// Why: noise on a few vertices leaves the median-based noise estimate reading the quiet majority,
// so sparse impulses read as clean and were left; the literature's impulsive noise also moves the
// fine relief around them when a smoother spreads them (docs/studies/noise-estimate.md).
//
// Scale, order, threads: lengths in mean edge lengths; per-vertex values in parallel from the
// sorted 1-rings, counts in vertex order: the same for any thread count; the drivers run it on the
// mesh in spatial order, the same for any input order.
#pragma once

#include "vcg_ext/analysis/curvature.h"
#include "vcg_ext/core/rings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vcg_ext {

struct ImpulseParams {
  // Mean edge lengths: below, a deviation is noise or a coarse mesh's own corner (0.3 read a clean
  // 866-vertex cube's corners as impulses; docs/studies/noise-estimate.md).
  double min_size = 0.4;
  // Times the deviations' robust std (their median magnitude / 0.6745, over the movable
  // vertices): impulses stand out from the quiet majority, while heavy Gaussian or scanner noise
  // has deviations beyond min_size on many vertices, and putting those back took part of the
  // noise the estimate then read (docs/studies/noise-estimate.md).
  double relative_size = 5.0;
  double isolation = 3.0;   // times every neighbour's deviation
  // The share of the movable vertices that must read as impulses before any is moved: clean,
  // Gaussian, scanner and heavy scanner noise read at most 0.33 %, sparse impulses 3-4 %
  // (docs/studies/noise-estimate.md).
  double min_share = 0.005;
  int rounds = 3;
};

struct Impulses {
  long found = 0;           // in the first round
  double share = 0;         // found over the movable vertices
  double median_size = 0;   // of the first round's deviations, in mean edge lengths
  long moved = 0;           // by repairImpulses over its rounds (0 below min_share)
};

namespace detail {

// Per vertex, its deviation along its normal (see the file comment), in mean edge lengths; 0 where
// `fixed` or without a ring.
inline std::vector<double> impulseDeviations(const std::vector<Vec3> &points,
                                             const std::vector<Face> &faces, const Rings &rings,
                                             const std::vector<std::uint8_t> &fixed, double edge,
                                             std::vector<Vec3> &normals) {
  const int n = rings.vertex_count;
  computeVertexNormals(points, faces, rings, normals);
  std::vector<double> offset(n, 0.0), deviation(n, 0.0);
#pragma omp parallel for schedule(static) if (parallelHeavy(n))
  for (int v = 0; v < n; ++v) {
    if (rings.ring1Size(v) == 0) continue;
    Vec3 mean = Vec3::Zero();
    for (const int *a = rings.ring1Begin(v); a != rings.ring1End(v); ++a) mean += points[*a];
    offset[v] = normals[v].dot(points[v] - mean / rings.ring1Size(v)) / edge;
  }
#pragma omp parallel if (parallelHeavy(n))
  {
    std::vector<double> around; // one buffer per thread
#pragma omp for schedule(static)
    for (int v = 0; v < n; ++v) {
      if (fixed[v] || rings.ring1Size(v) == 0) continue;
      around.clear();
      for (const int *a = rings.ring1Begin(v); a != rings.ring1End(v); ++a)
        around.push_back(offset[*a]);
      auto mid = around.begin() + around.size() / 2;
      std::nth_element(around.begin(), mid, around.end());
      deviation[v] = offset[v] - *mid;
    }
  }
  return deviation;
}

// The vertices whose deviation is an impulse's: large and isolated from every neighbour, or with
// `pairs`, from every neighbour but one.
inline std::vector<std::uint8_t> impulseMarks(const std::vector<double> &deviation,
                                              const Rings &rings,
                                              const std::vector<std::uint8_t> &fixed,
                                              const ImpulseParams &params, bool pairs) {
  const int n = rings.vertex_count;
  std::vector<std::uint8_t> marks(n, 0);
  std::vector<double> magnitudes;
  for (int v = 0; v < n; ++v)
    if (!fixed[v] && rings.ring1Size(v) > 0) magnitudes.push_back(std::abs(deviation[v]));
  if (magnitudes.empty()) return marks;
  auto mid = magnitudes.begin() + magnitudes.size() / 2;
  std::nth_element(magnitudes.begin(), mid, magnitudes.end());
  const double threshold = std::max(params.min_size, params.relative_size * *mid / 0.6745);
#pragma omp parallel for schedule(static) if (parallelHeavy(n))
  for (int v = 0; v < n; ++v) {
    const double size = std::abs(deviation[v]);
    if (fixed[v] || !(size > threshold)) continue;
    double largest = 0, second = 0;
    for (const int *a = rings.ring1Begin(v); a != rings.ring1End(v); ++a) {
      const double d = std::abs(deviation[*a]);
      if (d > largest) second = largest, largest = d;
      else second = std::max(second, d);
    }
    marks[v] = size > params.isolation * (pairs ? second : largest);
  }
  return marks;
}

} // namespace detail

// The impulses of `points` (one round; nothing moves).
inline Impulses findImpulses(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                             const Rings &rings, const std::vector<std::uint8_t> &fixed,
                             double edge, const ImpulseParams &params = {}) {
  Impulses out;
  if (!(edge > 0) || faces.empty()) return out;
  std::vector<Vec3> normals;
  const std::vector<double> deviation =
      detail::impulseDeviations(points, faces, rings, fixed, edge, normals);
  const std::vector<std::uint8_t> marks =
      detail::impulseMarks(deviation, rings, fixed, params, /*pairs=*/false);
  std::vector<double> sizes;
  long movable = 0;
  for (int v = 0; v < rings.vertex_count; ++v) {
    movable += !fixed[v] && rings.ring1Size(v) > 0;
    if (marks[v]) sizes.push_back(std::abs(deviation[v]));
  }
  out.found = long(sizes.size());
  out.share = movable > 0 ? double(out.found) / double(movable) : 0.0;
  if (!sizes.empty()) {
    auto mid = sizes.begin() + sizes.size() / 2;
    std::nth_element(sizes.begin(), mid, sizes.end());
    out.median_size = *mid;
  }
  return out;
}

// Moves the impulses of `points` back (params.rounds rounds, also two side by side; see the file
// comment), whatever their share. Returns the moves made.
inline long putBackImpulses(std::vector<Vec3> &points, const std::vector<Face> &faces,
                            const Rings &rings, const std::vector<std::uint8_t> &fixed,
                            double edge, const ImpulseParams &params = {}) {
  long total = 0;
  std::vector<Vec3> normals;
  for (int round = 0; round < params.rounds; ++round) {
    const std::vector<double> deviation =
        detail::impulseDeviations(points, faces, rings, fixed, edge, normals);
    const std::vector<std::uint8_t> marks =
        detail::impulseMarks(deviation, rings, fixed, params, /*pairs=*/true);
    long moved = 0;
    for (int v = 0; v < rings.vertex_count; ++v)
      if (marks[v]) {
        // An impulse d pulls each neighbour's ring mean by about d / k (k its valence), so its
        // deviation reads d (1 + 1 / k): moved back by d alone.
        const double k = rings.ring1Size(v);
        points[v] -= normals[v] * (deviation[v] * k / (k + 1) * edge);
        ++moved;
      }
    total += moved;
    if (moved == 0) break;
  }
  return total;
}

// True when `found` (findImpulses) holds enough impulses to act on (ImpulseParams::min_share).
inline bool enoughImpulses(const Impulses &found, const ImpulseParams &params = {}) {
  return found.found > 0 && found.share >= params.min_share;
}

// Finds the impulses of `points` and, when there are enough of them (enoughImpulses), puts them
// back (putBackImpulses). Returns the reading and how many moves were made.
inline Impulses repairImpulses(std::vector<Vec3> &points, const std::vector<Face> &faces,
                               const Rings &rings, const std::vector<std::uint8_t> &fixed,
                               double edge, const ImpulseParams &params = {}) {
  Impulses out = findImpulses(points, faces, rings, fixed, edge, params);
  if (enoughImpulses(out, params))
    out.moved = putBackImpulses(points, faces, rings, fixed, edge, params);
  return out;
}

} // namespace vcg_ext
