// Feature mode, stage A (vcg_ext/methods/feature/normal_filter.h): face geometry and rings, the noise estimate, the
// Taubin pre-pass and guided / bilateral normal filtering.
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/mesh_metrics.h>
#include <vcg_ext/methods/feature/normal_filter.h>

#include <random>

using namespace vcg_ext;

namespace {

double meanAngleDeg(const std::vector<Vec3> &a, const std::vector<Vec3> &b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += angleDeg(a[i], b[i]);
  return sum / a.size();
}

// Two planes meeting at a right angle along the y axis: z = |x| (a "roof" turned upside down);
// odd n puts a column of vertices on the crease.
MeshArrays roof(int n) {
  return test_meshes::heightField(n, -1, 1, -1, 1, [](double x, double) { return std::abs(x); });
}

} // namespace

TEST(NormalFilter, FaceGeometryOfOneTriangle) {
  const MeshArrays m = test_meshes::fromArrays({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, {{0, 1, 2}});
  FaceGeometry g;
  computeFaceGeometry(m.points, m.faces, g);
  EXPECT_DOUBLE_EQ(g.area[0], 2.0);
  EXPECT_EQ(g.normal[0], Vec3(0, 0, 1));
  EXPECT_TRUE(g.centroid[0].isApprox(Vec3(2.0 / 3, 2.0 / 3, 0)));
}

TEST(NormalFilter, FaceRingsOfAGrid) {
  // 4x4 vertices, every interior vertex of valence 6: an inner face shares a vertex with 12 others.
  const MeshArrays m = test_meshes::heightField(4, 0, 3, 0, 3, [](double, double) { return 0.0; });
  const FaceRings r = computeFaceRings(m.faces, computeRings(16, m.faces));
  // Face 8 is {5, 6, 10}: the lower triangle of the middle square, all three vertices interior.
  ASSERT_EQ(m.faces[8], (Face{5, 6, 10}));
  EXPECT_EQ(r.size(8), 13);
  EXPECT_TRUE(r.contains(8, 8));
  int neighbours = 0;
  for (int g : r.edge_neighbours[8]) neighbours += g >= 0;
  EXPECT_EQ(neighbours, 3);
  // Face 4 is {2, 3, 7}, in the corner where the diagonals leave it two boundary edges.
  ASSERT_EQ(m.faces[4], (Face{2, 3, 7}));
  neighbours = 0;
  for (int g : r.edge_neighbours[4]) neighbours += g >= 0;
  EXPECT_EQ(neighbours, 1);
}

TEST(NormalFilter, DihedralSpreadSeparatesCurvatureFromNoise) {
  auto spread = [](const MeshArrays &m) {
    FaceGeometry g;
    computeFaceGeometry(m.points, m.faces, g);
    return medianDihedralSpreadDeg(
        m.points, m.faces, g.normal, computeFaceRings(m.faces, computeRings(int(m.points.size()), m.faces)));
  };
  EXPECT_NEAR(spread(test_meshes::box(1, 1, 1, 8)), 0.0, 1e-9);
  // A coarse sphere bends every edge by ~9 degrees, all alike: the spread stays small.
  const MeshArrays sphere = test_meshes::icosphere(1, 3);
  EXPECT_LT(spread(sphere), 3.0);
  // A cylinder bends the edges across its axis only: spread about the bend angle (2π/24 = 15°).
  EXPECT_LT(spread(test_meshes::cylinder(1, 4, 24, 20)), 20.0);
  MeshArrays noisy = sphere;
  test_meshes::addNoise(noisy, 0.2 * 0.15, 2, [&](int i) { return sphere.points[i]; });
  EXPECT_GT(spread(noisy), 40.0); // 0.2 mean edge lengths of noise along the normals
}

TEST(NormalFilter, TaubinFlattensNoiseAndKeepsStraightBoundaries) {
  const MeshArrays clean =
      test_meshes::heightField(20, -1, 1, -1, 1, [](double, double) { return 0.0; });
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, 0.02, 4, [](int) { return Vec3(0, 0, 1); });
  const Rings rings = computeRings(int(clean.points.size()), clean.faces);
  std::vector<std::uint8_t> fixed(clean.points.size(), 0);
  std::vector<std::array<int, 2>> curve(clean.points.size(), {-1, -1});
  // Boundary neighbours along the four sides (corners have two as well, at a right angle).
  const int n = 20;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * n + i;
      if (!rings.boundary[v]) continue;
      if (j == 0 || j == n - 1) curve[v] = {i > 0 ? v - 1 : v + n, i < n - 1 ? v + 1 : v + n};
      if (i == 0 || i == n - 1) curve[v] = {j > 0 ? v - n : v + 1, j < n - 1 ? v + n : v + 1};
      if ((i == 0 || i == n - 1) && (j == 0 || j == n - 1)) curve[v] = {-1, -1}; // corners stay
    }
  std::vector<Vec3> smoothed = noisy.points;
  taubinSmooth(smoothed, rings, fixed, curve, 4);
  double rms_before = 0, rms_after = 0;
  for (size_t v = 0; v < smoothed.size(); ++v) {
    rms_before += noisy.points[v].z() * noisy.points[v].z();
    rms_after += smoothed[v].z() * smoothed[v].z();
    if (!rings.boundary[v]) continue;
    // A boundary vertex moves along its straight side only: the coordinate across it stays.
    const Vec3 &p = clean.points[v];
    if (std::abs(std::abs(p.x()) - 1) < 1e-12) EXPECT_DOUBLE_EQ(smoothed[v].x(), p.x());
    if (std::abs(std::abs(p.y()) - 1) < 1e-12) EXPECT_DOUBLE_EQ(smoothed[v].y(), p.y());
  }
  EXPECT_LT(rms_after, 0.35 * rms_before);
  // Fixed vertices stay exactly.
  std::fill(fixed.begin(), fixed.end(), 1);
  std::vector<Vec3> kept = noisy.points;
  taubinSmooth(kept, rings, fixed, curve, 4);
  EXPECT_EQ(kept, noisy.points);
}

