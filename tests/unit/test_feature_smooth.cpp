// The feature-preserving mode's driver (vcg_ext/methods/feature/feature_smooth.h): sharp edges survive normal noise,
// clean meshes stay put, volume and open boundaries are kept, and the result does not depend on
// thread count or vertex order.
#include <gtest/gtest.h>
#include <omp.h>
#include <algorithm>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/feature/feature_smooth.h>
#include <vcg_ext/methods/paper/paper_smooth.h>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::meanEdge;
using test_meshes::deviation;

namespace {

std::vector<Vec3> featureSmoothed(const MeshArrays &mesh,
                                  const FeatureSmoothParams &params = FeatureSmoothParams(),
                                  FeatureSmoothReport *report_out = nullptr) {
  std::vector<Vec3> out;
  VertexQuantities q;
  const FeatureSmoothReport r = featureSmoothMesh(mesh, params, out, q);
  if (report_out) *report_out = r;
  return out;
}

// A box of 8 × 8 squares per side with Gaussian noise of 0.3 mean edge lengths along each
// vertex's area-weighted normal (the literature's noise), for the stages' tests.
MeshArrays noisySmallBox() {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 8);
  return test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 3);
}
} // namespace

TEST(FeatureSmooth, NoisyBoxKeepsItsEdgesBetterThanTheRingBarycentreMode) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 16);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 3);
  FeatureSmoothReport report;
  const std::vector<Vec3> out = featureSmoothed(noisy, FeatureSmoothParams(), &report);
  std::vector<Vec3> ring_barycentre;
  VertexQuantities q;
  smoothMesh(noisy, SmoothParams(), ring_barycentre, q);

  const NormalDeviation before = deviation(noisy.points, clean);
  const NormalDeviation after = deviation(out, clean);
  const NormalDeviation other = deviation(ring_barycentre, clean);
  ASSERT_GT(before.sharp_faces, 100); // the box's 12 edges
  EXPECT_EQ(report.roughness, 1.0);    // 0.3 mean edge lengths of noise: full smoothing
  EXPECT_GT(before.theta_sharp_deg, 15.0);
  EXPECT_LT(after.theta_sharp_deg, 0.25 * before.theta_sharp_deg);
  EXPECT_LT(after.theta_sharp_deg, 0.5 * other.theta_sharp_deg);
  EXPECT_LT(after.theta_deg, 0.2 * before.theta_deg);
  EXPECT_EQ(after.flipped_faces, 0);
  EXPECT_TRUE(report.closed);
  EXPECT_NEAR(report.volume_after / signedVolume(clean.points, clean.faces), 1.0, 0.005);
  RecordProperty("theta_sharp_noisy", std::to_string(before.theta_sharp_deg));
  RecordProperty("theta_sharp_feature", std::to_string(after.theta_sharp_deg));
  RecordProperty("theta_sharp_ring_barycentre", std::to_string(other.theta_sharp_deg));
}

TEST(FeatureSmooth, CleanBoxAndSphereStayAlmostUntouched) {
  for (const MeshArrays &clean :
       {test_meshes::box(1.0, 0.8, 0.6, 16), test_meshes::icosphere(1.0, 4)}) {
    FeatureSmoothReport report;
    const std::vector<Vec3> out = featureSmoothed(clean, FeatureSmoothParams(), &report);
    EXPECT_LT(report.dihedral_spread_deg, 32.0); // measures clean: no smoothing passes
    EXPECT_EQ(report.roughness, 0.0);
    EXPECT_EQ(report.prepass_pairs, 0);
    EXPECT_LT(deviation(out, clean).theta_deg, 1.0);
    EXPECT_NEAR(report.volume_after / report.volume_before, 1.0, 0.005);
    // Nearly every vertex stays within a tenth of an edge (the box's corners round a little).
    std::vector<double> moves;
    for (size_t i = 0; i < out.size(); ++i) moves.push_back((out[i] - clean.points[i]).norm());
    std::sort(moves.begin(), moves.end());
    EXPECT_LT(moves[moves.size() * 95 / 100], 0.1 * meanEdge(clean));
    EXPECT_LT(moves.back(), 0.6 * meanEdge(clean));
  }
}

TEST(FeatureSmooth, NoisySphereKeepsItsVolumeAndGetsSmooth) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 4);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 5);
  FeatureSmoothReport report;
  const std::vector<Vec3> out = featureSmoothed(noisy, FeatureSmoothParams(), &report);
  EXPECT_LT(deviation(out, clean).theta_deg, 0.3 * deviation(noisy.points, clean).theta_deg);
  EXPECT_NEAR(report.volume_after / signedVolume(clean.points, clean.faces), 1.0, 0.005);
  EXPECT_NEAR(report.volume_after, signedVolume(out, clean.faces), 1e-12);
}

