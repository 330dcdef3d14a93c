// The automatic choice's evidence from windows of a large mesh (vcg_ext/methods/automatic/evidence_windows.h): the
// windows' core faces get the whole mesh's first-pass normals bit for bit (closed and open meshes),
// windows that cover the whole mesh give the whole mesh's evidence exactly, windows are refused
// when they would take too much of the mesh, and the seeds do not depend on the thread count.
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/automatic/evidence_windows.h>

#include <cstring>

using namespace vcg_ext;

namespace {

FirstPassCounts defaultCounts() {
  FirstPassCounts c;
  c.prepass_pairs = 4;
  c.reference_pairs = 4;
  c.first.kind = NormalFilterKind::Guided;
  c.first.sigma_s = 1.0;
  c.first.sigma_r = 0.25;
  c.first.iterations = 4;
  c.first.guidance_every = 4;
  c.first.area_power = 0.0;
  return c;
}

bool sameBits(const Vec3 &a, const Vec3 &b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }

// Checks that every core face of windows around `seeds` has the whole mesh's normals.
void expectCoreMatchesWholeMesh(const MeshArrays &mesh, const std::vector<int> &seeds,
                                int core_rings) {
  detail::DriverSetup setup = detail::driverSetup(mesh, false);
  addFaceRingLists(setup.face_rings, mesh.faces, setup.rings); // the whole mesh's first pass
  const FirstPassCounts counts = defaultCounts();
  std::vector<Vec3> filtered, reference;
  firstPassNormals(mesh, setup.rings, setup.face_rings, setup.fixed, setup.roles, counts,
                   setup.stats.mean_edge_length, filtered, reference);

  const int reach = core_rings + detail::windowMargin(counts, 1);
  const MeshWindows w = meshWindows(mesh, setup.rings, setup.fixed, seeds, core_rings, reach);
  ASSERT_LT(w.mesh.faces.size(), mesh.faces.size()); // the windows are a part of the mesh
  const Rings rings = computeRings(int(w.mesh.points.size()), w.mesh.faces, false);
  const detail::VertexRoles roles = detail::vertexRoles(w.mesh, rings, setup.stats.mean_edge_length);
  std::vector<std::uint8_t> fixed(w.fixed);
  for (size_t v = 0; v < fixed.size(); ++v) fixed[v] = fixed[v] || roles.frozen[v];
  std::vector<Vec3> window_filtered, window_reference;
  firstPassNormals(w.mesh, rings, computeFaceRings(w.mesh.faces, rings), fixed, roles, counts,
                   setup.stats.mean_edge_length, window_filtered, window_reference);
  long core = 0, differing = 0, differing_outside = 0;
  for (size_t g = 0; g < w.face.size(); ++g) {
    const bool same = sameBits(window_filtered[g], filtered[w.face[g]]) &&
                      sameBits(window_reference[g], reference[w.face[g]]);
    if (w.core[g]) ++core, differing += !same;
    else differing_outside += !same;
  }
  EXPECT_GT(core, 200);
  EXPECT_EQ(differing, 0);
  // The margin is needed: the window's cut does change the faces near it.
  EXPECT_GT(differing_outside, 0);
}

} // namespace

TEST(EvidenceWindows, CoreFacesGetTheWholeMeshsFirstPassNormalsBitForBit) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 5); // 10242 vertices
  test_meshes::addNoise(sphere, 0.004, 7);
  expectCoreMatchesWholeMesh(sphere, {100, 5000}, 6);
}

TEST(EvidenceWindows, OpenBoundariesInsideAWindowKeepTheirValues) {
  // A height field's boundary runs through the core of a window seeded near it.
  MeshArrays field = test_meshes::heightField(
      120, -1, 1, -1, 1, [](double x, double y) { return 0.2 * std::sin(3 * x) * std::cos(2 * y); });
  test_meshes::addNoise(field, 0.003, 11);
  expectCoreMatchesWholeMesh(field, {test_meshes::nearestVertex(field, -0.98, 0.0)}, 8);
}

