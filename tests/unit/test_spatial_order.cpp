// vcg_ext/core/spatial_order.h and spatial_taubin.h: the spatially reordered copy of a mesh is the same
// mesh (faces, orientation, selection) and the same for any input order; Taubin smoothing over a
// renumbered copy of the 1-ring graph gives taubinSmooth's result to the bit (interior, boundary
// curves, fixed vertices, several fields at once) and puts mesh neighbours near each other.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/feature/normal_filter.h>
#include <vcg_ext/methods/paper/paper_smooth.h>
#include <vcg_ext/smoothing/spatial_taubin.h>
#include <vcg_ext/smoothing/taubin_chebyshev.h>

#include <omp.h>
#include <random>
#include <set>

using namespace vcg_ext;

namespace {

// An open, noisy cylinder with its vertices shuffled: boundaries, and a scattered vertex order.
MeshArrays scatteredCylinder() {
  MeshArrays m = test_meshes::cylinder(1.0, 2.0, 48, 40);
  test_meshes::addNoise(m, 0.01, 7);
  return test_meshes::permuted(m, test_meshes::shuffledPermutation(int(m.points.size()), 3));
}

// The scattered cylinder with its rings and boundary curves: what a SpatialTaubin is built from.
struct CylinderGraph {
  MeshArrays m = scatteredCylinder();
  int n = int(m.points.size());
  Rings rings = computeRings(n, m.faces);
  detail::VertexRoles roles =
      detail::vertexRoles(m, rings, edgeStatistics(m.points, rings).mean_edge_length);
};

double meanIndexDistance(const MeshArrays &m, const std::function<int(int)> &index) {
  double sum = 0;
  for (const Face &f : m.faces)
    for (int k = 0; k < 3; ++k) sum += std::abs(index(f[k]) - index(f[(k + 1) % 3]));
  return sum / (3.0 * m.faces.size());
}

} // namespace

TEST(RingGraph, KindsAndAveragesFollowTheRingsInAnyLocalOrder) {
  CylinderGraph g;
  int still = 0; // an interior vertex made to stay
  while (g.rings.boundary[still]) ++still;
  std::vector<std::uint8_t> fixed(g.n, 0);
  fixed[still] = 1;
  const RingGraph graph(g.m.points, g.rings, fixed, g.roles.boundary_neighbours);
  ASSERT_EQ(graph.size(), g.n);
  const std::vector<Vec3> local = graph.toLocal(g.m.points);
  EXPECT_EQ(graph.toGlobal(local), g.m.points); // a permutation and its inverse
  int curves = 0, interiors = 0;
  for (int v = 0; v < g.n; ++v) {
    const int l = graph.local(v);
    EXPECT_EQ(local[l], g.m.points[v]);
    const RingGraph::Kind kind = graph.kindOf(l, false);
    const Vec3 mean = graph.average(local, l, kind);
    if (v == still) {
      EXPECT_EQ(kind, RingGraph::Kind::Still);
      EXPECT_EQ(mean, g.m.points[v]);
    } else if (g.rings.boundary[v]) {
      ++curves;
      EXPECT_EQ(kind, RingGraph::Kind::Curve);
      EXPECT_EQ(graph.kindOf(l, true), RingGraph::Kind::Still); // boundary_still
      const auto &c = g.roles.boundary_neighbours[v];
      EXPECT_EQ(mean, Vec3(0.5 * (g.m.points[c[0]] + g.m.points[c[1]])));
    } else {
      ++interiors;
      EXPECT_EQ(kind, RingGraph::Kind::Interior);
      Vec3 sum = Vec3::Zero(); // in the ring's order: the same bits
      for (const int *w = g.rings.ring1Begin(v); w != g.rings.ring1End(v); ++w)
        sum += g.m.points[*w];
      EXPECT_EQ(mean, Vec3(sum / double(g.rings.ring1Size(v))));
    }
  }
  EXPECT_EQ(curves, 2 * 48); // the cylinder's two boundary circles
  EXPECT_EQ(interiors, g.n - 2 * 48 - 1);
}

