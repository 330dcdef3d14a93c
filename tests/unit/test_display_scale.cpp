// vcg_ext/analysis/display_scale.h: the display scales of vertex quality (closed-form values, order
// independence, non-finite inputs) and, on a clean box, that saliency's display scale spreads the
// values MeshLab's full-range colour map sees.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/display_scale.h>
#include <vcg_ext/analysis/surface_analysis.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace vcg_ext;

TEST(DisplayScale, PercentileIsTheNearestRank) {
  std::vector<double> values;
  for (int i = 0; i < 101; ++i) values.push_back(100 - i); // 100 .. 0
  EXPECT_EQ(percentileOf(values, 0.99), 99.0);
  EXPECT_EQ(percentileOf(values, 0.5), 50.0);
  EXPECT_EQ(percentileOf(values, 0.0), 0.0);
  EXPECT_EQ(percentileOf(values, 1.0), 100.0);
  EXPECT_EQ(percentileOf({}, 0.5), 0.0);
}

TEST(DisplayScale, PercentileClippedDividesByThe99thAndClips) {
  std::vector<double> values;
  for (int i = 0; i <= 100; ++i) values.push_back(i);
  const std::vector<double> out = percentileClipped(values);
  EXPECT_DOUBLE_EQ(out[0], 0.0);
  EXPECT_DOUBLE_EQ(out[33], 33.0 / 99.0);
  EXPECT_DOUBLE_EQ(out[99], 1.0);
  EXPECT_DOUBLE_EQ(out[100], 1.0);
  EXPECT_EQ(percentileClipped(std::vector<double>(5, 0.0)), std::vector<double>(5, 0.0));
  EXPECT_EQ(percentileClipped({NAN, 1.0, 2.0})[0], 0.0);
}

TEST(DisplayScale, SignedLogKeepsSignAndMapsTheMedianMagnitudeToAsinhOne) {
  const std::vector<double> values = {-3, -1, 0.5, 1, 1, 2, 400};
  const std::vector<double> out = signedLogScale(values); // median |value| = 1
  ASSERT_EQ(out.size(), values.size());
  EXPECT_DOUBLE_EQ(out[1], -std::asinh(1.0));
  EXPECT_DOUBLE_EQ(out[3], std::asinh(1.0));
  EXPECT_DOUBLE_EQ(out[6], std::asinh(400.0));
  EXPECT_LT(out[0], 0);
  // Mostly zero (a flat mesh with one crease): scaled by the curved part, not left at zero.
  std::vector<double> flat(100, 0.0);
  flat[3] = 5, flat[4] = -5;
  const std::vector<double> f = signedLogScale(flat);
  EXPECT_DOUBLE_EQ(f[3], std::asinh(1.0));
  EXPECT_DOUBLE_EQ(f[0], 0.0);
}

TEST(DisplayScale, DoesNotDependOnOrder) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::vector<double> values(1000);
  for (double &v : values) v = g(rng) * g(rng);
  std::vector<int> perm(values.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = int(i);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::vector<double> shuffled(values.size());
  for (size_t i = 0; i < perm.size(); ++i) shuffled[i] = values[perm[i]];
  const std::vector<double> a = signedLogScale(values), b = signedLogScale(shuffled);
  for (size_t i = 0; i < perm.size(); ++i) EXPECT_EQ(b[i], a[perm[i]]);
}

TEST(DisplayScale, ABoxsCreasesAreSalientOnTheDisplayScale) {
  // Lee et al.'s saliency on the mean curvature of a clean box: its edges and corners stand out.
  // On the display scale the crease vertices reach the top of the colour map and the faces'
  // interiors stay low, so the full-range map shows the creases.
  const MeshArrays box = test_meshes::box(1.0, 1.0, 1.0, 12);
  const Rings rings = computeRings(int(box.points.size()), box.faces);
  SurfaceAnalysis analysis;
  analyseSurface(box.points, box.faces, rings, 0.02, analysis);
  const std::vector<double> shown = percentileClipped(analysis.saliency);
  double crease = 0, inside = 0;
  long creases = 0, insides = 0;
  for (size_t v = 0; v < box.points.size(); ++v) {
    const Vec3 a = box.points[v].cwiseAbs();
    const int on_faces = (a.x() > 0.999) + (a.y() > 0.999) + (a.z() > 0.999);
    if (on_faces >= 2) crease += shown[v], ++creases;
    else if ((a.array() < 0.5).count() == 2) inside += shown[v], ++insides;
  }
  ASSERT_GT(creases, 0);
  ASSERT_GT(insides, 0);
  EXPECT_GT(crease / creases, 0.5);
  EXPECT_LT(inside / insides, 0.1);
}
