// The lattice evaluation of saliency's Gaussian means (vcg_ext/saliency_lattice.h) against the
// exact sums, and the fast saliency against the exact one on a mesh large enough to use it.
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/curvature.h>
#include <vcg_ext/saliency.h>

using namespace vcg_ext;

namespace {

// Every unit test runs in this one binary: let all of them, whatever their mesh size, go through
// the parallel paths, so that the thread-count tests compare one thread with two for real.
[[maybe_unused]] const bool parallel_everywhere = (min_parallel_vertices = 0, true);

std::vector<double> sigmasOf(double epsilon) {
  std::vector<double> s;
  for (int k : detail::kSaliencySigmas) s.push_back(k * epsilon);
  return s;
}

std::vector<int> allVertices(int n) {
  std::vector<int> all(n);
  for (int v = 0; v < n; ++v) all[v] = v;
  return all;
}

// Exact means at all eight σ (the grid sweep, itself tested against brute force in
// test_saliency.cpp), at every `stride`-th vertex.
std::vector<std::array<double, detail::kSaliencySigmaCount>>
exactMeans(const MeshArrays &m, const std::vector<double> &map, double epsilon, int stride) {
  detail::UniformPointGrid grid;
  grid.build(m.points, map, allVertices(int(m.points.size())), 12 * epsilon);
  std::vector<std::array<double, detail::kSaliencySigmaCount>> out(m.points.size());
  for (size_t v = 0; v < m.points.size(); v += stride)
    detail::gaussianMeansAllSigmas(grid, m.points[v], epsilon, out[v].data());
  return out;
}

} // namespace

TEST(SaliencyLattice, ConstantMapGivesTheConstantEverywhere) {
  const auto m = test_meshes::icosphere(1.0, 4);
  const int n = int(m.points.size());
  std::vector<std::vector<double>> means(detail::kSaliencySigmaCount);
  detail::latticeGaussianMeans(m.points, allVertices(n), std::vector<double>(n, -2.5),
                               sigmasOf(0.02), {}, means);
  for (const auto &g : means) {
    ASSERT_EQ(int(g.size()), n);
    for (double x : g) EXPECT_NEAR(x, -2.5, 1e-12);
  }
}

TEST(SaliencyLattice, MeansOfASmoothMapMatchTheExactSums) {
  // 40962 vertices, edge ≈ 0.019; σ from 2ε = 0.03 to 12ε = 0.18.
  const auto m = test_meshes::icosphere(1.0, 6);
  const int n = int(m.points.size());
  std::vector<double> map(n);
  for (int v = 0; v < n; ++v) {
    const Vec3 &p = m.points[v];
    map[v] = std::sin(3 * p.x()) + std::cos(2 * p.y()) * p.z();
  }
  const double epsilon = 0.015;
  const auto exact = exactMeans(m, map, epsilon, 13);
  std::vector<std::vector<double>> means(detail::kSaliencySigmaCount);
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmasOf(epsilon), {}, means);
  for (int s = 0; s < detail::kSaliencySigmaCount; ++s) {
    double worst = 0, squares = 0;
    int count = 0;
    for (int v = 0; v < n; v += 13, ++count) {
      worst = std::max(worst, std::abs(means[s][v] - exact[v][s]));
      squares += (means[s][v] - exact[v][s]) * (means[s][v] - exact[v][s]);
    }
    const double rms = std::sqrt(squares / count);
    // The map spans 3.5. Measured: max 3.4e-3 … 1.1e-2 (growing with σ), RMS 5.7e-4 … 3.6e-3: the
    // lattice blurs the cut-off at 2σ over about ±σ/2.
    EXPECT_LT(worst, 0.015) << "sigma " << detail::kSaliencySigmas[s] << " epsilon";
    EXPECT_LT(rms, 0.005) << "sigma " << detail::kSaliencySigmas[s] << " epsilon";
    std::printf("sigma %2d eps: lattice vs exact mean, max |difference| %.2e, RMS %.2e\n",
                detail::kSaliencySigmas[s], worst, rms);
  }
}

TEST(SaliencyLattice, IndependentOfVertexOrderAndThreadCount) {
  auto m = test_meshes::icosphere(1.0, 5);
  test_meshes::addNoise(m, 0.003, 4);
  const int n = int(m.points.size());
  std::vector<double> map(n);
  for (int v = 0; v < n; ++v) map[v] = std::sin(9 * m.points[v].x()) + m.points[v].y();
  const auto sigmas = sigmasOf(0.02);
  std::vector<std::vector<double>> a(8), b(8), one(8), two(8);
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmas, {}, a);
  const auto perm = test_meshes::shuffledPermutation(n, 9);
  const auto p = test_meshes::permuted(m, perm);
  std::vector<double> pmap(n);
  for (int v = 0; v < n; ++v) pmap[perm[v]] = map[v];
  detail::latticeGaussianMeans(p.points, allVertices(n), pmap, sigmas, {}, b);
  for (int s = 0; s < 8; ++s)
    for (int v = 0; v < n; ++v) ASSERT_NEAR(a[s][v], b[s][perm[v]], 1e-12) << s << " " << v;

  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmas, {}, one);
  omp_set_num_threads(2);
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmas, {}, two);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
}

TEST(SaliencyLattice, FastSaliencyIsCloseToTheExactOneOnALargeNoisyMesh) {
  // 40962 vertices with noise: k2 is rough, as on a scan. With ε = 0.015 the 2σ ball holds
  // 50 vertices at σ = 2ε and 1800 at 12ε: the default options sum σ = 2ε exactly, the rest on the
  // lattice.
  auto m = test_meshes::icosphere(1.0, 6);
  test_meshes::addNoise(m, 0.002, 7);
  const int n = int(m.points.size());
  const Rings rings = computeRings(n, m.faces);
  CurvatureField c;
  computeCurvature(m.points, m.faces, rings, c);
  const double epsilon = 0.015;
  std::vector<double> fast, exact;
  computeSaliency(m.points, rings, c.k2, epsilon, fast);
  SaliencyOptions reference;
  reference.lattice_above_vertices = INFINITY;
  computeSaliency(m.points, rings, c.k2, epsilon, exact, reference);
  double worst = 0, mean = 0;
  for (int v = 0; v < n; ++v) {
    worst = std::max(worst, std::abs(fast[v] - exact[v]));
    mean += std::abs(fast[v] - exact[v]) / n;
  }
  EXPECT_EQ(*std::max_element(fast.begin(), fast.end()), 1.0);
  // Measured: mean 0.014, max 0.091 (saliency in [0, 1]).
  EXPECT_LT(mean, 0.02);
  EXPECT_LT(worst, 0.15);
  std::printf("fast vs exact saliency: mean |difference| %.4f, max %.4f\n", mean, worst);
}
