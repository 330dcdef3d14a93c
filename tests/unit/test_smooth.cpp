#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/paper/paper_smooth.h>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::meanEdge;

namespace {

double thetaDeg(const std::vector<Vec3> &result, const MeshArrays &reference) {
  return normalDeviation(result, reference.points, reference.faces,
                         buildEdgeTable(reference.faces))
      .theta_deg;
}

std::vector<Vec3> smoothed(const MeshArrays &mesh, const SmoothParams &params,
                           SmoothReport *report_out = nullptr) {
  std::vector<Vec3> out;
  VertexQuantities q;
  const SmoothReport r = smoothMesh(mesh, params, out, q);
  if (report_out) *report_out = r;
  return out;
}

} // namespace

TEST(Smooth, PlaneWithNormalNoiseGetsFlatterAndStaysInPlace) {
  const MeshArrays clean =
      test_meshes::heightField(40, -1, 1, -1, 1, [](double, double) { return 0.0; });
  MeshArrays noisy = clean;
  const double edge = meanEdge(clean);
  test_meshes::addNoise(noisy, 0.2 * edge, 7, [](int) { return Vec3(0, 0, 1); });
  const std::vector<Vec3> out = smoothed(noisy, SmoothParams());
  const double before = thetaDeg(noisy.points, clean), after = thetaDeg(out, clean);
  EXPECT_GT(before, 10.0);
  EXPECT_LT(after, 0.35 * before);
  double mean_height_change = 0;
  for (size_t i = 0; i < out.size(); ++i)
    mean_height_change += (out[i].z() - noisy.points[i].z()) / out.size();
  EXPECT_LT(std::abs(mean_height_change), 0.01 * edge);
}

TEST(Smooth, CleanSphereBarelyMovesInTheDefaultMode) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 4);
  SmoothParams params;
  const std::vector<Vec3> out = smoothed(sphere, params);
  const double edge = meanEdge(sphere);
  double mean_move = 0, mean_radius_error = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    mean_move += (out[i] - sphere.points[i]).norm() / out.size();
    mean_radius_error += std::abs(out[i].norm() - 1.0) / out.size();
  }
  EXPECT_LT(mean_move / params.iterations, 0.05 * edge);
  EXPECT_LT(mean_radius_error, 0.01 * edge);
}

TEST(Smooth, NoisyClosedMeshKeepsItsVolume) {
  const MeshArrays clean = test_meshes::icosphere(1.0, 4);
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, 0.3 * meanEdge(clean), 11);
  SmoothReport report;
  const std::vector<Vec3> out = smoothed(noisy, SmoothParams(), &report);
  EXPECT_TRUE(report.closed);
  const double ratio = signedVolume(out, clean.faces) / signedVolume(noisy.points, clean.faces);
  EXPECT_NEAR(ratio, 1.0, 0.01);
  EXPECT_NEAR(report.volume_after / report.volume_before, ratio, 1e-12);
  EXPECT_LT(thetaDeg(out, clean), 0.5 * thetaDeg(noisy.points, clean));
}