TEST(NormalFilter, GuidedFilterDenoisesAndKeepsARightAngleCrease) {
  const MeshArrays clean = roof(31);
  MeshArrays noisy = clean;
  test_meshes::addNoise(noisy, 0.25 * (2.0 / 30), 6, [](int) { return Vec3(0, 0, 1); });
  const Rings rings = computeRings(int(clean.points.size()), clean.faces);
  const FaceRings face_rings = computeFaceRings(clean.faces, rings);
  FaceGeometry truth, g;
  computeFaceGeometry(clean.points, clean.faces, truth);
  computeFaceGeometry(noisy.points, noisy.faces, g);
  const double edge = edgeStatistics(clean.points, rings).mean_edge_length;

  NormalFilterParams guided;
  guided.sigma_r = 0.25;
  guided.iterations = 15;
  NormalFilterParams bilateral = guided;
  bilateral.kind = NormalFilterKind::Bilateral;
  std::vector<Vec3> by_guided, by_bilateral;
  filterNormals(clean.faces, face_rings, g, guided, edge, by_guided);
  filterNormals(clean.faces, face_rings, g, bilateral, edge, by_bilateral);

  const double noisy_error = meanAngleDeg(g.normal, truth.normal);
  EXPECT_GT(noisy_error, 10.0);
  EXPECT_LT(meanAngleDeg(by_guided, truth.normal), 0.15 * noisy_error);
  // On the faces touching the crease (|x| < one edge) guidance keeps the two sides apart.
  double crease_guided = 0, crease_bilateral = 0;
  int count = 0;
  for (size_t f = 0; f < clean.faces.size(); ++f)
    if (std::abs(truth.centroid[f].x()) < edge) {
      crease_guided += angleDeg(by_guided[f], truth.normal[f]);
      crease_bilateral += angleDeg(by_bilateral[f], truth.normal[f]);
      ++count;
    }
  ASSERT_GT(count, 50);
  EXPECT_LT(crease_guided / count, 5.0);
  EXPECT_LT(crease_guided, crease_bilateral);
  RecordProperty("crease_guided_deg", std::to_string(crease_guided / count));
  RecordProperty("crease_bilateral_deg", std::to_string(crease_bilateral / count));
}

