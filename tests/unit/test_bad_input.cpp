// The bad-input catalogue (issue 6) through the filters' API-independent core, on MeshLab
// 2020.09's float CMeshO and on a double mesh (the scalar of 2025.07): what a user can load must
// never crash the filters, never produce a NaN/Inf position, and every refusal or cancel must leave
// the mesh bit for bit as it was.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>
#include <fuzz/fuzz_filters.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

using namespace saliency_bezier;
using test_meshes::fromArrays;
using vcg_ext::Face;
using vcg_ext::MeshArrays;
using vcg_ext::Vec3;

namespace {

const char *const kAttributes[] = {"Saliency", "MeanCurvature", "GaussianCurvature", "K1", "K2"};
const char *const kSmoothAttributes[] = {"Alpha", "Displacement"};

// The ring-barycentre placement (the paper's patch, a local per-vertex method): what most tests
// below check (each component smoothed as if alone, per-kind skip counts in the log) is its
// behaviour. The default automatic mode, like the feature and organic modes it runs, measures the
// noise over the whole mesh; it is covered by the tests that loop over every placement.
ParameterValues smoothDefaults() {
  ParameterValues p = defaultParameters(FilterId::SaliencyBezierSmooth);
  p["placement"] = 0;
  return p;
}

// Every placement the dialog offers (the last two run the feature-preserving and organic drivers).
const int kPlacements = [] {
  for (const ParamSpec &spec : parameterSpecs(FilterId::SaliencyBezierSmooth))
    if (spec.name == "placement") return int(spec.choices.size());
  return 0;
}();
ParameterValues analysisDefaults() { return defaultParameters(FilterId::ComputeSaliencyCurvature); }

template <class M>
FilterOutcome smooth(M &m, const ParameterValues &p = smoothDefaults(),
                     vcg::CallBackPos *cb = nullptr) {
  return applySaliencyBezierSmooth(m, p, cb);
}

template <class M>
FilterOutcome analyse(M &m, const ParameterValues &p = analysisDefaults(),
                      vcg::CallBackPos *cb = nullptr) {
  return applyComputeSaliency(m, p, cb);
}

std::string joined(const FilterOutcome &o) {
  std::string s;
  for (const std::string &line : o.log) s += line + "\n";
  return s;
}

// Largest coordinate difference between `m` scaled back by 1/s and `reference`.
template <class M>
double maxScaledDeviation(const M &m, const M &reference, double s) {
  double worst = 0;
  for (size_t v = 0; v < m.vert.size(); ++v)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(double(m.vert[v].cP()[k]) / s -
                                       double(reference.vert[v].cP()[k])));
  return worst;
}

// Live positions, quality and every attribute the filters write are finite.
template <class M>
void expectFiniteOutput(M &m) {
  for (const auto &v : m.vert) {
    if (v.IsD()) continue;
    ASSERT_TRUE(std::isfinite(double(v.cP()[0])) && std::isfinite(double(v.cP()[1])) &&
                std::isfinite(double(v.cP()[2])));
    ASSERT_TRUE(std::isfinite(double(v.cQ())));
  }
  for (const char *name : {"Saliency", "MeanCurvature", "GaussianCurvature", "K1", "K2", "Alpha",
                           "Displacement"}) {
    const std::vector<double> values = test_vcg::attribute(m, name);
    for (size_t i = 0; i < values.size(); ++i)
      if (!m.vert[i].IsD()) ASSERT_TRUE(std::isfinite(values[i])) << name << " at " << i;
  }
}

// Both filters refuse `m` with a message containing `reason` and leave it bit for bit unchanged.
template <class M>
void expectBothRefuse(M &m, const std::string &reason) {
  const std::string before = test_vcg::snapshot(m);
  const FilterOutcome smoothed = smooth(m);
  EXPECT_FALSE(smoothed.ok);
  EXPECT_NE(smoothed.error.find(reason), std::string::npos) << smoothed.error;
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
  const FilterOutcome analysed = analyse(m);
  EXPECT_FALSE(analysed.ok);
  EXPECT_NE(analysed.error.find(reason), std::string::npos) << analysed.error;
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
  for (const char *name : kAttributes) EXPECT_FALSE(test_vcg::hasVertexAttribute(m, name));
}

// A noisy 9x9 grid over [0,1]^2 in the plane z = 0 (noise along z).
MeshArrays noisyGrid(int n = 9, double sigma = 0.01, unsigned seed = 5) {
  MeshArrays g = test_meshes::heightField(n, 0, 1, 0, 1, [](double, double) { return 0.0; });
  test_meshes::addNoise(g, sigma, seed, [](int) { return Vec3(0, 0, 1); });
  return g;
}

MeshArrays noisySphere(int subdivisions = 3, double sigma = 0.02, unsigned seed = 9) {
  MeshArrays s = test_meshes::icosphere(1.0, subdivisions);
  test_meshes::addNoise(s, sigma, seed);
  return s;
}

// Root mean square of z over the listed vertices.
template <class M>
double rmsZ(const M &m, const std::vector<int> &vertices) {
  double sum = 0;
  for (int v : vertices) sum += double(m.vert[v].cP()[2]) * double(m.vert[v].cP()[2]);
  return std::sqrt(sum / vertices.size());
}

template <class M>
bool samePosition(const M &a, int va, const M &b, int vb) {
  const auto p = a.vert[va].cP(), q = b.vert[vb].cP();
  return std::memcmp(&p, &q, sizeof p) == 0;
}

