// The noise estimate on windows of a large mesh (vcg_ext/analysis/noise_windows.h): its figures are the
// whole mesh's measured over the windows' cores, bit for bit (closed and open meshes), close to
// the whole mesh's own, the same for any thread count, and a mesh too small for windows is left to
// the whole-mesh estimate.
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/noise_windows.h>

using namespace vcg_ext;

namespace {

// The estimate without its amplitude, whose coarse bands would need windows wider than a unit
// test's meshes (AmplitudeOnWindowsIsTheWholeMeshsOverTheCores has a larger one).
NoiseEstimateParams spectrumOnly() {
  NoiseEstimateParams p;
  p.amplitude = false;
  return p;
}

// Small windows, so that meshes of a unit test's size take several.
NoiseWindowParams smallWindows() {
  NoiseWindowParams p;
  p.core_rings = 10; // reach 29 rings: 6 windows on the sphere below
  p.face_share = 0.4;
  p.min_windows = 4;
  return p;
}

struct Measured {
  bool used = false;
  NoiseEstimate windows, masked, whole;
};

// The estimate on windows, the whole mesh's estimate with its medians over the same cores, and the
// whole mesh's own.
Measured measure(const MeshArrays &mesh, const NoiseWindowParams &params,
                 const NoiseEstimateParams &estimate = spectrumOnly()) {
  Measured out;
  const int n = int(mesh.points.size());
  const Rings rings = computeRings(n, mesh.faces);
  const double edge = edgeStatistics(mesh.points, rings).mean_edge_length;
  const detail::VertexRoles roles = detail::vertexRoles(mesh, rings, edge);
  out.used =
      estimateNoiseOnWindows(mesh, rings, roles.frozen, edge, out.windows, params, estimate);
  const FaceRings face_rings = computeFaceRings(mesh.faces, rings);
  out.whole = estimateNoise(mesh.points, mesh.faces, rings, face_rings, roles, estimate);
  // The cores as the windows take them: within core_rings of one seed per run of the order.
  const int reach = params.core_rings + noiseWindowMargin(estimate, params);
  const int windows = int(params.face_share * double(mesh.faces.size()) / (6.0 * reach * reach));
  const std::vector<int> distance =
      detail::ringDistance(rings, detail::windowSeeds(rings, roles.frozen, windows), reach);
  std::vector<std::uint8_t> core_vertex(n), core_face(mesh.faces.size());
  for (int v = 0; v < n; ++v) core_vertex[v] = distance[v] <= params.core_rings;
  for (size_t g = 0; g < mesh.faces.size(); ++g)
    core_face[g] = core_vertex[mesh.faces[g][0]] && core_vertex[mesh.faces[g][1]] &&
                   core_vertex[mesh.faces[g][2]];
  out.masked = detail::measureNoise(mesh.points, mesh.faces, rings, face_rings, roles,
                                    detail::noiseFrame(mesh.points, rings, edge), &core_vertex,
                                    &core_face, estimate);
  return out;
}

void expectSameBits(const NoiseEstimate &a, const NoiseEstimate &b) {
  EXPECT_EQ(a.spread_deg, b.spread_deg);
  EXPECT_EQ(a.smoothed_spread_deg, b.smoothed_spread_deg);
  EXPECT_EQ(a.noisy, b.noisy);
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.spectrum, b.spectrum);
  EXPECT_EQ(a.correlated_level, b.correlated_level);
  EXPECT_EQ(a.tail, b.tail);
  EXPECT_EQ(a.counted_vertices, b.counted_vertices);
}

MeshArrays noisySphere() {
  MeshArrays sphere = test_meshes::icosphere(1.0, 6); // 40962 vertices, edge about 0.03
  test_meshes::addNoise(sphere, 0.005, 5);
  return sphere;
}

} // namespace

TEST(NoiseWindows, CoresGetTheWholeMeshsValuesBitForBit) {
  const Measured m = measure(noisySphere(), smallWindows());
  ASSERT_TRUE(m.used);
  expectSameBits(m.windows, m.masked);
  EXPECT_GT(m.windows.counted_vertices, 1500);
  EXPECT_LT(m.windows.sampled_share, 0.5); // a sample, not the whole mesh
  EXPECT_GT(m.windows.sampled_share, 0.03);
}

TEST(NoiseWindows, OpenBoundariesInsideTheWindowsKeepTheirValues) {
  MeshArrays field = test_meshes::heightField(
      200, -1, 1, -1, 1, [](double x, double y) { return 0.2 * std::sin(3 * x) * std::cos(2 * y); });
  test_meshes::addNoise(field, 0.002, 11);
  const Measured m = measure(field, smallWindows());
  ASSERT_TRUE(m.used);
  expectSameBits(m.windows, m.masked);
  EXPECT_TRUE(m.windows.noisy);
}

