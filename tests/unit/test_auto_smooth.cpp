// The automatic mode: the sharp-feature evidence of vcg_ext/methods/automatic/mode_choice.h (closed-form counts on a
// box, no confirmed creases on a sphere whose normals were made staircase) and the driver of
// vcg_ext/methods/automatic/auto_smooth.h (a noisy box goes to the feature mode and a noisy sphere to the organic
// mode, with the chosen mode's exact result; the decision does not depend on thread count or
// vertex order; progress only grows and cancel stops).
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/automatic/auto_smooth.h>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::meanEdge;

namespace {

FaceRings faceRingsOf(const MeshArrays &m) {
  return computeFaceRings(m.faces, computeRings(int(m.points.size()), m.faces));
}

std::vector<Vec3> faceNormals(const MeshArrays &m) {
  FaceGeometry g;
  computeFaceGeometry(m.points, m.faces, g);
  return g.normal;
}

MeshArrays withRandomNoise(const MeshArrays &clean, double sigma, unsigned seed) {
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, sigma, seed);
  return noisy;
}

AutoSmoothReport autoSmoothed(const MeshArrays &mesh, std::vector<Vec3> &out) {
  VertexQuantities q;
  return autoSmoothMesh(mesh, AutoSmoothParams(), out, q);
}

} // namespace

TEST(SharpFeatureEvidence, BoxWithItsOwnNormalsHasOnlyFlatEdgesAndConfirmedCreases) {
  const int n = 6;
  const MeshArrays box = test_meshes::box(1.0, 0.8, 0.6, n);
  const std::vector<Vec3> normals = faceNormals(box);
  const SharpFeatureEvidence e = sharpFeatureEvidence(normals, normals, faceRingsOf(box));
  // Closed: every edge is shared by two faces; the box's 12 edges have n mesh edges each.
  EXPECT_EQ(e.edges, long(box.faces.size()) * 3 / 2);
  EXPECT_EQ(e.crease_pairs, 12L * n);
  EXPECT_EQ(e.confirmed_pairs, 12L * n);
  EXPECT_EQ(e.flat_pairs, e.edges - 12L * n);
  EXPECT_DOUBLE_EQ(e.confirmed_share, 1.0);
  EXPECT_DOUBLE_EQ(e.flat_share, double(e.edges - 12L * n) / double(e.edges));
}

TEST(SharpFeatureEvidence, InventedCreasesOnASphereAreNotConfirmed) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 4);
  const std::vector<Vec3> exact = faceNormals(sphere);
  // A staircase: every normal snapped to the nearest of the six axis directions (what a range
  // kernel does to a curved surface, in the extreme).
  std::vector<Vec3> staircase(exact.size());
  for (size_t f = 0; f < exact.size(); ++f) {
    int axis;
    exact[f].cwiseAbs().maxCoeff(&axis);
    staircase[f] = Vec3::Zero();
    staircase[f][axis] = exact[f][axis] > 0 ? 1 : -1;
  }
  const SharpFeatureEvidence e = sharpFeatureEvidence(staircase, exact, faceRingsOf(sphere));
  EXPECT_GT(e.crease_pairs, 100);
  EXPECT_EQ(e.confirmed_pairs, 0); // neighbouring faces of the sphere differ by a few degrees
  EXPECT_GT(e.flat_share, 0.8);    // inside each of the six cells
  // The sphere's own normals: no crease, and no edge flat to 1° at this resolution.
  const SharpFeatureEvidence own = sharpFeatureEvidence(exact, exact, faceRingsOf(sphere));
  EXPECT_EQ(own.crease_pairs, 0);
  EXPECT_EQ(own.flat_pairs, 0);
  EXPECT_EQ(own.confirmed_share, 0.0);
}

TEST(SharpFeatureEvidence, DegenerateFacesAreSkipped) {
  const MeshArrays box = test_meshes::box(1.0, 1.0, 1.0, 2);
  std::vector<Vec3> normals = faceNormals(box);
  normals[0] = Vec3::Zero();
  const SharpFeatureEvidence e = sharpFeatureEvidence(normals, faceNormals(box), faceRingsOf(box));
  EXPECT_EQ(e.edges, long(box.faces.size()) * 3 / 2 - 3);
}