// Vertex v of `m` is where `before` (test_vcg::positions of the input) had it.
template <class M>
bool unchanged(const M &m, int v, const std::vector<Vec3> &before) {
  return double(m.vert[v].cP()[0]) == before[v].x() && double(m.vert[v].cP()[1]) == before[v].y() &&
         double(m.vert[v].cP()[2]) == before[v].z();
}

MeshArrays concatenate(const std::vector<MeshArrays> &parts) {
  std::vector<Vec3> p;
  std::vector<Face> f;
  for (const MeshArrays &part : parts) {
    const int base = int(p.size());
    p.insert(p.end(), part.points.begin(), part.points.end());
    for (Face t : part.faces) f.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return fromArrays(std::move(p), std::move(f));
}

template <class M>
class BadInput : public ::testing::Test {};
using MeshTypes = ::testing::Types<test_vcg::FloatMesh, test_vcg::DoubleMesh>;
TYPED_TEST_SUITE(BadInput, MeshTypes);

} // namespace

TYPED_TEST(BadInput, EmptyMeshIsRefusedAndUnchanged) {
  TypeParam empty;
  expectBothRefuse(empty, "The mesh is empty.");
  // Every vertex deleted (MeshLab keeps them until compaction): empty as well.
  TypeParam all_deleted;
  test_vcg::assign(all_deleted, noisyGrid(3));
  for (auto &f : all_deleted.face) vcg::tri::Allocator<TypeParam>::DeleteFace(all_deleted, f);
  for (auto &v : all_deleted.vert) vcg::tri::Allocator<TypeParam>::DeleteVertex(all_deleted, v);
  expectBothRefuse(all_deleted, "The mesh is empty.");
}

TYPED_TEST(BadInput, PointCloudIsRefusedAndUnchanged) {
  MeshArrays cloud = noisyGrid();
  cloud.faces.clear();
  TypeParam m;
  test_vcg::assign(m, cloud);
  expectBothRefuse(m, "the mesh has no faces (a point cloud)");
  // Faces that are all deleted leave a point cloud too.
  TypeParam faces_deleted;
  test_vcg::assign(faces_deleted, noisyGrid());
  for (auto &f : faces_deleted.face) vcg::tri::Allocator<TypeParam>::DeleteFace(faces_deleted, f);
  expectBothRefuse(faces_deleted, "the mesh has no faces (a point cloud)");
}

TYPED_TEST(BadInput, NonFiniteCoordinatesAreRefusedAndUnchanged) {
  const double bad[] = {std::nan(""), INFINITY, -INFINITY};
  for (int axis = 0; axis < 3; ++axis) {
    MeshArrays g = noisyGrid();
    g.points[40][axis] = bad[axis];
    TypeParam m;
    test_vcg::assign(m, g);
    expectBothRefuse(m, "NaN or infinite vertex coordinates");
  }
  // An unreferenced vertex counts too: the filters do not guess which vertices matter.
  MeshArrays g = noisyGrid();
  g.points.push_back(Vec3(0.5, 0.5, std::nan("")));
  TypeParam m;
  test_vcg::assign(m, g);
  expectBothRefuse(m, "NaN or infinite vertex coordinates");
}

TYPED_TEST(BadInput, NonFiniteCoordinatesOfDeletedVerticesAreIgnored) {
  MeshArrays g = noisyGrid();
  g.points.push_back(Vec3(std::nan(""), 0, INFINITY));
  TypeParam m;
  test_vcg::assign(m, g);
  vcg::tri::Allocator<TypeParam>::DeleteVertex(m, m.vert.back());
  TypeParam reference;
  test_vcg::assign(reference, noisyGrid());
  ASSERT_TRUE(smooth(m).ok);
  ASSERT_TRUE(smooth(reference).ok);
  for (int v = 0; v < reference.vn; ++v) EXPECT_TRUE(samePosition(m, v, reference, v)) << v;
  EXPECT_TRUE(std::isnan(double(m.vert.back().cP()[0])));
  EXPECT_TRUE(analyse(m).ok);
  expectFiniteOutput(m);
}

TYPED_TEST(BadInput, BadParametersAreRefusedAndUnchanged) {
  TypeParam m;
  test_vcg::assign(m, noisyGrid());
  const std::string before = test_vcg::snapshot(m);
  for (const auto &[name, value] : std::vector<std::pair<std::string, double>>{
           {"iterations", std::nan("")}, {"iterations", -1}, {"alpha", INFINITY},
           {"placement", 9}, {"placement", -1}, {"saliency_scale", 0}, {"newton_step_limit", -1}}) {
    ParameterValues p = smoothDefaults();
    p[name] = value;
    const FilterOutcome o = smooth(m, p);
    EXPECT_FALSE(o.ok) << name;
    EXPECT_NE(o.error.find("Parameter '" + name + "'"), std::string::npos) << o.error;
    EXPECT_TRUE(test_vcg::snapshot(m) == before);
  }
  ParameterValues p = analysisDefaults();
  p["saliency_scale"] = std::nan("");
  EXPECT_FALSE(analyse(m, p).ok);
  p = smoothDefaults();
  p["selected_only"] = 1;
  const FilterOutcome o = smooth(m, p);
  EXPECT_FALSE(o.ok);
  EXPECT_NE(o.error.find("no vertex is selected"), std::string::npos);
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
}