TEST(NormalFilter, SameNormalsForOneAndTwoThreads) {
  MeshArrays noisy = test_meshes::icosphere(1, 3);
  test_meshes::addNoise(noisy, 0.03, 3);
  const Rings rings = computeRings(int(noisy.points.size()), noisy.faces);
  const FaceRings face_rings = computeFaceRings(noisy.faces, rings);
  FaceGeometry g;
  computeFaceGeometry(noisy.points, noisy.faces, g);
  const int threads = omp_get_max_threads();
  std::vector<Vec3> one, two;
  omp_set_num_threads(1);
  filterNormals(noisy.faces, face_rings, g, NormalFilterParams(), 0.15, one);
  omp_set_num_threads(2);
  filterNormals(noisy.faces, face_rings, g, NormalFilterParams(), 0.15, two);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, two);
}

TEST(KthSmallest, TheValueNthElementFindsForAnyThreadCountAndBracket) {
  // Above the parallel threshold (lowered here), with repeated values, a skewed distribution and
  // a sorted run (a regular sample of it is the bracket's worst case), for 1 and 2 threads.
  std::mt19937 rng(5);
  std::lognormal_distribution<double> skewed(0.0, 2.0);
  std::vector<double> values(200000);
  for (size_t i = 0; i < values.size(); ++i)
    values[i] = i < 50000 ? double(i) : i % 7 == 0 ? 3.0 : skewed(rng);
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (size_t k : {size_t(0), size_t(1), size_t(777), values.size() / 2, values.size() - 1}) {
      std::vector<double> a = values, b = values;
      std::nth_element(b.begin(), b.begin() + k, b.end());
      EXPECT_EQ(detail::kthSmallest(a, k, 1000), b[k]) << "k " << k << ", " << threads << " threads";
    }
  }
  // Past the sample's cap (65536 values): a narrow bracket, on values correlated along the array
  // (a smooth trend plus noise, as per-vertex values in spatial order are).
  std::vector<double> large(1500000);
  for (size_t i = 0; i < large.size(); ++i)
    large[i] = std::sin(1e-5 * double(i)) + 0.1 * skewed(rng);
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    for (size_t k : {size_t(3), large.size() / 2, large.size() - 2}) {
      std::vector<double> a = large, b = large;
      std::nth_element(b.begin(), b.begin() + k, b.end());
      EXPECT_EQ(detail::kthSmallest(a, k), b[k]) << "k " << k << ", " << threads << " threads";
    }
  }
  omp_set_num_threads(saved);
}

TEST(EraseNaN, KeepsTheOtherValuesInOrderOnLargeArrays) {
  // Above the parallel blocks' threshold: every third value NaN, one block all NaN.
  std::vector<double> values(2000000);
  std::vector<double> expected;
  for (size_t i = 0; i < values.size(); ++i) {
    const bool hole = i % 3 == 0 || (i >= 70000 && i < 70000 + 65536);
    values[i] = hole ? NAN : double(i);
    if (!hole) expected.push_back(double(i));
  }
  detail::eraseNaN(values);
  EXPECT_EQ(values, expected);
}

TEST(NormalFilter, DihedralSpreadSharesEachEdgesAngleWithTheSameBits) {
  // The angle of each edge is computed once for its two faces: the median must have the bits of
  // every face computing its own three angles, on a noisy sphere with flipped faces (inconsistent
  // neighbours compute their own), open boundaries and a non-manifold fin, for any thread count.
  MeshArrays m = test_meshes::icosphere(1, 4);
  test_meshes::addNoise(m, 0.03, 9);
  for (int f = 0; f < int(m.faces.size()); f += 37) std::swap(m.faces[f][1], m.faces[f][2]);
  m.faces.erase(m.faces.begin() + 100, m.faces.begin() + 130);
  m.points.push_back(Vec3(2, 0, 0));
  m.faces.push_back({m.faces[5][0], m.faces[5][1], int(m.points.size()) - 1}); // a third face on an edge
  const Rings rings = computeRings(int(m.points.size()), m.faces);
  const FaceRings face_rings = computeFaceRings(m.faces, rings);
  FaceGeometry g;
  computeFaceGeometry(m.points, m.faces, g);
  std::vector<double> spreads;
  for (int f = 0; f < int(m.faces.size()); ++f) {
    double lo = INFINITY, hi = -INFINITY;
    bool complete = g.normal[f].squaredNorm() > 0.5;
    for (int k = 0; k < 3 && complete; ++k) {
      const int h = face_rings.edge_neighbours[f][k];
      complete = h >= 0 && g.normal[h].squaredNorm() > 0.5;
      if (!complete) break;
      const Vec3 edge = (m.points[m.faces[f][(k + 1) % 3]] - m.points[m.faces[f][k]]).normalized();
      const Vec3 &a = g.normal[f], &b = g.normal[h];
      const double angle = std::atan2(a.cross(b).dot(edge), a.dot(b)) * 180.0 / M_PI;
      lo = std::min(lo, angle), hi = std::max(hi, angle);
    }
    if (complete) spreads.push_back(hi - lo);
  }
  std::nth_element(spreads.begin(), spreads.begin() + spreads.size() / 2, spreads.end());
  const double expected = spreads[spreads.size() / 2];
  EXPECT_GT(expected, 5.0);
  const int saved = min_parallel_vertices, threads = omp_get_max_threads();
  min_parallel_vertices = 0;
  for (int t : {1, 2, 3}) {
    omp_set_num_threads(t);
    EXPECT_EQ(medianDihedralSpreadDeg(m.points, m.faces, g.normal, face_rings), expected) << t;
  }
  omp_set_num_threads(threads);
  min_parallel_vertices = saved;
}

