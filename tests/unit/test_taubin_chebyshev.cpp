// vcg_ext/smoothing/taubin_chebyshev.h and SpatialTaubin::applyChebyshev: the series is Taubin's pair
// response (exactly for one pair, within the tolerance for many), its Clenshaw evaluation on a mesh
// gives the pairs' result to within the tolerance times the mesh's extent (boundary curves, fixed
// vertices, boundary_still, two fields), still vertices keep their bits, and the result does not
// depend on the thread count or on where the mesh lies.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/feature/normal_filter.h>
#include <vcg_ext/smoothing/spatial_taubin.h>
#include <vcg_ext/smoothing/taubin_chebyshev.h>
#include <vcg_ext/core/vertex_roles.h>

#include <omp.h>

using namespace vcg_ext;

namespace {

double chebyshevSeries(const std::vector<double> &c, double p) {
  double previous = 1, current = p, sum = c[0] + (c.size() > 1 ? c[1] * p : 0.0);
  for (size_t j = 2; j < c.size(); ++j) {
    const double next = 2 * p * current - previous;
    sum += c[j] * next;
    previous = current, current = next;
  }
  return sum;
}

double pairResponse(double p, double lambda, double mu) {
  return ((1 - mu) + mu * p) * ((1 - lambda) + lambda * p);
}

struct CylinderCase {
  MeshArrays mesh;
  Rings rings;
  detail::VertexRoles roles;
  std::vector<std::uint8_t> fixed;
  double extent = 0;
};

// An open, noisy cylinder: two boundary curves, and every 17th vertex fixed.
CylinderCase openCylinder(const Vec3 &offset = Vec3::Zero()) {
  CylinderCase s;
  s.mesh = test_meshes::cylinder(1.0, 2.0, 48, 40);
  test_meshes::addNoise(s.mesh, 0.02, 5);
  for (Vec3 &p : s.mesh.points) p += offset;
  const int n = int(s.mesh.points.size());
  s.rings = computeRings(n, s.mesh.faces);
  s.roles = detail::vertexRoles(s.mesh, s.rings, edgeStatistics(s.mesh.points, s.rings).mean_edge_length);
  s.fixed.assign(n, 0);
  for (int v = 0; v < n; v += 17) s.fixed[v] = 1;
  s.extent = 2.0; // the cylinder's height, its largest extent
  return s;
}

} // namespace

TEST(TaubinChebyshev, OnePairIsItsOwnQuadraticSeries) {
  const std::vector<double> c = taubinChebyshevCoefficients(1, 0.5, -0.53);
  ASSERT_EQ(c.size(), 3u);
  for (double p = -1; p <= 1; p += 0.125)
    EXPECT_NEAR(chebyshevSeries(c, p), pairResponse(p, 0.5, -0.53), 1e-15) << p;
  EXPECT_EQ(taubinChebyshevCoefficients(0, 0.5, -0.53), std::vector<double>{1.0});
}

TEST(TaubinChebyshev, ManyPairsNeedFarFewerTermsWithinTheTolerance) {
  const std::vector<double> c = taubinChebyshevCoefficients(64, 0.5, -0.51, 1e-10);
  EXPECT_LE(c.size(), 40u); // the polynomial itself has degree 128
  EXPECT_GE(c.size(), 30u);
  double worst = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double p = -1 + i / 1000.0;
    worst = std::max(worst, std::abs(chebyshevSeries(c, p) - std::pow(pairResponse(p, 0.5, -0.51), 64)));
  }
  EXPECT_LT(worst, 2e-10); // twice the tolerance: the dropped tail's value at 1 went to c_0
  EXPECT_GT(worst, 1e-14); // truncated, not exact
  EXPECT_TRUE(chebyshevPays(c, 64));
  EXPECT_FALSE(chebyshevPays(taubinChebyshevCoefficients(4, 0.5, -0.51), 4));
}

// The truncated series is exact at p = 1, where the response is 1: a constant field (a mesh's
// position, the smooth part of its shape) passes unchanged; without c_0's correction it would be
// scaled by up to the tolerance. Near 1 its error is far below the tolerance.
TEST(TaubinChebyshev, TruncatedSeriesIsExactWhereTheResponseIsOne) {
  int truncated = 0;
  for (const double tolerance : {1e-10, 1e-6, 1e-4, 1e-3})
    for (const int pairs : {8, 16, 32, 64}) {
      const std::vector<double> c = taubinChebyshevCoefficients(pairs, 0.5, -0.51, tolerance);
      const std::vector<double> full = taubinChebyshevCoefficients(pairs, 0.5, -0.51, 0.0);
      truncated += c.size() < full.size();
      EXPECT_NEAR(chebyshevSeries(c, 1.0), 1.0, 1e-14) << tolerance << " " << pairs;
      double dropped = 0;
      for (size_t j = c.size(); j < full.size(); ++j) dropped += std::abs(full[j]);
      EXPECT_LE(dropped, tolerance);
      // Near 1 (a smooth field: p = cos θ with θ a hundredth of a radian) the error is a small
      // part of the tolerance; anywhere within twice it.
      const double p = std::cos(0.01), exact = std::pow(pairResponse(p, 0.5, -0.51), pairs);
      EXPECT_LT(std::abs(chebyshevSeries(c, p) - exact), 0.1 * tolerance) << tolerance << " " << pairs;
      for (int i = 0; i <= 400; ++i) {
        const double q = -1 + i / 200.0;
        EXPECT_LT(std::abs(chebyshevSeries(c, q) - std::pow(pairResponse(q, 0.5, -0.51), pairs)),
                  2 * tolerance + 1e-15);
      }
    }
  EXPECT_EQ(truncated, 15); // all but 8 pairs at 1e-10, whose 17 terms all count
}