TYPED_TEST(BadInput, NonManifoldEdgeIsSkippedAndReportedTheRestIsSmoothed) {
  MeshArrays g = noisyGrid();
  // A fin on the interior edge (40, 41): that edge now has three faces.
  const int a = 40, b = 41, fin = int(g.points.size());
  g.points.push_back(Vec3(0.5625, 0.5, 0.3));
  g.faces.push_back({a, b, fin});
  g.selected.push_back(0);
  TypeParam m;
  test_vcg::assign(m, g);
  std::vector<int> interior;
  for (int v = 0; v < 81; ++v)
    if (v % 9 != 0 && v % 9 != 8 && v / 9 != 0 && v / 9 != 8 && v != a && v != b)
      interior.push_back(v);
  const double rms_before = rmsZ(m, interior);
  const std::vector<Vec3> before = test_vcg::positions(m);
  const FilterOutcome o = smooth(m);
  ASSERT_TRUE(o.ok) << o.error;
  EXPECT_TRUE(unchanged(m, a, before));
  EXPECT_TRUE(unchanged(m, b, before));
  EXPECT_NE(joined(o).find("2 non-manifold"), std::string::npos) << joined(o);
  EXPECT_LT(rmsZ(m, interior), 0.5 * rms_before);
  int moved = 0;
  for (int v : interior) moved += !unchanged(m, v, before);
  EXPECT_EQ(moved, int(interior.size()));
  expectFiniteOutput(m);
  const FilterOutcome analysed = analyse(m);
  ASSERT_TRUE(analysed.ok);
  EXPECT_NE(joined(analysed).find("2 non-manifold"), std::string::npos) << joined(analysed);
  expectFiniteOutput(m);
  // Curvature is undefined at a non-manifold vertex: zero, not made up.
  EXPECT_EQ(test_vcg::attribute(m, "K1")[a], 0.0);
}

TYPED_TEST(BadInput, NonManifoldVertexIsSkippedAndReportedTheRestIsSmoothed) {
  MeshArrays g = noisyGrid();
  // A second fan (two triangles above the grid) touching the grid only at vertex 40: a bow-tie.
  const int apex = 40, p = int(g.points.size());
  g.points.push_back(Vec3(0.4, 0.6, 0.2));
  g.points.push_back(Vec3(0.5, 0.7, 0.25));
  g.points.push_back(Vec3(0.6, 0.6, 0.2));
  g.faces.push_back({apex, p, p + 1});
  g.faces.push_back({apex, p + 1, p + 2});
  TypeParam m;
  test_vcg::assign(m, g);
  std::vector<int> interior;
  for (int v = 0; v < 81; ++v)
    if (v % 9 != 0 && v % 9 != 8 && v / 9 != 0 && v / 9 != 8 && v != apex) interior.push_back(v);
  const double rms_before = rmsZ(m, interior);
  const std::vector<Vec3> before = test_vcg::positions(m);
  const FilterOutcome o = smooth(m);
  ASSERT_TRUE(o.ok) << o.error;
  EXPECT_TRUE(unchanged(m, apex, before));
  EXPECT_NE(joined(o).find("1 non-manifold"), std::string::npos) << joined(o);
  EXPECT_LT(rmsZ(m, interior), 0.5 * rms_before);
  expectFiniteOutput(m);
}

TYPED_TEST(BadInput, DegenerateFacesFreezeTheirVerticesTheRestIsSmoothed) {
  MeshArrays g = noisyGrid();
  // Zero area: vertex 41 exactly on the segment from 40 to 50 (grid face {40, 41, 50}; the values
  // are exact in float too), and a face with a repeated vertex, {20, 21, 21}.
  g.points[40] = Vec3(0.5, 0.5, 0);
  g.points[50] = Vec3(0.625, 0.625, 0);
  g.points[41] = Vec3(0.5625, 0.5625, 0);
  g.faces.push_back({20, 21, 21});
  TypeParam m;
  test_vcg::assign(m, g);
  std::vector<int> interior;
  const std::set<int> degenerate = {40, 41, 50, 20, 21};
  for (int v = 0; v < 81; ++v)
    if (v % 9 != 0 && v % 9 != 8 && v / 9 != 0 && v / 9 != 8 && !degenerate.count(v))
      interior.push_back(v);
  const double rms_before = rmsZ(m, interior);
  const std::vector<Vec3> before = test_vcg::positions(m);
  const FilterOutcome o = smooth(m);
  ASSERT_TRUE(o.ok) << o.error;
  for (int v : degenerate) EXPECT_TRUE(unchanged(m, v, before)) << v;
  // The repeated index also gives edge (20, 21) a third and fourth face: non-manifold.
  EXPECT_NE(joined(o).find("2 non-manifold"), std::string::npos) << joined(o);
  EXPECT_NE(joined(o).find("3 on degenerate faces"), std::string::npos) << joined(o);
  EXPECT_LT(rmsZ(m, interior), 0.5 * rms_before);
  expectFiniteOutput(m);
  ASSERT_TRUE(analyse(m).ok);
  expectFiniteOutput(m);
}

TYPED_TEST(BadInput, UnreferencedAndDuplicateVerticesStayAndChangeNothingElse) {
  const MeshArrays g = noisyGrid();
  MeshArrays extra = g;
  extra.points.push_back(g.points[40]);       // an unreferenced duplicate
  extra.points.push_back(Vec3(30, -20, 10)); // an unreferenced vertex far away
  TypeParam m, reference;
  test_vcg::assign(m, extra);
  test_vcg::assign(reference, g);
  const std::vector<Vec3> before = test_vcg::positions(m);
  const FilterOutcome o = smooth(m);
  ASSERT_TRUE(o.ok) << o.error;
  ASSERT_TRUE(smooth(reference).ok);
  EXPECT_NE(joined(o).find("2 isolated"), std::string::npos) << joined(o);
  for (int v = 0; v < 81; ++v) EXPECT_TRUE(samePosition(m, v, reference, v)) << v;
  EXPECT_TRUE(unchanged(m, 81, before));
  EXPECT_TRUE(unchanged(m, 82, before));
  expectFiniteOutput(m);
  ASSERT_TRUE(analyse(m).ok);
  expectFiniteOutput(m);
}

