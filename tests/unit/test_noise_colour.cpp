// The noise's colour (vcg_ext/analysis/noise_estimate.h: correlated_level, noiseColour) and what the
// drivers do with it: band_shrink.h's coloured noise and trimmed (robust) band energies, the
// feature mode's extra iterations on planar meshes (feature_smooth.h).
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/feature/feature_smooth.h>
#include <vcg_ext/methods/organic/organic_smooth.h>

#include <random>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::meanEdge;

namespace {

NoiseEstimate withSpectrum(std::vector<double> spectrum) {
  NoiseEstimate e;
  e.noisy = true;
  e.spectrum = std::move(spectrum);
  e.level = e.spectrum[0];
  e.correlated_level = *std::max_element(e.spectrum.begin(), e.spectrum.end());
  return e;
}

const std::vector<int> kBands = {0, 1, 2, 4, 8, 16, 32, 64, 128};

struct Topology {
  Rings rings;
  detail::VertexRoles roles;
  std::vector<std::uint8_t> fixed;
  explicit Topology(const MeshArrays &m)
      : rings(computeRings(int(m.points.size()), m.faces)),
        roles(detail::vertexRoles(m, rings, meanEdge(m))), fixed(roles.frozen) {}
};

BandShrinkReport shrink(const MeshArrays &m, const BandShrinkParams &params) {
  const Topology s(m);
  std::vector<Vec3> points = m.points;
  return bandShrinkSmooth(points, m.faces, s.rings, s.fixed, s.roles.boundary_neighbours, params);
}

} // namespace

TEST(NoiseColour, CorrelatedLevelIsTheSpectrumsLargestBand) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const double edge = meanEdge(sphere);
  const NoiseEstimate white =
      estimateNoise(test_meshes::withNormalNoise(sphere, 0.1 * edge, 7).points, sphere.faces);
  EXPECT_EQ(white.correlated_level, *std::max_element(white.spectrum.begin(), white.spectrum.end()));
  EXPECT_NEAR(white.correlated_level, white.level, 0.15 * white.level); // white: flat
}

TEST(NoiseColour, ClosedFormFromTheSpectrum) {
  NoiseColourParams p; // octave rise capped at 1.35, total at 4, weight 1, no gates
  // Measured bands take their ratio squared; beyond, the last octave's rise (0.15 / 0.125 = 1.2)
  // continues.
  const std::vector<double> c = noiseColour(withSpectrum({0.1, 0.11, 0.125, 0.15}), kBands, p);
  ASSERT_EQ(c.size(), 8u);
  EXPECT_DOUBLE_EQ(c[0], 1.0);
  EXPECT_NEAR(c[1], 1.21, 1e-12);
  EXPECT_NEAR(c[3], 2.25, 1e-12);
  EXPECT_NEAR(c[4], std::pow(1.5 * 1.2, 2), 1e-12);
  EXPECT_NEAR(c[6], std::pow(1.5 * 1.2 * 1.2 * 1.2, 2), 1e-12);
  EXPECT_NEAR(c[7], std::pow(1.5 * std::pow(1.2, 4), 2), 1e-12);
  // The total rise is capped (2 · (4/3)⁴ = 6.3 > 4).
  EXPECT_NEAR(noiseColour(withSpectrum({0.1, 0.12, 0.15, 0.2}), kBands, p)[7], 16.0, 1e-12);
  // The octave rise is capped, and so is the total.
  p.max_octave_rise = 1.1;
  const std::vector<double> slow = noiseColour(withSpectrum({0.1, 0.11, 0.125, 0.15}), kBands, p);
  EXPECT_NEAR(slow[7], std::pow(1.5 * std::pow(1.1, 4), 2), 1e-12);
  // White noise (a flat or falling spectrum) is white in every band.
  for (double x : noiseColour(withSpectrum({0.2, 0.2, 0.19, 0.2}), kBands, {}))
    EXPECT_DOUBLE_EQ(x, 1.0);
  // Weight 0.5: the square root of the colour.
  NoiseColourParams half;
  half.weight = 0.5;
  EXPECT_NEAR(noiseColour(withSpectrum({0.1, 0.11, 0.125, 0.15}), kBands, half)[3], 1.5, 1e-12);
}

