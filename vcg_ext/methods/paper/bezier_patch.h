// Stage 5: the weighted bi-quadratic Bézier patch of one vertex (paper 3.2), and its differential
// geometry (paper 3.3).
//
// Inputs: parameters (u_k, v_k) of the fitted points (the driver projects q_i and its 2-ring onto
// the frame (e1, e2, N) and scales the min-max box to [0,1]²), the points, optional per-point
// weights and the paper's factor α. Output: the 9 control points b_ij of
//   B(u,v) = Σ_i Σ_j B_i,2(u) B_j,2(v) b_ij,
//   x = [b00 b01 b02 b10 b11 b12 b20 b21 b22] (paper order),
// minimising ‖α(Ax − B)‖² + ‖(1−α)Sx‖², S the paper's 4×9 "parallelogram" matrix.
//
// Orientation: the patch normal is n = Bu×Bv/|Bu×Bv| (paper), and the signs of H and of L, M, N
// follow it. Callers must build the frame so that e1 × e2 = N points along the vertex normal (u
// runs along e1, v along e2); then H > 0 where the surface bends toward the normal, as in stage 2,
// and a patch of z = a x² + b y² over the xy plane has H = a + b, K = 4ab at its apex.
//
// Everything here works on fixed-size Eigen types and never touches the heap.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"
#include "vcg_ext/core/small_ldlt.h"

#include <algorithm>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

namespace vcg_ext {

using BezierCoefficients = Eigen::Matrix<double, 9, 1>;

namespace detail {
// Quadratic Bernstein polynomials B_0,2, B_1,2, B_2,2 and their first and second derivatives.
inline void bernstein2(double t, double b[3], double db[3], double ddb[3]) {
  const double s = 1.0 - t;
  b[0] = s * s;
  b[1] = 2.0 * t * s;
  b[2] = t * t;
  db[0] = -2.0 * s;
  db[1] = 2.0 - 4.0 * t;
  db[2] = 2.0 * t;
  ddb[0] = 2.0;
  ddb[1] = -4.0;
  ddb[2] = 2.0;
}
} // namespace detail

// Row A_k of the paper's matrix A: B_i,2(u) B_j,2(v) at index 3i + j.
inline BezierCoefficients bernsteinProducts(double u, double v) {
  double bu[3], dbu[3], ddbu[3], bv[3], dbv[3], ddbv[3];
  detail::bernstein2(u, bu, dbu, ddbu);
  detail::bernstein2(v, bv, dbv, ddbv);
  BezierCoefficients a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[3 * i + j] = bu[i] * bv[j];
  return a;
}

struct BezierPatch {
  std::array<Vec3, 9> b; // b[3*i + j] = b_ij; i goes with u, j with v

  Vec3 eval(double u, double v) const {
    const BezierCoefficients a = bernsteinProducts(u, v);
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 9; ++k) p += a[k] * b[k];
    return p;
  }

  void derivatives(double u, double v, Vec3 &Bu, Vec3 &Bv, Vec3 &Buu, Vec3 &Buv, Vec3 &Bvv) const {
    double bu[3], dbu[3], ddbu[3], bv[3], dbv[3], ddbv[3];
    detail::bernstein2(u, bu, dbu, ddbu);
    detail::bernstein2(v, bv, dbv, ddbv);
    Bu.setZero();
    Bv.setZero();
    Buu.setZero();
    Buv.setZero();
    Bvv.setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Vec3 &c = b[3 * i + j];
        Bu += dbu[i] * bv[j] * c;
        Bv += bu[i] * dbv[j] * c;
        Buu += ddbu[i] * bv[j] * c;
        Buv += dbu[i] * dbv[j] * c;
        Bvv += bu[i] * ddbv[j] * c;
      }
  }

  // The third derivatives that are not identically zero (Buuu = Bvvv = 0 on a bi-quadratic patch).
  void thirdDerivatives(double u, double v, Vec3 &Buuv, Vec3 &Buvv) const {
    double bu[3], dbu[3], ddbu[3], bv[3], dbv[3], ddbv[3];
    detail::bernstein2(u, bu, dbu, ddbu);
    detail::bernstein2(v, bv, dbv, ddbv);
    Buuv.setZero();
    Buvv.setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Buuv += ddbu[i] * dbv[j] * b[3 * i + j];
        Buvv += dbu[i] * ddbv[j] * b[3 * i + j];
      }
  }

  // Unit normal Bu×Bv/|Bu×Bv|; zero where the patch is singular (Bu ∥ Bv or a zero derivative).
  Vec3 normal(double u, double v) const {
    Vec3 Bu, Bv, Buu, Buv, Bvv;
    derivatives(u, v, Bu, Bv, Buu, Buv, Bvv);
    const Vec3 m = Bu.cross(Bv);
    const double len2 = m.squaredNorm();
    if (!(len2 > kSingularSin2 * Bu.squaredNorm() * Bv.squaredNorm()) || !std::isfinite(len2))
      return Vec3::Zero();
    return m / std::sqrt(len2);
  }

  // K = (LN−M²)/(EG−F²), H = (NE−2MF+LG)/(2(EG−F²)) (paper 3.3). False where EG−F² = |Bu×Bv|² is
  // tiny relative to |Bu|²|Bv|² (the parametrisation is singular there and K, H are undefined).
  bool curvature(double u, double v, double &K, double &H) const {
    double Ku, Kv, Hu, Hv;
    return evaluateCurvature(u, v, K, H, false, Ku, Kv, Hu, Hv);
  }

  // K, H and their exact partial derivatives in u and v (for stage 7's Newton Jacobian).
  bool curvatureWithGradient(double u, double v, double &K, double &H, double &Ku, double &Kv,
                             double &Hu, double &Hv) const {
    return evaluateCurvature(u, v, K, H, true, Ku, Kv, Hu, Hv);
  }

  // sin² of the angle between Bu and Bv below which the parametrisation counts as singular.
  static constexpr double kSingularSin2 = 1e-20;

