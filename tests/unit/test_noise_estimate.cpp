// The noise estimate of vcg_ext/analysis/noise_estimate.h: smooth analytic surfaces read clean, added noise
// of known std reads noisy with a level near the truth (white and correlated over a few rings),
// the result does not depend on scale, placement or vertex order, and degenerate input does not
// crash.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/noise_estimate.h>

#include <random>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::meanEdge;

namespace {

NoiseEstimate estimate(const MeshArrays &m) { return estimateNoise(m.points, m.faces); }

MeshArrays wavyField() {
  return test_meshes::heightField(80, -1, 1, -1, 1, [](double x, double y) {
    return 0.15 * std::sin(3 * x) * std::cos(2 * y) + 0.1 * x * x;
  });
}

} // namespace

TEST(NoiseEstimate, SmoothAnalyticSurfacesReadClean) {
  const MeshArrays surfaces[] = {test_meshes::icosphere(1.0, 4), test_meshes::icosphere(3.0, 2),
                                 test_meshes::cylinder(1.0, 3.0, 64, 40), wavyField(),
                                 test_meshes::box(1.0, 0.7, 0.5, 12)};
  for (const MeshArrays &m : surfaces) {
    const NoiseEstimate e = estimate(m);
    RecordProperty("level", std::to_string(e.level));
    EXPECT_FALSE(e.noisy) << "spread " << e.spread_deg << " decay " << e.decay;
    EXPECT_LT(e.level, 0.02);
  }
}

TEST(NoiseEstimate, WhiteNoiseLevelWithinTenPercent) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const double edge = meanEdge(sphere);
  // Within 10 % up to 0.2 mean edge lengths; at 0.4 the normals the bands are measured along are
  // themselves noisy and the level reads low (measured 0.345).
  for (double k : {0.05, 0.1, 0.2, 0.4}) {
    const NoiseEstimate e = estimate(test_meshes::withNormalNoise(sphere, k * edge, 7));
    EXPECT_TRUE(e.noisy) << k;
    EXPECT_NEAR(e.level, k, (k < 0.3 ? 0.1 : 0.2) * k) << k;
    // White: the spectrum stays flat over the fine bands.
    EXPECT_NEAR(e.spectrum[1], e.level, 0.15 * e.level) << k;
  }
  // Random directions: the normal component has the same std.
  MeshArrays random = sphere;
  test_meshes::addNoise(random, 0.1 * edge, 3);
  const NoiseEstimate e = estimate(random);
  EXPECT_TRUE(e.noisy);
  EXPECT_NEAR(e.level, 0.1, 0.012);
}

TEST(NoiseEstimate, OpenBoundaryAndOutliers) {
  const MeshArrays field = wavyField();
  const double edge = meanEdge(field);
  MeshArrays noisy = test_meshes::withNormalNoise(field, 0.1 * edge, 5);
  const NoiseEstimate e = estimate(noisy);
  EXPECT_TRUE(e.noisy);
  EXPECT_NEAR(e.level, 0.1, 0.012);
  // 0.2 % of the vertices thrown 10 mean edge lengths off: the medians hardly move.
  for (int v = 0; v < int(noisy.points.size()); v += 500) noisy.points[v].z() += 10 * edge;
  const NoiseEstimate with_outliers = estimate(noisy);
  EXPECT_TRUE(with_outliers.noisy);
  EXPECT_NEAR(with_outliers.level, e.level, 0.05 * e.level);
}

TEST(NoiseEstimate, RingCorrelatedNoise) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const double edge = meanEdge(sphere);
  const double sigma = 0.3;
  const NoiseEstimate e = estimate(test_meshes::withCorrelatedNoise(sphere, sigma * edge, 2, 11));
  RecordProperty("spectrum", std::to_string(e.spectrum[0]) + " " + std::to_string(e.spectrum[1]) +
                                 " " + std::to_string(e.spectrum[2]) + " " +
                                 std::to_string(e.spectrum[3]));
  EXPECT_TRUE(e.noisy);
  // Correlated noise puts less into the finest band than white noise of the same std, and the
  // white-equivalent spectrum rises toward the coarser bands (white noise: flat).
  EXPECT_LT(e.level, sigma);
  EXPECT_GT(e.spectrum[2], 1.3 * e.spectrum[0]);
  // Measured (2 steps of correlation, std 0.3): level 0.108, the spectrum's largest band (4-8
  // pairs) 0.250, within 20 % of the truth. (With 4 steps or more at this std the decay is above
  // 0.9 and the mesh reads clean: smooth bumps of a few rings look like shape.)
  EXPECT_NEAR(e.level, 0.108, 0.02);
  EXPECT_NEAR(*std::max_element(e.spectrum.begin(), e.spectrum.end()), sigma, 0.2 * sigma);
}

