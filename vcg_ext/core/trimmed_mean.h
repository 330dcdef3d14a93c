// Trimmed means: the mean of the values below a quantile, which a minority of outlying values
// (creases, relief, spikes) does not reach.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace vcg_ext {

// Mean of the values below the `quantile` quantile (at least one value; reorders x). 0 when empty.
inline double trimmedMean(std::vector<double> &x, double quantile) {
  if (x.empty()) return 0.0;
  const size_t keep = std::max<size_t>(1, size_t(quantile * double(x.size())));
  std::nth_element(x.begin(), x.begin() + long(keep - 1), x.end());
  double sum = 0;
  for (size_t i = 0; i < keep; ++i) sum += x[i];
  return sum / double(keep);
}

// E[x² | x² below its `quantile` quantile] for x ~ N(0, 1): what trimmedMean of squared Gaussian
// values gives for unit variance (1 at quantile 1, 0.368 at 0.75, 0.143 at 0.5).
inline double gaussianTrimmedSquare(double quantile) {
  if (!(quantile < 1.0)) return 1.0;
  if (!(quantile > 0.0)) return 0.0;
  double lo = 0, hi = 40; // a with P(|x| < a) = erf(a / √2) = quantile
  for (int i = 0; i < 200; ++i) {
    const double a = 0.5 * (lo + hi);
    (std::erf(a / std::sqrt(2.0)) < quantile ? lo : hi) = a;
  }
  const double a = 0.5 * (lo + hi), pi = 3.14159265358979323846;
  return (quantile - 2.0 * a * std::exp(-0.5 * a * a) / std::sqrt(2.0 * pi)) / quantile;
}

} // namespace vcg_ext