TEST(SpatialTaubin, SameBitsAsTaubinSmoothWithBoundariesAndFixedVertices) {
  const CylinderGraph g;
  const MeshArrays &m = g.m;
  const int n = g.n;
  const Rings &rings = g.rings;
  const detail::VertexRoles &roles = g.roles;
  std::vector<std::uint8_t> fixed(n, 0), fixed_and_boundary(n, 0);
  for (int v = 0; v < n; v += 17) fixed[v] = 1;
  for (int v = 0; v < n; ++v) fixed_and_boundary[v] = fixed[v] || rings.boundary[v];
  ASSERT_GT(std::count(rings.boundary.begin(), rings.boundary.end(), 1), 90);

  // A second field: a different signal on the same graph.
  std::vector<Vec3> other(n);
  for (int v = 0; v < n; ++v) other[v] = Vec3(std::sin(v), std::cos(3.0 * v), 0.5 * v / n);

  std::vector<Vec3> expected_points = m.points, expected_other = other;
  taubinSmooth(expected_points, rings, fixed, roles.boundary_neighbours, 5, 0.5, -0.51);
  taubinSmooth(expected_other, rings, fixed, roles.boundary_neighbours, 5, 0.5, -0.51);
  taubinSmooth(expected_points, rings, fixed_and_boundary, roles.boundary_neighbours, 3, 0.5, -0.51);
  taubinSmooth(expected_other, rings, fixed_and_boundary, roles.boundary_neighbours, 3, 0.5, -0.51);

  const SpatialTaubin taubin(m.points, rings, fixed, roles.boundary_neighbours);
  std::vector<Vec3> points = taubin.toLocal(m.points), local_other = taubin.toLocal(other);
  taubin.smooth({&points, &local_other}, 5, 0.5, -0.51);
  taubin.smooth({&points, &local_other}, 3, 0.5, -0.51, /*boundary_still=*/true);
  const std::vector<Vec3> got_points = taubin.toGlobal(points), got_other = taubin.toGlobal(local_other);
  int moved = 0;
  for (int v = 0; v < n; ++v) {
    ASSERT_EQ(got_points[v], expected_points[v]) << "vertex " << v;
    ASSERT_EQ(got_other[v], expected_other[v]) << "vertex " << v;
    moved += got_points[v] != m.points[v];
    if (fixed[v]) EXPECT_EQ(got_points[v], m.points[v]);
  }
  EXPECT_GT(moved, n / 2);
}

// The noise estimate's case: a mesh already in the drivers' spatial order keeps its numbering
// (nothing sorted, local = global) and gets taubinSmooth's bits.
TEST(SpatialTaubin, GivenOrderKeepsTheNumberingAndTheBits) {
  const CylinderGraph g;
  const int n = g.n;
  std::vector<std::uint8_t> fixed(n, 0);
  for (int v = 0; v < n; v += 13) fixed[v] = 1;
  std::vector<Vec3> expected = g.m.points;
  taubinSmooth(expected, g.rings, fixed, g.roles.boundary_neighbours, 4, 0.5, -0.53);
  const SpatialTaubin taubin(g.m.points, g.rings, fixed, g.roles.boundary_neighbours,
                             /*given_order=*/true);
  for (int v = 0; v < n; ++v) ASSERT_EQ(taubin.local(v), v);
  std::vector<Vec3> scratch;
  EXPECT_EQ(&taubin.inGlobalOrder(g.m.points, scratch), &g.m.points); // read as it is, no copy
  EXPECT_TRUE(scratch.empty());
  std::vector<Vec3> points = g.m.points;
  taubin.smooth({&points}, 4, 0.5, -0.53);
  int moved = 0;
  for (int v = 0; v < n; ++v) {
    ASSERT_EQ(points[v], expected[v]) << "vertex " << v;
    moved += points[v] != g.m.points[v];
  }
  EXPECT_GT(moved, n / 2);
}

// Releasing the step buffers between calls changes nothing: they come back on the next call.
TEST(SpatialTaubin, ReleasedBuffersComeBackWithTheSameBits) {
  const CylinderGraph g;
  std::vector<std::uint8_t> fixed(g.n, 0);
  const SpatialTaubin taubin(g.m.points, g.rings, fixed, g.roles.boundary_neighbours);
  std::vector<Vec3> whole = taubin.toLocal(g.m.points), halves = whole;
  taubin.smooth({&whole}, 4, 0.5, -0.53);
  taubin.smooth({&halves}, 2, 0.5, -0.53);
  taubin.releaseBuffers();
  taubin.smooth({&halves}, 2, 0.5, -0.53);
  EXPECT_EQ(halves, whole);
  EXPECT_NE(whole, taubin.toLocal(g.m.points));
}