// Heavy noise correlated over six smoothing steps changes little under one Taubin pair, so the
// pair's test reads it clean; its amplitude reads it, trimmed and plain alike (noise_estimate.h's
// amplitude_noisy), while clean shapes' trimmed readings stay far below.
TEST(NoiseEstimate, NoiseCorrelatedOverManyRingsReadsNoisyByItsAmplitude) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5); // 10242 vertices: all eight bands
  const MeshArrays noisy = test_meshes::withCorrelatedNoise(sphere, 0.7 * meanEdge(sphere), 6, 11);
  NoiseEstimateParams pair_only;
  pair_only.amplitude_noisy = 0;
  const NoiseEstimate before = estimateNoise(noisy.points, noisy.faces, pair_only);
  EXPECT_FALSE(before.noisy) << "decay " << before.decay;
  EXPECT_EQ(before.amplitude, 0.0);
  const NoiseEstimate e = estimate(noisy);
  RecordProperty("amplitude", std::to_string(e.amplitude) + " " + std::to_string(e.trimmed_amplitude));
  EXPECT_TRUE(e.noisy);
  EXPECT_TRUE(e.noisy_by_amplitude);
  EXPECT_EQ(e.decay, before.decay);
  EXPECT_NEAR(e.amplitude, 0.7, 0.2);
  EXPECT_GE(e.trimmed_amplitude, NoiseEstimateParams().amplitude_noisy_share * e.amplitude);
  // Such noise tilts the normals: its spread is past the gate below which the amplitude does not
  // decide (and is not read).
  EXPECT_GE(e.spread_deg, NoiseEstimateParams().amplitude_noisy_min_spread_deg);
  NoiseEstimateParams gated;
  gated.amplitude_noisy_min_spread_deg = e.spread_deg + 1;
  const NoiseEstimate below = estimateNoise(noisy.points, noisy.faces, gated);
  EXPECT_FALSE(below.noisy);
  EXPECT_EQ(below.trimmed_amplitude, 0.0);
  for (const MeshArrays &m : {sphere, test_meshes::box(1.0, 0.7, 0.5, 40),
                              test_meshes::cylinder(1.0, 3.0, 128, 80)}) {
    const NoiseEstimate clean = estimate(m);
    EXPECT_FALSE(clean.noisy) << "trimmed " << clean.trimmed_amplitude;
    EXPECT_FALSE(clean.noisy_by_amplitude);
    EXPECT_EQ(clean.amplitude, 0.0); // not kept on a mesh that reads clean
  }
}

TEST(NoiseEstimate, ScaleAndPlacementInvariant) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 4);
  const MeshArrays noisy = test_meshes::withNormalNoise(sphere, 0.08 * meanEdge(sphere), 2);
  const NoiseEstimate reference = estimate(noisy);
  for (double scale : {1e-3, 1e4}) {
    MeshArrays moved = noisy;
    for (Vec3 &p : moved.points) p = p * scale + Vec3(5.0, -3.0, 2.0) * scale;
    const NoiseEstimate e = estimate(moved);
    EXPECT_EQ(e.noisy, reference.noisy);
    EXPECT_NEAR(e.level, reference.level, 1e-3 * reference.level) << scale;
    EXPECT_NEAR(e.decay, reference.decay, 1e-6) << scale;
  }
}

TEST(NoiseEstimate, VertexAndFaceOrderInvariant) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 4);
  const MeshArrays noisy = test_meshes::withNormalNoise(sphere, 0.06 * meanEdge(sphere), 4);
  const NoiseEstimate reference = estimate(noisy);
  const NoiseEstimate permuted = estimate(test_meshes::permuted(
      noisy, test_meshes::shuffledPermutation(int(noisy.points.size()), 9)));
  const NoiseEstimate reordered = estimate(test_meshes::facesReordered(noisy, 3));
  // The white-noise probe runs in single precision, its neighbour sums in ring order: the
  // spectrum agrees to float rounding (the drivers put every mesh in spatial order first, so the
  // filters' results do not depend on the input's order at all).
  ASSERT_EQ(reference.spectrum.size(), 4u);
  for (const NoiseEstimate &e : {permuted, reordered}) {
    EXPECT_EQ(e.noisy, reference.noisy);
    EXPECT_NEAR(e.level, reference.level, 1e-6 * reference.level);
    EXPECT_NEAR(e.spread_deg, reference.spread_deg, 1e-9);
    EXPECT_NEAR(e.smoothed_spread_deg, reference.smoothed_spread_deg, 1e-9);
    ASSERT_EQ(e.spectrum.size(), reference.spectrum.size());
    for (size_t b = 0; b < e.spectrum.size(); ++b)
      EXPECT_NEAR(e.spectrum[b], reference.spectrum[b], 1e-6 * reference.spectrum[b]);
  }
}

