#include <gtest/gtest.h>
#include <vcg_ext/methods/paper/placement.h>

#include <cmath>
#include <random>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::paraboloidPatch;

namespace {

bool inUnitSquare(const NewtonResult &r) {
  return std::isfinite(r.u) && std::isfinite(r.v) && r.u >= 0 && r.u <= 1 && r.v >= 0 && r.v <= 1;
}

} // namespace

TEST(Placement, NewtonFindsTheParameterWithTheTargetCurvature) {
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0);
  const double us = 0.3, vs = 0.75;
  double Ks, Hs;
  ASSERT_TRUE(p.curvature(us, vs, Ks, Hs));
  for (bool analytic : {true, false}) {
    NewtonOptions opt;
    opt.analytic_jacobian = analytic;
    opt.iterations = 8;
    opt.tolerance = 1e-12;
    const NewtonResult r = solveCurvatureTarget(p, 0.34, 0.7, Ks, Hs, opt);
    EXPECT_EQ(r.status, NewtonStatus::Converged) << "analytic " << analytic;
    double K, H;
    ASSERT_TRUE(p.curvature(r.u, r.v, K, H));
    EXPECT_NEAR(K, Ks, 1e-10);
    EXPECT_NEAR(H, Hs, 1e-10);
    EXPECT_NEAR(r.u, us, 1e-8);
    EXPECT_NEAR(r.v, vs, 1e-8);
    EXPECT_LT(r.residual, opt.tolerance);
    EXPECT_LT(r.iterations, 8); // stopped early once solved
    EXPECT_GE(r.iterations, 4);
  }
  // Quadratic convergence: from 0.01 away the scaled residual goes 5.6e-2, 1.2e-3, 3.1e-6, so the
  // paper's 2 iterations reach the default tolerance (1e-6) only from closer.
  NewtonResult r = solveCurvatureTarget(p, 0.31, 0.74, Ks, Hs, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::NotConverged);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_NEAR(r.residual, 3.1e-6, 0.1e-6);
  r = solveCurvatureTarget(p, 0.305, 0.745, Ks, Hs, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::Converged);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_NEAR(r.u, us, 1e-5);
  EXPECT_NEAR(r.v, vs, 1e-5);
  double K, H;
  ASSERT_TRUE(p.curvature(r.u, r.v, K, H));
  EXPECT_LE(std::abs(K - Ks), 1e-6 * Hs * Hs); // c = max(|H*|, √|K*|, 1/size) = H* here
  EXPECT_LE(std::abs(H - Hs), 1e-6 * Hs);
}

TEST(Placement, AlreadySolvedStartTakesNoStep) {
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0);
  double Ks, Hs;
  ASSERT_TRUE(p.curvature(0.2, 0.4, Ks, Hs));
  const NewtonResult r = solveCurvatureTarget(p, 0.2, 0.4, Ks, Hs, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::Converged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.u, 0.2);
  EXPECT_EQ(r.v, 0.4);
  EXPECT_EQ(r.residual, 0.0);
}

TEST(Placement, UnreachableTargetIsNotConvergedButStaysInTheSquare) {
  const BezierPatch p = paraboloidPatch(1e-3, 2e-3, 1.0); // nearly flat: |K| < 1e-5, |H| < 4e-3
  double K0, H0;
  ASSERT_TRUE(p.curvature(0.3, 0.6, K0, H0));
  for (int iterations : {2, 10}) {
    NewtonOptions opt;
    opt.iterations = iterations;
    const NewtonResult r = solveCurvatureTarget(p, 0.3, 0.6, 100.0, H0, opt);
    EXPECT_NE(r.status, NewtonStatus::Converged);
    EXPECT_TRUE(inUnitSquare(r)) << r.u << " " << r.v;
    EXPECT_GT(r.residual, 0.5); // K off by ~100%: the residual is in units of c² = |K*|
  }
  // A reachable H but a K off by a lot: also refused.
  const NewtonResult r = solveCurvatureTarget(p, 0.3, 0.6, K0, 1.0, NewtonOptions{});
  EXPECT_NE(r.status, NewtonStatus::Converged);
  EXPECT_TRUE(inUnitSquare(r));
}