TEST(EvidenceWindows, WindowsOverTheWholeMeshGiveTheWholeMeshsEvidence) {
  // A noisy box: creases, confirmed ones and flat edges to count.
  MeshArrays box = test_meshes::box(1.0, 0.8, 0.6, 16);
  test_meshes::addNoise(box, 0.004, 3);
  detail::DriverSetup setup = detail::driverSetup(box, false);
  addFaceRingLists(setup.face_rings, box.faces, setup.rings); // the whole mesh's first pass
  const FirstPassCounts counts = defaultCounts();
  std::vector<Vec3> filtered, reference;
  firstPassNormals(box, setup.rings, setup.face_rings, setup.fixed, setup.roles, counts,
                   setup.stats.mean_edge_length, filtered, reference);
  const SharpFeatureEvidence whole =
      modelScaleEvidence(filtered, reference, setup.face_rings, box.points, box.faces, 30,
                         25, 1);
  EvidenceWindowParams everything;
  everything.min_windows = everything.max_windows = 2;
  everything.core_rings = 1000;
  everything.max_face_share = 1.0;
  const WindowedEvidence windowed = windowedEvidence(box, setup, counts, 30, 25, 1, everything);
  ASSERT_TRUE(windowed.used);
  EXPECT_EQ(windowed.core_faces, long(box.faces.size()));
  EXPECT_EQ(windowed.evidence.edges, whole.edges);
  EXPECT_EQ(windowed.evidence.flat_pairs, whole.flat_pairs);
  EXPECT_EQ(windowed.evidence.crease_pairs, whole.crease_pairs);
  EXPECT_EQ(windowed.evidence.confirmed_pairs, whole.confirmed_pairs);
  EXPECT_DOUBLE_EQ(windowed.evidence.crease_density, whole.crease_density);
  EXPECT_GT(whole.confirmed_pairs, 0); // the counts are not trivially zero
  EXPECT_GT(whole.flat_pairs, 0);
}

TEST(EvidenceWindows, WindowsThatWouldTakeMostOfTheMeshAreRefused) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 4); // 5120 faces: 48 windows cover it
  test_meshes::addNoise(sphere, 0.01, 3);
  const detail::DriverSetup setup = detail::driverSetup(sphere, false);
  const WindowedEvidence w = windowedEvidence(sphere, setup, defaultCounts(), 30, 25, 1);
  EXPECT_FALSE(w.used);
  EXPECT_EQ(w.evidence.edges, 0);
}

TEST(EvidenceWindows, SeedsAreSpreadOverTheVertexOrderAndSkipFixedVertices) {
  const MeshArrays sphere = test_meshes::icosphere(1.0, 3); // 642 vertices
  const Rings rings = computeRings(int(sphere.points.size()), sphere.faces);
  std::vector<std::uint8_t> fixed(sphere.points.size(), 0);
  fixed[80] = 1; // the middle of the first of four runs of 160/161 vertices
  const std::vector<int> seeds = detail::windowSeeds(rings, fixed, 4);
  EXPECT_EQ(seeds, (std::vector<int>{81, 240, 401, 561}));
}

TEST(EvidenceWindows, WindowFaceCountTakesTheFacesWithEveryCornerWithinReach) {
  // Around an icosahedron corner (valence 5, its neighbours regular at this subdivision): no face
  // has every corner at distance 0; its own five faces lie within one ring; within two, each of
  // its five sectors holds 1 + 3 triangles.
  const MeshArrays sphere = test_meshes::icosphere(1.0, 2);
  const Rings rings = computeRings(int(sphere.points.size()), sphere.faces);
  ASSERT_EQ(rings.ring1Size(0), 5);
  const std::vector<int> distance = detail::ringDistance(rings, {0}, 3);
  EXPECT_EQ(detail::windowFaceCount(sphere.faces, distance, 0), 0);
  EXPECT_EQ(detail::windowFaceCount(sphere.faces, distance, 1), 5);
  EXPECT_EQ(detail::windowFaceCount(sphere.faces, distance, 2), 20);
}
