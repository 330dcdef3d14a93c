// Stage 7: the new vertex position on its patch (paper 3.3).
//
// Inputs: the vertex's fitted patch (stage 5), its own parameter (u0, v0) and the target curvatures
// K* = k1'k2', H* = (k1'+k2')/2 from stage 6. Output: a parameter (u, v) in [0,1]² where
// K(u,v) = K*, H(u,v) = H* if Newton's method finds it; the new vertex is patch.eval(u, v).
// Paper: Newton from (u0, v0), 2 iterations, clamp to [0,1]² afterwards. Added here:
// - a safeguard (max_step > 0): a step whose clamped point lies farther than max_step from
//   B(u0, v0) is halved, up to 8 times; if none fits, the iteration stops at the last accepted point;
// - an early stop when the residual is already within tolerance;
// - a status: Converged only if the returned point really has the target curvatures (scaled
//   residual below tolerance); otherwise the (finite, clamped) point is still returned and the
//   caller decides.
// H's sign follows the patch normal Bu×Bv (see bezier_patch.h): H* must use the same orientation.
#pragma once

#include "vcg_ext/methods/paper/bezier_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vcg_ext {

struct NewtonOptions {
  int iterations = 2;             // paper: 2
  bool analytic_jacobian = true;  // false: central differences in (u, v)
  double max_step = 0;            // world length; 0 = no safeguard (paper)
  double tolerance = 1e-6;        // on the scaled residual (see solveCurvatureTarget)
  double difference_step = 1e-5;  // parameter step of the central-difference Jacobian
};

enum class NewtonStatus {
  Converged,        // the returned point has K*, H* to within tolerance
  NotConverged,     // iterations used up, or the safeguard / a singular patch point stopped it
  SingularJacobian, // ∇K ∥ ∇H, or K or H constant over the patch, before the target was reached
  InvalidTarget     // K*, H*, u0 or v0 not finite; returns the clamped start (or the centre)
};

struct NewtonResult {
  double u, v;
  NewtonStatus status;
  double residual; // scaled residual at the returned (u, v); +inf where K, H are undefined there
  int iterations;  // Newton steps taken
};

namespace detail {
inline double clamp01(double t) { return std::min(1.0, std::max(0.0, t)); }

// Residual of K − K*, H − H* in units of a curvature scale c = max(|H*|, √|K*|, 1/D), D the size of
// the control net: curvatures well below 1/D cannot be told apart from flat over the patch.
struct CurvatureResidual {
  double K_target, H_target, c;
  double operator()(double K, double H) const {
    return std::max(std::abs(H - H_target) / c, std::abs(K - K_target) / (c * c));
  }
};

inline bool curvatureJacobian(const BezierPatch &patch, double u, double v, const NewtonOptions &opt,
                              double &K, double &H, double &Ku, double &Kv, double &Hu, double &Hv) {
  if (opt.analytic_jacobian) return patch.curvatureWithGradient(u, v, K, H, Ku, Kv, Hu, Hv);
  const double h = opt.difference_step;
  double Kp, Hp, Km, Hm;
  if (!patch.curvature(u, v, K, H)) return false;
  if (!patch.curvature(u + h, v, Kp, Hp) || !patch.curvature(u - h, v, Km, Hm)) return false;
  Ku = (Kp - Km) / (2 * h);
  Hu = (Hp - Hm) / (2 * h);
  if (!patch.curvature(u, v + h, Kp, Hp) || !patch.curvature(u, v - h, Km, Hm)) return false;
  Kv = (Kp - Km) / (2 * h);
  Hv = (Hp - Hm) / (2 * h);
  return true;
}

// The residual for the targets K*, H*, its scale c from them and the control net's size.
inline CurvatureResidual curvatureResidual(const BezierPatch &patch, double K_target,
                                           double H_target) {
  Vec3 lo = patch.b[0], hi = patch.b[0];
  for (const Vec3 &p : patch.b) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double size = (hi - lo).norm();
  const double floor = size > 0 ? 1.0 / size : 1.0;
  return {K_target, H_target, std::max({std::abs(H_target), std::sqrt(std::abs(K_target)), floor})};
}

// Whether Newton's system is singular: ∇K ∥ ∇H (|det J| / (|∇K| |∇H|), the sine of the angle
// between the rows, below 1e-10), or K or H (in units of the curvature scale c) does not vary
// over the patch beyond rounding, as on a plane.
inline bool singularJacobian(double Ku, double Kv, double Hu, double Hv, double c) {
  constexpr double kSingularDet = 1e-10, kFlat = 1e-10;
  const double det = Ku * Hv - Kv * Hu;
  const double gradK = std::hypot(Ku, Kv), gradH = std::hypot(Hu, Hv);
  return !(std::abs(det) > kSingularDet * gradK * gradH) || !(gradK > kFlat * c * c) ||
         !(gradH > kFlat * c);
}

// The safeguard's damping of the step (du, dv) from (u, v): 1 without a safeguard (max_step <= 0),
// else the first of 1, 1/2, ... 1/256 whose clamped point lies within max_step of `start`; −1
// when none does.
inline double stepDamping(const BezierPatch &patch, const Vec3 &start, double u, double v,
                          double du, double dv, double max_step) {
  if (max_step <= 0) return 1.0;
  constexpr int kMaxHalvings = 8;
  double t = 1.0;
  for (int halving = 0; halving <= kMaxHalvings; ++halving, t *= 0.5) {
    const Vec3 p = patch.eval(clamp01(u + t * du), clamp01(v + t * dv));
    if ((p - start).norm() <= max_step) return t;
  }
  return -1.0;
}

} // namespace detail