TEST(Placement, SafeguardBoundsTheMove) {
  // A target near the patch corner: the first full Newton step jumps far.
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0);
  double Kc, Hc;
  ASSERT_TRUE(p.curvature(0.05, 0.95, Kc, Hc));
  const double u0 = 0.45, v0 = 0.55;
  const Vec3 start = p.eval(u0, v0);
  NewtonOptions free_opt;
  const NewtonResult free_run = solveCurvatureTarget(p, u0, v0, Kc, Hc, free_opt);
  const double free_move = (p.eval(free_run.u, free_run.v) - start).norm();
  ASSERT_GT(free_move, 0.3); // without the safeguard the vertex moves a lot

  for (double max_step : {0.02, 0.1, 0.25}) {
    NewtonOptions opt;
    opt.max_step = max_step;
    opt.iterations = 4;
    const NewtonResult r = solveCurvatureTarget(p, u0, v0, Kc, Hc, opt);
    EXPECT_TRUE(inUnitSquare(r));
    const double move = (p.eval(r.u, r.v) - start).norm();
    EXPECT_LE(move, max_step) << "max_step " << max_step;
    EXPECT_GT(move, 0.0) << "max_step " << max_step; // a halved step is still taken
    EXPECT_GE(r.iterations, 1);
  }
  // Unreachable target with the safeguard: still bounded.
  NewtonOptions opt;
  opt.max_step = 0.05;
  opt.iterations = 10;
  const NewtonResult r = solveCurvatureTarget(p, u0, v0, 50.0, 0.1, opt);
  EXPECT_NE(r.status, NewtonStatus::Converged);
  EXPECT_LE((p.eval(r.u, r.v) - start).norm(), 0.05);
}

TEST(Placement, FlatPatchHasSingularJacobianUnlessTargetIsFlat) {
  BezierPatch plane;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) plane.b[3 * i + j] = Vec3(0.5 * i, 0.5 * j + 0.1 * i, 0.2 * i - 0.3 * j);
  NewtonResult r = solveCurvatureTarget(plane, 0.3, 0.4, 0.0, 0.5, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::SingularJacobian);
  EXPECT_EQ(r.u, 0.3);
  EXPECT_EQ(r.v, 0.4);
  EXPECT_EQ(r.iterations, 0);
  r = solveCurvatureTarget(plane, 0.3, 0.4, 0.0, 0.0, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::Converged);
  EXPECT_EQ(r.iterations, 0);
}

TEST(Placement, NonFiniteInputIsAnInvalidTarget) {
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0);
  NewtonResult r = solveCurvatureTarget(p, 0.3, 0.4, NAN, 0.5, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::InvalidTarget);
  EXPECT_EQ(r.u, 0.3);
  EXPECT_EQ(r.v, 0.4);
  r = solveCurvatureTarget(p, NAN, 0.4, 0.1, 0.5, NewtonOptions{});
  EXPECT_EQ(r.status, NewtonStatus::InvalidTarget);
  EXPECT_TRUE(inUnitSquare(r));
}

TEST(Placement, AnalyticAndDifferenceJacobiansTakeTheSameSteps) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> height(-0.3, 0.3), unit(0.1, 0.9);
  for (int trial = 0; trial < 5; ++trial) {
    BezierPatch p;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) p.b[3 * i + j] = Vec3(0.5 * i, 0.5 * j, height(rng));
    double Ks, Hs;
    const double us = unit(rng), vs = unit(rng);
    ASSERT_TRUE(p.curvature(us, vs, Ks, Hs));
    NewtonOptions analytic, differences;
    differences.analytic_jacobian = false;
    const double u0 = std::clamp(us + 0.03, 0.0, 1.0), v0 = std::clamp(vs - 0.03, 0.0, 1.0);
    const NewtonResult a = solveCurvatureTarget(p, u0, v0, Ks, Hs, analytic);
    const NewtonResult d = solveCurvatureTarget(p, u0, v0, Ks, Hs, differences);
    EXPECT_EQ(a.status, d.status);
    EXPECT_NEAR(a.u, d.u, 1e-7);
    EXPECT_NEAR(a.v, d.v, 1e-7);
  }
}