TYPED_TEST(BadInput, UnweldedSeamSmoothsLikeTwoSeparateMeshes) {
  // Two grids sharing the line x = 1 geometrically but with duplicated vertices (an unwelded seam,
  // as STL files give): topologically two meshes, each smoothed as if alone.
  MeshArrays left = noisyGrid(9, 0.01, 3), right = noisyGrid(9, 0.01, 4);
  for (Vec3 &p : right.points) p.x() += 1;
  for (int j = 0; j < 9; ++j) right.points[j * 9] = left.points[j * 9 + 8];
  TypeParam both;
  test_vcg::assign(both, concatenate({left, right}));
  TypeParam left_alone;
  test_vcg::assign(left_alone, left);
  TypeParam right_alone;
  test_vcg::assign(right_alone, right);
  ASSERT_TRUE(smooth(both).ok);
  ASSERT_TRUE(smooth(left_alone).ok);
  ASSERT_TRUE(smooth(right_alone).ok);
  for (int v = 0; v < 81; ++v) {
    EXPECT_TRUE(samePosition(both, v, left_alone, v)) << v;
    EXPECT_TRUE(samePosition(both, 81 + v, right_alone, v)) << v;
  }
}

TYPED_TEST(BadInput, SingleTriangle) {
  const MeshArrays triangle =
      fromArrays({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.8, 0)}, {Face{0, 1, 2}});
  {
    TypeParam m;
    test_vcg::assign(m, triangle);
    const std::vector<Vec3> before = test_vcg::positions(m);
    const FilterOutcome o = smooth(m);
    ASSERT_TRUE(o.ok) << o.error;
    // Three boundary corners: nothing may move.
    for (int v = 0; v < 3; ++v) EXPECT_TRUE(unchanged(m, v, before));
    expectFiniteOutput(m);
  }
  // Every placement with boundary vertices treated like the others: finite and in the plane.
  for (int placement = 0; placement < kPlacements; ++placement) {
    TypeParam m;
    test_vcg::assign(m, triangle);
    ParameterValues p = smoothDefaults();
    p["boundary"] = 0;
    p["placement"] = placement;
    p["fold_handling"] = placement == 1;
    ASSERT_TRUE(smooth(m, p).ok);
    expectFiniteOutput(m);
    for (int v = 0; v < 3; ++v) EXPECT_EQ(double(m.vert[v].cP()[2]), 0.0);
  }
  TypeParam m;
  test_vcg::assign(m, triangle);
  const FilterOutcome o = analyse(m);
  ASSERT_TRUE(o.ok) << o.error;
  expectFiniteOutput(m);
  // No interior vertex: curvature and saliency are zero, not invented.
  for (const char *name : kAttributes)
    for (double value : test_vcg::attribute(m, name)) EXPECT_EQ(value, 0.0) << name;
}

TYPED_TEST(BadInput, ManySmallComponentsSmoothEachAsIfAlone) {
  std::vector<MeshArrays> parts;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> offset(-20, 20);
  for (int k = 0; k < 60; ++k) {
    MeshArrays part;
    if (k % 3 == 0) {
      part = fromArrays({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},
                        {Face{0, 2, 1}, Face{0, 1, 3}, Face{0, 3, 2}, Face{1, 2, 3}});
      test_meshes::addNoise(part, 0.05, 100 + k);
    } else if (k % 3 == 1) {
      part = fromArrays({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.8, 0.1)}, {Face{0, 1, 2}});
    } else {
      part = noisyGrid(4, 0.02, 200 + k);
    }
    const Vec3 shift(offset(rng), offset(rng), offset(rng));
    for (Vec3 &p : part.points) p += shift;
    parts.push_back(part);
  }
  TypeParam all;
  test_vcg::assign(all, concatenate(parts));
  const std::vector<Vec3> before = test_vcg::positions(all);
  const FilterOutcome o = smooth(all);
  ASSERT_TRUE(o.ok) << o.error;
  expectFiniteOutput(all);
  int base = 0, moved = 0;
  for (const MeshArrays &part : parts) {
    TypeParam alone;
    test_vcg::assign(alone, part);
    ASSERT_TRUE(smooth(alone).ok);
    for (int v = 0; v < int(part.points.size()); ++v) {
      EXPECT_TRUE(samePosition(all, base + v, alone, v)) << base + v;
      moved += !unchanged(all, base + v, before);
    }
    base += int(part.points.size());
  }
  EXPECT_GT(moved, 100);
  ASSERT_TRUE(analyse(all).ok);
  expectFiniteOutput(all);
}