TEST(FeatureSmooth, RandomDirectionNoiseGetsUnfolded) {
  // Noise with a tangential part folds faces. Without the pre-pass (which unfolds most of them on
  // its own), the tangential relaxation around folded faces is what unfolds them: moves along the
  // filtered normals alone cannot.
  const MeshArrays clean = test_meshes::icosphere(1.0, 4);
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, 0.25 * meanEdge(clean), 8);
  FeatureSmoothParams relaxing;
  relaxing.prepass_pairs = 0;
  FeatureSmoothParams not_relaxing = relaxing;
  not_relaxing.tangential = 0;
  const NormalDeviation before = deviation(noisy.points, clean);
  const NormalDeviation relaxed = deviation(featureSmoothed(noisy, relaxing), clean);
  const NormalDeviation unrelaxed = deviation(featureSmoothed(noisy, not_relaxing), clean);
  RecordProperty("flipped_noisy", before.flipped_faces);
  RecordProperty("flipped_relaxed", relaxed.flipped_faces);
  RecordProperty("flipped_unrelaxed", unrelaxed.flipped_faces);
  ASSERT_GT(before.flipped_faces, 50);
  EXPECT_LT(relaxed.flipped_faces, 0.25 * unrelaxed.flipped_faces);
  EXPECT_LT(relaxed.theta_deg, unrelaxed.theta_deg);
  // With the default pre-pass: smooth and unfolded.
  const NormalDeviation with_prepass = deviation(featureSmoothed(noisy), clean);
  EXPECT_LE(with_prepass.flipped_faces, 2);
  EXPECT_LT(with_prepass.theta_deg, 0.25 * before.theta_deg);
}

TEST(FeatureSmooth, OpenBoundaryStaysInPlace) {
  // A noisy plane: boundary vertices move along the boundary and the normal, not inward.
  const MeshArrays clean =
      test_meshes::heightField(30, -1, 1, -1, 1, [](double, double) { return 0.0; });
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 9);
  FeatureSmoothReport report;
  const std::vector<Vec3> out = featureSmoothed(noisy, FeatureSmoothParams(), &report);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.boundary_vertices, 4 * 29);
  const Rings rings = computeRings(int(clean.points.size()), clean.faces);
  const double edge = meanEdge(clean);
  double inward_sum = 0, worst_across = 0;
  int sides = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    const Vec3 &p = clean.points[i];
    const bool on_x = std::abs(std::abs(p.x()) - 1) < 1e-9, on_y = std::abs(std::abs(p.y()) - 1) < 1e-9;
    if (!rings.boundary[i] || on_x == on_y) continue; // interior or a corner
    // Across a straight side is the inward direction: the signed move toward the interior.
    const double inward = on_x ? -(out[i].x() - p.x()) * p.x() : -(out[i].y() - p.y()) * p.y();
    inward_sum += inward;
    worst_across = std::max(worst_across, std::abs(inward));
    ++sides;
  }
  EXPECT_EQ(sides, 4 * 28);
  EXPECT_LT(std::abs(inward_sum / sides), 0.05 * edge); // no shrinkage to speak of
  EXPECT_LT(worst_across, 0.25 * edge);
  EXPECT_LT(deviation(out, clean).theta_deg, 0.3 * deviation(noisy.points, clean).theta_deg);
}

TEST(FeatureSmooth, SameResultForOneAndTwoThreadsAndPermutedVertices) {
  const MeshArrays box = test_meshes::box(1.0, 0.8, 0.6, 10);
  const MeshArrays noisy = test_meshes::withNormalNoise(box, 0.3 * meanEdge(box), 4);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<Vec3> one = featureSmoothed(noisy);
  omp_set_num_threads(2);
  const std::vector<Vec3> two = featureSmoothed(noisy);
  omp_set_num_threads(threads);
  ASSERT_EQ(one.size(), two.size());
  for (size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]) << i;

  // Renumbered vertices, reordered faces: the same bits (the driver runs in spatial order).
  const std::vector<int> perm = test_meshes::shuffledPermutation(int(noisy.points.size()), 12);
  const std::vector<Vec3> shuffled =
      featureSmoothed(test_meshes::facesReordered(test_meshes::permuted(noisy, perm), 5));
  ASSERT_EQ(shuffled.size(), one.size());
  for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(shuffled[perm[i]], one[i]) << i;
}

TEST(FeatureSmooth, FrozenVerticesAndInputStayAndCancelStops) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 3);
  MeshArrays noisy = test_meshes::withNormalNoise(sphere, 0.3 * meanEdge(sphere), 6);
  noisy.points.push_back(Vec3(5, 5, 5)); // isolated: referenced by no face
  const MeshArrays copy = noisy;
  FeatureSmoothReport report;
  const std::vector<Vec3> out = featureSmoothed(noisy, FeatureSmoothParams(), &report);
  EXPECT_EQ(report.frozen_vertices, 1);
  EXPECT_EQ(out.back(), Vec3(5, 5, 5));
  EXPECT_EQ(noisy.points, copy.points);
  EXPECT_EQ(report.outer_iterations_done, FeatureSmoothParams().outer_iterations);

  int calls = 0;
  std::vector<Vec3> cancelled;
  VertexQuantities q;
  const FeatureSmoothReport stopped = featureSmoothMesh(
      noisy, FeatureSmoothParams(), cancelled, q, [&](int, const char *) { return ++calls < 3; });
  EXPECT_TRUE(stopped.cancelled);
  EXPECT_EQ(calls, 3);
}

