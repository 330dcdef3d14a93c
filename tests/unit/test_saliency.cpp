#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/curvature.h>
#include <vcg_ext/analysis/saliency.h>

using namespace vcg_ext;

namespace {

struct MeshWithK2 {
  MeshArrays mesh;
  Rings rings;
  std::vector<double> k2;
};

MeshWithK2 withK2(MeshArrays m) {
  MeshWithK2 r{std::move(m), {}, {}};
  r.rings = computeRings(int(r.mesh.points.size()), r.mesh.faces);
  CurvatureField c;
  computeCurvature(r.mesh.points, r.mesh.faces, r.rings, c);
  r.k2 = c.k2;
  return r;
}

MeshWithK2 noisySphere() {
  auto m = test_meshes::icosphere(1.0, 4); // 2562 vertices, edge ≈ 0.075
  test_meshes::addNoise(m, 0.01, 11);
  return withK2(std::move(m));
}

} // namespace

TEST(Saliency, GaussianBumpOnAPlaneIsTheSalientRegion) {
  const double bx = 0.3, by = -0.2, width = 0.1;
  const auto s = withK2(test_meshes::heightField(101, -1, 1, -1, 1, [&](double x, double y) {
    return 0.1 * std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / (2 * width * width));
  }));
  const double epsilon = 0.01; // cut-offs 4ε … 24ε = 2 … 12 grid edges
  std::vector<double> sal;
  computeSaliency(s.mesh.points, s.rings, s.k2, epsilon, sal);
  ASSERT_EQ(sal.size(), s.mesh.points.size());
  const auto top = std::max_element(sal.begin(), sal.end());
  EXPECT_EQ(*top, 1.0);
  EXPECT_GE(*std::min_element(sal.begin(), sal.end()), 0.0);
  const Vec3 &argmax = s.mesh.points[top - sal.begin()];
  const double distance = std::hypot(argmax.x() - bx, argmax.y() - by);
  EXPECT_LT(distance, 3 * 0.02) << "argmax at " << argmax.transpose(); // within 3 grid edges
  std::printf("bump: argmax %.3f from the centre (grid edge 0.02)\n", distance);
  // Far from the bump (beyond its tail plus the largest cut-off) nothing is salient.
  for (size_t v = 0; v < sal.size(); ++v) {
    const Vec3 &p = s.mesh.points[v];
    if (std::hypot(p.x() - bx, p.y() - by) > 5 * width + 24 * epsilon) EXPECT_LT(sal[v], 1e-3) << v;
  }
}

TEST(Saliency, ConstantMapGivesZeroAndAffineMapsGiveTheSameSaliency) {
  const auto s = noisySphere();
  std::vector<double> zero;
  computeSaliency(s.mesh.points, s.rings, std::vector<double>(s.k2.size(), 3.5), 0.02, zero);
  for (double x : zero) EXPECT_EQ(x, 0.0);

  // Differences of weighted means ignore an offset, and the normalisations ignore a scale.
  std::vector<double> base, affine, shifted(s.k2);
  for (double &x : shifted) x = -4 * x + 7;
  computeSaliency(s.mesh.points, s.rings, s.k2, 0.02, base);
  computeSaliency(s.mesh.points, s.rings, shifted, 0.02, affine);
  double max_difference = 0;
  for (size_t v = 0; v < base.size(); ++v)
    max_difference = std::max(max_difference, std::abs(base[v] - affine[v]));
  EXPECT_LT(max_difference, 1e-9);
  EXPECT_EQ(*std::max_element(base.begin(), base.end()), 1.0);
}

TEST(Saliency, WeightExpMatchesTheLibraryExpOnTheWeightsRange) {
  // The only range the weights take inside their cut-off: −d²/2σ² in (−2, 0].
  double worst = 0;
  for (int i = 0; i <= 20000; ++i) {
    const double x = -2.0 * i / 20000;
    worst = std::max(worst, std::abs(detail::gaussianWeightExp(x) / std::exp(x) - 1));
  }
  EXPECT_LT(worst, 2e-14);
  EXPECT_EQ(detail::gaussianWeightExp(0.0), 1.0);
}