TEST(AutoSmooth, NoisyBoxGoesToTheFeatureModeWithItsExactResult) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 16);
  const MeshArrays noisy = test_meshes::withNormalNoise(clean, 0.3 * meanEdge(clean), 3);
  std::vector<Vec3> out, feature;
  const AutoSmoothReport r = autoSmoothed(noisy, out);
  VertexQuantities q;
  featureSmoothMesh(noisy, FeatureSmoothParams(), feature, q);
  EXPECT_TRUE(r.chose_feature);
  EXPECT_FALSE(r.feature.declined);
  EXPECT_GT(r.evidence.flat_share, AutoSmoothParams().feature_flat_share);
  EXPECT_EQ(out, feature);
  RecordProperty("flat_share", std::to_string(r.evidence.flat_share));
  RecordProperty("confirmed_share", std::to_string(r.evidence.confirmed_share));
}

TEST(AutoSmooth, NoisySphereGoesToTheOrganicModeWithItsExactResult) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 4);
  const MeshArrays noisy = withRandomNoise(clean, 0.25 * meanEdge(clean), 5);
  std::vector<Vec3> out, organic;
  const AutoSmoothReport r = autoSmoothed(noisy, out);
  VertexQuantities q;
  organicSmoothMesh(noisy, OrganicSmoothParams(), organic, q);
  EXPECT_FALSE(r.chose_feature);
  EXPECT_TRUE(r.feature.declined);
  EXPECT_LT(r.evidence.flat_share, AutoSmoothParams().feature_flat_share);
  EXPECT_LT(r.evidence.confirmed_share, AutoSmoothParams().feature_confirmed_share);
  EXPECT_EQ(out, organic);
  const auto theta = [&](const std::vector<Vec3> &p) {
    return normalDeviation(p, clean.points, clean.faces, buildEdgeTable(clean.faces)).theta_deg;
  };
  EXPECT_LT(theta(out), 0.1 * theta(noisy.points));
  EXPECT_NEAR(r.organic.volume_after / signedVolume(clean.points, clean.faces), 1.0, 0.005);
  RecordProperty("flat_share", std::to_string(r.evidence.flat_share));
  RecordProperty("confirmed_share", std::to_string(r.evidence.confirmed_share));
}

TEST(AutoSmooth, LargeMeshesDecideOnWindowsWithTheWholeMeshsChoiceAndResult) {
  // 41k vertices, with cores of 6 rings: 8 windows take about 35 % of its faces.
  const MeshArrays clean = test_meshes::icosphere(1.0, 6);
  const MeshArrays noisy = withRandomNoise(clean, 0.2 * meanEdge(clean), 9);
  std::vector<Vec3> windowed_out, whole_out;
  VertexQuantities q;
  AutoSmoothParams params;
  params.windows.core_rings = 6;
  const AutoSmoothReport windowed = autoSmoothMesh(noisy, params, windowed_out, q);
  AutoSmoothParams whole_params = params;
  whole_params.windows.max_windows = 0; // the evidence on the whole mesh
  const AutoSmoothReport whole = autoSmoothMesh(noisy, whole_params, whole_out, q);
  EXPECT_TRUE(windowed.windowed);
  EXPECT_FALSE(whole.windowed);
  EXPECT_GT(windowed.window_faces, long(noisy.faces.size()) / 10);
  EXPECT_LT(windowed.window_faces, long(noisy.faces.size()) / 2);
  EXPECT_EQ(windowed.chose_feature, whole.chose_feature);
  // A sample of the whole mesh's evidence, and the chosen mode's result bit for bit.
  EXPECT_NEAR(windowed.evidence.flat_share, whole.evidence.flat_share, 0.03);
  EXPECT_EQ(windowed_out, whole_out);
}

TEST(AutoSmooth, CleanMeshesStayAsTheyAre) {
  for (const MeshArrays &clean :
       {test_meshes::box(1.0, 0.8, 0.6, 16), test_meshes::icosphere(1.0, 4)}) {
    std::vector<Vec3> out;
    autoSmoothed(clean, out);
    EXPECT_LT(normalDeviation(out, clean.points, clean.faces, buildEdgeTable(clean.faces)).theta_deg,
              1.0);
  }
}

