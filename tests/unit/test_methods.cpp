// The method table (vcg_ext/methods.h) and the parameters every method shares (driver_setup.h):
// each parameter a row says its method reads changes that method's result, on a noisy closed CAD
// part (a box) and a noisy open organic surface (a bumpy height field); the strength (iterations in
// the measured methods) orders how far vertices move and smooths a mesh measured as clean only
// when asked; the face patches' α flattens them.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <support/measures.h>

using namespace vcg_ext;
using test_meshes::largestDifference;

namespace {

MeshArrays noisyBox() {
  MeshArrays box = test_meshes::box(1.0, 0.8, 0.6, 8);
  test_meshes::addNoise(box, 0.3 * 0.2, 7); // random directions, 0.3 of the 0.2 grid spacing
  return box;
}

MeshArrays noisyBumps() {
  MeshArrays bumps = test_meshes::heightField(24, -1, 1, -1, 1, [](double x, double y) {
    return 0.25 * std::sin(2.5 * x) * std::cos(2.0 * y);
  });
  test_meshes::addNoise(bumps, 0.3 * 2.0 / 23, 11);
  return bumps;
}

struct Result {
  std::vector<Vec3> points;
  VertexQuantities q;
  MethodRun run;
};

Result runMethod(const MethodRow &row, const MeshArrays &mesh, const MethodParams &params) {
  Result r;
  r.run = row.run(mesh, params, r.points, r.q, nullptr);
  return r;
}

double meanDisplacement(const Result &r) {
  double sum = 0;
  for (double d : r.q.displacement) sum += d;
  return sum / double(r.q.displacement.size());
}

// A value other than the default for every parameter a row can list.
const std::map<std::string, std::function<void(MethodParams &)>> &changes() {
  static const std::map<std::string, std::function<void(MethodParams &)>> table = {
      {"iterations", [](MethodParams &p) { p.iterations = 6; }},
      {"alpha_override", [](MethodParams &p) { p.alpha_override = false; }},
      {"alpha", [](MethodParams &p) { p.alpha = 0.4; }},
      {"boundary", [](MethodParams &p) { p.boundary = BoundaryMode::Fixed; }},
      {"fold_handling", [](MethodParams &p) { p.folds = FoldHandling::Paper; }},
      {"uniform_curvature", [](MethodParams &p) { p.uniform_variant = UniformCurvatureVariant::Paper; }},
      {"newton_iterations", [](MethodParams &p) { p.newton_iterations = 4; }},
      {"newton_step_limit", [](MethodParams &p) { p.newton_step_limit = 0.2; }},
  };
  return table;
}

} // namespace

TEST(Methods, TableRowsAreTheScriptIndicesOfOldScripts) {
  const auto &table = methodTable();
  ASSERT_EQ(table.size(), 6u);
  const char *keys[] = {"ring", "patch", "newton", "feature", "organic", "automatic"};
  for (size_t i = 0; i < table.size(); ++i) EXPECT_STREQ(table[i].key, keys[i]);
  EXPECT_STREQ(table[kDefaultMethod].key, "automatic");
}

TEST(Methods, EveryParameterARowListsChangesItsResult) {
  const MeshArrays meshes[] = {noisyBox(), noisyBumps()};
  for (const MethodRow &row : methodTable()) {
    const std::vector<Vec3> base[] = {runMethod(row, meshes[0], MethodParams()).points,
                                      runMethod(row, meshes[1], MethodParams()).points};
    for (const char *name : row.reads) {
      SCOPED_TRACE(std::string(row.key) + " reads " + name);
      ASSERT_TRUE(changes().count(name)) << "no test value for " << name;
      double largest = 0;
      for (int k = 0; k < 2; ++k) {
        // The boundary rule acts on the open mesh only.
        if (std::string(name) == "boundary" && k == 0) continue;
        MethodParams changed;
        changes().at(name)(changed);
        largest = std::max(largest, largestDifference(base[k], runMethod(row, meshes[k], changed).points));
      }
      EXPECT_GT(largest, 1e-6);
    }
  }
}