TEST(NoiseEstimate, DegenerateInputDoesNotCrash) {
  EXPECT_FALSE(estimateNoise({}, {}).noisy);
  const std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const NoiseEstimate one = estimateNoise(triangle, {{0, 1, 2}});
  EXPECT_FALSE(one.noisy);
  EXPECT_EQ(one.level, 0.0);
  // A fin: three triangles on one edge (non-manifold), plus an isolated vertex.
  const std::vector<Vec3> fin = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {9, 9, 9}};
  const NoiseEstimate e = estimateNoise(fin, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  EXPECT_FALSE(e.noisy);
  EXPECT_TRUE(std::isfinite(e.level));
  // All vertices at one point, an index out of range, a non-finite coordinate.
  EXPECT_FALSE(estimateNoise({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {{0, 1, 2}}).noisy);
  EXPECT_FALSE(estimateNoise(triangle, {{0, 1, 3}}).noisy);
  MeshArrays sphere = test_meshes::icosphere(1.0, 3);
  sphere.points[5] = Vec3(NAN, 0, 0);
  const NoiseEstimate with_nan = estimate(sphere);
  EXPECT_FALSE(with_nan.noisy);
}

namespace {
// Gaussian noise along the clean normals whose std is `sigma` on the lower half of the sphere and
// `ratio` times that on the upper half: the way a scanner's noise grows with depth.
MeshArrays withTwoLevelNoise(const MeshArrays &clean, double sigma, double ratio, unsigned seed) {
  const Rings rings = computeRings(int(clean.points.size()), clean.faces);
  std::vector<Vec3> normals;
  computeVertexNormals(clean.points, clean.faces, rings, normals);
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, sigma, seed, [&](int i) {
    return Vec3(normals[i] * (clean.points[i].z() > 0 ? ratio : 1.0));
  });
  return noisy;
}
} // namespace

TEST(NoiseEstimate, TheTailReadsOneForGaussianNoiseAndMoreForAMixture) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const double edge = meanEdge(sphere);
  for (double k : {0.1, 0.2}) {
    const NoiseEstimate e = estimate(test_meshes::withNormalNoise(sphere, k * edge, 7));
    RecordProperty("tail_gaussian", std::to_string(e.tail));
    EXPECT_NEAR(e.tail, 1.0, 0.05) << k;
  }
  // Half the vertices at 3x the std: a mixture whose rms is sqrt(5) = 2.24 stds of the quiet half
  // and whose |x| has its median at 1.1 of them, so rms / (median / 0.6745) = 1.37. The band mixes
  // a vertex with its ring, which blurs the seam a little.
  const NoiseEstimate e = estimate(withTwoLevelNoise(sphere, 0.1 * edge, 3.0, 7));
  RecordProperty("tail_mixture", std::to_string(e.tail));
  EXPECT_NEAR(e.tail, 1.37, 0.07);
}

TEST(NoiseEstimate, HeavyTailFactorRampsWithTheLevelAndIsCapped) {
  NoiseEstimate e;
  e.tail = 1.4;
  const HeavyTailParams params; // power 1, from 0.08 to 0.12 mean edge lengths, at most 2
  e.level = 0.05;
  EXPECT_EQ(heavyTailFactor(e, params), 1.0); // light noise: the band may be shape
  e.level = 0.10;
  EXPECT_NEAR(heavyTailFactor(e, params), 1.2, 1e-12);
  e.level = 0.3;
  EXPECT_NEAR(heavyTailFactor(e, params), 1.4, 1e-12);
  HeavyTailParams squared = params;
  squared.power = 2;
  EXPECT_NEAR(heavyTailFactor(e, squared), 1.96, 1e-12);
  e.tail = 3.0;
  EXPECT_NEAR(heavyTailFactor(e, squared), 2.0, 1e-12); // the cap
  HeavyTailParams off = params;
  off.power = 0;
  EXPECT_EQ(heavyTailFactor(e, off), 1.0);
  e.tail = 0.9; // lighter tails than Gaussian noise's: never less than the measured amount
  EXPECT_EQ(heavyTailFactor(e, params), 1.0);
}

