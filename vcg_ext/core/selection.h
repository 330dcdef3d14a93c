// Order statistics on large arrays: NaN removal and the k-th smallest value, in parallel where
// that pays, with the bits of a serial std::nth_element (medians everywhere in the analysis).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vcg_ext {

namespace detail {
// Removes the NaN entries (the "no value" of per-element arrays filled in parallel), keeping the
// others in order.
inline void eraseNaN(std::vector<double> &values) {
  const long n = long(values.size());
  constexpr long kBlock = 1 << 16;
  if (n < 16 * kBlock) {
    values.erase(std::remove_if(values.begin(), values.end(), [](double x) { return std::isnan(x); }),
                 values.end());
    return;
  }
  // Large arrays in parallel blocks: each block's kept values, then copied to their places.
  const long blocks = (n + kBlock - 1) / kBlock;
  std::vector<long> start(blocks + 1, 0);
#pragma omp parallel for schedule(static)
  for (long b = 0; b < blocks; ++b)
    for (long i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i)
      start[b + 1] += !std::isnan(values[size_t(i)]);
  for (long b = 0; b < blocks; ++b) start[b + 1] += start[b];
  std::vector<double> kept(static_cast<size_t>(start[blocks]));
#pragma omp parallel for schedule(static)
  for (long b = 0; b < blocks; ++b) {
    long at = start[b];
    for (long i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i)
      if (!std::isnan(values[size_t(i)])) kept[size_t(at++)] = values[size_t(i)];
  }
  values.swap(kept);
}

// The k-th smallest of `values` (0-based): the value std::nth_element puts at position k, which
// does not depend on how it is found. Large arrays: a bracket around it from a regular sample, one
// counting sweep (in parallel), then a selection among the values inside the bracket (a sample
// that misses falls back to std::nth_element). From 50k values on, where a plain selection is a
// serial step the noise estimate takes several times (docs/studies/performance.md).
// Reorders `values`.
inline double kthSmallest(std::vector<double> &values, size_t k,
                          size_t parallel_from = 50000) {
  const size_t n = values.size();
#ifndef _OPENMP
  parallel_from = n + 1; // one thread: the plain selection
#endif
  if (n < parallel_from || n < 2 || k >= n) {
    std::nth_element(values.begin(), values.begin() + std::min(k, n - 1), values.end());
    return values[std::min(k, n - 1)];
  }
  // The sample: one value in every 16, at most 65536; the bracket ±4 standard deviations of the
  // k-th value's rank in it (at least 32 ranks), found by two selections. A larger sample takes a
  // narrower bracket (a few per cent of the noise estimate's millions of probe values), and the
  // bracket's selection is most of the serial time.
  const size_t samples = std::min<size_t>(n / 16, size_t(1) << 16);
  std::vector<double> sample(samples);
  for (size_t i = 0; i < samples; ++i) sample[i] = values[i * (n / samples)];
  const double q = double(k) / double(n);
  const size_t at = std::min(samples - 1, size_t(q * double(samples)));
  const size_t margin =
      std::max<size_t>(32, size_t(std::ceil(4.0 * std::sqrt(double(samples) * q * (1 - q)))));
  const size_t lo_rank = at > margin ? at - margin : 0,
               hi_rank = std::min(samples - 1, at + margin);
  std::nth_element(sample.begin(), sample.begin() + hi_rank, sample.end());
  const double hi = sample[hi_rank];
  std::nth_element(sample.begin(), sample.begin() + lo_rank, sample.begin() + hi_rank);
  const double lo = lo_rank < hi_rank ? sample[lo_rank] : hi;
  const long count = long(n);
  long below = 0;
  std::vector<std::vector<double>> inside;
#ifdef _OPENMP
  inside.resize(omp_get_max_threads());
#pragma omp parallel reduction(+ : below)
  {
    std::vector<double> &mine = inside[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long i = 0; i < count; ++i) {
      const double x = values[size_t(i)];
      if (x < lo) ++below;
      else if (x <= hi) mine.push_back(x);
    }
  }
#endif
  size_t within = 0;
  for (const auto &part : inside) within += part.size();
  if (size_t(below) > k || k >= size_t(below) + within) {
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
  }
  std::vector<double> middle;
  middle.reserve(within);
  for (auto &part : inside) middle.insert(middle.end(), part.begin(), part.end());
  std::nth_element(middle.begin(), middle.begin() + (k - size_t(below)), middle.end());
  return middle[k - size_t(below)];
}
} // namespace detail

} // namespace vcg_ext