TEST(AutoSmooth, SameDecisionAndResultForOneAndTwoThreadsAndPermutedVertices) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 3);
  const MeshArrays noisy = withRandomNoise(clean, 0.25 * meanEdge(clean), 8);
  const int threads = omp_get_max_threads();
  std::vector<Vec3> one, two, shuffled;
  omp_set_num_threads(1);
  const AutoSmoothReport r1 = autoSmoothed(noisy, one);
  omp_set_num_threads(2);
  const AutoSmoothReport r2 = autoSmoothed(noisy, two);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
  EXPECT_EQ(r1.evidence.flat_pairs, r2.evidence.flat_pairs);
  EXPECT_EQ(r1.evidence.confirmed_pairs, r2.evidence.confirmed_pairs);

  const std::vector<int> perm = test_meshes::shuffledPermutation(int(noisy.points.size()), 3);
  // Renumbered vertices, reordered faces: the same bits (the driver runs in spatial order).
  const AutoSmoothReport rp =
      autoSmoothed(test_meshes::facesReordered(test_meshes::permuted(noisy, perm), 5), shuffled);
  EXPECT_EQ(rp.chose_feature, r1.chose_feature);
  EXPECT_EQ(rp.evidence.crease_pairs, r1.evidence.crease_pairs);
  ASSERT_EQ(shuffled.size(), one.size());
  for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(shuffled[perm[i]], one[i]) << i;
}

TEST(AutoSmooth, ProgressOnlyGrowsAndCancelStops) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 3);
  const MeshArrays noisy = withRandomNoise(clean, 0.25 * meanEdge(clean), 9);
  std::vector<int> seen;
  std::vector<Vec3> out;
  VertexQuantities q;
  const AutoSmoothReport r = autoSmoothMesh(noisy, AutoSmoothParams(), out, q,
                                            [&](int percent, const char *) {
                                              seen.push_back(percent);
                                              return true;
                                            });
  ASSERT_FALSE(r.chose_feature); // the organic path: two drivers' progress in one range
  ASSERT_GT(seen.size(), 3u);
  for (size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]) << i;
  EXPECT_LE(seen.back(), 100);

  for (int stop_at : {1, 4}) { // in the decision, and in the organic mode
    int calls = 0;
    std::vector<Vec3> cancelled;
    const AutoSmoothReport stopped = autoSmoothMesh(
        noisy, AutoSmoothParams(), cancelled, q, [&](int, const char *) { return ++calls < stop_at; });
    EXPECT_TRUE(stopped.cancelled) << stop_at;
    EXPECT_EQ(calls, stop_at);
  }
}

TEST(FlatnessStride, OneUpToTheFittedSizesThenTheSquareRootOfTheFaceCount) {
  EXPECT_EQ(flatnessStride(0), 1);
  EXPECT_EQ(flatnessStride(100000), 1);
  EXPECT_EQ(flatnessStride(440000), 1);  // the largest meshes the thresholds were fitted on
  EXPECT_EQ(flatnessStride(460000), 2);
  EXPECT_EQ(flatnessStride(2000000), 3); // a 1M-vertex mesh
  EXPECT_EQ(flatnessStride(20000000), 10);
}

TEST(FlatnessStride, TheWalkGoesStraightOnAPlane) {
  const MeshArrays plane =
      test_meshes::heightField(41, -1, 1, -1, 1, [](double, double) { return 0.0; });
  const FaceRings rings = faceRingsOf(plane);
  std::vector<Vec3> centroids;
  computeFaceCentroids(plane.points, plane.faces, centroids);
  // The face nearest the middle, and the distance its walks reach: growing with every step, by
  // at least a third of the grid spacing per step (a zigzag across a strip of triangles).
  int middle = 0;
  for (int f = 0; f < int(centroids.size()); ++f)
    if (centroids[f].norm() < centroids[middle].norm()) middle = f;
  const double spacing = 2.0 / 40;
  for (int j = 0; j < 3; ++j) {
    double before = 0;
    for (int stride = 1; stride <= 12; ++stride) {
      const int g = detail::faceAlongWalk(middle, j, stride, rings, centroids);
      ASSERT_GE(g, 0);
      const double d = (centroids[g] - centroids[middle]).norm();
      EXPECT_GT(d, before);
      EXPECT_GT(d, stride * spacing / 3);
      before = d;
    }
  }
}