TEST(Saliency, GridSweepMatchesBruteForceGaussianMeans) {
  const auto s = noisySphere();
  const double epsilon = 0.015;
  std::vector<int> all(s.mesh.points.size());
  for (size_t v = 0; v < all.size(); ++v) all[v] = int(v);
  for (int cells_per_radius : {1, 2, 3}) {
    detail::UniformPointGrid grid;
    grid.build(s.mesh.points, s.k2, all, 24 * epsilon / cells_per_radius);
    for (int v = 0; v < int(all.size()); v += 7) {
      double means[detail::kSaliencySigmaCount];
      detail::gaussianMeansAllSigmas(grid, s.mesh.points[v], epsilon, means);
      for (int k = 0; k < detail::kSaliencySigmaCount; ++k) {
        const double sigma = detail::kSaliencySigmas[k] * epsilon;
        double num = 0, den = 0;
        for (size_t x = 0; x < all.size(); ++x) {
          const double d = (s.mesh.points[x] - s.mesh.points[v]).norm();
          if (d >= 2 * sigma) continue;
          const double w = std::exp(-d * d / (2 * sigma * sigma));
          num += w * s.k2[x], den += w;
        }
        EXPECT_NEAR(means[k], num / den, 1e-10 * (1 + std::abs(num / den))) << v << " " << k;
      }
    }
  }
  // The whole stage does not depend on the cell size either.
  std::vector<double> a, b;
  detail::computeSaliencyWithCells(s.mesh.points, s.rings, s.k2, epsilon, a, 1);
  detail::computeSaliencyWithCells(s.mesh.points, s.rings, s.k2, epsilon, b, 4);
  for (size_t v = 0; v < a.size(); ++v) EXPECT_NEAR(a[v], b[v], 1e-12);
}

TEST(Saliency, MatchesAStraightforwardImplementationOfLeeEtAl) {
  // O(n²) means, S_i = |G(σ_i) − G(2σ_i)|, S_i / M_i · (1 − mean of the other 1-ring peaks)², sum.
  auto m = test_meshes::icosphere(1.0, 3); // 642 vertices
  test_meshes::addNoise(m, 0.01, 2);
  const auto s = withK2(std::move(m));
  const int n = int(s.mesh.points.size());
  const double epsilon = 0.02;
  auto mean = [&](int v, double sigma) {
    double num = 0, den = 0;
    for (int x = 0; x < n; ++x) {
      const double d = (s.mesh.points[x] - s.mesh.points[v]).norm();
      const double w = d < 2 * sigma ? std::exp(-d * d / (2 * sigma * sigma)) : 0.0;
      num += w * s.k2[x], den += w;
    }
    return num / den;
  };
  std::vector<double> expected(n, 0.0);
  for (int scale = 2; scale <= 6; ++scale) {
    std::vector<double> S(n);
    for (int v = 0; v < n; ++v)
      S[v] = std::abs(mean(v, scale * epsilon) - mean(v, 2 * scale * epsilon));
    const double M = *std::max_element(S.begin(), S.end());
    double peaks = 0;
    int count = 0;
    for (int v = 0; v < n; ++v) {
      bool peak = true;
      for (const int *w = s.rings.ring1Begin(v); w != s.rings.ring1End(v); ++w) peak &= S[v] >= S[*w];
      if (peak) peaks += S[v] / M, ++count;
    }
    ASSERT_GT(count, 1);
    const double other = (peaks - 1) / (count - 1);
    for (int v = 0; v < n; ++v) expected[v] += S[v] / M * (1 - other) * (1 - other);
  }
  const double top = *std::max_element(expected.begin(), expected.end());
  std::vector<double> sal;
  computeSaliency(s.mesh.points, s.rings, s.k2, epsilon, sal);
  for (int v = 0; v < n; ++v) EXPECT_NEAR(sal[v], expected[v] / top, 1e-9) << v;
}

TEST(Saliency, IndependentOfVertexOrderAndThreadCount) {
  const auto s = noisySphere();
  std::vector<double> a, b;
  computeSaliency(s.mesh.points, s.rings, s.k2, 0.02, a);
  const auto perm = test_meshes::shuffledPermutation(int(s.mesh.points.size()), 5);
  const auto p = withK2(test_meshes::permuted(s.mesh, perm));
  computeSaliency(p.mesh.points, p.rings, p.k2, 0.02, b);
  for (size_t v = 0; v < a.size(); ++v) EXPECT_NEAR(a[v], b[perm[v]], 1e-12) << v;

  const int threads = omp_get_max_threads();
  std::vector<double> one, two;
  omp_set_num_threads(1);
  computeSaliency(s.mesh.points, s.rings, s.k2, 0.02, one);
  omp_set_num_threads(2);
  computeSaliency(s.mesh.points, s.rings, s.k2, 0.02, two);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
}

