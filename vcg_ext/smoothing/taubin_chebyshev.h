// Many Taubin λ|μ pairs at once: the Chebyshev series of their frequency response, truncated.
//
// Input: a pair count K, Taubin's λ and μ, a tolerance. Output: the coefficients c_0..c_d of
// Σ c_j T_j(p) ≈ t(p)^K, where p is an eigenvalue of the 1-ring averaging operator P (a Taubin step
// with factor f is (1 − f) I + f P) and t(p) = ((1 − μ) + μp)((1 − λ) + λp) is one pair's
// response; the coefficients left out sum to at most `tolerance` in absolute value, and their sum
// at p = 1 is added to c_0, so that the series is exact at p = 1 (t(1) = 1). Papers:
// Taubin 1995 (the pair as a polynomial filter); the Chebyshev approximation of graph filters as in
// Hammond, Vandergheynst, Gribonval 2011 (spectral graph wavelets), evaluated by Clenshaw's
// recurrence (SpatialTaubin::applyChebyshev).
//
// Why: t(p)^K is a polynomial of degree 2K, but a smooth one: its Chebyshev coefficients fall off
// fast: 64 pairs (128 steps) are within 1e-10 of a series of degree 36, 32 pairs of one of degree
// 29 (within 1e-4: degrees 18 and 15, 16 pairs one of degree 11, 8 pairs one of 9). The band
// shrinkage's four coarsest bands (8–16 to 64–128 pairs) take 240 of its 256 steps; as series
// truncated at its tolerance of 1e-4, 57 operator applications. P's eigenvalues lie in [−1, 1]
// (rows average neighbours; boundary curves and still vertices make it block triangular, each
// block similar to a symmetric one), where |T_j| ≤ 1, so the truncation error is at most twice
// the tolerance times the field's extent, and it vanishes at p = 1: a field's smooth part (the
// shape, whose extent is the mesh's) lies near p = 1, where T_j(p) − 1 is small, so only its fine
// variation (the noise, a fraction of an edge length) carries the error. Without that correction
// the truncation would scale the whole shape about its centre by up to the tolerance.
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
  // Drop the longest tail whose coefficients sum to at most the tolerance, and give c_0 what the
  // tail held at p = 1 (every T_j(1) is 1): the series stays exact where the response is 1.
  double tail = 0, dropped = 0;
  size_t keep = power.size();
  while (keep > 1 && tail + std::abs(power[keep - 1]) <= tolerance) {
    dropped += power[keep - 1];
    tail += std::abs(power[--keep]);
  }
  power.resize(keep);
  power[0] += dropped;
  return power;
}

// Whether the series is cheaper than the pairs themselves: a Clenshaw step reads one field more
// than a Taubin step (1.36 times its time on 2.6M vertices), a pair is two steps.
inline bool chebyshevPays(const std::vector<double> &coefficients, int pairs) {
  return 1.4 * double(coefficients.size()) < 2.0 * pairs;
}

} // namespace vcg_ext