TEST(Methods, CommonParametersActInEveryMethod) {
  const MeshArrays box = noisyBox(), bumps = noisyBumps();
  for (const MethodRow &row : methodTable()) {
    SCOPED_TRACE(row.key);
    const Result base = runMethod(row, box, MethodParams());
    MethodParams no_volume;
    no_volume.preserve_volume = false;
    EXPECT_GT(largestDifference(base.points, runMethod(row, box, no_volume).points), 1e-6);
    // Only the selected half moves; the rest stays bit for bit.
    MeshArrays half = box;
    for (size_t v = 0; v < half.points.size(); ++v) half.selected[v] = half.points[v].x() > 0;
    MethodParams selected;
    selected.selected_only = true;
    const Result some = runMethod(row, half, selected);
    long moved_unselected = 0;
    for (size_t v = 0; v < half.points.size(); ++v)
      moved_unselected += !half.selected[v] && some.points[v] != box.points[v];
    EXPECT_EQ(moved_unselected, 0);
    EXPECT_GT(largestDifference(some.points, box.points), 1e-6);
    // The saliency scale changes the Saliency of the result.
    MethodParams wider;
    wider.saliency_scale = 0.02;
    const Result a = runMethod(row, bumps, MethodParams()), b = runMethod(row, bumps, wider);
    double saliency_change = 0;
    for (size_t v = 0; v < a.q.saliency.size(); ++v)
      saliency_change = std::max(saliency_change, std::abs(a.q.saliency[v] - b.q.saliency[v]));
    EXPECT_GT(saliency_change, 1e-3);
  }
}

TEST(Methods, StrengthOrdersTheMeasuredMethodsDisplacement) {
  const MeshArrays box = noisyBox();
  for (int row : {3, 4, 5}) {
    const MethodRow &method = methodTable()[row];
    SCOPED_TRACE(method.key);
    double previous = -1;
    for (int iterations : {0, 1, 3, 6}) {
      MethodParams p;
      p.iterations = iterations;
      const Result r = runMethod(method, box, p);
      const double moved = meanDisplacement(r);
      if (iterations == 0) EXPECT_EQ(moved, 0.0);
      else EXPECT_GT(moved, previous);
      previous = moved;
    }
  }
}

TEST(Methods, AMeshMeasuredAsCleanIsSmoothedOnlyWhenAskedFor) {
  const MeshArrays clean = test_meshes::box(1.0, 0.8, 0.6, 8);
  for (int row : {3, 4, 5}) {
    const MethodRow &method = methodTable()[row];
    SCOPED_TRACE(method.key);
    const Result as_measured = runMethod(method, clean, MethodParams());
    EXPECT_EQ(largestDifference(as_measured.points, clean.points), 0.0);
    EXPECT_NE(as_measured.run.summary.find("measures as clean"), std::string::npos)
        << as_measured.run.summary;
    MethodParams more;
    more.iterations = 6;
    EXPECT_GT(largestDifference(runMethod(method, clean, more).points, clean.points), 1e-6);
  }
}

TEST(Methods, SummaryNamesTheMethodThatRanAndWhatMoved) {
  const Result r = runMethod(methodTable()[kDefaultMethod], noisyBox(), MethodParams());
  EXPECT_EQ(r.run.method, "feature-preserving");
  EXPECT_EQ(r.run.summary.rfind("Automatic (sharp features", 0), 0u) << r.run.summary;
  EXPECT_NE(r.run.summary.find("vertices moved, by"), std::string::npos) << r.run.summary;
}

// The summary says when correlated noise took more filter iterations (correlatedNoiseFactor), and
// not when it did not or nothing ran.
TEST(Methods, CorrelatedPhraseNamesTheFactorAndTheShare) {
  NoiseEstimate noise;
  noise.correlated_share = 0.498;
  EXPECT_EQ(detail::correlatedPhrase(1.396, 0.8, noise),
            ", the filter iterations and vertex updates x 1.40 for noise 50 % correlated");
  EXPECT_EQ(detail::correlatedPhrase(1.0, 0.8, noise), "");
  EXPECT_EQ(detail::correlatedPhrase(1.4, 0.0, noise), "");
}

