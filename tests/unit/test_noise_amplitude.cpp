// vcg_ext/analysis/noise_amplitude.h: the noise templates measured again on a regular torus; the
// fit recovering known mixtures; the amplitude of white and correlated noise on a plane and a
// sphere near the truth (in clean edge units); a clean sphere read as shape, not noise; the same
// result in any vertex order and for any thread count.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <support/measures.h>
#include <vcg_ext/analysis/noise_amplitude.h>
#include <vcg_ext/analysis/noise_estimate.h>

#include <omp.h>
#include <random>

using namespace vcg_ext;

namespace {

// A regular torus lattice (every vertex of valence 6, no boundary) of rows x cols vertices.
MeshArrays torusLattice(int rows, int cols) {
  std::vector<Vec3> p;
  std::vector<Face> f;
  auto at = [&](int i, int j) { return ((i + rows) % rows) * cols + (j + cols) % cols; };
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double u = 2 * M_PI * i / rows, v = 2 * M_PI * j / cols;
      p.emplace_back((3 + std::cos(u)) * std::cos(v), (3 + std::cos(u)) * std::sin(v),
                     std::sin(u));
      f.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      f.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return test_meshes::fromArrays(std::move(p), std::move(f));
}

// The amplitude of a mesh as the drivers read it: in spatial order, in the noise frame.
NoiseAmplitude amplitudeOf(const MeshArrays &m) {
  const Rings rings = computeRings(int(m.points.size()), m.faces);
  const double edge = edgeStatistics(m.points, rings).mean_edge_length;
  const detail::VertexRoles roles = detail::vertexRoles(m, rings, edge);
  return measureNoiseAmplitude(
      detail::inNoiseFrame(m.points, rings, detail::noiseFrame(m.points, rings, edge)), m.faces,
      rings, roles);
}

MeshArrays plane() {
  return test_meshes::heightField(120, 0, 119, 0, 119, [](double, double) { return 0.0; });
}

} // namespace

TEST(NoiseAmplitude, TemplatesAreTheBandSharesOfCorrelatedNoiseOnARegularLattice) {
  const MeshArrays torus = torusLattice(96, 96);
  const int n = int(torus.points.size());
  const Rings rings = computeRings(n, torus.faces);
  const std::vector<std::uint8_t> still(n, 0), counted(n, 1);
  const std::vector<std::array<int, 2>> curve(n, {-1, -1});
  const SpatialTaubin taubin(torus.points, rings, still, curve, /*given_order=*/true);
  const std::vector<Vec3> along_x(n, Vec3::UnitX());
  for (const NoiseTemplate &t : noiseTemplates()) {
    std::vector<double> mean(8, 0.0);
    for (unsigned seed = 0; seed < 6; ++seed) {
      // The probe: unit-variance white noise smoothed t.steps times, as x of a field read along x.
      std::mt19937 rng(seed);
      std::normal_distribution<double> g;
      std::vector<double> z(n), next(n);
      for (double &x : z) x = g(rng);
      for (int s = 0; s < t.steps; ++s) {
        for (int v = 0; v < n; ++v) {
          double sum = 0;
          for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) sum += z[*w];
          next[v] = 0.5 * z[v] + 0.5 * sum / rings.ring1Size(v);
        }
        z.swap(next);
      }
      double square = 0;
      for (double x : z) square += x * x / n;
      std::vector<Vec3> field(n);
      for (int v = 0; v < n; ++v) field[v] = Vec3(z[v] / std::sqrt(square), 0, 0);
      const std::vector<double> e = bandEnergiesAlongNormals(field, taubin, along_x, counted, {});
      for (int b = 0; b < 8; ++b) mean[b] += e[b] / 6;
    }
    for (int b = 0; b < 8; ++b)
      // Six probes on 9216 vertices: the coarse bands of the most correlated noise hold few
      // independent samples (their standard error is about 5 %).
      EXPECT_NEAR(mean[b], t.energy[b], 0.15 * t.energy[b]) << "s " << t.steps << " band " << b;
  }
}

TEST(NoiseAmplitude, FitRecoversAMixtureOfWhiteAndCorrelatedNoiseBesideShape) {
  const auto &white = noiseTemplates()[0].energy, &four = noiseTemplates()[3].energy;
  std::vector<double> energy(8);
  for (int b = 0; b < 8; ++b)
    energy[b] = 0.04 * white[b] + 0.21 * four[b] + 1e-3 * std::pow(3.0, b - 7);
  const NoiseAmplitude a = fitNoiseAmplitude(energy);
  EXPECT_EQ(a.correlation_steps, 4);
  EXPECT_NEAR(a.correlated_share, 0.21 / 0.25, 0.01);
  // sqrt(0.25) = 0.5 in the noisy mesh's units, 0.5 / sqrt(1 - 2 0.25 d) in clean ones.
  const double d = (0.04 * 1.0006 + 0.21 * 0.2267) / 0.25;
  EXPECT_NEAR(a.amplitude, 0.5 / std::sqrt(1 - 0.5 * d), 0.01);
  EXPECT_LT(a.fit_error, 1e-6);
}