// The residual's scale: |H*|, √|K*|, or 1 over the control net's size, whichever is largest.
TEST(PlacementStages, CurvatureResidualScaleIsTheTargetOrTheNetsSize) {
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0); // a net 2 wide, 2 deep, 2.2 high
  const detail::CurvatureResidual flat = detail::curvatureResidual(p, 0.0, 0.0);
  EXPECT_DOUBLE_EQ(flat.c, 1.0 / std::sqrt(4.0 + 4.0 + 2.2 * 2.2));
  EXPECT_DOUBLE_EQ(detail::curvatureResidual(p, 9.0, 2.0).c, 3.0);
  EXPECT_DOUBLE_EQ(detail::curvatureResidual(p, 1.0, -4.0).c, 4.0);
  const detail::CurvatureResidual r = detail::curvatureResidual(p, 4.0, 1.0); // c = 2
  EXPECT_DOUBLE_EQ(r(4.0, 1.5), 0.25);  // |ΔH| / c
  EXPECT_DOUBLE_EQ(r(6.0, 1.0), 0.5);   // |ΔK| / c²
}

// Singular: the gradients parallel, or either one flat at the curvature scale.
TEST(PlacementStages, SingularJacobianWhenTheGradientsAreParallelOrFlat) {
  EXPECT_FALSE(detail::singularJacobian(1, 0, 0, 1, 1.0));
  EXPECT_TRUE(detail::singularJacobian(1, 2, 2, 4, 1.0));      // ∇H = 2 ∇K
  EXPECT_TRUE(detail::singularJacobian(1e-12, 0, 0, 1, 1.0));  // K flat
  EXPECT_TRUE(detail::singularJacobian(1, 0, 0, 1e-12, 1.0));  // H flat
  EXPECT_FALSE(detail::singularJacobian(1e-8, 0, 0, 1e-6, 1e-3)); // not at a small scale
}

// The safeguard's damping: the whole step where it stays within reach, halved until it does, −1
// when even 1/256 of it does not; 1 without a safeguard.
TEST(PlacementStages, StepDampingHalvesUntilThePointIsWithinReach) {
  const BezierPatch p = paraboloidPatch(0.8, 0.3, 1.0);
  const Vec3 start = p.eval(0.5, 0.5);
  EXPECT_EQ(detail::stepDamping(p, start, 0.5, 0.5, 0.4, 0.0, 0.0), 1.0);
  EXPECT_EQ(detail::stepDamping(p, start, 0.5, 0.5, 0.1, 0.0, 1.0), 1.0);
  const double t = detail::stepDamping(p, start, 0.5, 0.5, 0.4, 0.0, 0.2);
  // x(u) = 2u − 1 on this net: B(0.9, 0.5), B(0.7, 0.5) and B(0.6, 0.5) (0.2 across and a
  // little up) are too far, B(0.55, 0.5) is not.
  EXPECT_EQ(t, 0.125);
  EXPECT_LE((p.eval(0.5 + t * 0.4, 0.5) - start).norm(), 0.2);
  EXPECT_GT((p.eval(0.5 + 2 * t * 0.4, 0.5) - start).norm(), 0.2);
  // From a start already out of reach of itself (another start): no step fits.
  EXPECT_EQ(detail::stepDamping(p, p.eval(0.0, 0.0), 1.0, 1.0, 0.1, 0.1, 0.01), -1.0);
}