private:
  // Written with the unnormalised normal m = Bu×Bv, |m|² = W = EG − F²:
  //   K = (ℓn − m̃²)/W²,  H = (ñE − 2m̃F + ℓG)/(2 W^{3/2}),  ℓ = Buu·m, m̃ = Buv·m, ñ = Bvv·m,
  // which avoids differentiating the normalisation.
  bool evaluateCurvature(double u, double v, double &K, double &H, bool with_gradient, double &Ku,
                         double &Kv, double &Hu, double &Hv) const {
    Vec3 Bu, Bv, Buu, Buv, Bvv;
    derivatives(u, v, Bu, Bv, Buu, Buv, Bvv);
    const double E = Bu.dot(Bu), F = Bu.dot(Bv), G = Bv.dot(Bv);
    const Vec3 m = Bu.cross(Bv);
    const double W = m.squaredNorm(); // = EG − F², without the cancellation
    if (!std::isfinite(W) || !(W > kSingularSin2 * E * G)) return false;
    const double l = Buu.dot(m), mm = Buv.dot(m), n = Bvv.dot(m);
    const double sqrtW = std::sqrt(W);
    const double P = n * E - 2.0 * mm * F + l * G;
    K = (l * n - mm * mm) / (W * W);
    H = P / (2.0 * W * sqrtW);
    if (!with_gradient) return std::isfinite(K) && std::isfinite(H);

    Vec3 Buuv, Buvv;
    thirdDerivatives(u, v, Buuv, Buvv);
    const Vec3 m_u = Buu.cross(Bv) + Bu.cross(Buv);
    const Vec3 m_v = Buv.cross(Bv) + Bu.cross(Bvv);
    const double E_u = 2.0 * Bu.dot(Buu), E_v = 2.0 * Bu.dot(Buv);
    const double F_u = Buu.dot(Bv) + Bu.dot(Buv), F_v = Buv.dot(Bv) + Bu.dot(Bvv);
    const double G_u = 2.0 * Bv.dot(Buv), G_v = 2.0 * Bv.dot(Bvv);
    const double W_u = 2.0 * m.dot(m_u), W_v = 2.0 * m.dot(m_v);
    // Buuu = Bvvv = 0 for a bi-quadratic patch.
    const double l_u = Buu.dot(m_u), l_v = Buuv.dot(m) + Buu.dot(m_v);
    const double mm_u = Buuv.dot(m) + Buv.dot(m_u), mm_v = Buvv.dot(m) + Buv.dot(m_v);
    const double n_u = Buvv.dot(m) + Bvv.dot(m_u), n_v = Bvv.dot(m_v);
    const double num = l * n - mm * mm;
    Ku = (l_u * n + l * n_u - 2.0 * mm * mm_u) / (W * W) - 2.0 * num * W_u / (W * W * W);
    Kv = (l_v * n + l * n_v - 2.0 * mm * mm_v) / (W * W) - 2.0 * num * W_v / (W * W * W);
    const double P_u = n_u * E + n * E_u - 2.0 * (mm_u * F + mm * F_u) + l_u * G + l * G_u;
    const double P_v = n_v * E + n * E_v - 2.0 * (mm_v * F + mm * F_v) + l_v * G + l * G_v;
    Hu = P_u / (2.0 * W * sqrtW) - 0.75 * P * W_u / (W * W * sqrtW);
    Hv = P_v / (2.0 * W * sqrtW) - 0.75 * P * W_v / (W * W * sqrtW);
    return std::isfinite(K) && std::isfinite(H) && std::isfinite(Ku) && std::isfinite(Kv) &&
           std::isfinite(Hu) && std::isfinite(Hv);
  }
};

