// Per-vertex values on scales that MeshLab's colour map shows well at its default settings, which
// spread the full range of vertex quality over the colours: a few extreme values (sharp corners,
// tiny faces, noise) would otherwise leave everything else one colour.
//
// Inputs: per-vertex values. Outputs: the same values rescaled. Both are independent of vertex
// order (a percentile and a median) and of the mesh's scale.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace vcg_ext {

// The value at `fraction` (0..1) of the sorted values (nearest rank); 0 for none.
inline double percentileOf(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, size_t(fraction * double(values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + long(k), values.end());
  return values[k];
}

// Non-negative values (saliency) divided by their `fraction` percentile and clipped to [0, 1]:
// the top 1 % share the top colour, the rest spread over the others. Measured on the clean
// Fandisk: divided by the maximum, 98 % of the vertices fall below 0.45 and its creases barely
// show; divided by the 99th percentile they stand out.
inline std::vector<double> percentileClipped(const std::vector<double> &values,
                                             double fraction = 0.99) {
  const double top = percentileOf(values, fraction);
  std::vector<double> out(values.size(), 0.0);
  if (!(top > 0) || !std::isfinite(top)) return out;
  for (size_t i = 0; i < values.size(); ++i)
    out[i] = std::isfinite(values[i]) ? std::clamp(values[i] / top, 0.0, 1.0) : 0.0;
  return out;
}

// Signed values (curvatures) on a signed log scale: asinh(value / m), m the median magnitude, so
// that typical values read about ±0.9, a value 100 times larger about ±5.3, and the sign stays.
inline std::vector<double> signedLogScale(const std::vector<double> &values) {
  std::vector<double> magnitude(values.size());
  for (size_t i = 0; i < values.size(); ++i)
    magnitude[i] = std::isfinite(values[i]) ? std::abs(values[i]) : 0.0;
  double m = percentileOf(magnitude, 0.5);
  if (!(m > 0)) m = percentileOf(magnitude, 0.99); // mostly flat: scale by the curved part
  std::vector<double> out(values.size(), 0.0);
  if (!(m > 0) || !std::isfinite(m)) return out;
  for (size_t i = 0; i < values.size(); ++i)
    out[i] = std::isfinite(values[i]) ? std::asinh(values[i] / m) : 0.0;
  return out;
}

} // namespace vcg_ext