// The band shrinkage's case: a double field and a float field in one sweep over the graph (their
// neighbour sums share the reads; the float sums run in the lanes of one register) give, to the
// bit, what each gives alone, for the steps and for the Chebyshev series.
TEST(SpatialTaubin, DoubleAndFloatFieldsTogetherGiveTheBitsOfEachAlone) {
  const CylinderGraph g;
  const int n = g.n;
  std::vector<std::uint8_t> fixed(n, 0);
  for (int v = 0; v < n; v += 13) fixed[v] = 1;
  const SpatialTaubin taubin(g.m.points, g.rings, fixed, g.roles.boundary_neighbours);
  // A float field in local order, as the band shrinkage makes its probe.
  std::vector<Vec3f> probe(n);
  for (int l = 0; l < n; ++l)
    probe[l] = Vec3f(float(std::sin(0.7 * l)), float(std::cos(1.3 * l)), float(l % 5) - 2.0f);
  const std::vector<Vec3> points = taubin.toLocal(g.m.points);

  std::vector<Vec3> together = points, alone = points;
  std::vector<Vec3f> probe_together = probe, probe_alone = probe;
  taubin.smooth({&together}, {&probe_together}, 4, 0.5, -0.51);
  taubin.smooth({&alone}, 4, 0.5, -0.51);
  taubin.smooth({}, {&probe_alone}, 4, 0.5, -0.51);
  EXPECT_EQ(together, alone);
  EXPECT_EQ(probe_together, probe_alone);
  EXPECT_NE(probe_alone, probe); // the float field did move

  const std::vector<double> c = taubinChebyshevCoefficients(24, 0.5, -0.51, 1e-10);
  std::vector<Vec3> series_together, series_alone;
  std::vector<Vec3f> probe_series_together, probe_series_alone;
  taubin.applyChebyshev({&points}, {&series_together}, {&probe}, {&probe_series_together}, c);
  taubin.applyChebyshev({&points}, {&series_alone}, c);
  taubin.applyChebyshev({}, {}, {&probe}, {&probe_series_alone}, c);
  EXPECT_EQ(series_together, series_alone);
  EXPECT_EQ(probe_series_together, probe_series_alone);
  EXPECT_NE(probe_series_alone, probe);
}

TEST(SpatialTaubin, RenumberingBringsNeighboursTogether) {
  const MeshArrays m = scatteredCylinder();
  const int n = int(m.points.size());
  const Rings rings = computeRings(n, m.faces);
  const std::vector<std::uint8_t> fixed(n, 0);
  const std::vector<std::array<int, 2>> no_curve(n, {-1, -1});
  const SpatialTaubin taubin(m.points, rings, fixed, no_curve);
  // Shuffled: about n/3 apart on average; along the Morton curve, a few dozen.
  const double before = meanIndexDistance(m, [](int v) { return v; });
  const double after = meanIndexDistance(m, [&](int v) { return taubin.local(v); });
  EXPECT_GT(before, 0.25 * n);
  EXPECT_LT(after, 0.1 * before);
  // A permutation, and toGlobal undoes toLocal.
  std::vector<int> seen(n, 0);
  for (int v = 0; v < n; ++v) ++seen[taubin.local(v)];
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n);
  EXPECT_EQ(taubin.toGlobal(taubin.toLocal(m.points)), m.points);
  // Renumbered: the mesh's order is a copy.
  std::vector<Vec3> scratch;
  const std::vector<Vec3> local = taubin.toLocal(m.points);
  EXPECT_EQ(&taubin.inGlobalOrder(local, scratch), &scratch);
  EXPECT_EQ(scratch, m.points);
}