// The paper's S: one row per quadrilateral of the control net, b_i,j − b_i,j+1 − b_i+1,j +
// b_i+1,j+1, zero when the quadrilateral is a parallelogram.
inline const Eigen::Matrix<double, 4, 9> &parallelogramMatrix() {
  static const Eigen::Matrix<double, 4, 9> S = [] {
    Eigen::Matrix<double, 4, 9> s;
    s << 1, -1, 0, -1, 1, 0, 0, 0, 0, //
        0, 1, -1, 0, -1, 1, 0, 0, 0,  //
        0, 0, 0, 1, -1, 0, -1, 1, 0,  //
        0, 0, 0, 0, 1, -1, 0, -1, 1;
    return s;
  }();
  return S;
}

enum class FitStatus {
  Ok,
  RankDeficient, // the normal equations are singular; solved by the minimum-norm pseudo-inverse
  Failed         // non-finite input, α outside (0,1], negative weight or no point; `out` untouched
};

// Relative pivot / eigenvalue thresholds of the fit. The normal matrix depends only on (u,v), w and
// α (not on the points' scale), so relative thresholds are geometry-independent.
struct FitThresholds {
  static constexpr double ldlt_pivot_ratio = 1e-10; // below: do not trust LDLᵀ, use the eigen solve
  static constexpr double pseudo_inverse = 1e-11;   // eigenvalues below this × the largest: dropped
};

namespace detail {

// The fit's normal equations M x = rhs (x: the 9 control points minus `centre`, one column per
// coordinate), data term weighted by α², smoothness (the parallelogram term) by (1 − α)².
// AᵀA has 45 distinct entries but only 36 distinct values: entry ((i,j),(k,l)) is
// Σ B_i(u)B_k(u) · B_j(v)B_l(v), a product of one of 6 u-pairs and one of 6 v-pairs. The sums run
// over chunks of 8 points as dot products of fixed length (unrolled and vectorised; the
// accumulators stay in registers), the last chunk padded with zero weights.
inline void bezierNormalEquations(const double *u, const double *v, const Vec3 *points,
                                  const double *w, int n, double alpha, const Vec3 &centre,
                                  double M[9][9], double rhs[9][3]) {
  constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  constexpr int kChunk = 8;
  double products[6][6] = {};
  for (int r = 0; r < 9; ++r) rhs[r][0] = rhs[r][1] = rhs[r][2] = 0.0;
  const double a2 = alpha * alpha;
  for (int first = 0; first < n; first += kChunk) {
    alignas(16) double pu[6][kChunk], pv[6][kChunk], bb[9][kChunk], d[3][kChunk];
    for (int c = 0; c < kChunk; ++c) {
      const int k = first + c;
      const bool real = k < n;
      const double wk = real ? a2 * (w ? w[k] : 1.0) : 0.0;
      const double uk = real ? u[k] : 0.0, vk = real ? v[k] : 0.0;
      const double su = 1.0 - uk, sv = 1.0 - vk;
      const double bu[3] = {su * su, 2.0 * uk * su, uk * uk};
      const double bv[3] = {sv * sv, 2.0 * vk * sv, vk * vk};
      pu[0][c] = wk * bu[0] * bu[0], pu[1][c] = wk * bu[0] * bu[1], pu[2][c] = wk * bu[0] * bu[2];
      pu[3][c] = wk * bu[1] * bu[1], pu[4][c] = wk * bu[1] * bu[2], pu[5][c] = wk * bu[2] * bu[2];
      pv[0][c] = bv[0] * bv[0], pv[1][c] = bv[0] * bv[1], pv[2][c] = bv[0] * bv[2];
      pv[3][c] = bv[1] * bv[1], pv[4][c] = bv[1] * bv[2], pv[5][c] = bv[2] * bv[2];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) bb[3 * i + j][c] = wk * bu[i] * bv[j];
      const Vec3 delta = real ? Vec3(points[k] - centre) : Vec3::Zero();
      d[0][c] = delta.x(), d[1][c] = delta.y(), d[2][c] = delta.z();
    }
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) {
        double sum = 0;
        for (int c = 0; c < kChunk; ++c) sum += pu[a][c] * pv[b][c];
        products[a][b] += sum;
      }
    for (int r = 0; r < 9; ++r)
      for (int x = 0; x < 3; ++x) {
        double sum = 0;
        for (int c = 0; c < kChunk; ++c) sum += bb[r][c] * d[x][c];
        rhs[r][x] += sum;
      }
  }
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c <= r; ++c) M[r][c] = M[c][r] = products[kPair[r / 3][c / 3]][kPair[r % 3][c % 3]];
  const double s2 = (1.0 - alpha) * (1.0 - alpha);
  if (s2 > 0.0) {
    static const Eigen::Matrix<double, 9, 9> StS =
        parallelogramMatrix().transpose() * parallelogramMatrix();
    for (int r = 0; r < 9; ++r)
      for (int c = 0; c < 9; ++c) M[r][c] += s2 * StS(r, c);
  }
}