// Smoothing a mesh scaled by s gives the scaled result (relative to the bounding box), for both
// filters' outputs: positions scale with s, curvatures with 1/s, saliency is unchanged.
TYPED_TEST(BadInput, HugeAndTinyCoordinatesAreScaleEquivariant) {
  const MeshArrays base = noisySphere();
  const double diagonal = 2 * std::sqrt(3.0);
  // Every driver: the ring barycentre, the feature mode, the organic mode (whose noise probe once
  // hashed raw coordinates: 1e-3 of the diagonal off at 1e7) and the automatic mode.
  for (int placement : {3, 4, kPlacements - 1}) {
    ParameterValues p = smoothDefaults();
    p["placement"] = placement;
    TypeParam reference;
    test_vcg::assign(reference, base);
    ASSERT_TRUE(smooth(reference, p).ok);
    for (double s : {1e7, 1e-7}) {
      MeshArrays scaled = base;
      for (Vec3 &q : scaled.points) q = q * s + Vec3(3, -2, 5) * s; // moved as well
      TypeParam m;
      test_vcg::assign(m, scaled);
      ASSERT_TRUE(smooth(m, p).ok);
      const std::vector<Vec3> got = test_vcg::positions(m), want = test_vcg::positions(reference);
      double worst = 0;
      for (size_t v = 0; v < got.size(); ++v)
        worst = std::max(worst, (got[v] / s - Vec3(3, -2, 5) - want[v]).norm());
      EXPECT_LT(worst / diagonal, 1e-6) << "placement " << placement << ", scale " << s;
    }
  }
  TypeParam reference;
  test_vcg::assign(reference, base);
  ASSERT_TRUE(smooth(reference).ok);
  TypeParam reference_analysis;
  test_vcg::assign(reference_analysis, base);
  ASSERT_TRUE(analyse(reference_analysis).ok);
  const std::vector<double> k1 = test_vcg::attribute(reference_analysis, "K1");
  const std::vector<double> saliency = test_vcg::attribute(reference_analysis, "Saliency");
  double k1_max = 0;
  for (double k : k1) k1_max = std::max(k1_max, std::abs(k));
  for (double s : {1e7, 1e-7}) {
    MeshArrays scaled = base;
    for (Vec3 &p : scaled.points) p *= s;
    TypeParam m;
    test_vcg::assign(m, scaled);
    const FilterOutcome o = smooth(m);
    ASSERT_TRUE(o.ok) << o.error;
    expectFiniteOutput(m);
    const double worst = maxScaledDeviation(m, reference, s);
    EXPECT_LT(worst / diagonal, 1e-6) << "scale " << s;

    TypeParam a;

    test_vcg::assign(a, scaled);
    ASSERT_TRUE(analyse(a).ok);
    expectFiniteOutput(a);
    const std::vector<double> k1_scaled = test_vcg::attribute(a, "K1");
    const std::vector<double> saliency_scaled = test_vcg::attribute(a, "Saliency");
    double worst_k1 = 0, worst_saliency = 0;
    for (size_t v = 0; v < k1.size(); ++v) {
      worst_k1 = std::max(worst_k1, std::abs(k1_scaled[v] * s - k1[v]));
      worst_saliency = std::max(worst_saliency, std::abs(saliency_scaled[v] - saliency[v]));
    }
    EXPECT_LT(worst_k1 / k1_max, 1e-5) << "scale " << s;
    EXPECT_LT(worst_saliency, 1e-5) << "scale " << s;
  }
}

// Far from the origin (a scan in survey coordinates): only the double mesh can hold a 1-unit mesh
// at 1e7 (float's spacing there is 1); the result is the translated result.
TEST(BadInputDouble, HugeOffsetIsTranslationEquivariant) {
  const MeshArrays base = noisyGrid();
  test_vcg::DoubleMesh reference;
  test_vcg::assign(reference, base);
  ASSERT_TRUE(smooth(reference).ok);
  const Vec3 offset(1e7, -3e7, 2e7);
  MeshArrays far = base;
  for (Vec3 &p : far.points) p += offset;
  test_vcg::DoubleMesh m;
  test_vcg::assign(m, far);
  ASSERT_TRUE(smooth(m).ok);
  double worst = 0;
  for (size_t v = 0; v < m.vert.size(); ++v)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(m.vert[v].cP()[k] - offset[k] - reference.vert[v].cP()[k]));
  EXPECT_LT(worst / std::sqrt(2.0), 1e-6);
}

// Scales that double arithmetic on products of lengths cannot carry are refused, not overflowed
// or silently left unsmoothed (below ~1e-77 the normals' squared norms vanish).
TYPED_TEST(BadInput, AbsurdScalesAreRefused) {
  MeshArrays g = noisyGrid();
  g.points[7].y() = 1e31;
  TypeParam huge;
  test_vcg::assign(huge, g);
  expectBothRefuse(huge, "coordinates beyond 1e30");
  MeshArrays microscopic = noisySphere(1);
  for (Vec3 &p : microscopic.points) p *= 1e-31;
  TypeParam tiny;
  test_vcg::assign(tiny, microscopic);
  expectBothRefuse(tiny, "smaller than 1e-30 across");
  MeshArrays collapsed = noisySphere(1);
  for (Vec3 &p : collapsed.points) p = Vec3(1, 2, 3);
  TypeParam point;
  test_vcg::assign(point, collapsed);
  expectBothRefuse(point, "all its vertices coincide");
}

