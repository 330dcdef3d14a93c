// The lattice evaluation of saliency's Gaussian means (vcg_ext/analysis/saliency_lattice.h) against the
// exact sums, and the fast saliency against the exact one on a mesh large enough to use it.
#include <gtest/gtest.h>
#include <random>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/curvature.h>
#include <vcg_ext/analysis/saliency.h>

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
  // Two threads take the three chains one each (on a mesh this small); four run the chains one
  // after another, each on all four, and so do two above the size limit for whole chains.
  std::vector<std::vector<double>> four(8), two_in_turn(8);
  detail::LatticeOptions in_turn;
  in_turn.chains_in_parallel_below = 0;
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmas, in_turn, two_in_turn);
  omp_set_num_threads(4);
  detail::latticeGaussianMeans(m.points, allVertices(n), map, sigmas, {}, four);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, four);
  EXPECT_EQ(one, two_in_turn);
}

// The convolution reads each row as dense runs (zeros between nodes); its sums must be those of
// the nodes alone, term by term in the same order (rows by dz, dy; nodes by x): the same bits as
// the sparse sum written out here. Rows with runs split (gaps above 2R) and kept whole (gaps up
// to 2R), nodes at the lattice's edges, one and three σ per lattice.
TEST(SaliencyLattice, DenseRunsConvolveToTheBitsOfTheSparseSum) {
  for (const std::vector<double> &sigmas : {std::vector<double>{2.0}, {2.0, 2.7, 3.4}}) {
    detail::SparseLattice lattice;
    lattice.h = 1;
    lattice.nx = 80, lattice.ny = 12;
    std::vector<std::uint64_t> keys;
    std::uint64_t state = 12345;
    auto next = [&] { return state = state * 6364136223846793005ull + 1442695040888963407ull; };
    for (std::uint64_t l = 0; l < 10; ++l)
      for (std::uint64_t j = 0; j < lattice.ny; ++j)
        for (std::uint64_t i = 0; i < lattice.nx; ++i)
          // Clusters along x (about 1 node in 3 near x = 5..20 and 60..75), some rows empty.
          if ((j + l) % 5 != 3 && ((i >= 5 && i <= 20) || i >= 60 || i == 0) && next() % 3 == 0)
            keys.push_back((l * lattice.ny + j) * lattice.nx + i);
    lattice.assign(keys, false);
    const detail::LatticeKernel kernel = detail::latticeKernel(1.0, sigmas, 1.0);
    const int R = kernel.R, S = kernel.S, width = kernel.width, count = lattice.size();
    std::vector<double> sum_weight(2 * size_t(count));
    for (double &v : sum_weight) v = double(next() % 2001) / 1000.0 - 1.0;
    std::vector<double> out(size_t(count) * 2 * S);
    detail::convolveLatticeRows(lattice, kernel, detail::denseRuns(lattice, sum_weight, R), out);

    long compared = 0;
    for (int t = 0; t < count; ++t) {
      const std::int64_t x = lattice.x[t], j = std::int64_t(lattice.key[t] / lattice.nx % lattice.ny),
                         l = std::int64_t(lattice.key[t] / (lattice.nx * lattice.ny));
      std::vector<double> acc(2 * S, 0.0);
      for (int dz = -R; dz <= R; ++dz)
        for (int dy = -R; dy <= R; ++dy) {
          const int d2 = dy * dy + dz * dz;
          if (d2 > R * R || l + dz < 0 || j + dy < 0 || j + dy >= std::int64_t(lattice.ny)) continue;
          const int reach = int(std::sqrt(double(R * R - d2)) + 1e-9);
          for (int q = 0; q < count; ++q) {
            const std::int64_t qj = std::int64_t(lattice.key[q] / lattice.nx % lattice.ny),
                               ql = std::int64_t(lattice.key[q] / (lattice.nx * lattice.ny));
            const std::int64_t dx = lattice.x[q] - x;
            if (ql != l + dz || qj != j + dy || dx < -reach || dx > reach) continue;
            const double *w =
                &kernel.table[((size_t(dz + R) * width + (dy + R)) * width + (dx + R)) * S];
            for (int s = 0; s < S; ++s) {
              acc[2 * s] += w[s] * sum_weight[2 * size_t(q)];
              acc[2 * s + 1] += w[s] * sum_weight[2 * size_t(q) + 1];
            }
          }
        }
      for (int q = 0; q < 2 * S; ++q) ASSERT_EQ(out[size_t(t) * 2 * S + q], acc[q]) << t << " " << q;
      ++compared;
    }
    EXPECT_GT(compared, 300);
  }
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

// latticeGaussianMeansChain's stages one by one.
TEST(SaliencyLatticeStages, SigmasGoToTheLevelWhoseSpacingTheyHoldKToTwoKTimes) {
  double base_h = 0;
  std::vector<int> level;
  EXPECT_EQ(detail::sigmaLevels({1, 2, 4}, 2, base_h, level), 3);
  EXPECT_EQ(base_h, 0.5);
  EXPECT_EQ(level, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(detail::sigmaLevels({5, 3, 12}, 2, base_h, level), 3);
  EXPECT_EQ(base_h, 1.5);
  EXPECT_EQ(level, (std::vector<int>{0, 0, 2})); // 5/3 < 2; 12/3 = 4
  std::vector<int> slot_sigma, first_slot;
  detail::sigmaSlots(level, 3, slot_sigma, first_slot);
  EXPECT_EQ(slot_sigma, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(first_slot, (std::vector<int>{0, 2, 2, 3})); // level 1 holds none
  detail::sigmaSlots({1, 0, 1}, 2, slot_sigma, first_slot);
  EXPECT_EQ(slot_sigma, (std::vector<int>{1, 0, 2}));
  EXPECT_EQ(first_slot, (std::vector<int>{0, 1, 3}));
}

TEST(SaliencyLatticeStages, TrilinearWeightsSumToOneAndSitOnANode) {
  double w[8];
  detail::trilinearWeights(Vec3(0.25, 0.5, 0.75), Vec3::Zero(), 1.0, w);
  EXPECT_DOUBLE_EQ(w[0], 0.75 * 0.5 * 0.25);
  EXPECT_DOUBLE_EQ(w[7], 0.25 * 0.5 * 0.75);
  double sum = 0;
  for (double x : w) sum += x;
  EXPECT_NEAR(sum, 1.0, 1e-15);
  detail::trilinearWeights(Vec3(2, 4, 6), Vec3::Zero(), 2.0, w); // on node (1, 2, 3)
  EXPECT_EQ(w[0], 1.0);
  for (int corner = 1; corner < 8; ++corner) EXPECT_EQ(w[corner], 0.0);
}

TEST(SaliencyLatticeStages, SplatAndRestrictionKeepTheTotalWeightAndSum) {
  std::vector<detail::WeightedPoint> points;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 3);
  double value_sum = 0;
  for (int a = 0; a < 500; ++a) {
    points.push_back({u(rng), u(rng), 0.1 * u(rng), u(rng)});
    value_sum += points.back().value;
  }
  detail::LatticePyramid pyramid = detail::emptyPyramid(points, 0.25, 3);
  const detail::PointCells cells = detail::bucketIntoCells(points, pyramid, true);
  EXPECT_EQ(cells.start.back(), 500);
  std::vector<std::vector<double>> splat(3);
  splat[0] = detail::splatPoints(points, cells, pyramid, true);
  for (int L = 1; L < 3; ++L) splat[L] = detail::restrictToLevel(L, pyramid, splat[L - 1], true);
  for (int L = 0; L < 3; ++L) {
    double sum = 0, weight = 0;
    for (size_t p = 0; p < splat[L].size(); p += 2) sum += splat[L][p], weight += splat[L][p + 1];
    EXPECT_NEAR(weight, 500.0, 1e-9) << L;
    EXPECT_NEAR(sum, value_sum, 1e-9) << L;
    EXPECT_EQ(pyramid.lattice[L].h, 0.25 * (1 << L));
  }
  EXPECT_LT(pyramid.lattice[2].size(), pyramid.lattice[1].size());
  EXPECT_LT(pyramid.lattice[1].size(), pyramid.lattice[0].size());
}

TEST(SaliencyLatticeStages, SigmasFallIntoPowerOfTwoChains) {
  // The saliency's eight σ (in ε): 2, 3, 4, 5, 6, 8, 10, 12.
  const std::vector<std::vector<int>> chains =
      detail::sigmaChains({2, 3, 4, 5, 6, 8, 10, 12});
  EXPECT_EQ(chains, (std::vector<std::vector<int>>{{0, 2, 5}, {1, 4, 7}, {3, 6}}));
}

TEST(SaliencyLatticeStages, CellOrderIsAPermutationByCellsKeepingTheInputOrderWithinOne) {
  const std::vector<Vec3> positions{Vec3(2.5, 0, 0), Vec3(0.1, 0, 0), Vec3(2.2, 0, 0),
                                    Vec3(0.7, 0, 0), Vec3(1.5, 0, 0), Vec3(9, 9, 9)};
  // Vertex 5 is not active; cells of 1 along x from the lowest active point (0.1).
  EXPECT_EQ(detail::cellOrder(positions, {0, 1, 2, 3, 4}, 1.0),
            (std::vector<int>{1, 3, 4, 0, 2}));
}