TEST(FeatureSmooth, SelectedOnlyMovesOnlySelectedVertices) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 3);
  MeshArrays noisy = test_meshes::withNormalNoise(sphere, 0.3 * meanEdge(sphere), 7);
  for (size_t i = 0; i < noisy.points.size(); ++i) noisy.selected[i] = noisy.points[i].z() > 0;
  FeatureSmoothParams params;
  params.selected_only = true;
  const std::vector<Vec3> out = featureSmoothed(noisy, params);
  long moved = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!noisy.selected[i]) EXPECT_EQ(out[i], noisy.points[i]);
    else moved += out[i] != noisy.points[i];
  }
  EXPECT_GT(moved, long(out.size() / 3));
}

TEST(FeatureSmooth, NoiseEstimateScalesTheSmoothing) {
  // The passes scale with the measured noise: the clean box is left as it is (its spread does not
  // decay under a Taubin pair), faint noise (0.05 mean edge lengths) gets part of the passes and is
  // smoothed, strong noise all of them.
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 16);
  const double edge = meanEdge(clean);
  FeatureSmoothReport none, faint, strong;
  EXPECT_EQ(featureSmoothed(clean, FeatureSmoothParams(), &none), clean.points);
  EXPECT_EQ(none.roughness, 0.0);
  EXPECT_FALSE(none.noise.noisy);
  const MeshArrays faint_noise = test_meshes::withNormalNoise(clean, 0.05 * edge, 21);
  const std::vector<Vec3> out = featureSmoothed(faint_noise, FeatureSmoothParams(), &faint);
  EXPECT_TRUE(faint.noise.noisy);
  EXPECT_GT(faint.roughness, 0.1);
  EXPECT_LT(faint.roughness, 0.95);
  EXPECT_GT(faint.normal_iterations, 0);
  // Part of the passes: the roughness's share of them, then the planar extra of a box (its flat
  // share after the first guidance period, feature_smooth.h's planar_extra).
  const FeatureSmoothParams p;
  const double shift = p.planar_correlated_shift * correlatedNoiseRamp(faint.noise);
  const double planar = p.planar_extra * std::clamp((faint.flat_share - p.planar_share_from + shift) /
                                                        (p.planar_share_full - p.planar_share_from),
                                                    0.0, 1.0);
  EXPECT_EQ(faint.normal_iterations,
            std::lround(std::lround(faint.amount * p.normals.iterations) * (1 + planar)));
  EXPECT_LT(std::lround(faint.amount * p.normals.iterations), p.normals.iterations);
  EXPECT_LT(deviation(out, clean).theta_deg, 0.5 * deviation(faint_noise.points, clean).theta_deg);
  featureSmoothed(test_meshes::withNormalNoise(clean, 0.3 * edge, 23), FeatureSmoothParams(), &strong);
  EXPECT_EQ(strong.roughness, 1.0);
  EXPECT_LT(faint.dihedral_spread_deg, strong.dihedral_spread_deg);
}

// A coarse closed mesh loses volume to the Taubin pre-pass and the patch updates (1.2 % on this
// 162-vertex sphere); with `preserve_volume` the final offsets along the normals restore it.
TEST(FeatureSmooth, PreserveVolumeRestoresTheInputVolumeOfACoarseMesh) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 2);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 11);
  FeatureSmoothParams keep, lose;
  lose.preserve_volume = false;
  FeatureSmoothReport kept, lost;
  const std::vector<Vec3> out = featureSmoothed(noisy, keep, &kept);
  featureSmoothed(noisy, lose, &lost);
  ASSERT_GT(kept.roughness, 0.5);  // the noise is seen, so the mesh is smoothed
  const double lost_ratio = lost.volume_after / lost.volume_before;
  const double kept_ratio = kept.volume_after / kept.volume_before;
  EXPECT_GT(std::abs(lost_ratio - 1.0), 5e-3);  // measured 0.9878
  EXPECT_LT(std::abs(kept_ratio - 1.0), 2e-4);   // measured 0.99997
  EXPECT_NEAR(kept.volume_after, signedVolume(out, noisy.faces), 1e-12);
}