TEST(FlatnessStride, AFinerSphereComparedFartherApartReadsAsCurvedAsACoarseOne) {
  // Edge by edge, a fine sphere reads as flat where a coarse one does not (1° per edge); with the
  // walk as many edges long as the fine sphere is finer, it reads as the coarse one does.
  const auto flat_share = [](const MeshArrays &sphere, int stride) {
    const std::vector<Vec3> normals = faceNormals(sphere);
    std::vector<Vec3> centroids;
    computeFaceCentroids(sphere.points, sphere.faces, centroids);
    return detail::flatShareAtStride(normals, faceRingsOf(sphere), centroids, stride,
                                     std::cos(M_PI / 180.0));
  };
  const MeshArrays coarse = test_meshes::icosphere(1.0, 4), fine = test_meshes::icosphere(1.0, 7);
  EXPECT_EQ(flat_share(coarse, 1), 0.0);
  EXPECT_GT(flat_share(fine, 1), 0.5);
  EXPECT_LT(flat_share(fine, 8), 0.01);
  // A plane reads as flat at any stride.
  const MeshArrays plane =
      test_meshes::heightField(41, -1, 1, -1, 1, [](double, double) { return 0.0; });
  EXPECT_DOUBLE_EQ(flat_share(plane, 8), 1.0);
}

TEST(FlatnessStride, BelowTheStrideTheChoiceReadsTheEdgeByEdgeEvidence) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 5);
  const std::vector<Vec3> exact = faceNormals(sphere);
  const FaceRings rings = faceRingsOf(sphere);
  const SharpFeatureEvidence edges = sharpFeatureEvidence(exact, exact, rings, 30, 25, 1.0);
  const SharpFeatureEvidence model =
      modelScaleEvidence(exact, exact, rings, sphere.points, sphere.faces, 30, 25, 1.0);
  EXPECT_EQ(model.flat_stride, 1);
  EXPECT_EQ(model.flat_share, edges.flat_share);
  EXPECT_EQ(model.flat_pairs, edges.flat_pairs);
  EXPECT_EQ(model.confirmed_share, edges.confirmed_share);
}

// The choice's thresholds: either share at its threshold (plus the margin) says sharp features.
TEST(AutoSmoothStages, SharpFeaturesByEitherShareAgainstItsThresholdAndMargin) {
  AutoSmoothParams params;
  params.feature_flat_share = 0.25;
  params.feature_confirmed_share = 0.75;
  SharpFeatureEvidence e;
  e.flat_share = 0.25, e.confirmed_share = 0.5, e.crease_density = 8.0;
  EXPECT_TRUE(detail::hasSharpFeatures(e, params));
  EXPECT_FALSE(detail::hasSharpFeatures(e, params, 0.01, 0.0));
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, -0.01, 0.0));
  e.flat_share = 0.1, e.confirmed_share = 0.75;
  EXPECT_TRUE(detail::hasSharpFeatures(e, params));
  EXPECT_FALSE(detail::hasSharpFeatures(e, params, 0.0, 0.05));
  e.confirmed_share = 0.7;
  EXPECT_FALSE(detail::hasSharpFeatures(e, params));
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, 0.0, -0.05));
}

// The confirmed share counts only where the creases are dense enough for feature lines
// (min_crease_density, 2 per √edges); the flat share does not ask for creases.
TEST(AutoSmoothStages, ConfirmedShareCountsOnlyWithEnoughCreasesPerRootOfTheEdges) {
  AutoSmoothParams params; // 0.235, 0.785, 2.0
  SharpFeatureEvidence e;
  e.flat_share = 0.05, e.confirmed_share = 0.9, e.crease_density = 2.0;
  EXPECT_TRUE(detail::hasSharpFeatures(e, params));
  EXPECT_FALSE(detail::hasSharpFeatures(e, params, 0, 0, 1, 0.1));  // not clear of it by 0.1
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, 0, 0, 1, -0.1));
  e.crease_density = 0.5; // the 10M bunny: a confirmed share alone does not make a CAD part
  EXPECT_FALSE(detail::hasSharpFeatures(e, params));
  e.flat_share = 0.3;     // planar faces do, creases or not
  EXPECT_TRUE(detail::hasSharpFeatures(e, params));
}