TEST(NoiseAmplitude, CleanEdgeUnitsUndoTheEdgesTheNoiseLengthened) {
  EXPECT_DOUBLE_EQ(cleanEdgeUnits(0.0, 1.0), 0.0);
  EXPECT_NEAR(cleanEdgeUnits(1.0 / std::sqrt(3.0), 1.0), 1.0, 1e-12); // white, one edge length
  EXPECT_NEAR(cleanEdgeUnits(0.3, 0.1), 0.3 / std::sqrt(1 - 0.018), 1e-12);
  EXPECT_DOUBLE_EQ(cleanEdgeUnits(0.9, 1.0), 1.8); // past the pole: twice the reading
}

TEST(NoiseAmplitude, WhiteAndCorrelatedNoiseOnAPlaneReadNearTheirLevel) {
  const MeshArrays flat = plane(); // edges about 1.1 (sides 1, diagonals 1.41)
  const double edge = test_meshes::meanEdge(flat);
  for (double level : {0.2, 0.6}) {
    for (int steps : {0, 2, 4}) {
      const MeshArrays noisy = test_meshes::withCorrelatedNoise(flat, level * edge, steps, 5);
      const NoiseAmplitude a = amplitudeOf(noisy);
      EXPECT_NEAR(a.amplitude, level, 0.15 * level) << "level " << level << " steps " << steps;
      if (steps >= 2 && level >= 0.6)
        EXPECT_GE(a.correlation_steps, 2) << "level " << level << " steps " << steps;
    }
  }
}

TEST(NoiseAmplitude, ACleanSphereIsShapeAndANoisyOneReadsItsNoise) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const double edge = test_meshes::meanEdge(sphere);
  EXPECT_LT(amplitudeOf(sphere).amplitude, 0.05);
  const NoiseAmplitude noisy = amplitudeOf(test_meshes::withCorrelatedNoise(sphere, 0.4 * edge, 2, 3));
  EXPECT_NEAR(noisy.amplitude, 0.4, 0.08);
}

TEST(NoiseAmplitude, SameResultInAnyVertexOrderAndForAnyThreadCount) {
  const MeshArrays noisy =
      test_meshes::withCorrelatedNoise(test_meshes::icosphere(1.0, 5), 0.005, 2, 9);
  const SpatialOrder a = spatialOrder(noisy);
  const SpatialOrder b = spatialOrder(
      test_meshes::permuted(noisy, test_meshes::shuffledPermutation(int(noisy.points.size()), 4)));
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const NoiseAmplitude one = amplitudeOf(a.mesh);
  omp_set_num_threads(2);
  const NoiseAmplitude two = amplitudeOf(b.mesh);
  omp_set_num_threads(threads);
  EXPECT_GT(one.amplitude, 0.1);
  EXPECT_EQ(one.amplitude, two.amplitude);
  EXPECT_EQ(one.band_energy, two.band_energy);
}

TEST(NoiseAmplitude, SmallMeshesReadTheBandsTheyHoldAndTinyOnesNone) {
  // 64 vertices per pair of the coarsest band, at least seven bands (up to 64 pairs).
  EXPECT_EQ(amplitudeBandCount(2562), 0);
  EXPECT_EQ(amplitudeBandCount(4096), 7);
  EXPECT_EQ(amplitudeBandCount(6475), 7); // the Fandisk
  EXPECT_EQ(amplitudeBandCount(8192), 8);
  const MeshArrays coarse = test_meshes::icosphere(1.0, 4); // 2562 vertices
  const double coarse_edge = test_meshes::meanEdge(coarse);
  EXPECT_EQ(amplitudeOf(test_meshes::withCorrelatedNoise(coarse, 0.4 * coarse_edge, 2, 3)).amplitude,
            0.0);
  // 6144 vertices: seven bands; white and correlated noise read near their level, the clean
  // torus as shape.
  const MeshArrays small = torusLattice(64, 96);
  const double edge = test_meshes::meanEdge(small);
  EXPECT_LT(amplitudeOf(small).amplitude, 0.05);
  for (int steps : {0, 2}) {
    const NoiseAmplitude a =
        amplitudeOf(test_meshes::withCorrelatedNoise(small, 0.4 * edge, steps, 3));
    EXPECT_EQ(a.band_energy.size(), 7u);
    EXPECT_NEAR(a.amplitude, 0.4, 0.08) << "steps " << steps;
  }
}

TEST(NoiseAmplitude, TheTrimmedReadingAgreesOnNoiseAndLeavesACleanBoxsCreasesOut) {
  // Noise's band displacements are Gaussian at every vertex whatever its correlation: the
  // trimmed energies read what the plain ones do.
  const MeshArrays flat = plane();
  const double edge = test_meshes::meanEdge(flat);
  for (int steps : {0, 4}) {
    const NoiseAmplitude a = amplitudeOf(test_meshes::withCorrelatedNoise(flat, 0.4 * edge, steps, 5));
    RecordProperty("trimmed_" + std::to_string(steps), std::to_string(a.trimmed_amplitude));
    EXPECT_NEAR(a.trimmed_amplitude, a.amplitude, 0.1 * a.amplitude) << "steps " << steps;
  }
  // A clean box (9602 vertices): its creases are all the plain amplitude reads, and the trimmed
  // energies leave them out.
  const NoiseAmplitude box = amplitudeOf(test_meshes::box(1.0, 0.7, 0.5, 40));
  RecordProperty("box", std::to_string(box.amplitude) + " " + std::to_string(box.trimmed_amplitude));
  EXPECT_GT(box.amplitude, 0.0);
  EXPECT_LT(box.trimmed_amplitude, 0.3 * box.amplitude);
}
