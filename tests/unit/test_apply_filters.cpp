// The stages of the filters' API-independent core (filter_saliency_bezier_smooth/apply_filters.h)
// that the bad-input catalogue (test_bad_input.cpp) does not check one by one: the analysis
// filter's log and its curvature directions, and the dispatch by filter.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>

using namespace saliency_bezier;
using vcg_ext::Vec3;

// The log says how many vertices are salient, on the boundary and without faces, the mean |H|,
// and the values stored clamped.
TEST(ApplyFilterStages, AnalysisLogCountsWhatItSays) {
  // Two triangles (open: four boundary vertices) and a vertex in no face.
  const vcg_ext::MeshArrays m = test_meshes::fromArrays(
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(5, 5, 5)},
      {vcg_ext::Face{0, 1, 2}, vcg_ext::Face{1, 3, 2}});
  const vcg_ext::Rings rings = vcg_ext::computeRings(5, m.faces);
  vcg_ext::SurfaceAnalysis a;
  a.saliency = {0.9, 0.1, 0.6, 0.0, 0.0};
  a.curvature.mean = {1, -1, 2, 0, 0};
  const std::vector<std::string> log = detail::analysisLog(rings, a, 0.5, 0.003, 0);
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[0], "Saliency and curvature of 5 vertices in 0.500 s (epsilon = 0.003 of the bbox "
                    "diagonal).");
  EXPECT_EQ(log[1], "Vertices with saliency > 0.5: 2; mean |H| = 0.8; boundary vertices (curvature "
                    "from neighbours): 4.");
  EXPECT_EQ(log[2], "Curvature and saliency undefined, set to 0: 0 non-manifold, 1 isolated (in no "
                    "face) vertices.");
  EXPECT_EQ(detail::analysisLog(rings, a, 0.5, 0.003, 7).back(), detail::clampedLog(7));
}

// The principal directions and curvatures go to vcglib's own fields when the mesh has them
// (MeshLab's optional component), and nowhere otherwise.
TEST(ApplyFilterStages, CurvatureDirectionsGoToTheMeshsOwnFieldsWhereItHasThem) {
  test_vcg::FloatMesh m;
  test_vcg::assign(m, test_meshes::icosphere(1.0, 1));
  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(m);
  const size_t n = arrays.points.size();
  vcg_ext::CurvatureField c;
  c.dir1.assign(n, Vec3(1, 0, 0));
  c.dir2.assign(n, Vec3(0, 1, 0));
  c.k1.assign(n, 2.0);
  c.k2.assign(n, -0.5);
  const std::string before = test_vcg::snapshot(m);
  detail::storeCurvatureDirections(m, arrays, c); // the component is off: nothing to write
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
  m.vert.EnableCurvatureDir();
  detail::storeCurvatureDirections(m, arrays, c);
  for (size_t i = 0; i < n; ++i) {
    const auto &v = m.vert[arrays.mesh_slot[i]];
    EXPECT_EQ(v.cPD1()[0], 1.0f);
    EXPECT_EQ(v.cPD2()[1], 1.0f);
    EXPECT_EQ(v.cK1(), 2.0f);
    EXPECT_EQ(v.cK2(), -0.5f);
  }
}

// applyFilterById runs the filter it names: the analysis leaves the positions and stores the
// saliency; the smoothing moves a noisy mesh as applySaliencyBezierSmooth does.
TEST(ApplyFilterStages, DispatchRunsTheFilterItNames) {
  vcg_ext::MeshArrays noisy = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(noisy, 0.01, 7);
  test_vcg::DoubleMesh analysed, smoothed, direct;
  test_vcg::assign(analysed, noisy);
  test_vcg::assign(smoothed, noisy);
  test_vcg::assign(direct, noisy);
  const FilterOutcome a = applyFilterById(FilterId::ComputeSaliencyCurvature, analysed,
                                          defaultParameters(FilterId::ComputeSaliencyCurvature),
                                          nullptr);
  EXPECT_TRUE(a.ok);
  EXPECT_EQ(test_vcg::positions(analysed), noisy.points);
  EXPECT_TRUE(test_vcg::hasVertexAttribute(analysed, "Saliency"));
  const ParameterValues p = defaultParameters(FilterId::SaliencyBezierSmooth);
  EXPECT_TRUE(applyFilterById(FilterId::SaliencyBezierSmooth, smoothed, p, nullptr).ok);
  EXPECT_TRUE(applySaliencyBezierSmooth(direct, p, nullptr).ok);
  EXPECT_NE(test_vcg::positions(smoothed), noisy.points);
  EXPECT_EQ(test_vcg::positions(smoothed), test_vcg::positions(direct));
}