// Just inside the limits: smoothing is still scale-equivariant (positions), and curvatures beyond
// a float mesh's range (K = 1/r^2 = 1e58 at r = 1e-29) are stored as its largest value and reported.
TYPED_TEST(BadInput, ExtremeScalesInsideTheLimits) {
  const MeshArrays base = noisySphere(2);
  TypeParam reference;
  test_vcg::assign(reference, base);
  ASSERT_TRUE(smooth(reference).ok);
  for (double s : {1e-25, 1e25}) {
    MeshArrays scaled = base;
    for (Vec3 &p : scaled.points) p *= s;
    TypeParam m;
    test_vcg::assign(m, scaled);
    ASSERT_TRUE(smooth(m).ok);
    expectFiniteOutput(m);
    const double worst = maxScaledDeviation(m, reference, s);
    EXPECT_LT(worst / 2, 1e-6) << "scale " << s;
  }
  MeshArrays tiny = base;
  for (Vec3 &p : tiny.points) p *= 1e-29;
  TypeParam m;
  test_vcg::assign(m, tiny);
  const FilterOutcome o = analyse(m);
  ASSERT_TRUE(o.ok) << o.error;
  expectFiniteOutput(m);
  const std::vector<double> gauss = test_vcg::attribute(m, "GaussianCurvature");
  const double largest = *std::max_element(gauss.begin(), gauss.end());
  if (std::is_same_v<typename TypeParam::ScalarType, float>) {
    EXPECT_EQ(largest, double(std::numeric_limits<float>::max()));
    EXPECT_NE(joined(o).find("beyond the mesh's number range"), std::string::npos) << joined(o);
  } else {
    TypeParam unit;
    test_vcg::assign(unit, base);
    ASSERT_TRUE(analyse(unit).ok);
    const std::vector<double> unit_gauss = test_vcg::attribute(unit, "GaussianCurvature");
    EXPECT_NEAR(largest * 1e-58 / *std::max_element(unit_gauss.begin(), unit_gauss.end()), 1.0,
                1e-6);
  }
}

TYPED_TEST(BadInput, QuadsAndPolygonsAreTriangulatedOnImport) {
  // A 10x10-vertex grid of quads with noise, and one hexagon, as an ASCII PLY.
  const int n = 10;
  std::mt19937 rng(17);
  std::normal_distribution<double> noise(0, 0.01);
  std::string text;
  std::vector<std::string> vertices, faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      char line[96];
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g", i / 9.0, j / 9.0, noise(rng));
      vertices.push_back(line);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      faces.push_back("4 " + std::to_string(a) + " " + std::to_string(a + 1) + " " +
                      std::to_string(a + n + 1) + " " + std::to_string(a + n));
    }
  const int hexagon = int(vertices.size());
  for (int k = 0; k < 6; ++k) {
    char line[96];
    std::snprintf(line, sizeof line, "%.9g %.9g 0", 3 + std::cos(k * M_PI / 3), std::sin(k * M_PI / 3));
    vertices.push_back(line);
  }
  std::string hex = "6";
  for (int k = 0; k < 6; ++k) hex += " " + std::to_string(hexagon + k);
  faces.push_back(hex);
  text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertices.size()) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto &v : vertices) text += v + "\n";
  for (const auto &f : faces) text += f + "\n";
  const std::string path = ::testing::TempDir() + "sbs_quads.ply";
  std::ofstream(path) << text;

  TypeParam m;
  int mask = 0;
  ASSERT_EQ(vcg::tri::io::ImporterPLY<TypeParam>::Open(m, path.c_str(), mask), 0);
  EXPECT_EQ(m.vn, n * n + 6);
  EXPECT_EQ(m.fn, 2 * (n - 1) * (n - 1) + 4); // fan triangulation: a quad gives 2, a hexagon 4
  std::vector<int> interior;
  for (int v = 0; v < n * n; ++v)
    if (v % n != 0 && v % n != n - 1 && v / n != 0 && v / n != n - 1) interior.push_back(v);
  const double rms_before = rmsZ(m, interior);
  const std::vector<Vec3> before = test_vcg::positions(m);
  ParameterValues p = smoothDefaults();
  p["boundary"] = 1; // fixed: the interior's noise is what this measures
  const FilterOutcome o = smooth(m, p);
  ASSERT_TRUE(o.ok) << o.error;
  expectFiniteOutput(m);
  EXPECT_LT(rmsZ(m, interior), 0.5 * rms_before);
  // The hexagon's six vertices are boundary corners (60 degree turns): they stay.
  for (int k = 0; k < 6; ++k) EXPECT_TRUE(unchanged(m, hexagon + k, before));
  std::remove(path.c_str());
}