// A set-up without face rings (a large mesh's: its noise estimate ran on windows) gets them built
// by the feature mode: the same result, bit for bit, as from a set-up that had its edge neighbours.
TEST(FeatureSmooth, BuildsTheFaceRingsWhenTheSetUpHasNone) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 12);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 4);
  detail::DriverSetup with = detail::driverSetup(noisy, false);
  ASSERT_FALSE(with.face_rings.edge_neighbours.empty());
  detail::DriverSetup without = with;
  without.face_rings = FaceRings();
  std::vector<Vec3> a, b;
  VertexQuantities qa, qb;
  const FeatureSmoothReport ra =
      detail::featureSmoothAsGiven(noisy, FeatureSmoothParams(), a, qa, nullptr, nullptr, &with);
  const FeatureSmoothReport rb = detail::featureSmoothAsGiven(noisy, FeatureSmoothParams(), b, qb,
                                                              nullptr, nullptr, &without);
  ASSERT_EQ(a.size(), noisy.points.size());
  EXPECT_EQ(a, b);
  EXPECT_EQ(qa.saliency, qb.saliency);
  EXPECT_EQ(ra.vertices_moved, rb.vertices_moved);
  EXPECT_GT(ra.vertices_moved, long(noisy.points.size()) / 2);
}

// The planar extra (FeatureSmoothParams::planar_extra): none up to planar_share_from, linear to
// twice the counts at planar_share_full (the defaults 0.3 / 0.45, extra 1), rounded; fully
// correlated noise (correlatedNoiseRamp 1) lowers both by 0.15, half correlated by 0.075.
TEST(FeatureSmoothStages, PlanarExtraScalesTheCountsByTheFlatShare) {
  const FeatureSmoothParams params;
  auto counts = [&](double flat_share, double correlated_ramp = 0.0) {
    int normal = 10, vertex = 6;
    detail::addPlanarExtra(flat_share, correlated_ramp, params, normal, vertex);
    return std::make_pair(normal, vertex);
  };
  EXPECT_EQ(counts(0.15, 1.0), std::make_pair(10, 6));
  EXPECT_EQ(counts(0.225, 1.0), std::make_pair(15, 9));
  EXPECT_EQ(counts(0.3, 1.0), std::make_pair(20, 12));
  EXPECT_EQ(counts(0.3, 0.5), std::make_pair(15, 9)); // ramp 0.225 .. 0.375
  EXPECT_EQ(counts(0.1), std::make_pair(10, 6));
  EXPECT_EQ(counts(0.3), std::make_pair(10, 6));
  EXPECT_EQ(counts(0.375), std::make_pair(15, 9)); // half way: 1.5 times
  EXPECT_EQ(counts(0.45), std::make_pair(20, 12));
  EXPECT_EQ(counts(0.9), std::make_pair(20, 12));
  FeatureSmoothParams off = params;
  off.planar_extra = 0;
  int normal = 10, vertex = 6;
  detail::addPlanarExtra(0.9, 1.0, off, normal, vertex);
  EXPECT_EQ(normal, 10);
  EXPECT_EQ(vertex, 6);
}

// A fold marks the vertices of the folded face and, per relax ring, one ring more; an unfolded
// mesh marks none (its triangulation is kept).
TEST(FeatureSmoothStages, FoldMarksGrowByOneRingPerRelaxRing) {
  const MeshArrays plane = test_meshes::heightField(9, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const Rings rings = computeRings(int(plane.points.size()), plane.faces);
  std::vector<Vec3> filtered;
  computeFaceNormals(plane.points, plane.faces, filtered);
  std::vector<std::uint8_t> folded, relax(plane.points.size()), scratch(plane.points.size());
  auto marked = [&](const std::vector<Vec3> &normals, int relax_rings) {
    detail::markVerticesNearFolds(plane.points, plane.faces, normals, rings, 0.5, relax_rings,
                                  folded, relax, scratch);
    return std::count(relax.begin(), relax.end(), 1);
  };
  EXPECT_EQ(marked(filtered, 0), 0);
  EXPECT_EQ(marked(filtered, 2), 0);
  // One face whose filtered normal points the other way: that face is folded.
  const int centre_face = int(plane.faces.size()) / 2;
  std::vector<Vec3> flipped = filtered;
  flipped[centre_face] = -flipped[centre_face];
  EXPECT_EQ(marked(flipped, 0), 3);
  EXPECT_EQ(std::count(folded.begin(), folded.end(), 1), 1);
  // Each ring adds the 1-ring of what is marked: strictly more, and a superset.
  const std::vector<std::uint8_t> ring0 = relax;
  const long one = marked(flipped, 1);
  const std::vector<std::uint8_t> ring1 = relax;
  const long two = marked(flipped, 2);
  EXPECT_GT(one, 3);
  EXPECT_GT(two, one);
  for (size_t v = 0; v < ring0.size(); ++v) {
    EXPECT_LE(ring0[v], ring1[v]);
    EXPECT_LE(ring1[v], relax[v]);
  }
  // One ring around a triangle in the interior of this grid: its 3 vertices and their neighbours.
  std::vector<std::uint8_t> expected(plane.points.size(), 0);
  for (int c = 0; c < 3; ++c) {
    const int v = plane.faces[centre_face][c];
    expected[v] = 1;
    for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) expected[*w] = 1;
  }
  EXPECT_EQ(ring1, expected);
}