// measureNoise's stages one by one.
TEST(NoiseEstimateStages, DecisionReadsTheSpreadAndWhatOnePairLeavesOfIt) {
  const NoiseEstimateParams params;
  auto decided = [&](double spread, double smoothed) {
    NoiseEstimate e;
    e.spread_deg = spread;
    detail::decideNoisy(smoothed, params, e);
    return e;
  };
  EXPECT_TRUE(decided(55, 54).noisy);                 // above 50°: noisy whatever the decay
  const NoiseEstimate dropped = decided(10, 6);        // decay 0.6 and 4° gone
  EXPECT_TRUE(dropped.noisy);
  EXPECT_DOUBLE_EQ(dropped.decay, 0.6);
  EXPECT_FALSE(decided(10, 9).noisy);                  // decay 0.9 > 0.85
  EXPECT_FALSE(decided(3, 1).noisy);                   // decay 0.33 but only 2° gone
  const NoiseEstimate flat = decided(0.005, 0.001);    // a flat mesh: no ratio
  EXPECT_EQ(flat.decay, 1.0);
  EXPECT_FALSE(flat.noisy);
}

TEST(NoiseEstimateStages, ProbeBandMedianCountsOnlyTheMarkedVertices) {
  const std::vector<Vec3f> before{Vec3f(1, 2, 3), Vec3f(0, 0, 0), Vec3f(5, 5, 5)};
  const std::vector<Vec3f> after{Vec3f(1, 1, 1), Vec3f(9, 9, 9), Vec3f(5, 2, 5)};
  // Vertex 1 not counted: the differences 0, 1, 2 and 0, 3, 0 sorted, the median at index 3.
  EXPECT_EQ(detail::probeBandMedian(before, after, {1, 0, 1}), 1.0);
  EXPECT_EQ(detail::probeBandMedian(before, after, {0, 1, 0}), 9.0);
}

TEST(NoiseEstimateStages, SpectrumIsTheMedianAlongTheNormalsOverTheProbesMedian) {
  // A flat grid lifted by 0.1 or 0.3 (alternating rows) in band 0, and nothing in band 1.
  const MeshArrays flat = test_meshes::heightField(12, 0, 1, 0, 1, [](double, double) { return 0; });
  const Rings rings = computeRings(int(flat.points.size()), flat.faces);
  std::vector<std::vector<Vec3>> snapshot(3, flat.points);
  for (size_t v = 0; v < flat.points.size(); ++v)
    snapshot[0][v].z() = (v / 12) % 2 ? 0.3 : 0.1;
  std::vector<std::uint8_t> interior(flat.points.size());
  for (size_t v = 0; v < interior.size(); ++v) interior[v] = !rings.boundary[v];
  NoiseEstimate e;
  std::vector<Vec3> normals;
  detail::spectrumAlongNormals(snapshot, flat.faces, rings, interior, {0.5, 0.5}, e, normals);
  ASSERT_EQ(e.spectrum.size(), 2u);
  EXPECT_EQ(e.counted_vertices, 100); // the 10 x 10 interior vertices
  EXPECT_NEAR(e.spectrum[0], 0.3 / 0.5, 1e-12); // median of 50 × 0.1 and 50 × 0.3: the 51st
  EXPECT_EQ(e.spectrum[1], 0.0);
  EXPECT_EQ(e.level, e.spectrum[0]);
  EXPECT_EQ(e.correlated_level, e.spectrum[0]);
  EXPECT_NEAR(e.tail, std::sqrt((0.01 + 0.09) / 2) / (0.3 / 0.6745), 1e-12);
  EXPECT_TRUE(snapshot[1].empty()); // freed after its last read
}