TYPED_TEST(BadInput, DeletedElementsGiveTheCompactedResult) {
  using Allocator = vcg::tri::Allocator<TypeParam>;
  TypeParam m;
  test_vcg::assign(m, noisySphere());
  std::mt19937 rng(21);
  // As MeshLab's "Delete selected vertices": a vertex and its faces; then some faces alone; and
  // one vertex deleted without its faces (a face left pointing at a deleted vertex is skipped).
  std::set<int> dead_vertices;
  while (dead_vertices.size() < 40) dead_vertices.insert(int(rng() % m.vert.size()));
  int lone = 0;
  for (int v : dead_vertices) {
    if (lone++ == 0) continue;
    for (auto &f : m.face)
      if (!f.IsD() && (f.V(0) == &m.vert[v] || f.V(1) == &m.vert[v] || f.V(2) == &m.vert[v]))
        Allocator::DeleteFace(m, f);
  }
  for (int v : dead_vertices) Allocator::DeleteVertex(m, m.vert[v]);
  for (int k = 0; k < 30; ++k) {
    auto &f = m.face[rng() % m.face.size()];
    if (!f.IsD()) Allocator::DeleteFace(m, f);
  }
  const MeshArrays live = vcg_ext::extractArrays(m);
  TypeParam compact;
  test_vcg::assign(compact, live);
  ASSERT_EQ(compact.vn, m.vn);
  ASSERT_LT(compact.fn, m.fn); // the faces of the vertex deleted alone are not in `live`
  const std::vector<Vec3> before = test_vcg::positions(m);
  const int vn_before = m.vn, fn_before = m.fn;

  const FilterOutcome o = smooth(m);
  ASSERT_TRUE(o.ok) << o.error;
  ASSERT_TRUE(smooth(compact).ok);
  expectFiniteOutput(m);
  const std::vector<double> k1 = test_vcg::attribute(m, "K1"),
                            k1_compact = test_vcg::attribute(compact, "K1");
  for (size_t c = 0; c < live.points.size(); ++c) {
    const int slot = live.mesh_slot[c];
    EXPECT_TRUE(samePosition(m, slot, compact, int(c))) << slot;
    EXPECT_EQ(k1[slot], k1_compact[c]);
    EXPECT_EQ(m.vert[slot].cQ(), compact.vert[c].cQ());
  }
  for (int v : dead_vertices) {
    EXPECT_TRUE(unchanged(m, v, before));
    EXPECT_TRUE(m.vert[v].IsD());
  }
  EXPECT_EQ(m.vn, vn_before);
  EXPECT_EQ(m.fn, fn_before);
}

namespace {
// A progress callback that counts its calls and refuses the `cancel_at`-th (0: never).
int g_calls = 0, g_cancel_at = 0;
bool countingCallback(int, const char *) { return ++g_calls != g_cancel_at; }
} // namespace

TYPED_TEST(BadInput, CancelAtAnyPointRestoresTheExactInput) {
  for (int placement : {0, 2, kPlacements - 2, kPlacements - 1}) {
    // A mesh that already carries everything the filters write (an earlier run, different values).
    TypeParam m, probe;
    ParameterValues first = smoothDefaults();
    first["iterations"] = 1;
    for (TypeParam *mesh : {&m, &probe}) {
      test_vcg::assign(*mesh, noisySphere());
      ASSERT_TRUE(smooth(*mesh, first).ok);
    }
    ParameterValues p = smoothDefaults();
    p["placement"] = placement;
    g_calls = 0, g_cancel_at = 0;
    ASSERT_TRUE(smooth(probe, p, countingCallback).ok);
    const int total = g_calls;
    ASSERT_GE(total, 3) << "placement " << placement;
    const std::string before = test_vcg::snapshot(m);
    for (int at : std::set<int>{1, 2, 3, total / 2, total - 1, total}) {
      g_calls = 0, g_cancel_at = at;
      const FilterOutcome o = smooth(m, p, countingCallback);
      EXPECT_FALSE(o.ok) << "cancel at call " << at << " of " << total;
      EXPECT_NE(o.error.find("Cancelled"), std::string::npos);
      EXPECT_TRUE(test_vcg::snapshot(m) == before) << "cancel at call " << at;
    }
  }
  TypeParam m;
  test_vcg::assign(m, noisySphere());
  ASSERT_TRUE(analyse(m).ok);
  const std::string before = test_vcg::snapshot(m);
  for (int at : {1, 2, 3}) {
    g_calls = 0, g_cancel_at = at;
    ParameterValues p = analysisDefaults();
    p["quality"] = 3;
    EXPECT_FALSE(analyse(m, p, countingCallback).ok);
    EXPECT_TRUE(test_vcg::snapshot(m) == before) << "cancel at call " << at;
  }
}

// The float mesh with MeshLab's optional curvature directions switched on: they are written on
// success and untouched on cancel.
TEST(BadInputFloat, CancelLeavesEnabledCurvatureDirectionsUntouched) {
  test_vcg::FloatMesh m;
  test_vcg::assign(m, noisySphere(2));
  m.vert.EnableCurvatureDir();
  for (auto &v : m.vert) v.PD1() = vcg::Point3f(1, 2, 3), v.K1() = 7;
  const std::string before = test_vcg::snapshot(m);
  g_calls = 0, g_cancel_at = 2;
  EXPECT_FALSE(analyse(m, analysisDefaults(), countingCallback).ok);
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
  ASSERT_TRUE(analyse(m).ok);
  EXPECT_NE(m.vert[0].PD1(), vcg::Point3f(1, 2, 3));
  EXPECT_NEAR(m.vert[0].PD1().Norm(), 1.0, 1e-6);
}

// Every parameter combination on a noisy mesh with every defect at once: no NaN, ever.
TYPED_TEST(BadInput, EveryModeOnADefectiveMeshGivesFiniteOutput) {
  MeshArrays g = noisyGrid(9, 0.05, 31);
  g.points.push_back(Vec3(0.5625, 0.5, 0.3)); // fin: non-manifold edge (40, 41)
  g.faces.push_back({40, 41, 81});
  g.faces.push_back({20, 21, 21});                       // repeated index
  g.faces.push_back({60, 61, 70});                       // a duplicate face
  g.points.push_back(g.points[5]);                       // unreferenced duplicate
  g.points.push_back(Vec3(0.1, 0.1, 0.1) + g.points[5]); // isolated
  for (int placement = 0; placement < kPlacements; ++placement)
    for (int boundary = 0; boundary < 4; ++boundary)
      for (int folds = 0; folds < 2; ++folds)
        for (int alpha_override = 0; alpha_override < 2; ++alpha_override) {
          TypeParam m;
          test_vcg::assign(m, g);
          ParameterValues p = smoothDefaults();
          p["placement"] = placement, p["boundary"] = boundary, p["fold_handling"] = folds;
          p["alpha_override"] = alpha_override;
          p["newton_step_limit"] = placement == 2 && folds ? 0 : 1;
          p["quality"] = (placement * 3 + boundary) % 7;
          const FilterOutcome o = smooth(m, p);
          ASSERT_TRUE(o.ok) << o.error;
          expectFiniteOutput(m);
        }
}