// The vertex sweep onto the filtered planes leaves a flat mesh where it is when the filtered
// normals are its own, moves a lifted vertex back to the plane, and counts non-finite moves.
TEST(FeatureSmoothStages, VertexSweepMovesOntoTheFilteredPlanes) {
  MeshArrays plane = test_meshes::heightField(9, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const detail::DriverSetup setup = detail::driverSetup(plane, false);
  std::vector<Vec3> filtered, centroid, next(plane.points.size());
  computeFaceNormals(plane.points, plane.faces, filtered);
  const int lifted = 40; // an interior vertex of the 9×9 grid
  ASSERT_FALSE(setup.rings.boundary[lifted]);
  std::vector<Vec3> current = plane.points;
  current[lifted].z() = 0.05;
  computeFaceCentroids(current, plane.faces, centroid);
  FeatureSmoothParams params;
  params.tangential = 0;
  const std::vector<detail::SymmetricMatrix3> no_projectors;
  const std::vector<std::uint8_t> no_relax(plane.points.size(), 0);
  std::vector<Vec3> vertex_normals; // the boundary's moves read them
  computeBoundaryVertexNormals(current, plane.faces, setup.rings, vertex_normals);
  const detail::FeatureMoveInputs inputs{filtered, nullptr, centroid, no_projectors, no_relax,
                                         vertex_normals};
  const double edge = setup.stats.mean_edge_length;
  EXPECT_EQ(detail::featureVertexSweep(current, setup, params, edge, inputs, next), 0);
  // The lifted vertex moves onto the mean of its faces' planes: horizontal, through centroids
  // lifted by a third of its height.
  EXPECT_NEAR(next[lifted].z(), 0.05 / 3, 1e-12);
  EXPECT_NEAR(next[lifted].x(), current[lifted].x(), 1e-12);
  // Vertices away from it stay exactly (their planes pass through them).
  const int far = 10;
  EXPECT_EQ(next[far], current[far]);
  // A non-finite position is not moved and is counted.
  current[far] = Vec3(std::nan(""), 0, 0);
  EXPECT_EQ(detail::featureVertexSweep(current, setup, params, edge, inputs, next), 1);
}

// The "Alpha" attribute: per vertex the mean of its faces' patch α (the paper's rule), or the
// override's α at every vertex with faces, filled in after the saliency.
TEST(DriverStages, VertexAlphaIsTheMeanOfItsFacesOrTheOverride) {
  // Two triangles sharing the edge 1-2, and vertex 4 without faces.
  const MeshArrays m = test_meshes::fromArrays(
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(5, 5, 5)},
      {Face{0, 1, 2}, Face{1, 3, 2}});
  const Rings rings = computeRings(5, m.faces);
  const std::vector<double> by_faces = detail::vertexAlphaOfPatches(rings, {0.2, 0.6});
  EXPECT_EQ(by_faces, (std::vector<double>{0.2, 0.4, 0.4, 0.6, 1.0}));
  std::vector<Vec3> result = m.points;
  VertexQuantities q;
  detail::PatchAlpha override;
  override.record(rings, {}, 0.35); // the user's α: one value
  detail::describeResult(m.points, result, m.faces, rings, 0.1, q, std::move(override));
  EXPECT_EQ(q.alpha, (std::vector<double>{0.35, 0.35, 0.35, 0.35, 1.0}));
  detail::PatchAlpha rule;
  rule.record(rings, {0.2, 0.6}, 0.9); // the paper's rule: per face
  detail::describeResult(m.points, result, m.faces, rings, 0.1, q, std::move(rule));
  EXPECT_EQ(q.alpha, by_faces);
  detail::describeResult(m.points, result, m.faces, rings, 0.1, q); // no patch update ran
  EXPECT_EQ(q.alpha, std::vector<double>(5, 1.0));
}

// What the feature mode stores as Alpha is the α its patch fits used: the default's 1, the user's
// override, or the paper's saliency rule (below 1 where saliency varies within a fit's data).
TEST(FeatureSmooth, AlphaAttributeShowsTheAlphaThePatchFitsUsed) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 16);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 3);
  auto run = [&](bool alpha_override, double alpha, std::vector<Vec3> &out) {
    FeatureSmoothParams params;
    params.alpha_override = alpha_override;
    params.patches.alpha = alpha;
    VertexQuantities q;
    featureSmoothMesh(noisy, params, out, q);
    return q.alpha;
  };
  std::vector<Vec3> plain, half, paper;
  const std::vector<double> alpha_plain = run(true, 1.0, plain);
  const std::vector<double> alpha_half = run(true, 0.5, half);
  const std::vector<double> alpha_paper = run(false, 1.0, paper);
  ASSERT_EQ(alpha_plain.size(), noisy.points.size());
  EXPECT_EQ(alpha_plain, std::vector<double>(noisy.points.size(), 1.0));
  EXPECT_EQ(alpha_half, std::vector<double>(noisy.points.size(), 0.5));
  EXPECT_NE(half, plain); // (α means something in this mode)
  const auto [lo, hi] = std::minmax_element(alpha_paper.begin(), alpha_paper.end());
  double mean = 0;
  for (double a : alpha_paper) mean += a / double(alpha_paper.size());
  RecordProperty("alpha_paper_min", std::to_string(*lo));
  RecordProperty("alpha_paper_mean", std::to_string(mean));
  EXPECT_GT(*lo, 0.0);
  EXPECT_LE(*hi, 1.0);
  // Measured: mean 0.062, min 4e-5 (saliency varies a lot within a fit's data on a noisy box).
  EXPECT_LT(mean, 0.2);
  EXPECT_NE(paper, plain);
}