TEST(TaubinChebyshev, ClenshawOnAMeshMatchesThePairsWithBoundariesAndFixedVertices) {
  const CylinderCase s = openCylinder();
  const int n = int(s.mesh.points.size());
  ASSERT_GT(std::count(s.rings.boundary.begin(), s.rings.boundary.end(), 1), 90);
  std::vector<Vec3> other(n);
  for (int v = 0; v < n; ++v) other[v] = Vec3(std::sin(v), std::cos(3.0 * v), 0.5 * v / n);
  const SpatialTaubin taubin(s.mesh.points, s.rings, s.fixed, s.roles.boundary_neighbours);
  for (const bool boundary_still : {false, true}) {
    std::vector<Vec3> expected = taubin.toLocal(s.mesh.points), expected_other = taubin.toLocal(other);
    taubin.smooth({&expected, &expected_other}, 32, 0.5, -0.51, boundary_still);
    const std::vector<Vec3> input = taubin.toLocal(s.mesh.points), input_other = taubin.toLocal(other);
    std::vector<Vec3> got, got_other;
    taubin.applyChebyshev({&input, &input_other}, {&got, &got_other},
                          taubinChebyshevCoefficients(32, 0.5, -0.51), boundary_still);
    const std::vector<Vec3> global = taubin.toGlobal(got);
    double worst = 0, worst_other = 0;
    int moved = 0;
    for (int l = 0; l < n; ++l) {
      worst = std::max(worst, (got[l] - expected[l]).norm());
      worst_other = std::max(worst_other, (got_other[l] - expected_other[l]).norm());
    }
    for (int v = 0; v < n; ++v) {
      const bool still = s.fixed[v] || (boundary_still && s.rings.boundary[v]);
      if (still) EXPECT_EQ(global[v], s.mesh.points[v]) << "vertex " << v; // to the bit
      moved += global[v] != s.mesh.points[v];
    }
    EXPECT_LT(worst, 1e-9 * s.extent) << boundary_still;
    EXPECT_LT(worst_other, 1e-9) << boundary_still;
    EXPECT_GT(moved, n / 2);
  }
}

TEST(TaubinChebyshev, SameBitsForAnyThreadCountAndTheSameResultFarFromTheOrigin) {
  const std::vector<double> c = taubinChebyshevCoefficients(64, 0.5, -0.51);
  auto run = [&](const CylinderCase &s, int threads) {
    const SpatialTaubin taubin(s.mesh.points, s.rings, s.fixed, s.roles.boundary_neighbours);
    const std::vector<Vec3> input = taubin.toLocal(s.mesh.points);
    std::vector<Vec3> out;
    const int before = omp_get_max_threads(), saved_parallel = min_parallel_vertices;
    omp_set_num_threads(threads);
    min_parallel_vertices = 0; // parallel even on this small mesh
    taubin.applyChebyshev({&input}, {&out}, c);
    omp_set_num_threads(before);
    min_parallel_vertices = saved_parallel;
    return taubin.toGlobal(out);
  };
  const CylinderCase here = openCylinder();
  EXPECT_EQ(run(here, 1), run(here, 2));
  // 1e6 away (survey coordinates): the series is summed about the field's centre.
  const Vec3 offset(1e6, -2e6, 5e5);
  const std::vector<Vec3> near = run(here, 2), far = run(openCylinder(offset), 2);
  double worst = 0;
  for (size_t v = 0; v < near.size(); ++v) worst = std::max(worst, (far[v] - offset - near[v]).norm());
  EXPECT_LT(worst, 1e-8); // the coordinates' own rounding at 1e6 is about 1e-10
}