// A nearly singular patch fit (9 points near a grid corner almost interpolating the 9 control
// points) once threw boundary vertices 36 grid steps (4.6 units) off a noisy unit plane; such a
// patch is now a failed fit and the vertex stays.
TYPED_TEST(BadInput, NoVertexIsThrownFarFromItsNeighbourhood) {
  const MeshArrays g = noisyGrid();
  for (int placement = 0; placement < 3; ++placement) {
    TypeParam m;
    test_vcg::assign(m, g);
    ParameterValues p = smoothDefaults();
    p["boundary"] = 0; // boundary vertices fitted like the others (the paper)
    p["placement"] = placement;
    const FilterOutcome o = smooth(m, p);
    ASSERT_TRUE(o.ok) << o.error;
    // In the plane the paper's boundary shrinks; off the plane nothing may go beyond the noise.
    double noise = 0, worst = 0;
    for (int v = 0; v < 81; ++v) {
      noise = std::max(noise, std::abs(g.points[v].z()));
      worst = std::max(worst, std::abs(double(m.vert[v].cP()[2])));
    }
    // Paper (Newton) moves along the patch toward its curvature target, as far as its step limit
    // (one mean edge, 0.125 here) lets it.
    EXPECT_LT(worst, placement == 2 ? 0.125 : noise) << "placement " << placement << "\n"
                                                      << joined(o);
    EXPECT_NE(joined(o).find("failed fits"), std::string::npos) << joined(o);
  }
}

// The fuzz target's checks on its committed seed corpus and on every input a longer fuzz run ever
// failed on (tests/fuzz/regressions/, named after what they found): any violation aborts.
TEST(FuzzCorpus, SeedsAndPastFindingsPass) {
  namespace fs = std::filesystem;
  const fs::path fuzz_dir = fs::path(__FILE__).parent_path().parent_path() / "fuzz";
  int inputs = 0;
  for (const char *folder : {"corpus", "regressions"}) {
    if (!fs::is_directory(fuzz_dir / folder)) continue;
    for (const auto &entry : fs::directory_iterator(fuzz_dir / folder)) {
      std::ifstream file(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
      SCOPED_TRACE(entry.path().string());
      sbs_fuzz::runInput(reinterpret_cast<const uint8_t *>(bytes.data()), bytes.size());
      ++inputs;
    }
  }
  EXPECT_GE(inputs, 20);
}

// Attributes of the filters' names left by something else with another type (vcglib's lookup
// checks only the size, so an int "Saliency" on a float mesh used to be written as a float).
TYPED_TEST(BadInput, StaleAttributesOfAnotherTypeAreReplaced) {
  using Allocator = vcg::tri::Allocator<TypeParam>;
  using Scalar = typename TypeParam::ScalarType;
  TypeParam m;
  test_vcg::assign(m, noisySphere(2));
  auto stale_int = Allocator::template AddPerVertexAttribute<int>(m, "Saliency");
  auto stale_point = Allocator::template AddPerVertexAttribute<vcg::Point3f>(m, "K1");
  for (size_t i = 0; i < m.vert.size(); ++i) stale_int[i] = 7, stale_point[i] = vcg::Point3f(1, 2, 3);
  ASSERT_TRUE(smooth(m).ok);
  for (const auto &a : m.vert_attr)
    if (a._name == "Saliency" || a._name == "K1")
      EXPECT_TRUE(a._type == std::type_index(typeid(Scalar))) << a._name;
  const std::vector<double> saliency = test_vcg::attribute(m, "Saliency");
  ASSERT_EQ(saliency.size(), m.vert.size());
  EXPECT_EQ(*std::max_element(saliency.begin(), saliency.end()), 1.0); // rescaled to [0, 1]
  expectFiniteOutput(m);
}

// A closed mesh that the fits flatten (an octahedron: every vertex's 2-ring is the whole mesh) lost
// all its volume, and the first-order volume-restoring offset (missing volume / swept area, with
// the swept area near 0) threw its vertices 1e15 edge lengths away (found by the fuzzer).
TYPED_TEST(BadInput, CollapsingClosedMeshGetsNoRunawayVolumeOffset) {
  const MeshArrays octahedron =
      fromArrays({Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                  Vec3(0, 0, -1)},
                 {Face{0, 2, 4}, Face{2, 1, 4}, Face{1, 3, 4}, Face{3, 0, 4}, Face{2, 0, 5},
                  Face{1, 2, 5}, Face{3, 1, 5}, Face{0, 3, 5}, Face{4, 4, 5}});
  TypeParam m;
  test_vcg::assign(m, octahedron);
  ParameterValues p = smoothDefaults();
  p["placement"] = 1;
  p["alpha"] = 0.65490196078431373;
  p["preserve_volume"] = 1;
  const FilterOutcome o = smooth(m, p);
  ASSERT_TRUE(o.ok) << o.error;
  expectFiniteOutput(m);
  for (const Vec3 &q : test_vcg::positions(m)) EXPECT_LE(q.cwiseAbs().maxCoeff(), 1.0) << joined(o);
}