TEST(SpatialOrder, SameMeshInAnOrderThatDoesNotDependOnTheInputOrder) {
  MeshArrays m = test_meshes::cylinder(1.0, 2.0, 24, 12);
  m.selected.assign(m.points.size(), 0);
  for (size_t v = 0; v < m.points.size(); v += 5) m.selected[v] = 1;
  const SpatialOrder order = spatialOrder(m);
  const int n = int(m.points.size());
  ASSERT_EQ(order.mesh.points.size(), m.points.size());
  // Every vertex once, with its position and selection.
  std::vector<int> seen(n, 0);
  for (int v = 0; v < n; ++v) {
    ++seen[order.input_of[v]];
    EXPECT_EQ(order.mesh.points[v], m.points[order.input_of[v]]);
    EXPECT_EQ(order.mesh.selected[v], m.selected[order.input_of[v]]);
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n);
  // The same oriented faces: each input face, mapped and rotated to its lowest corner, appears.
  auto canonical = [](Face f) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    return f;
  };
  std::multiset<Face> expected, got(order.mesh.faces.begin(), order.mesh.faces.end());
  std::vector<int> new_of(n);
  for (int v = 0; v < n; ++v) new_of[order.input_of[v]] = v;
  for (const Face &f : m.faces) expected.insert(canonical({new_of[f[0]], new_of[f[1]], new_of[f[2]]}));
  EXPECT_EQ(got, expected);
  EXPECT_TRUE(std::is_sorted(order.mesh.faces.begin(), order.mesh.faces.end()));
  // Values computed in the new order go back to the input's.
  std::vector<Vec3> values = order.mesh.points;
  order.toInputOrder(values);
  EXPECT_EQ(values, m.points);

  // Any renumbering and face order of the input gives the same reordered mesh.
  const std::vector<int> perm = test_meshes::shuffledPermutation(n, 9);
  const SpatialOrder again = spatialOrder(test_meshes::facesReordered(test_meshes::permuted(m, perm), 4));
  EXPECT_EQ(again.mesh.points, order.mesh.points);
  EXPECT_EQ(again.mesh.faces, order.mesh.faces);
}

TEST(SpatialOrder, ExtremeAndNonFiniteCoordinatesStillGiveAPermutation) {
  // Coordinates spanning the whole double range (the extent overflows to infinity), a single
  // point (zero extent), and NaN / infinite positions: an order of every vertex, non-finite last.
  const std::vector<std::vector<Vec3>> cases = {
      {Vec3(-1e308, 0, 0), Vec3(1e308, 1, 0), Vec3(0, -1e308, 1e308), Vec3(5, 5, 5)},
      {Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)},
      {Vec3(NAN, 0, 0), Vec3(0, 0, 0), Vec3(INFINITY, 1, 1), Vec3(1, 1, 1), Vec3(4e-320, 0, 0)}};
  for (const std::vector<Vec3> &points : cases) {
    const std::vector<int> order = mortonOrder(points);
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (int v = 0; v < int(points.size()); ++v) EXPECT_EQ(sorted[v], v);
    bool seen_non_finite = false;
    for (int v : order) {
      if (!points[v].allFinite()) seen_non_finite = true;
      else EXPECT_FALSE(seen_non_finite) << "a finite vertex after a non-finite one";
    }
  }
}

// The order in parallel (pairs of Morton code and vertex sorted by libstdc++'s parallel sort, then
// ties by position) is the serial order, for one thread or two: codes shared
// by many vertices (duplicates, vertices in one lattice cell), non-finite positions last by index.
TEST(SpatialOrder, ParallelSortGivesTheComparisonSortsOrderForAnyThreadCount) {
  MeshArrays m = test_meshes::cylinder(1.0, 2.0, 60, 50);
  test_meshes::addNoise(m, 0.01, 5);
  const int n0 = int(m.points.size());
  for (int v = 0; v < n0; v += 7) m.points.push_back(m.points[v]); // exact duplicates
  for (int v = 0; v < 40; ++v) m.points.push_back(m.points[3] + Vec3(1e-12 * v, 0, 0)); // one cell
  m.points.push_back(Vec3(NAN, 0, 0));
  m.points.push_back(Vec3(0, INFINITY, 0));
  const int n = int(m.points.size());
  const std::vector<Vec3> &p = m.points;
  const std::vector<int> got_serial = mortonOrder(p);
  const int saved = min_parallel_vertices, threads = omp_get_max_threads();
  min_parallel_vertices = 0;
  std::vector<std::vector<int>> got;
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    got.push_back(mortonOrder(p));
  }
  omp_set_num_threads(threads);
  min_parallel_vertices = saved;
  EXPECT_EQ(got[0], got_serial);
  EXPECT_EQ(got[1], got_serial);
  // A permutation with the duplicates next to each other in index order and the two non-finite
  // positions last, in index order.
  std::vector<int> sorted = got_serial;
  std::sort(sorted.begin(), sorted.end());
  for (int v = 0; v < n; ++v) ASSERT_EQ(sorted[v], v);
  EXPECT_EQ(got_serial[n - 2], n - 2);
  EXPECT_EQ(got_serial[n - 1], n - 1);
  std::vector<int> position(n);
  for (int i = 0; i < n; ++i) position[got_serial[i]] = i;
  for (int k = 0, v = 0; v < n0; v += 7, ++k) {
    const int copy = n0 + k;
    EXPECT_EQ(position[copy], position[v] + 1) << v; // equal positions: by index, adjacent
  }
  // Faces: sorted as std::sort sorts them, whatever the thread count.
  MeshArrays a = m, b = m;
  a.points.resize(n0), b.points.resize(n0);
  min_parallel_vertices = 0;
  omp_set_num_threads(2);
  putInSpatialOrder(a);
  omp_set_num_threads(1);
  putInSpatialOrder(b);
  omp_set_num_threads(threads);
  min_parallel_vertices = saved;
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_TRUE(std::is_sorted(a.faces.begin(), a.faces.end()));
}