// Creases per √edges: a box's creases (its edges) read about the same at two resolutions, while a
// smooth sphere under heavier relative noise reads far lower and falls with the resolution.
TEST(AutoSmoothStages, CreaseDensityOfFeatureLinesDoesNotDependOnTheResolution) {
  auto density = [](MeshArrays mesh, double noise, unsigned seed) {
    test_meshes::addNoise(mesh, noise * meanEdge(mesh), seed);
    detail::DriverSetup setup = detail::driverSetup(mesh, false);
    addFaceRingLists(setup.face_rings, mesh.faces, setup.rings);
    FirstPassCounts counts;
    counts.prepass_pairs = counts.reference_pairs = 4;
    counts.first.iterations = 4;
    std::vector<Vec3> filtered, reference;
    firstPassNormals(mesh, setup.rings, setup.face_rings, setup.fixed, setup.roles, counts,
                     setup.stats.mean_edge_length, filtered, reference);
    return sharpFeatureEvidence(filtered, reference, setup.face_rings, 30, 25, 1).crease_density;
  };
  const double coarse = density(test_meshes::box(1.0, 0.8, 0.6, 12), 0.1, 5);
  const double fine = density(test_meshes::box(1.0, 0.8, 0.6, 36), 0.1, 5);
  EXPECT_GT(coarse, 2.0); // measured 2.89 (0.54 × line length / √area gives 2.7)
  EXPECT_NEAR(fine / coarse, 1.0, 0.1);
  const double sphere = density(test_meshes::icosphere(1.0, 4), 0.5, 5);
  EXPECT_GT(sphere, 0.0); // noise did leave creases
  EXPECT_LT(sphere, 0.5);
  EXPECT_LT(density(test_meshes::icosphere(1.0, 5), 0.5, 5), sphere);
}

// After a check delayed by heavy noise the flat share's threshold is the plain one times the delay
// factor to flat_share_factor_power: organic shapes read flatter after more filter iterations.
TEST(AutoSmoothStages, FlatShareThresholdGrowsWithTheCheckDelay) {
  AutoSmoothParams params; // 0.235, power 0.3
  SharpFeatureEvidence e;
  e.flat_share = 0.28, e.confirmed_share = 0.6; // an organic mesh under white noise of 1 edge
  EXPECT_TRUE(detail::hasSharpFeatures(e, params));               // no delay: 0.235
  EXPECT_FALSE(detail::hasSharpFeatures(e, params, 0, 0, 3.0));   // 0.235 * 3^0.3 = 0.327
  e.flat_share = 0.35;                                            // a CAD part there
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, 0, 0, 3.0));
  EXPECT_FALSE(detail::hasSharpFeatures(e, params, 0, 0, 4.0));   // 0.235 * 4^0.3 = 0.357
  e.flat_share = 0.236;
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, 0, 0, 0.5));    // a factor below 1 counts as 1
  params.flat_share_factor_power = 0;                              // off: the plain threshold
  e.flat_share = 0.28;
  EXPECT_TRUE(detail::hasSharpFeatures(e, params, 0, 0, 3.0));
}

// The crease-confirming copy: the pre-pass's own positions when it ran the reference's pairs,
// else that many Taubin pairs of the input.
TEST(AutoSmoothStages, ReferenceNormalsAreThePrepassWhenItRanTheSamePairs) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 3);
  const MeshArrays noisy = withRandomNoise(clean, 0.2 * meanEdge(clean), 4);
  const detail::DriverSetup setup = detail::driverSetup(noisy, false, BoundaryMode::NoInward);
  std::vector<Vec3> taubin4 = noisy.points, expected;
  taubinSmooth(taubin4, setup.rings, setup.fixed, setup.roles.boundary_neighbours, 4);
  computeFaceNormals(taubin4, noisy.faces, expected);
  std::vector<Vec3> normals, from_prepass;
  detail::referenceNormals(noisy, setup, clean.points, 2, 4, normals); // pre-pass of 2 pairs
  EXPECT_EQ(normals, expected);
  detail::referenceNormals(noisy, setup, clean.points, 4, 4, from_prepass);
  EXPECT_EQ(from_prepass, faceNormals(clean)); // (the positions it was given)
}

// The decision on the whole mesh fills the report: a box's own normals are flat and creased, a
// sphere's are neither.
TEST(AutoSmoothStages, DecisionOnTheFirstPassFillsTheReport) {
  const AutoSmoothParams params;
  for (const bool box : {true, false}) {
    const MeshArrays m = box ? test_meshes::box(1.0, 0.8, 0.6, 8) : test_meshes::icosphere(1.0, 3);
    const detail::DriverSetup setup = detail::driverSetup(m, false, BoundaryMode::NoInward);
    AutoSmoothReport report;
    const bool feature = detail::decideOnFirstPass(m, params, setup, faceNormals(m), m.points,
                                                   params.reference_pairs, report);
    EXPECT_EQ(feature, box);
    EXPECT_EQ(report.chose_feature, box);
    EXPECT_TRUE(report.decided);
    EXPECT_EQ(report.evidence.flat_share > 0.5, box) << report.evidence.flat_share;
    EXPECT_GE(report.seconds_reference, 0.0);
  }
}