TEST(FeatureSmoothStages, FilterPassStopsAtTheCheckpointOnlyWhenTheCheckDeclines) {
  const MeshArrays noisy = noisySmallBox();
  detail::DriverSetup setup = detail::driverSetup(noisy, false);
  detail::ensureFaceRings(noisy, setup); // (as the driver does)
  FeatureSmoothParams params;
  params.planar_extra = 0; // the counts stay as measured
  const FeaturePassCounts counts = detail::featurePassCounts(noisy, params, setup);
  ASSERT_GT(counts.normal_iterations, counts.checkIterations(params));
  int calls = 0;
  auto run = [&](bool check, bool accept) {
    NormalFilterParams normal_filter = params.normals;
    normal_filter.iterations = counts.normal_iterations;
    int vertex_iterations = counts.vertex_iterations;
    detail::FeaturePassBuffers b(int(noisy.points.size()));
    FeatureSmoothReport report;
    const FilteredNormalsCheck first_pass_check =
        [&](const std::vector<Vec3> &normals, const std::vector<Vec3> &, int,
            const detail::DriverSetup &) {
          ++calls;
          EXPECT_EQ(normals.size(), noisy.faces.size());
          return accept;
        };
    const bool went_on = detail::filterPassNormals(check, noisy, setup, params, counts,
                                                   first_pass_check, noisy.points, normal_filter,
                                                   vertex_iterations, b, report);
    return std::make_pair(went_on, b.filtered);
  };
  const auto [declined, declined_normals] = run(true, false);
  EXPECT_FALSE(declined);
  EXPECT_EQ(calls, 1);
  const auto [accepted, filtered] = run(true, true);
  const auto [unchecked, unchecked_normals] = run(false, false); // a later pass: no check
  EXPECT_TRUE(accepted);
  EXPECT_TRUE(unchecked);
  EXPECT_EQ(calls, 2);
  // The checkpoint does not change the filtered normals.
  EXPECT_EQ(filtered, unchecked_normals);
  ASSERT_EQ(filtered.size(), noisy.faces.size());
  for (const Vec3 &n : filtered) EXPECT_NEAR(n.norm(), 1.0, 1e-6);
}

TEST(FeatureSmoothStages, VertexUpdateOntoPlanesOrPatchesAndThePatchesAlpha) {
  const MeshArrays noisy = noisySmallBox();
  detail::DriverSetup setup = detail::driverSetup(noisy, false);
  detail::ensureFaceRings(noisy, setup); // (as the driver does)
  FeatureSmoothParams params;
  params.patches.alpha = 0.8;
  const int n = int(noisy.points.size());
  for (bool use_patches : {false, true}) {
    detail::FeaturePassBuffers b(n);
    computeFaceNormals(noisy.points, noisy.faces, b.filtered);
    b.next.resize(n);
    detail::featureTangentProjectors(setup.rings, setup.fixed, b.filtered, b.tangent_projector);
    std::vector<Vec3> current = noisy.points;
    FeatureSmoothReport report;
    detail::featureVertexUpdate(use_patches, noisy, setup, params, current, b, report);
    EXPECT_NE(current, noisy.points);
    EXPECT_EQ(b.next, noisy.points); // the positions before, swapped out
    EXPECT_TRUE(b.alpha.per_vertex.empty()); // the override: one value
    EXPECT_EQ(b.alpha.uniform, use_patches ? 0.8 : 1.0);
    EXPECT_EQ(b.centroid.size(), use_patches ? 0u : noisy.faces.size());
    EXPECT_EQ(b.patches.size(), use_patches ? noisy.faces.size() : 0u);
  }
}

// A driver's MethodRun: its name, row, roughness and movement in mean edge lengths; a cancelled
// run says only that.
TEST(DriverStages, MeasuredRunTakesTheReportsRoughnessAndMovement) {
  struct Report {
    bool cancelled = false;
    double roughness = 0.75, mean_edge_length = 0.5;
  } report;
  VertexQuantities q;
  q.displacement = {0.0, 0.5, 1.5};
  const MethodRun run = detail::measuredRun(report, "organic", 4, q);
  EXPECT_FALSE(run.cancelled);
  EXPECT_EQ(run.method, "organic");
  EXPECT_EQ(run.method_index, 4);
  EXPECT_EQ(run.roughness, 0.75);
  EXPECT_EQ(run.vertices_moved, 2);
  EXPECT_DOUBLE_EQ(run.mean_displacement_edges, (2.0 / 3.0) / 0.5);
  report.cancelled = true;
  const MethodRun cancelled = detail::measuredRun(report, "organic", 4, q);
  EXPECT_TRUE(cancelled.cancelled);
  EXPECT_EQ(cancelled.method, "");
  EXPECT_EQ(cancelled.vertices_moved, 0);
}