// The rank-revealing fallback: X = M⁺ rhs, the pseudo-inverse from the symmetric
// eigen-decomposition (eigenvalues below FitThresholds::pseudo_inverse of the largest dropped:
// RankDeficient).
inline FitStatus pseudoInverseSolve(const double M[9][9], const double rhs[9][3],
                                    Eigen::Matrix<double, 9, 3> &X) {
  Eigen::Matrix<double, 9, 9> A;
  Eigen::Matrix<double, 9, 3> R;
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 9; ++c) A(r, c) = M[r][c];
    for (int c = 0; c < 3; ++c) R(r, c) = rhs[r][c];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(A);
  if (eig.info() != Eigen::Success) return FitStatus::Failed;
  const auto &lambda = eig.eigenvalues(); // ascending
  const double lmax = lambda[8];
  if (!(lmax > 0.0)) return FitStatus::Failed;
  FitStatus status = FitStatus::Ok;
  Eigen::Matrix<double, 9, 1> inv;
  for (int k = 0; k < 9; ++k) {
    if (lambda[k] > FitThresholds::pseudo_inverse * lmax) {
      inv[k] = 1.0 / lambda[k];
    } else {
      inv[k] = 0.0;
      status = FitStatus::RankDeficient;
    }
  }
  const auto &V = eig.eigenvectors();
  X.noalias() = V * (inv.asDiagonal() * (V.transpose() * R));
  return status;
}

} // namespace detail

// Weighted least-squares fit of the patch:
//   minimise α² Σ_k w_k |A_k x − q_k|² + (1−α)² |S x|²   (w = nullptr: all w_k = 1),
// i.e. w_k weights the squared residual of point k (its row of A and B is multiplied by √w_k).
// The points are centred on their mean before the solve: the fit is translation invariant in
// exact arithmetic (A's rows sum to 1, S's rows to 0) and a minimum-norm solution then keeps the
// undetermined control points near the data instead of near the world origin.
inline FitStatus fitBezierPatch(const double *u, const double *v, const Vec3 *points, const double *w,
                                int n, double alpha, BezierPatch &out) {
  if (n < 1 || !(alpha > 0.0 && alpha <= 1.0)) return FitStatus::Failed;
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(u[k]) || !std::isfinite(v[k]) || !points[k].allFinite()) return FitStatus::Failed;
    if (w && !(w[k] >= 0.0 && std::isfinite(w[k]))) return FitStatus::Failed;
    centre += points[k];
  }
  centre /= double(n);
  double M[9][9], rhs[9][3];
  detail::bezierNormalEquations(u, v, points, w, n, alpha, centre, M, rhs);

  Eigen::Matrix<double, 9, 3> X;
  FitStatus status = FitStatus::Ok;
  double L[9][9];
  std::copy(&M[0][0], &M[0][0] + 81, &L[0][0]);
  if (detail::ldlt9(L, FitThresholds::ldlt_pivot_ratio)) {
    double solution[9][3]; // the three coordinates together
    detail::ldlt9Solve<3>(L, &rhs[0][0], &solution[0][0]);
    for (int i = 0; i < 9; ++i)
      for (int r = 0; r < 3; ++r) X(i, r) = solution[i][r];
  } else {
    status = detail::pseudoInverseSolve(M, rhs, X);
    if (status == FitStatus::Failed) return status;
  }
  if (!X.allFinite()) return FitStatus::Failed;
  for (int k = 0; k < 9; ++k) out.b[k] = X.row(k).transpose() + centre;
  return status;
}

} // namespace vcg_ext