TEST(NoiseColour, GatesByLevelAndRise) {
  NoiseColourParams p;
  p.level_white = 0.1, p.level_coloured = 0.15, p.rise_white = 1.1, p.rise_coloured = 1.3;
  // Below either gate: white.
  for (double x : noiseColour(withSpectrum({0.08, 0.09, 0.1, 0.12}), kBands, p)) EXPECT_EQ(x, 1.0);
  for (double x : noiseColour(withSpectrum({0.2, 0.2, 0.205, 0.21}), kBands, p)) EXPECT_EQ(x, 1.0);
  // Level 0.125 and rise 1.2: half way through both, weight 0.25.
  const std::vector<double> c = noiseColour(withSpectrum({0.125, 0.13, 0.14, 0.15}), kBands, p);
  EXPECT_NEAR(c[3], std::pow(1.2, 2 * 0.25), 1e-12);
  // Above both: the full colour.
  const std::vector<double> full = noiseColour(withSpectrum({0.2, 0.21, 0.23, 0.3}), kBands, p);
  EXPECT_NEAR(full[3], 2.25, 1e-12);
  // Degenerate spectra: white.
  EXPECT_EQ(noiseColour(NoiseEstimate(), kBands, p), std::vector<double>(8, 1.0));
  EXPECT_EQ(noiseColour(withSpectrum({0.0, 0.1, 0.1, 0.1}), kBands, {}), std::vector<double>(8, 1.0));
}

TEST(NoiseColour, ColouredNoiseLowersTheGainsAndWhiteKeepsThemBitForBit) {
  MeshArrays noisy = test_meshes::icosphere(1.0, 4);
  test_meshes::addNoise(noisy, 0.2 * meanEdge(noisy), 5);
  const BandShrinkReport plain = shrink(noisy, BandShrinkParams());
  BandShrinkParams white;
  white.noise_colour.assign(8, 1.0);
  EXPECT_EQ(shrink(noisy, white).gains, plain.gains);
  BandShrinkParams coloured;
  coloured.noise_colour = {1, 1.2, 1.5, 2, 3, 4, 5, 6};
  const BandShrinkReport c = shrink(noisy, coloured);
  for (size_t b = 0; b < c.gains.size(); ++b) {
    EXPECT_LE(c.gains[b], plain.gains[b]) << b;
    // 1 − α·colour·N/E: the gain's distance from 1 grows by the colour unless clamped.
    if (plain.gains[b] > 0 && c.gains[b] > 0)
      EXPECT_NEAR(1 - c.gains[b], coloured.noise_colour[b] * (1 - plain.gains[b]), 1e-9) << b;
  }
  EXPECT_EQ(c.alpha, plain.alpha); // the α rule reads the white bands
}

TEST(NoiseColour, TrimmedEnergiesIgnoreSpikes) {
  // A bumpy sphere (shape in the fine bands) with white noise: trimmed energies give about the
  // same fine-band gains; with a few spikes added the plain energies take the spikes for shape
  // and keep the fine bands, the trimmed ones do not.
  MeshArrays noisy = test_meshes::icosphere(1.0, 4);
  for (Vec3 &p : noisy.points)
    p *= 1.0 + 0.02 * std::sin(15 * p.x()) * std::sin(15 * p.y()) * std::sin(15 * p.z());
  const double edge = meanEdge(noisy);
  test_meshes::addNoise(noisy, 0.05 * edge, 5);
  const BandShrinkParams robust; // the defaults: trimmed at the median up to 4 pairs
  EXPECT_EQ(robust.robust_quantile, 0.5);
  EXPECT_EQ(robust.robust_max_pairs, 4);
  BandShrinkParams all;
  all.robust_quantile = 1.0;
  const BandShrinkReport plain = shrink(noisy, all), trimmed = shrink(noisy, robust);
  RecordProperty("white", std::to_string(plain.gains[2]) + " " + std::to_string(trimmed.gains[2]));
  for (size_t b = 0; b < 3; ++b) EXPECT_NEAR(trimmed.gains[b], plain.gains[b], 0.15) << b;
  for (size_t b = 3; b < plain.gains.size(); ++b) EXPECT_EQ(trimmed.gains[b], plain.gains[b]) << b;
  MeshArrays spiky = noisy;
  for (int v = 0; v < int(spiky.points.size()); v += 40) spiky.points[v] *= 1.0 + 3 * edge;
  const BandShrinkReport spiky_plain = shrink(spiky, all),
                         spiky_trimmed = shrink(spiky, robust);
  RecordProperty("gains", std::to_string(spiky_plain.gains[0]) + " " +
                              std::to_string(spiky_trimmed.gains[0]));
  EXPECT_GT(spiky_plain.gains[0], 0.5);
  EXPECT_LT(spiky_trimmed.gains[0], spiky_plain.gains[0] - 0.3);
}