// The organic mode runs on the feature mode's set-up, so with its selection and boundary mode;
// after the decision its progress fills the rest of the range.
TEST(AutoSmoothStages, OrganicModeTakesTheSetUpsSelectionAndTheRestOfTheProgress) {
  AutoSmoothParams params;
  params.feature.selected_only = true;
  params.feature.boundary = BoundaryMode::Fixed;
  params.organic.strength = 1.5;
  const OrganicSmoothParams organic = detail::organicParamsOf(params);
  EXPECT_TRUE(organic.selected_only);
  EXPECT_EQ(organic.boundary, BoundaryMode::Fixed);
  EXPECT_EQ(organic.strength, 1.5);
  std::vector<int> seen;
  const ProgressFn progress = [&](int percent, const char *) {
    seen.push_back(percent);
    return percent < 60;
  };
  const ProgressFn mapped = detail::progressFrom(20, progress);
  EXPECT_TRUE(mapped(0, ""));
  EXPECT_TRUE(mapped(25, ""));
  EXPECT_FALSE(mapped(50, "")); // the caller's answer comes back
  EXPECT_FALSE(mapped(99, ""));
  EXPECT_EQ(seen, (std::vector<int>{20, 40, 60, 99}));
  EXPECT_FALSE(detail::progressFrom(20, ProgressFn()));
}

// The log's reasons: both shares (with their errors and the windows' share on windows) and the
// decision's time in the form of the path it took.
TEST(AutoSmoothStages, LogSaysWhyAndHowLongTheDecisionTook) {
  AutoSmoothReport r;
  r.evidence.flat_share = 0.3, r.evidence.confirmed_share = 0.9, r.evidence.crease_density = 5;
  r.seconds_setup = 0.25, r.seconds_reference = 0.125;
  EXPECT_EQ(detail::evidencePhrase(r, 1000),
            "0.300 of the edges flat and 0.900 of the creases confirmed after guided filtering");
  r.check_factor = 3.0; // heavy noise: the flat share's threshold 0.235 * 3^0.3
  EXPECT_EQ(detail::evidencePhrase(r, 1000),
            "0.300 of the edges flat (0.327 needed: the check waited x 3.00 for heavy noise) and "
            "0.900 of the creases confirmed after guided filtering");
  r.check_factor = 1.0;
  r.chose_feature = true;
  EXPECT_EQ(detail::decisionTimeLine(r),
            "Time of the decision: shared topology 0.250 s, Taubin copy and evidence 0.125 s.");
  r.chose_feature = false;
  r.feature.seconds_prepass = 0.5, r.feature.seconds_normals = 0.25;
  EXPECT_NE(detail::decisionTimeLine(r).find("first normal filter iterations 0.750 s"),
            std::string::npos);
  r.windowed = true;
  r.window_faces = 300, r.flat_error = 0.01, r.confirmed_error = 0.02, r.seconds_windows = 0.5;
  r.evidence.flat_stride = 2;
  EXPECT_EQ(detail::evidencePhrase(r, 1000),
            "0.300 ± 0.010 of face pairs 2 edges apart flat and 0.900 ± 0.020 of the creases "
            "confirmed after guided filtering, on windows holding 30 % of the faces");
  EXPECT_EQ(detail::decisionTimeLine(r),
            "Time of the decision: shared topology 0.250 s, evidence on windows 0.500 s.");
  // Creases too sparse for a confirmed share that could have counted (within its 3 errors).
  r.evidence.flat_share = 0.05, r.evidence.confirmed_share = 0.77, r.evidence.crease_density = 0.55;
  r.crease_density_error = 0.24;
  EXPECT_EQ(detail::evidencePhrase(r, 1000),
            "0.050 ± 0.010 of face pairs 2 edges apart flat and 0.770 ± 0.020 of the creases "
            "confirmed (too few creases to count: 0.55 ± 0.24 per square root of the edges, 2.0 "
            "needed) after guided filtering, on windows holding 30 % of the faces");
  r.evidence.confirmed_share = 0.6; // it could not have counted: nothing said
  EXPECT_EQ(detail::evidencePhrase(r, 1000).find("too few"), std::string::npos);
}