TEST(NoiseWindows, TheSampleReadsTheWholeMeshsNoise) {
  const Measured m = measure(noisySphere(), smallWindows());
  ASSERT_TRUE(m.used);
  EXPECT_TRUE(m.whole.noisy);
  EXPECT_TRUE(m.windows.noisy);
  // Medians over about 2000 vertices: a few per cent of sampling error.
  EXPECT_NEAR(m.windows.level, m.whole.level, 0.05 * m.whole.level);
  EXPECT_NEAR(m.windows.correlated_level, m.whole.correlated_level, 0.06 * m.whole.correlated_level);
  EXPECT_NEAR(m.windows.spread_deg, m.whole.spread_deg, 0.03 * m.whole.spread_deg);
  EXPECT_NEAR(m.windows.decay, m.whole.decay, 0.03);
}

TEST(NoiseWindows, TheSameForAnyThreadCount) {
  const MeshArrays sphere = noisySphere();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Measured one = measure(sphere, smallWindows());
  omp_set_num_threads(2);
  const Measured two = measure(sphere, smallWindows());
  omp_set_num_threads(threads);
  ASSERT_TRUE(one.used && two.used);
  expectSameBits(one.windows, two.windows);
}

TEST(NoiseWindows, SmallMeshesAreLeftToTheWholeMeshEstimate) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 4); // 2562 vertices: fewer windows than the least
  test_meshes::addNoise(sphere, 0.01, 3);
  const Rings rings = computeRings(int(sphere.points.size()), sphere.faces);
  const double edge = edgeStatistics(sphere.points, rings).mean_edge_length;
  const detail::VertexRoles roles = detail::vertexRoles(sphere, rings, edge);
  NoiseEstimate untouched;
  untouched.level = -1;
  EXPECT_FALSE(
      estimateNoiseOnWindows(sphere, rings, roles.frozen, edge, untouched, {}, spectrumOnly()));
  EXPECT_EQ(untouched.level, -1);
  // Windows that would take most of the mesh are refused too.
  NoiseWindowParams wide = smallWindows();
  wide.core_rings = 20;
  wide.face_share = 2.0;
  const MeshArrays big = noisySphere();
  const Rings big_rings = computeRings(int(big.points.size()), big.faces);
  const double big_edge = edgeStatistics(big.points, big_rings).mean_edge_length;
  EXPECT_FALSE(estimateNoiseOnWindows(big, big_rings,
                                      detail::vertexRoles(big, big_rings, big_edge).frozen,
                                      big_edge, untouched, wide, spectrumOnly()));
  EXPECT_EQ(untouched.level, -1);
}

// The sample's size has a ceiling (NoiseWindowParams::max_windows): past it a larger mesh takes
// the same number of windows, a smaller share of its faces, and reads about the same level.
TEST(NoiseWindows, AtMostMaxWindowsTakeTheirCoresAsTheSample) {
  const MeshArrays sphere = noisySphere();
  const int n = int(sphere.points.size());
  const Rings rings = computeRings(n, sphere.faces);
  const double edge = edgeStatistics(sphere.points, rings).mean_edge_length;
  const detail::VertexRoles roles = detail::vertexRoles(sphere, rings, edge);
  NoiseWindowParams params = smallWindows();
  NoiseEstimate all, capped;
  ASSERT_TRUE(
      estimateNoiseOnWindows(sphere, rings, roles.frozen, edge, all, params, spectrumOnly()));
  params.max_windows = 4;
  ASSERT_TRUE(
      estimateNoiseOnWindows(sphere, rings, roles.frozen, edge, capped, params, spectrumOnly()));
  // 6 windows, then 4 (their cores do not overlap on this sphere: the share falls by a third).
  EXPECT_NEAR(capped.sampled_share / all.sampled_share, 4.0 / 6.0, 0.05);
  EXPECT_NEAR(capped.level / all.level, 1.0, 0.05);
  params.max_windows = 3; // under min_windows: the whole mesh's estimate instead
  EXPECT_FALSE(
      estimateNoiseOnWindows(sphere, rings, roles.frozen, edge, capped, params, spectrumOnly()));
}

// The amplitude takes its own few windows with margins that cover its coarse bands
// (readAmplitudeOnWindows): its mean over their cores reads the whole mesh's amplitude, and the
// spectrum's figures stay those of the usual windows, bit for bit.
TEST(NoiseWindows, AmplitudeOnItsOwnWindowsReadsTheWholeMeshs) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 7); // 163842 vertices, edge about 0.008
  test_meshes::addNoise(sphere, 0.003, 8);
  const Measured m = measure(sphere, smallWindows(), NoiseEstimateParams());
  ASSERT_TRUE(m.used);
  expectSameBits(m.windows, m.masked);
  EXPECT_GT(m.whole.amplitude, 0.2);
  EXPECT_NEAR(m.windows.amplitude, m.whole.amplitude, 0.05 * m.whole.amplitude);
  EXPECT_EQ(m.windows.correlation_steps, m.whole.correlation_steps);
}