TEST(NoiseColour, TrimmedEnergiesRemoveNoiseWhoseLevelVariesOverTheSurface) {
  // Scanner noise grows with depth: here its level is three times higher on one half of a
  // sphere. The plain 2-4 pair band's energy holds the loud half's noise, which the probe (at the
  // median level) does not, so it reads as shape and the band is kept in part; the trimmed
  // energies compare the typical vertices and remove more of it.
  MeshArrays noisy = test_meshes::icosphere(1.0, 4);
  const double edge = meanEdge(noisy);
  MeshArrays loud = noisy;
  test_meshes::addNoise(noisy, 0.1 * edge, 7);
  for (size_t v = 0; v < noisy.points.size(); ++v) {
    const Vec3 &clean = loud.points[v];
    if (clean.z() > 0) noisy.points[v] = clean + 3.0 * (noisy.points[v] - clean);
  }
  BandShrinkParams two_pairs; // the earlier default: trimmed up to 2 pairs only
  two_pairs.robust_max_pairs = 2;
  const BandShrinkReport before = shrink(noisy, two_pairs), after = shrink(noisy, BandShrinkParams());
  RecordProperty("band 2-4", std::to_string(before.gains[2]) + " " + std::to_string(after.gains[2]));
  EXPECT_GT(before.gains[2], 0.2);
  EXPECT_LT(after.gains[2], before.gains[2] - 0.1);
  for (size_t b = 3; b < after.gains.size(); ++b) EXPECT_EQ(after.gains[b], before.gains[b]) << b;
}

TEST(NoiseColour, PlanarMeshesTakeExtraFeatureIterations) {
  // A noisy box: its flat share after the first guidance period is high, so the feature mode runs
  // up to twice its normal filter iterations and vertex updates; a noisy sphere takes none.
  MeshArrays box = test_meshes::box(1.0, 0.7, 0.5, 14), sphere = test_meshes::icosphere(1.0, 4);
  test_meshes::addNoise(box, 0.3 * meanEdge(box), 3);
  test_meshes::addNoise(sphere, 0.3 * meanEdge(sphere), 3);
  const FeatureSmoothParams extra; // the defaults: up to twice from a flat share of 0.3 to 0.45
  FeatureSmoothParams none;
  none.planar_extra = 0.0;
  auto run = [](const MeshArrays &m, const FeatureSmoothParams &p) {
    std::vector<Vec3> out;
    VertexQuantities q;
    return featureSmoothMesh(m, p, out, q);
  };
  const FeatureSmoothReport box_plain = run(box, none), box_extra = run(box, extra);
  // extra = clamp((flat − 0.3) / 0.15, 0, 1): the counts grow by that share (measured flat 0.41).
  EXPECT_GT(box_extra.flat_share, 0.35);
  const double share = std::clamp((box_extra.flat_share - 0.3) / 0.15, 0.0, 1.0);
  EXPECT_EQ(box_extra.vertex_iterations, std::lround(box_plain.vertex_iterations * (1 + share)));
  EXPECT_EQ(box_extra.normal_iterations, std::lround(box_plain.normal_iterations * (1 + share)));
  EXPECT_GT(box_extra.vertex_iterations, box_plain.vertex_iterations);
  const FeatureSmoothReport sphere_plain = run(sphere, none), sphere_extra = run(sphere, extra);
  EXPECT_LT(sphere_extra.flat_share, 0.3);
  EXPECT_EQ(sphere_extra.vertex_iterations, sphere_plain.vertex_iterations);
  EXPECT_EQ(sphere_extra.normal_iterations, sphere_plain.normal_iterations);
}