TEST(NoiseEstimateStages, ProbeFollowsThePositionInTheFrameNotTheIndex) {
  const MeshArrays m = wavyField();
  const Rings rings = computeRings(int(m.points.size()), m.faces);
  const detail::NoiseFrame frame = detail::noiseFrame(m.points, rings, 0.05);
  const std::vector<Vec3> framed = detail::inNoiseFrame(m.points, rings, frame);
  EXPECT_EQ(framed[0], Vec3((m.points[0] - frame.lowest) / 0.05));
  // Moved as a whole, the mesh has the same framed positions and probe.
  MeshArrays moved = m;
  for (Vec3 &p : moved.points) p += Vec3(3, -2, 7);
  const std::vector<Vec3> framed_moved =
      detail::inNoiseFrame(moved.points, rings, detail::noiseFrame(moved.points, rings, 0.05));
  const std::vector<Vec3f> probe = detail::hashedProbe(framed);
  double largest = 0;
  for (size_t v = 0; v < framed.size(); ++v)
    largest = std::max(largest, (framed[v] - framed_moved[v]).norm());
  EXPECT_LT(largest, 1e-9);
  double sum2 = 0;
  for (const Vec3f &p : probe) sum2 += double(p.squaredNorm()) / (3.0 * probe.size());
  EXPECT_NEAR(sum2, 1.0, 0.05); // unit std per component
}

TEST(NoiseEstimate, AmplitudeNeedSaturatesAtATenthOfAnEdgeOnNoisyMeshesOnly) {
  NoiseEstimate e;
  e.amplitude = 0.05;
  EXPECT_EQ(amplitudeNeed(e), 0.0); // reads clean
  e.noisy = true;
  EXPECT_NEAR(amplitudeNeed(e), 0.5, 1e-12); // (level 0, not read: no ramp)
  e.amplitude = 0.14; // a red spectrum's amplitude; its finest band reads 0.04
  EXPECT_EQ(amplitudeNeed(e), 1.0);
  HeavyNoiseParams off;
  off.need_weight = 0;
  EXPECT_EQ(amplitudeNeed(e, off), 0.0);
  e.amplitude = NAN;
  EXPECT_EQ(amplitudeNeed(e), 0.0);
}

// The amplitude asks for the need only as far as it lies beyond the finest band: not at an
// amplitude under 1.8 times the level (white noise, light noise on a CAD part's shape), in full
// from 2.4 times it (a red spectrum), linear between.
TEST(NoiseEstimate, AmplitudeNeedRampsInWithTheAmplitudeOverTheFinestBandsLevel) {
  NoiseEstimate e;
  e.noisy = true;
  e.amplitude = 0.097;
  e.level = 0.056; // 1.73: the subdivided Bunny under 2-view scanner noise
  EXPECT_EQ(amplitudeNeed(e), 0.0);
  e.amplitude = 0.14;
  e.level = 0.04; // 3.5: a red spectrum
  EXPECT_EQ(amplitudeNeed(e), 1.0);
  e.level = 0.14 / 2.1; // halfway up the ramp
  EXPECT_NEAR(amplitudeNeed(e), 0.5, 1e-12);
  e.amplitude = 0.07;
  e.level = 0.07 / 2.1; // and half of a need of 0.7
  EXPECT_NEAR(amplitudeNeed(e), 0.35, 1e-12);
  HeavyNoiseParams no_ramp;
  no_ramp.need_ratio_from = no_ramp.need_ratio_full = 0;
  EXPECT_NEAR(amplitudeNeed(e, no_ramp), 0.7, 1e-12);
}

// How correlated a noise is: the larger of its fitted share's ramp (0.3 to 0.55) and the ramp of
// its amplitude over its finest band's level (2.4 to 3.2), times the amplitude's ramp (0.1-0.15).
TEST(NoiseEstimate, CorrelatedRampReadsTheShareOrTheAmplitudeFarBeyondTheFinestBand) {
  NoiseEstimate e;
  e.noisy = true;
  e.amplitude = 0.1625;
  e.correlated_share = 0.28; // a red spectrum the fit gave to white noise (cylinder red_0.6)
  e.level = 0.1625 / 2.0;    // 2: white noise with impulses reads up to about this
  EXPECT_EQ(correlatedNoiseRamp(e), 0.0);
  e.level = 0.1625 / 2.8; // halfway up the ratio's ramp
  EXPECT_NEAR(correlatedNoiseRamp(e), 0.5, 1e-12);
  e.level = 0.0462; // the cylinder's: 3.5
  EXPECT_EQ(correlatedNoiseRamp(e), 1.0);
  e.amplitude = 0.125; // halfway up the amplitude's ramp
  e.level = 0.125 / 3.5;
  EXPECT_NEAR(correlatedNoiseRamp(e), 0.5, 1e-12);
  CorrelatedNoiseParams share_only;
  share_only.ratio_from = share_only.ratio_full = 0;
  EXPECT_EQ(correlatedNoiseRamp(e, share_only), 0.0);
  e.correlated_share = 0.55; // the share alone is full
  EXPECT_NEAR(correlatedNoiseRamp(e, share_only), 0.5, 1e-12);
}