// The summary's amplitude says what was read and, when the amplitude made the mesh noisy, so.
TEST(Methods, AmplitudePhraseSaysWhenTheAmplitudeMadeTheMeshNoisy) {
  NoiseEstimate noise;
  EXPECT_EQ(detail::amplitudePhrase(noise), ""); // not read
  noise.amplitude = 0.4123;
  EXPECT_EQ(detail::amplitudePhrase(noise), "amplitude 0.412 (white), ");
  noise.correlation_steps = 4;
  noise.correlated_share = 0.8;
  noise.trimmed_amplitude = 0.3987;
  noise.noisy_by_amplitude = true;
  EXPECT_EQ(detail::amplitudePhrase(noise),
            "amplitude 0.412 (80 % of it correlated over about 2 rings), noisy by its amplitude "
            "(0.399 on trimmed bands: noise correlated over several rings, which one pair barely "
            "changes), ");
}

TEST(Strengthen, ScalesBelowOneAndAddsFullAmountsAboveIt) {
  EXPECT_DOUBLE_EQ(detail::strengthen(0.6, 1.0), 0.6);
  EXPECT_DOUBLE_EQ(detail::strengthen(0.6, 0.5), 0.3);
  EXPECT_DOUBLE_EQ(detail::strengthen(0.6, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(detail::strengthen(0.6, 2.0), 1.6);
  EXPECT_DOUBLE_EQ(detail::strengthen(0.0, 2.0), 1.0); // clean, asked for twice: a full amount
  EXPECT_DOUBLE_EQ(detail::strengthen(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(detail::strengthen(0.3, -1.0), 0.0);
}

TEST(FacePatchAlpha, LowerAlphaFitsAFlatterPatch) {
  // A paraboloid z = 0.3 (x² + y²): the patch of its centre face bends less as α falls.
  const MeshArrays bowl = test_meshes::heightField(9, -1, 1, -1, 1, [](double x, double y) {
    return 0.3 * (x * x + y * y);
  });
  const Rings rings = computeRings(int(bowl.points.size()), bowl.faces);
  const FaceRings face_rings = computeFaceRings(bowl.faces, rings);
  FaceGeometry geometry;
  computeFaceGeometry(bowl.points, bowl.faces, geometry);
  const double edge = edgeStatistics(bowl.points, rings).mean_edge_length;
  const int centre_face = int(bowl.faces.size()) / 2;
  double previous = INFINITY;
  for (double alpha : {1.0, 0.6, 0.3, 0.0}) {
    FacePatches patches;
    FacePatchParams params;
    params.alpha = alpha;
    fitFacePatches(bowl.points, bowl.faces, face_rings, geometry.normal, edge, params, {}, patches);
    const FacePatch p = patches.patch(centre_face);
    const double bending = std::abs(p.c[6]) + std::abs(p.c[2]); // x² and y² coefficients
    EXPECT_LT(bending, previous) << "alpha " << alpha;
    previous = bending;
  }
  EXPECT_LT(previous, 0.05 * 0.3); // α = 0: nearly a plane
}

TEST(FacePatchAlpha, SaliencyRuleGivesOneWhereNothingIsSalientAndTheRatioElsewhere) {
  const MeshArrays grid = test_meshes::heightField(5, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const Rings rings = computeRings(int(grid.points.size()), grid.faces);
  const FaceRings face_rings = computeFaceRings(grid.faces, rings);
  std::vector<double> saliency(grid.points.size(), 0.0);
  EXPECT_EQ(faceAlphaFromSaliency(grid.faces, face_rings, saliency),
            std::vector<double>(grid.faces.size(), 1.0));
  for (size_t v = 0; v < saliency.size(); ++v) saliency[v] = 0.5 + 0.1 * double(v % 3);
  const std::vector<double> alpha = faceAlphaFromSaliency(grid.faces, face_rings, saliency);
  for (size_t f = 0; f < alpha.size(); ++f) {
    double lo = INFINITY, hi = 0;
    for (const int *g = face_rings.begin(int(f)); g != face_rings.end(int(f)); ++g)
      for (int v : grid.faces[*g]) lo = std::min(lo, saliency[v]), hi = std::max(hi, saliency[v]);
    EXPECT_DOUBLE_EQ(alpha[f], lo / hi);
  }
}