TEST(Smooth, SameResultForOneAndTwoThreadsAndPermutedVertices) {
  MeshArrays noisy = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(noisy, 0.02, 5);
  for (PlacementMode mode :
       {PlacementMode::RingBarycentre, PlacementMode::PatchPoint, PlacementMode::Paper}) {
    SmoothParams params;
    params.placement = mode;
    params.alpha_override = mode != PlacementMode::Paper; // the paper's saliency alpha too
    omp_set_num_threads(1);
    const std::vector<Vec3> one = smoothed(noisy, params);
    omp_set_num_threads(2);
    const std::vector<Vec3> two = smoothed(noisy, params);
    for (size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << "vertex " << i;

    const std::vector<int> perm = test_meshes::shuffledPermutation(int(noisy.points.size()), 3);
    const std::vector<Vec3> shuffled = smoothed(test_meshes::permuted(noisy, perm), params);
    double worst = 0;
    for (size_t i = 0; i < one.size(); ++i)
      worst = std::max(worst, (one[i] - shuffled[perm[i]]).norm());
    // Summation order inside a neighbourhood follows the vertex numbering: equal up to rounding,
    // which the paper's Newton solve (near-singular Jacobians, ALGORITHM.md) amplifies.
    EXPECT_LT(worst, mode == PlacementMode::Paper ? 1e-5 : 1e-12) << "placement " << int(mode);
  }
}

TEST(Smooth, PaperPlacementAsPrintedMovesVerticesFarAndTheSafeguardBoundsIt) {
  // ALGORITHM.md: Newton toward the uniform curvature usually has no solution on the patch; as
  // printed (no safeguard) the clamp throws vertices to the patch border.
  MeshArrays noisy = test_meshes::icosphere(1.0, 4);
  const double edge = meanEdge(noisy);
  test_meshes::addNoise(noisy, 0.2 * edge, 13);
  SmoothParams params;
  params.placement = PlacementMode::Paper;
  params.iterations = 1;
  params.newton_step_limit = 0;
  SmoothReport report;
  const std::vector<Vec3> printed = smoothed(noisy, params, &report);
  params.newton_step_limit = 1.0;
  const std::vector<Vec3> guarded = smoothed(noisy, params);
  double printed_max = 0, guarded_max = 0;
  for (size_t i = 0; i < printed.size(); ++i) {
    printed_max = std::max(printed_max, (printed[i] - noisy.points[i]).norm());
    guarded_max = std::max(guarded_max, (guarded[i] - noisy.points[i]).norm());
  }
  EXPECT_GT(report.newton_failures, long(noisy.points.size()) / 2);
  EXPECT_GT(printed_max, 1.0 * edge);
  EXPECT_LT(guarded_max, printed_max);
}

TEST(Smooth, BoundaryModes) {
  const MeshArrays clean =
      test_meshes::heightField(25, -1, 1, -1, 1, [](double x, double y) { return 0.3 * x * y; });
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, 0.2 * meanEdge(clean), 17, [](int) { return Vec3(0, 0, 1); });
  const Rings rings = computeRings(int(clean.points.size()), clean.faces);
  SmoothParams params;
  params.boundary = BoundaryMode::Fixed;
  const std::vector<Vec3> fixed = smoothed(noisy, params);
  params.boundary = BoundaryMode::AlongBoundary;
  const std::vector<Vec3> along = smoothed(noisy, params);
  for (int v = 0; v < rings.vertex_count; ++v) {
    if (!rings.boundary[v]) continue;
    EXPECT_EQ(fixed[v], noisy.points[v]);
    // On a straight side (x = +-1, not a corner), moving along the boundary keeps x.
    const bool corner = std::abs(std::abs(clean.points[v].x()) - 1) < 1e-12 &&
                        std::abs(std::abs(clean.points[v].y()) - 1) < 1e-12;
    if (!corner && std::abs(std::abs(clean.points[v].x()) - 1) < 1e-12)
      EXPECT_NEAR(along[v].x(), noisy.points[v].x(), 1e-12);
  }
}

TEST(Smooth, SelectedOnlyMovesOnlySelectedVertices) {
  MeshArrays noisy = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(noisy, 0.02, 19);
  for (size_t i = 0; i < noisy.points.size(); ++i) noisy.selected[i] = noisy.points[i].z() > 0;
  SmoothParams params;
  params.selected_only = true;
  const std::vector<Vec3> out = smoothed(noisy, params);
  long moved_selected = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!noisy.selected[i]) EXPECT_EQ(out[i], noisy.points[i]);
    else moved_selected += out[i] != noisy.points[i];
  }
  EXPECT_GT(moved_selected, long(out.size()) / 3);
}

TEST(Smooth, CancelAtAnyStageLeavesTheOutputUntouched) {
  MeshArrays noisy = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(noisy, 0.02, 23);
  for (int cancel_at_call : {1, 2, 3, 5}) {
    int calls = 0;
    std::vector<Vec3> out = {Vec3(7, 7, 7)};
    VertexQuantities q;
    const SmoothReport r = smoothMesh(noisy, SmoothParams(), out, q, [&](int, const char *) {
      return ++calls < cancel_at_call;
    });
    EXPECT_TRUE(r.cancelled);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0], Vec3(7, 7, 7));
  }
}