inline NewtonResult solveCurvatureTarget(const BezierPatch &patch, double u0, double v0,
                                         double K_target, double H_target,
                                         const NewtonOptions &opt) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  NewtonResult result{0.5, 0.5, NewtonStatus::InvalidTarget, kInf, 0};
  if (!std::isfinite(u0) || !std::isfinite(v0)) return result;
  result.u = detail::clamp01(u0);
  result.v = detail::clamp01(v0);
  if (!std::isfinite(K_target) || !std::isfinite(H_target)) return result;
  const detail::CurvatureResidual residualOf = detail::curvatureResidual(patch, K_target, H_target);

  const Vec3 start = patch.eval(result.u, result.v);
  double u = result.u, v = result.v; // iterates are not clamped (paper); only what is returned is
  bool singular = false;
  int steps = 0;
  for (; steps < opt.iterations; ++steps) {
    double K, H, Ku, Kv, Hu, Hv;
    if (!detail::curvatureJacobian(patch, u, v, opt, K, H, Ku, Kv, Hu, Hv)) {
      singular = true;
      break;
    }
    if (residualOf(K, H) <= opt.tolerance) break;
    if (detail::singularJacobian(Ku, Kv, Hu, Hv, residualOf.c)) {
      singular = true;
      break;
    }
    const double det = Ku * Hv - Kv * Hu, fK = K - K_target, fH = H - H_target;
    const double du = -(Hv * fK - Kv * fH) / det;
    const double dv = -(-Hu * fK + Ku * fH) / det;
    const double t = detail::stepDamping(patch, start, u, v, du, dv, opt.max_step);
    if (t < 0 || !std::isfinite(u + t * du) || !std::isfinite(v + t * dv)) break;
    u += t * du;
    v += t * dv;
  }

  result.u = detail::clamp01(u);
  result.v = detail::clamp01(v);
  result.iterations = steps;
  double K, H;
  result.residual = patch.curvature(result.u, result.v, K, H) ? residualOf(K, H) : kInf;
  if (result.residual <= opt.tolerance)
    result.status = NewtonStatus::Converged;
  else
    result.status = singular ? NewtonStatus::SingularJacobian : NewtonStatus::NotConverged;
  return result;
}

} // namespace vcg_ext