TEST(Saliency, IsolatedVerticesAndDegenerateEpsilonGiveZeros) {
  auto m = test_meshes::heightField(9, 0, 1, 0, 1, [](double x, double y) { return x * y; });
  std::vector<double> map(m.points.size());
  for (size_t v = 0; v < map.size(); ++v) map[v] = std::sin(7 * m.points[v].x()) * m.points[v].y();
  std::vector<double> without, sal;
  computeSaliency(m.points, computeRings(int(m.points.size()), m.faces), map, 0.02, without);
  m.points.emplace_back(0.5, 0.5, 0.25); // isolated, on the surface
  map.push_back(1e6);                    // would dominate every mean near it if it were used
  const Rings r = computeRings(int(m.points.size()), m.faces);
  computeSaliency(m.points, r, map, 0.02, sal);
  EXPECT_EQ(sal.back(), 0.0);
  for (size_t v = 0; v < without.size(); ++v) EXPECT_EQ(sal[v], without[v]);
  EXPECT_EQ(*std::max_element(sal.begin(), sal.end()), 1.0);
  computeSaliency(m.points, r, map, 0.0, sal);
  for (double x : sal) EXPECT_EQ(x, 0.0);
}

// computeSaliency's stages.
TEST(SaliencyStages, CentredMapAndItsHalfSpreadOverTheActiveVertices) {
  std::vector<double> centred;
  EXPECT_EQ(detail::centredMap({1, 3, 100, 5}, {0, 1, 3}, centred), 2.0);
  EXPECT_EQ(centred, (std::vector<double>{-2, 0, 0, 2})); // vertex 2 not active: 0
  EXPECT_EQ(detail::centredMap({4, 4}, {0, 1}, centred), 0.0); // a constant map: nothing to see
}

TEST(SaliencyStages, SigmasWhoseBallsHoldFewVerticesAreSummedExactly) {
  const MeshArrays grid = test_meshes::heightField(30, 0, 1, 0, 1, [](double, double) { return 0; });
  const Rings rings = computeRings(int(grid.points.size()), grid.faces);
  const std::vector<int> active = detail::verticesWithFaces(rings);
  ASSERT_EQ(active.size(), grid.points.size());
  const double edge = edgeStatistics(grid.points, rings).mean_edge_length;
  SaliencyOptions options; // at most 100 vertices per ball
  // ε = one mean edge: the 2σ ball of σ = 2ε (radius 4 edges) covers 50.3 edge², 58 vertices of
  // 0.866 edge²; at σ = 3ε it covers 113 edge², 131 vertices: only the smallest σ is exact.
  EXPECT_EQ(detail::exactSigmaCount(grid.points, rings, active, edge, options), 1);
  // ε = half an edge: σ = 2ε … 5ε (radii 2 … 5 edges, 78.5 edge² at 5) exact, 6ε (113) not.
  EXPECT_EQ(detail::exactSigmaCount(grid.points, rings, active, 0.5 * edge, options), 4);
  options.lattice_above_vertices = INFINITY;
  EXPECT_EQ(detail::exactSigmaCount(grid.points, rings, active, edge, options), 8);
  options.lattice_above_vertices = 0;
  EXPECT_EQ(detail::exactSigmaCount(grid.points, rings, active, edge, options), 0);
}

TEST(SaliencyStages, RowsInABallHoldEveryPointWithinItsRadiusOnce) {
  const auto s = noisySphere();
  std::vector<int> all(s.mesh.points.size());
  for (size_t v = 0; v < all.size(); ++v) all[v] = int(v);
  detail::UniformPointGrid grid;
  grid.build(s.mesh.points, s.k2, all, 0.1);
  const double radius = 0.25;
  for (int v = 0; v < int(all.size()); v += 97) {
    const Vec3 &p = s.mesh.points[v];
    int inside = 0, visited = 0;
    detail::forEachRowInBall(grid, p, radius,
                             [&](const detail::GridPoint *q, const detail::GridPoint *end) {
                               for (; q != end; ++q, ++visited)
                                 inside += (Vec3(q->x, q->y, q->z) - p).squaredNorm() <
                                           radius * radius;
                             });
    int expected = 0;
    for (const Vec3 &x : s.mesh.points) expected += (x - p).squaredNorm() < radius * radius;
    EXPECT_EQ(inside, expected) << v;
    EXPECT_LT(visited, int(all.size()) / 2) << v; // rows near the ball only, not the whole grid
  }
}

TEST(SaliencyStages, GaussianSumsOfChunksAreTheMeansOfAllPoints) {
  // Three points at squared distances 0, σ² and 5σ² from the query (σ = 2ε, the smallest): the
  // last is outside the 2σ cut-off. Added in two chunks, the mean is the weighted mean of the two
  // inside: (1·1 + e^−1/2·3) / (1 + e^−1/2).
  const double epsilon = 0.5, sigma = detail::kSaliencySigmas[0] * epsilon;
  detail::GaussianSums sums(epsilon, 1);
  const double d2[] = {0, sigma * sigma, 5 * sigma * sigma}, value[] = {1, 3, 100};
  sums.add(d2, value, 1);
  sums.add(d2 + 1, value + 1, 2);
  double mean = 0;
  sums.means(&mean);
  const double w = std::exp(-0.5);
  EXPECT_NEAR(mean, (1 + 3 * w) / (1 + w), 1e-13);
}