namespace {

// GNF's patch consistency straight from its definition (all pairs; each inner edge found by a
// search of the ring), in the filter's single-precision arithmetic.
float directConsistency(int f, const FaceRings &r, const std::vector<detail::Normal3f> &n) {
  float largest2 = 0, largest_jump = 0, jump_sum = 0;
  for (const int *a = r.begin(f); a != r.end(f); ++a) {
    for (const int *b = a + 1; b != r.end(f); ++b) {
      const float dx = n[*a].x() - n[*b].x(), dy = n[*a].y() - n[*b].y(), dz = n[*a].z() - n[*b].z();
      largest2 = std::max(largest2, (dx * dx + dy * dy) + dz * dz);
    }
    for (int b : r.edge_neighbours[*a]) {
      if (b <= *a || !r.contains(f, b)) continue;
      const float dx = n[*a].x() - n[b].x(), dy = n[*a].y() - n[b].y(), dz = n[*a].z() - n[b].z();
      const float d = std::sqrt((dx * dx + dy * dy) + dz * dz);
      largest_jump = std::max(largest_jump, d);
      jump_sum += d;
    }
  }
  return std::sqrt(largest2) * largest_jump / (1e-9f + jump_sum);
}

} // namespace

TEST(NormalFilter, PatchConsistencyIsItsDefinitionBitForBit) {
  // Noisy sphere plus a roof (a crease, boundary faces): jumps taken once per edge and summed with
  // zeros for the edges that are not inner must give the definition's bits.
  for (MeshArrays m : {test_meshes::icosphere(1, 3), roof(15)}) {
    test_meshes::addNoise(m, 0.04, 5);
    const FaceRings r = computeFaceRings(m.faces, computeRings(int(m.points.size()), m.faces));
    FaceGeometry g;
    computeFaceGeometry(m.points, m.faces, g);
    std::vector<detail::Normal3f> n(g.normal.size());
    for (size_t f = 0; f < n.size(); ++f) n[f] = g.normal[f].cast<float>();
    const std::vector<float> area(g.area.begin(), g.area.end());
    detail::EdgeJumps jumps;
    detail::normalJumps(r, n, jumps);
    int differing = 0, positive = 0;
    for (int f = 0; f < int(n.size()); ++f) {
      float consistency;
      detail::Normal3f mean;
      detail::patchConsistency(f, r, n, area, jumps, consistency, mean);
      differing += consistency != directConsistency(f, r, n);
      positive += consistency > 0;
    }
    EXPECT_EQ(differing, 0);
    EXPECT_EQ(positive, int(n.size())); // (noisy: every patch has some inconsistency)
  }
}

