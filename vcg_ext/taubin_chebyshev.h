// Many Taubin λ|μ pairs at once: the Chebyshev series of their frequency response, truncated.
//
// Input: a pair count K, Taubin's λ and μ, a tolerance. Output: the coefficients c_0..c_d of
// Σ c_j T_j(p) ≈ t(p)^K, where p is an eigenvalue of the 1-ring averaging operator P (a Taubin step
// with factor f is (1 − f) I + f P) and t(p) = ((1 − μ) + μp)((1 − λ) + λp) is one pair's
// response; the coefficients left out sum to at most `tolerance` in absolute value. Papers:
// Taubin 1995 (the pair as a polynomial filter); the Chebyshev approximation of graph filters as in
// Hammond, Vandergheynst, Gribonval 2011 (spectral graph wavelets), evaluated by Clenshaw's
// recurrence (SpatialTaubin::applyChebyshev).
//
// Why: t(p)^K is a polynomial of degree 2K, but a smooth one: its Chebyshev coefficients fall off
// fast: 64 pairs (128 steps) are within 1e-10 of a series of degree 36, 32 pairs of one of degree
// 29 (within 1e-6: degrees 25 and 20, and 16 pairs one of degree 16). The band shrinkage's three
// coarsest bands (16–32, 32–64, 64–128 pairs) take 224 of its 256 steps; as series truncated at
// its tolerance of 1e-6, 64 operator applications. P's eigenvalues lie in [−1, 1] (rows average
// neighbours; boundary curves and still vertices make it block triangular, each block similar to a
// symmetric one), where |T_j| ≤ 1, so the truncation error is at most the tolerance times the
// field's extent.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace vcg_ext {

// The Chebyshev coefficients of t(p)^pairs (see above), truncated where the tail sums to at most
// `tolerance`. pairs ≤ 0: {1} (the identity).
inline std::vector<double> taubinChebyshevCoefficients(int pairs, double lambda, double mu,
                                                       double tolerance = 1e-10) {
  // t(p) = a + b p + c p², and p² = (T_0 + T_2) / 2.
  const double a = (1 - mu) * (1 - lambda), b = (1 - mu) * lambda + mu * (1 - lambda),
               c = lambda * mu;
  const std::vector<double> pair = {a + 0.5 * c, b, 0.5 * c};
  std::vector<double> power = {1.0};
  for (int k = 0; k < pairs; ++k) {
    // T_m T_n = (T_{m+n} + T_{|m−n|}) / 2.
    std::vector<double> next(power.size() + 2, 0.0);
    for (size_t m = 0; m < power.size(); ++m)
      for (size_t n = 0; n < pair.size(); ++n) {
        const double product = 0.5 * power[m] * pair[n];
        next[m + n] += product;
        next[m > n ? m - n : n - m] += product;
      }
    power.swap(next);
  }
  // Drop the longest tail whose coefficients sum to at most the tolerance.
  double tail = 0;
  size_t keep = power.size();
  while (keep > 1 && tail + std::abs(power[keep - 1]) <= tolerance) tail += std::abs(power[--keep]);
  power.resize(keep);
  return power;
}

// Whether the series is cheaper than the pairs themselves: a Clenshaw step reads one field more
// than a Taubin step (measured 1.36 times its time on 2.6M vertices), a pair is two steps.
inline bool chebyshevPays(const std::vector<double> &coefficients, int pairs) {
  return 1.4 * double(coefficients.size()) < 2.0 * pairs;
}

} // namespace vcg_ext