// The logs' stage times: seconds of a steady clock since the start given.
TEST(DriverStages, SecondsSinceCountsFromTheStart) {
  const double two = secondsSince(Clock::now() - std::chrono::milliseconds(2000));
  EXPECT_GE(two, 2.0);
  EXPECT_LT(two, 60.0);
  EXPECT_LT(secondsSince(Clock::now()), 1.0);
}

// A driver's progress: pass p at fraction f reports span·(p + f) / passes percent, at most 99,
// and passes the user's cancel back; none given, none asked.
TEST(DriverStages, PassProgressSpreadsThePassesOverItsSpan) {
  std::vector<int> seen;
  const ProgressFn progress = [&](int percent, const char *) {
    seen.push_back(percent);
    return percent < 80;
  };
  const detail::PassProgress two{progress, 2, 90.0};
  EXPECT_TRUE(two(0, 0.5, ""));
  EXPECT_TRUE(two(1, 0.5, ""));
  EXPECT_FALSE(two(1, 1.0, ""));
  const detail::PassProgress none{progress, 0, 100.0}; // no passes: counted as one
  EXPECT_TRUE(none(0, 0.5, ""));
  EXPECT_FALSE(none(3, 0.0, ""));
  EXPECT_EQ(seen, (std::vector<int>{22, 67, 90, 50, 99}));
  const ProgressFn nothing;
  EXPECT_TRUE((detail::PassProgress{nothing, 2, 90.0})(1, 1.0, ""));
}

// One outer pass: the automatic choice's check may decline it (nothing moves), the user may
// cancel it, else the vertices move and the pass counts as done; the counts go to the report.
TEST(FeatureSmoothStages, OnePassMovesTheVerticesUnlessDeclinedOrCancelled) {
  const MeshArrays noisy = noisySmallBox();
  FeatureSmoothParams params;
  params.planar_extra = 0; // the counts stay as measured
  auto pass = [&](bool accept, bool go_on, std::vector<Vec3> &current, FeatureSmoothReport &report) {
    detail::DriverSetup setup = detail::driverSetup(noisy, false);
    detail::ensureFaceRings(noisy, setup);
    const FeaturePassCounts counts = detail::featurePassCounts(noisy, params, setup);
    detail::reportPassCounts(counts, setup, report);
    EXPECT_EQ(report.normal_iterations, counts.normal_iterations);
    EXPECT_EQ(report.vertex_iterations, counts.vertex_iterations);
    EXPECT_EQ(report.roughness, counts.roughness);
    NormalFilterParams normal_filter = params.normals;
    normal_filter.iterations = counts.normal_iterations;
    int vertex_iterations = counts.vertex_iterations;
    detail::FeaturePassBuffers b(int(noisy.points.size()));
    const FilteredNormalsCheck check = [&](const std::vector<Vec3> &, const std::vector<Vec3> &,
                                           int, const detail::DriverSetup &) { return accept; };
    const ProgressFn progress = [&](int, const char *) { return go_on; };
    current = noisy.points;
    return detail::featurePass(0, noisy, setup, params, counts, check,
                               detail::PassProgress{progress, 2, 90.0}, normal_filter,
                               vertex_iterations, current, b, report);
  };
  std::vector<Vec3> current;
  FeatureSmoothReport declined, cancelled, done;
  EXPECT_EQ(pass(false, true, current, declined), detail::PassEnd::Declined);
  EXPECT_EQ(current, noisy.points);
  EXPECT_EQ(pass(true, false, current, cancelled), detail::PassEnd::Cancelled);
  EXPECT_EQ(cancelled.outer_iterations_done, 0);
  EXPECT_EQ(pass(true, true, current, done), detail::PassEnd::Done);
  EXPECT_EQ(done.outer_iterations_done, 1);
  EXPECT_GT(done.normal_iterations, 0);
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 8); // (noisySmallBox's)
  EXPECT_GT(deviation(noisy.points, clean).theta_deg, 2 * deviation(current, clean).theta_deg);
}