// The single-precision fields (the band shrinkage's probe) ride along in the same sweeps: the
// double fields keep their bits, the float ones follow the same steps and series to float
// rounding, and still vertices keep their float values exactly.
TEST(TaubinChebyshev, FloatFieldsRideAlongWithoutChangingTheDoubleOnes) {
  const CylinderCase s = openCylinder();
  const int n = int(s.mesh.points.size());
  std::vector<Vec3> other(n);
  for (int v = 0; v < n; ++v) other[v] = Vec3(std::sin(v), std::cos(3.0 * v), 0.5 * v / n);
  const SpatialTaubin taubin(s.mesh.points, s.rings, s.fixed, s.roles.boundary_neighbours);
  const std::vector<double> c = taubinChebyshevCoefficients(32, 0.5, -0.51);
  const std::vector<Vec3> input = taubin.toLocal(s.mesh.points), input_other = taubin.toLocal(other);
  std::vector<Vec3f> input_float(n);
  for (int l = 0; l < n; ++l) input_float[l] = input_other[l].cast<float>();

  // Steps: double alone against double with a float field alongside.
  std::vector<Vec3> alone = input, with_float = input, other_steps = input_other;
  std::vector<Vec3f> float_steps = input_float;
  taubin.smooth({&alone}, 6, 0.5, -0.51);
  taubin.smooth({&with_float, &other_steps}, {&float_steps}, 6, 0.5, -0.51);
  // Series: the same.
  std::vector<Vec3> series_alone, series_with_float, series_other;
  std::vector<Vec3f> series_float;
  taubin.applyChebyshev({&input}, {&series_alone}, c);
  taubin.applyChebyshev({&input, &input_other}, {&series_with_float, &series_other},
                        {&input_float}, {&series_float}, c);
  double worst_steps = 0, worst_series = 0;
  int moved = 0;
  for (int l = 0; l < n; ++l) {
    ASSERT_EQ(alone[l], with_float[l]) << l;
    ASSERT_EQ(series_alone[l], series_with_float[l]) << l;
    worst_steps = std::max(worst_steps, (float_steps[l].cast<double>() - other_steps[l]).norm());
    worst_series = std::max(worst_series, (series_float[l].cast<double>() - series_other[l]).norm());
    moved += float_steps[l] != input_float[l];
  }
  // The field's values are up to ~1: float rounding over a few dozen operations.
  EXPECT_LT(worst_steps, 1e-5);
  EXPECT_LT(worst_series, 1e-5);
  EXPECT_GT(worst_series, 0.0); // a float result, not a copy of the double one
  EXPECT_GT(moved, n / 2);
  const std::vector<Vec3> global_points = taubin.toGlobal(with_float);
  for (int v = 0; v < n; ++v)
    if (s.fixed[v]) {
      const int l = taubin.local(v);
      EXPECT_EQ(float_steps[l], input_float[l]) << v;
      EXPECT_EQ(series_float[l], input_float[l]) << v;
    }
}

TEST(TaubinChebyshev, OneDoubleAndOneFloatFieldTogetherGiveTheBitsOfEachAlone) {
  // The band shrinkage's case (one double and one float field) reads the neighbours once for both:
  // each field's arithmetic must stay what it is alone, for steps, series and boundary still.
  const CylinderCase s = openCylinder();
  const int n = int(s.mesh.points.size());
  const SpatialTaubin taubin(s.mesh.points, s.rings, s.fixed, s.roles.boundary_neighbours);
  const std::vector<double> c = taubinChebyshevCoefficients(32, 0.5, -0.51);
  const std::vector<Vec3> input = taubin.toLocal(s.mesh.points);
  std::vector<Vec3f> input_float(n);
  for (int l = 0; l < n; ++l)
    input_float[l] = Vec3f(float(std::sin(l)), float(std::cos(3.0 * l)), float(0.5 * l / n));
  for (bool still : {false, true}) {
    std::vector<Vec3> alone = input, together = input;
    std::vector<Vec3f> float_alone = input_float, float_together = input_float;
    taubin.smooth({&alone}, 5, 0.5, -0.51, still);
    taubin.smooth({}, {&float_alone}, 5, 0.5, -0.51, still);
    taubin.smooth({&together}, {&float_together}, 5, 0.5, -0.51, still);
    std::vector<Vec3> series_alone, series_together;
    std::vector<Vec3f> series_float_alone, series_float_together;
    taubin.applyChebyshev({&input}, {&series_alone}, c, still);
    taubin.applyChebyshev({}, {}, {&input_float}, {&series_float_alone}, c, still);
    taubin.applyChebyshev({&input}, {&series_together}, {&input_float}, {&series_float_together}, c,
                          still);
    int moved = 0;
    for (int l = 0; l < n; ++l) {
      ASSERT_EQ(alone[l], together[l]) << l;
      ASSERT_EQ(float_alone[l], float_together[l]) << l;
      ASSERT_EQ(series_alone[l], series_together[l]) << l;
      ASSERT_EQ(series_float_alone[l], series_float_together[l]) << l;
      moved += together[l] != input[l];
    }
    EXPECT_GT(moved, n / 2);
  }
}