TEST(NormalFilter, ACheckpointSeesTheNormalsSoFarAndDoesNotChangeTheResult) {
  MeshArrays noisy = roof(21);
  test_meshes::addNoise(noisy, 0.3 * (2.0 / 20), 7);
  const Rings rings = computeRings(int(noisy.points.size()), noisy.faces);
  const FaceRings face_rings = computeFaceRings(noisy.faces, rings);
  const double edge = edgeStatistics(noisy.points, rings).mean_edge_length;
  NormalFilterParams p;
  p.iterations = 6;
  p.guidance_every = 4;
  auto filtered = [&](int iterations, int at, const NormalFilterCheckpoint &checkpoint) {
    NormalFilterParams q = p;
    q.iterations = iterations;
    std::vector<Vec3> n;
    computeFaceNormals(noisy.points, noisy.faces, n);
    filterNormalsInPlace(noisy.points, noisy.faces, face_rings, q, edge, n, at, checkpoint);
    return n;
  };
  const std::vector<Vec3> after2 = filtered(2, 0, nullptr), after6 = filtered(6, 0, nullptr),
                          after9 = filtered(9, 0, nullptr);
  ASSERT_NE(after2, after6);
  // Inside a guidance period (after 2 of its 4 iterations), going on to 6 or to 9 in all.
  for (int total : {6, 9}) {
    std::vector<Vec3> seen;
    const std::vector<Vec3> result = filtered(6, 2, [&](const std::vector<Vec3> &n) {
      seen = n;
      return total;
    });
    EXPECT_EQ(seen, after2);
    EXPECT_EQ(result, total == 6 ? after6 : after9);
  }
  // At a period's end, and a checkpoint that stops the filter there.
  std::vector<Vec3> seen;
  EXPECT_EQ(filtered(6, 4, [&](const std::vector<Vec3> &n) { return seen = n, 6; }), after6);
  EXPECT_EQ(seen, filtered(4, 0, nullptr));
  EXPECT_EQ(filtered(6, 2, [](const std::vector<Vec3> &) { return 0; }), after2);
}

namespace {

// A regular tetrahedron, faces oriented outwards.
MeshArrays tetrahedron() {
  MeshArrays m;
  m.points = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  m.faces = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return m;
}

} // namespace

// Each edge's signed dihedral angle is computed once and read by both faces: on a tetrahedron
// every edge turns by 180° − acos(1/3) (convex: positive), six computed and six shared; two faces
// folded at a right angle read +90° (convex) and −90° once folded the other way.
TEST(NormalFilter, DihedralAnglesAreSignedAndComputedOncePerEdge) {
  const MeshArrays tet = tetrahedron();
  const FaceRings rings = computeFaceRings(tet.faces, computeRings(4, tet.faces));
  FaceGeometry g;
  computeFaceGeometry(tet.points, tet.faces, g);
  detail::DihedralAngles angles;
  detail::dihedralAngles(tet.points, tet.faces, g.normal, rings, angles);
  int shared = 0;
  for (int f = 0; f < 4; ++f)
    for (int k = 0; k < 3; ++k) {
      shared += angles.shared[f][k] >= 0;
      EXPECT_NEAR(angles.at(f, k, rings.edge_neighbours[f][k]),
                  180.0 - std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-12);
    }
  EXPECT_EQ(shared, 6);
  const std::vector<double> spreads = detail::dihedralSpreads(g.normal, rings, angles, nullptr);
  for (double s : spreads) EXPECT_NEAR(s, 0.0, 1e-12);
  const std::vector<std::uint8_t> counted = {1, 0, 1, 1};
  EXPECT_TRUE(std::isnan(detail::dihedralSpreads(g.normal, rings, angles, &counted)[1]));

  for (const double side : {-1.0, 1.0}) { // d below the first face's plane (convex) or above it
    MeshArrays fold;
    fold.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 0, side)};
    fold.faces = {{0, 1, 2}, {1, 0, 3}};
    const FaceRings fold_rings = computeFaceRings(fold.faces, computeRings(4, fold.faces));
    FaceGeometry fg;
    computeFaceGeometry(fold.points, fold.faces, fg);
    detail::dihedralAngles(fold.points, fold.faces, fg.normal, fold_rings, angles);
    EXPECT_NEAR(angles.at(0, 0, 1), -90.0 * side, 1e-12) << side;
    EXPECT_NEAR(angles.at(1, 0, 0), -90.0 * side, 1e-12) << side;
    EXPECT_EQ(angles.shared[1][0], 0); // the higher face reads the lower one's angle
    // Neither face has three neighbours: no spread.
    for (double s : detail::dihedralSpreads(fg.normal, fold_rings, angles, nullptr))
      EXPECT_TRUE(std::isnan(s));
  }
}