TEST(NoiseEstimate, HeavyNoiseFactorIsOneUpToItsAmplitudeThenAPowerOfItCapped) {
  NoiseEstimate e;
  EXPECT_EQ(heavyNoiseFactor(e), 1.0); // not read
  e.amplitude = 0.3;
  EXPECT_EQ(heavyNoiseFactor(e), 1.0); // the public benchmark's levels
  e.amplitude = 0.49;
  EXPECT_NEAR(heavyNoiseFactor(e), std::pow(0.49 / 0.35, 3.0), 1e-12);
  e.amplitude = 1.0;
  EXPECT_EQ(heavyNoiseFactor(e), 4.0); // capped
  HeavyNoiseParams off;
  off.power = 0;
  EXPECT_EQ(heavyNoiseFactor(e, off), 1.0);
  e.amplitude = NAN;
  EXPECT_EQ(heavyNoiseFactor(e), 1.0);
}

// Correlated noise (its amplitude's correlated share past CorrelatedNoiseParams::share_from) asks
// the feature mode for up to 1 + extra times the filter iterations; white noise and meshes that
// read clean ask for nothing more.
TEST(NoiseEstimate, CorrelatedNoiseFactorRampsWithTheCorrelatedShare) {
  NoiseEstimate e;
  e.amplitude = 0.2;
  e.correlated_share = 0.7;
  EXPECT_EQ(correlatedNoiseFactor(e), 1.0); // reads clean
  e.noisy = true;
  EXPECT_NEAR(correlatedNoiseFactor(e), 1.5, 1e-12); // past share_full
  e.correlated_share = 0.425;                         // half way from 0.3 to 0.55
  EXPECT_NEAR(correlatedNoiseFactor(e), 1.25, 1e-12);
  e.correlated_share = 0.22; // white noise on the public Fandisk reads 0.22
  EXPECT_EQ(correlatedNoiseFactor(e), 1.0);
  e.correlated_share = 0.7;
  e.amplitude = 0.125; // half way into the amplitude's ramp (0.1 to 0.15)
  EXPECT_NEAR(correlatedNoiseFactor(e), 1.25, 1e-12);
  e.amplitude = 0.09; // light noise: the measured passes remove it
  EXPECT_EQ(correlatedNoiseFactor(e), 1.0);
  e.amplitude = 0; // not read (a mesh under 4096 vertices)
  EXPECT_EQ(correlatedNoiseFactor(e), 1.0);
  e.amplitude = 0.2;
  CorrelatedNoiseParams off;
  off.extra = 0;
  EXPECT_EQ(correlatedNoiseFactor(e, off), 1.0);
  e.correlated_share = NAN;
  EXPECT_EQ(correlatedNoiseFactor(e), 1.0);
}

// The correlated range's ramp alone (the planar extra reads it too): the factor's ramp, whatever
// the factor's extra.
TEST(NoiseEstimate, CorrelatedNoiseRampIsTheFactorsRampWhateverItsExtra) {
  NoiseEstimate e;
  e.noisy = true;
  e.amplitude = 0.2;
  e.correlated_share = 0.7;
  CorrelatedNoiseParams off;
  off.extra = 0;
  EXPECT_EQ(correlatedNoiseRamp(e), 1.0);
  EXPECT_EQ(correlatedNoiseRamp(e, off), 1.0);
  e.correlated_share = 0.425;
  EXPECT_NEAR(correlatedNoiseRamp(e), 0.5, 1e-12);
  e.amplitude = 0.125;
  EXPECT_NEAR(correlatedNoiseRamp(e), 0.25, 1e-12);
  e.noisy = false;
  EXPECT_EQ(correlatedNoiseRamp(e), 0.0);
}

TEST(NoiseEstimate, RampBetweenIsLinearClampedAndAStepWhenItsEndsMeet) {
  EXPECT_EQ(rampBetween(0.2, 0.3, 0.55), 0.0);
  EXPECT_NEAR(rampBetween(0.4, 0.3, 0.55), 0.4, 1e-12);
  EXPECT_EQ(rampBetween(0.9, 0.3, 0.55), 1.0);
  EXPECT_EQ(rampBetween(0.29, 0.3, 0.3), 0.0);
  EXPECT_EQ(rampBetween(0.3, 0.3, 0.3), 1.0);
}
