// LDLᵀ of a symmetric positive definite 9×9 matrix without pivoting, and its solve: the normal
// equations of the patch fits (bezier_patch.h, face_patches.h).
//
// Input: the lower triangle of M (row-major, M[i][j] for j ≤ i). Output: L below the diagonal and D
// on it, in place. Papers: none (Golub & Van Loan, Algorithm 4.1.2).
//
// Why not Eigen's LDLT: it pivots (a search and row swaps at every column), which the fits do not
// need: their matrices are positive semi-definite, and a pivot that is not positive, or tiny
// against the largest, is the rank deficiency the callers test for anyway. Unpivoted, the
// face-patch update is faster (docs/studies/performance.md).
#pragma once

#include <algorithm>
#include <cmath>

namespace vcg_ext {
namespace detail {

// In place (see above). False when a pivot is not positive or at most 1e-14 of M's largest diagonal
// entry, or when the smallest pivot is at most `pivot_ratio` times the largest: rank deficiency,
// for which the callers have their own fallback.
inline bool ldlt9(double M[9][9], double pivot_ratio) {
  double largest = 0;
  for (int k = 0; k < 9; ++k) largest = std::max(largest, M[k][k]);
  if (!(largest > 0) || !std::isfinite(largest)) return false;
  double smallest = INFINITY, biggest = 0;
  for (int k = 0; k < 9; ++k) {
    double ld[9]; // L[k][j]·D[j]
    double d = M[k][k];
    for (int j = 0; j < k; ++j) {
      ld[j] = M[k][j] * M[j][j];
      d -= M[k][j] * ld[j];
    }
    // Pivots of a semi-definite matrix are ≥ 0 in exact arithmetic; here rounding only.
    if (!(d > 1e-14 * largest) || !std::isfinite(d)) return false;
    M[k][k] = d;
    smallest = std::min(smallest, d), biggest = std::max(biggest, d);
    for (int i = k + 1; i < 9; ++i) {
      double x = M[i][k];
      for (int j = 0; j < k; ++j) x -= M[i][j] * ld[j];
      M[i][k] = x / d;
    }
  }
  return smallest > pivot_ratio * biggest;
}

// X = M⁻¹ B from ldlt9's factors for R right-hand sides at once (row-major 9×R arrays: B[i·R + r]):
// L Y = B, D Z = Y (by the reciprocal of each pivot), Lᵀ X = Z.
template <int R>
inline void ldlt9Solve(const double L[9][9], const double *B, double *X) {
  double y[9][R];
  for (int i = 0; i < 9; ++i) {
    double v[R];
    for (int r = 0; r < R; ++r) v[r] = B[i * R + r];
    for (int j = 0; j < i; ++j)
      for (int r = 0; r < R; ++r) v[r] -= L[i][j] * y[j][r];
    for (int r = 0; r < R; ++r) y[i][r] = v[r];
  }
  for (int i = 0; i < 9; ++i) {
    const double inverse = 1.0 / L[i][i];
    for (int r = 0; r < R; ++r) y[i][r] *= inverse;
  }
  for (int i = 8; i >= 0; --i) {
    double v[R];
    for (int r = 0; r < R; ++r) v[r] = y[i][r];
    for (int j = i + 1; j < 9; ++j)
      for (int r = 0; r < R; ++r) v[r] -= L[j][i] * X[j * R + r];
    for (int r = 0; r < R; ++r) X[i * R + r] = v[r];
  }
}

} // namespace detail
} // namespace vcg_ext