// parallelSort: std::sort's sequence, whether the input is shuffled, sorted already (the check that
// skips the sort) or sorted but for its last two values (which the check must not skip).
TEST(ParallelSort, GivesStdSortsSequenceForShuffledSortedAndNearlySortedInput) {
  std::mt19937 random(5);
  std::vector<std::pair<std::uint64_t, int>> shuffled(60000);
  for (int i = 0; i < int(shuffled.size()); ++i) shuffled[i] = {random() % 5000, i};
  std::vector<std::pair<std::uint64_t, int>> expected = shuffled;
  std::sort(expected.begin(), expected.end());

  std::vector<std::pair<std::uint64_t, int>> values = shuffled;
  vcg_ext::detail::parallelSort(values);
  EXPECT_TRUE(values == expected);
  vcg_ext::detail::parallelSort(values); // sorted already
  EXPECT_TRUE(values == expected);
  values = expected;
  std::swap(values[values.size() - 1], values[values.size() - 2]);
  ASSERT_FALSE(values == expected);
  vcg_ext::detail::parallelSort(values);
  EXPECT_TRUE(values == expected);
  // Any number of threads (blocks of the merge sort: 1, 2, 4, 8) and sizes that do not split
  // evenly.
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2, 3, 5, 8})
    for (size_t size : {size_t(59999), size_t(7), size_t(1)}) {
      omp_set_num_threads(threads);
      std::vector<std::pair<std::uint64_t, int>> part(shuffled.begin(), shuffled.begin() + size);
      std::vector<std::pair<std::uint64_t, int>> sorted = part;
      std::sort(sorted.begin(), sorted.end());
      vcg_ext::detail::parallelSort(part);
      EXPECT_TRUE(part == sorted) << threads << " threads, " << size << " values";
    }
  omp_set_num_threads(saved);
}

// sortFacesByCorners: std::sort's sequence in linear time, with repeated faces, first corners
// spread unevenly, and first corners out of range on either side, for 1 and 2 threads.
TEST(SortFacesByCorners, GivesStdSortsSequence) {
  std::mt19937 random(11);
  const int n = 30000;
  std::vector<Face> faces(100000);
  for (Face &f : faces) {
    const int a = int(random() % (n / 3)); // many faces per first corner
    f = {a, int(random() % n), int(random() % n)};
  }
  faces[10] = faces[20];                            // a repeated face
  faces[30] = {-1, 5, 7}, faces[31] = {-3, 2, 2};   // out of range below
  faces[40] = {n, 1, 2}, faces[41] = {n + 5, 0, 0}; // and above
  std::vector<Face> expected = faces;
  std::sort(expected.begin(), expected.end());
  const int saved_threads = omp_get_max_threads();
  const int saved = min_parallel_vertices;
  min_parallel_vertices = 1000;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    std::vector<Face> got = faces;
    detail::sortFacesByCorners(got, n);
    EXPECT_TRUE(got == expected) << threads << " threads";
  }
  min_parallel_vertices = saved;
  omp_set_num_threads(saved_threads);
}