TEST(Smooth, NonManifoldIsolatedAndDegenerateVerticesAreFrozen) {
  MeshArrays m = test_meshes::heightField(6, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const int n = int(m.points.size());
  m.points.push_back(Vec3(5, 5, 5)); // isolated
  m.points.push_back(Vec3(0.5, 0.5, 1)); // bow-tie apex shared with vertex 14 via a dangling fan
  m.points.push_back(Vec3(0.6, 0.5, 1));
  m.faces.push_back({14, n + 1, n + 2});
  m.faces.push_back({7, 8, 8}); // degenerate (repeated vertex)
  m.selected.assign(m.points.size(), 0);
  test_meshes::addNoise(m, 0.01, 29, [](int) { return Vec3(0, 0, 1); });
  SmoothReport report;
  const std::vector<Vec3> out = smoothed(m, SmoothParams(), &report);
  EXPECT_EQ(out[n], m.points[n]);
  EXPECT_EQ(out[14], m.points[14]);
  EXPECT_EQ(out[7], m.points[7]);
  EXPECT_EQ(out[8], m.points[8]);
  EXPECT_GE(report.frozen_vertices, 4);
  for (const Vec3 &p : out) EXPECT_TRUE(p.allFinite());
}

TEST(Smooth, RefusesEmptyPointCloudAndNonFiniteInput) {
  MeshArrays empty;
  EXPECT_NE(validateForSmoothing(empty), "");
  MeshArrays cloud = test_meshes::icosphere(1.0, 1);
  cloud.faces.clear();
  EXPECT_NE(validateForSmoothing(cloud).find("no faces"), std::string::npos);
  MeshArrays nan = test_meshes::icosphere(1.0, 1);
  nan.points[3].x() = std::nan("");
  EXPECT_NE(validateForSmoothing(nan).find("NaN"), std::string::npos);
  EXPECT_EQ(validateForSmoothing(test_meshes::icosphere(1.0, 1)), "");
}

// smoothMesh's stages: the set-up's report, the placement sweep and its cancel, the result's
// description.
TEST(PaperStages, SetUpReportCountsWhyVerticesCannotMove) {
  MeshArrays m = test_meshes::heightField(6, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const int n = int(m.points.size());
  m.points.push_back(Vec3(5, 5, 5));     // isolated
  m.points.push_back(Vec3(0.5, 0.5, 1)); // a second fan at vertex 14: non-manifold
  m.points.push_back(Vec3(0.6, 0.5, 1));
  m.faces.push_back({14, n + 1, n + 2});
  const detail::DriverSetup setup = detail::driverSetup(m, false, BoundaryMode::Paper, false, true);
  SmoothReport report;
  detail::reportPaperSetup(setup, report);
  EXPECT_EQ(report.isolated_vertices, 1);
  EXPECT_EQ(report.nonmanifold_vertices, 1);
  EXPECT_EQ(report.frozen_vertices, 2);
  EXPECT_FALSE(report.closed);
  EXPECT_NEAR(report.mean_edge_length, meanEdge(m), 1e-12);
}

TEST(PaperStages, SweepMovesOnlyMovableVerticesAndStopsWhenABlockSaysSo) {
  MeshArrays noisy = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(noisy, 0.02, 23);
  noisy.selected.assign(noisy.points.size(), 0);
  noisy.selected[0] = 1;
  const detail::DriverSetup setup =
      detail::driverSetup(noisy, /*selected_only=*/true, BoundaryMode::Paper, false, true);
  SurfaceAnalysis analysis;
  computeVertexNormals(noisy.points, noisy.faces, setup.rings, analysis.curvature.normal);
  analysis.saliency.assign(noisy.points.size(), 0.0);
  const SmoothParams params; // the ring barycentre
  std::vector<double> alpha(noisy.points.size(), 1.0);
  std::vector<Vec3> next(noisy.points.size());
  SmoothReport report;
  std::vector<int> stops;
  EXPECT_TRUE(detail::paperVertexSweep(noisy, setup, noisy.points, analysis, params, alpha, next,
                                       report, [&](int stop) { return stops.push_back(stop), true; }));
  EXPECT_EQ(stops, std::vector<int>{int(noisy.points.size())}); // one block of fewer than 65536
  EXPECT_NE(next[0], noisy.points[0]);                           // the selected vertex moved
  for (size_t v = 1; v < next.size(); ++v) EXPECT_EQ(next[v], noisy.points[v]);
  EXPECT_FALSE(detail::paperVertexSweep(noisy, setup, noisy.points, analysis, params, alpha,
                                        next, report, [](int) { return false; }));
}

// placeVertex's stages.
TEST(PaperStages, NeighbourhoodAlphaIsTheSaliencySpreadOrTheOverride) {
  SmoothParams params;
  params.alpha = 0.3;
  const std::vector<double> saliency{0.2, 0.8, 0.4, 0.0};
  EXPECT_EQ(detail::neighbourhoodAlpha({0, 1, 2}, saliency, 1.0, params), 0.3); // the override
  params.alpha_override = false;
  EXPECT_DOUBLE_EQ(detail::neighbourhoodAlpha({0, 1, 2}, saliency, 1.0, params), 0.25);
  EXPECT_EQ(detail::neighbourhoodAlpha({3}, saliency, 1.0, params), 1.0); // nothing salient
}

TEST(PaperStages, ProjectionOfAFlatNeighbourhoodAndItsRingBarycentre) {
  const MeshArrays grid = test_meshes::heightField(7, 0, 1, 0, 1, [](double, double) { return 0; });
  const Rings rings = computeRings(49, grid.faces);
  CurvatureField c;
  computeVertexNormals(grid.points, grid.faces, rings, c.normal);
  const int centre = 3 * 7 + 3;
  LocalFrame frame;
  NeighbourhoodScratch scratch;
  detail::Counters counters;
  ASSERT_TRUE(detail::projectNeighbourhoodOf(centre, grid, rings, grid.points, c,
                                             FoldHandling::Paper, frame, scratch, counters));
  EXPECT_EQ(scratch.vertices.size(), 19u); // the vertex and its 2-ring
  EXPECT_EQ(counters.fold_fallbacks, 0);
  // A regular ring's barycentre is the vertex itself: its own patch parameters.
  double u = -1, v = -1;
  detail::ringBarycentreParameters(centre, rings, grid.points, frame, u, v);
  EXPECT_NEAR(u, scratch.u[0], 1e-12);
  EXPECT_NEAR(v, scratch.v[0], 1e-12);
  // Without a normal there is nothing to project onto: counted as a failed fit.
  c.normal[centre] = Vec3::Zero();
  for (const int *w = rings.ring2Begin(centre); w != rings.ring2End(centre); ++w)
    c.normal[*w] = Vec3::Zero();
  EXPECT_FALSE(detail::projectNeighbourhoodOf(centre, grid, rings, grid.points, c,
                                              FoldHandling::Ignore, frame, scratch, counters));
  EXPECT_EQ(counters.fit_failures, 1);
}

// The paper's iteration analysis: the curvature (or only the normals where nothing reads more),
// the saliency where asked; the user's cancel stops it.
TEST(PaperStages, IterationAnalysisComputesWhatThePlacementReads) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 3);
  const Rings rings = computeRings(int(sphere.points.size()), sphere.faces);
  const SmoothParams params;
  const ProgressFn go_on = [](int, const char *) { return true; };
  for (const bool curvature : {false, true})
    for (const bool saliency : {false, true}) {
      if (saliency && !curvature) continue; // (the saliency reads k2)
      SurfaceAnalysis analysis;
      SmoothReport report;
      EXPECT_TRUE(detail::analyseIteration(0, sphere, rings, sphere.points, params, curvature,
                                           saliency, 0.1, detail::PassProgress{go_on, 1, 100.0},
                                           analysis, report));
      EXPECT_EQ(analysis.curvature.normal.size(), sphere.points.size());
      EXPECT_EQ(analysis.curvature.mean.size(), curvature ? sphere.points.size() : 0u);
      if (curvature) EXPECT_NEAR(std::abs(analysis.curvature.mean[0]), 1.0, 0.05); // a unit sphere
      EXPECT_EQ(analysis.saliency.size(), saliency ? sphere.points.size() : 0u);
    }
  SurfaceAnalysis analysis;
  SmoothReport report;
  const ProgressFn stop = [](int, const char *) { return false; };
  EXPECT_FALSE(detail::analyseIteration(0, sphere, rings, sphere.points, params, true, true, 0.1,
                                        detail::PassProgress{stop, 1, 100.0}, analysis, report));
  EXPECT_TRUE(analysis.saliency.empty()); // stopped after the curvature
}