// Noise whose finest band reads little but whose amplitude is a tenth of an edge or more (a redder
// spectrum) gets the full need: the need reads the amplitude (amplitudeNeed).
TEST(FeatureSmoothStages, TheNeedReadsTheAmplitudeBesideTheFinestBand) {
  const MeshArrays noisy = noisySmallBox();
  detail::DriverSetup setup = detail::driverSetup(noisy, false);
  FeatureSmoothParams params;
  setup.input_spread_deg = 10; // below clean_spread_deg: the spread asks for nothing
  setup.noise.noisy = true;
  setup.noise.level = 0.04;
  setup.noise.spectrum.assign(4, 0.04);
  setup.noise.amplitude = 0.15;
  EXPECT_NEAR(detail::featurePassCounts(noisy, params, setup).roughness, 1.0, 1e-12);
  params.heavy.need_weight = 0; // the finest band alone
  EXPECT_NEAR(detail::featurePassCounts(noisy, params, setup).roughness, 0.4, 1e-12);
}

// Correlated noise multiplies the normal filter iterations and vertex updates, not the pre-pass
// (whose positions the automatic choice reads) nor the check's iterations.
TEST(FeatureSmoothStages, CorrelatedNoiseTakesMoreFilterIterationsNotALongerPrepass) {
  const MeshArrays noisy = noisySmallBox();
  detail::DriverSetup setup = detail::driverSetup(noisy, false);
  FeatureSmoothParams params;
  setup.noise.noisy = true;
  setup.noise.amplitude = 0.2;
  setup.noise.correlated_share = 0.1; // white
  const FeaturePassCounts white = detail::featurePassCounts(noisy, params, setup);
  EXPECT_EQ(white.correlated_factor, 1.0);
  setup.noise.correlated_share = 0.8;
  const FeaturePassCounts correlated = detail::featurePassCounts(noisy, params, setup);
  EXPECT_NEAR(correlated.correlated_factor, 1.0 + params.correlated.extra, 1e-12);
  EXPECT_EQ(white.correlated_ramp, 0.0); // (what the planar extra's thresholds are lowered by)
  EXPECT_EQ(correlated.correlated_ramp, 1.0);
  EXPECT_EQ(correlated.prepass_pairs, white.prepass_pairs);
  EXPECT_EQ(correlated.normal_iterations,
            int(std::lround(correlated.amount * 1.5 * params.normals.iterations)));
  EXPECT_GT(correlated.normal_iterations, white.normal_iterations);
  EXPECT_GT(correlated.vertex_iterations, white.vertex_iterations);
  EXPECT_EQ(correlated.checkIterations(params), white.checkIterations(params));
}

// Correlated noise on a box large enough for the amplitude to be read: the driver's counts carry
// the planar extra read against the ramp lowered by correlatedNoiseRamp, and the lowering matters.
TEST(FeatureSmooth, ThePlanarExtraReadsTheCorrelatedRampOnACorrelatedNoisyBox) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 32);
  ASSERT_GE(clean.points.size(), 4096u);
  const MeshArrays noisy = test_meshes::withCorrelatedNoise(clean, 0.4 * meanEdge(clean), 2, 5);
  FeatureSmoothReport r;
  featureSmoothed(noisy, FeatureSmoothParams(), &r);
  const FeatureSmoothParams p;
  const double ramp = correlatedNoiseRamp(r.noise, p.correlated);
  ASSERT_GT(ramp, 0.0) << "amplitude " << r.noise.amplitude << ", share "
                       << r.noise.correlated_share;
  auto counts = [&](double with_ramp) {
    int normal = int(std::lround(r.amount * r.correlated_factor * p.normals.iterations));
    int vertex = int(std::lround(r.amount * r.correlated_factor * p.vertex_iterations));
    detail::addPlanarExtra(r.flat_share, with_ramp, p, normal, vertex);
    return std::make_pair(normal, vertex);
  };
  EXPECT_EQ(std::make_pair(r.normal_iterations, r.vertex_iterations), counts(ramp))
      << "flat share " << r.flat_share;
  EXPECT_GT(r.normal_iterations, counts(0.0).first) << "flat share " << r.flat_share;
}

// Heavy noise (its amplitude past HeavyNoiseParams::from) multiplies the passes and the normal
// filter iterations the first pass's check waits for; at the public benchmark's levels nothing
// changes.
TEST(FeatureSmoothStages, HeavyNoiseTakesMorePassesAndALaterCheck) {
  const MeshArrays noisy = noisySmallBox();
  detail::DriverSetup setup = detail::driverSetup(noisy, false);
  FeatureSmoothParams params;
  setup.noise.amplitude = 0.3;
  const FeaturePassCounts plain = detail::featurePassCounts(noisy, params, setup);
  EXPECT_EQ(plain.heavy_factor, 1.0);
  EXPECT_EQ(plain.checkIterations(params), params.check_iterations);
  setup.noise.amplitude = 0.7; // factor (0.7 / 0.35)^3 = 8, capped at 4
  const FeaturePassCounts heavy = detail::featurePassCounts(noisy, params, setup);
  EXPECT_EQ(heavy.heavy_factor, 4.0);
  EXPECT_NEAR(heavy.amount, 4.0 * plain.amount, 1e-12);
  EXPECT_GT(heavy.normal_iterations, 3 * plain.normal_iterations);
  EXPECT_EQ(heavy.checkIterations(params), 4 * params.check_iterations);
}
