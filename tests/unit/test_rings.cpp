#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/core/rings.h>

using namespace vcg_ext;

TEST(Rings, ClosedIcosphereHasValence5And6AndNoBoundary) {
  const auto m = test_meshes::icosphere(1.0, 2); // 162 vertices
  const Rings r = computeRings(int(m.points.size()), m.faces);
  int valence5 = 0;
  for (int v = 0; v < r.vertex_count; ++v) {
    EXPECT_FALSE(r.boundary[v]);
    EXPECT_FALSE(r.nonmanifold[v]);
    EXPECT_EQ(r.ring1Size(v), r.face_offsets[v + 1] - r.face_offsets[v]);
    valence5 += r.ring1Size(v) == 5;
    EXPECT_TRUE(r.ring1Size(v) == 5 || r.ring1Size(v) == 6);
  }
  EXPECT_EQ(valence5, 12); // Euler: the 12 original icosahedron vertices
}

TEST(Rings, GridInteriorTwoRingOfValence6Vertex) {
  const auto m = test_meshes::heightField(7, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const Rings r = computeRings(int(m.points.size()), m.faces);
  const int centre = 3 * 7 + 3;
  EXPECT_EQ(r.ring1Size(centre), 6);
  EXPECT_FALSE(r.boundary[centre]);
  EXPECT_EQ(r.ring2Size(centre), 18); // the 6 + 12 vertices of a regular valence-6 patch
  for (const int *w = r.ring1Begin(centre); w != r.ring1End(centre); ++w)
    EXPECT_TRUE(std::binary_search(r.ring2Begin(centre), r.ring2End(centre), *w));
  EXPECT_TRUE(r.boundary[0]);
  EXPECT_FALSE(r.nonmanifold[0]);
  const EdgeStatistics s = edgeStatistics(m.points, r);
  EXPECT_NEAR(s.bbox_diagonal, std::sqrt(2.0), 1e-12);
  // Edges are 1/6 (axis) and sqrt(2)/6 (diagonals), one diagonal per quad.
  const double axis = 2 * 6 * 7, diag = 36;
  EXPECT_NEAR(s.mean_edge_length, (axis / 6 + diag * std::sqrt(2.0) / 6) / (axis + diag), 1e-12);
}

TEST(Rings, BowTieAndIsolatedVerticesAreFlagged) {
  // Two triangles sharing only vertex 0, plus an unreferenced vertex 5.
  std::vector<Face> faces = {{0, 1, 2}, {0, 3, 4}};
  const Rings r = computeRings(6, faces);
  EXPECT_TRUE(r.nonmanifold[0]);
  EXPECT_FALSE(r.nonmanifold[1]);
  EXPECT_TRUE(r.isolated[5]);
  EXPECT_EQ(r.ring1Size(5), 0);
}

TEST(Rings, EdgeSharedByThreeFacesIsNonManifold) {
  std::vector<Face> faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const Rings r = computeRings(5, faces);
  EXPECT_TRUE(r.nonmanifold[0]);
  EXPECT_TRUE(r.nonmanifold[1]);
  EXPECT_FALSE(r.nonmanifold[2]);
}

// computeRings' stages one by one.
TEST(RingsStages, FacesAroundVerticesAndTheirEdgeEnds) {
  // Two triangles sharing the edge 1-2; vertex 4 has no face.
  const std::vector<Face> faces{{0, 1, 2}, {1, 3, 2}};
  Rings r;
  r.vertex_count = 5;
  detail::facesAroundVertices(5, faces, r);
  EXPECT_EQ(r.face_offsets, (std::vector<int>{0, 1, 3, 5, 6, 6}));
  EXPECT_EQ(r.faces, (std::vector<int>{0, 0, 1, 0, 1, 1}));
  std::vector<int> ends;
  detail::edgeEndsAround(1, r, faces, ends);
  EXPECT_EQ(ends, (std::vector<int>{0, 2, 2, 3})); // the shared edge twice, the others once
  detail::edgeEndsAround(4, r, faces, ends);
  EXPECT_TRUE(ends.empty());
}

TEST(RingsStages, OneFanOrABowTie) {
  // Vertex 0 in two triangles that share only it (a bow-tie), then in a fan of two.
  const std::vector<Face> bow_tie{{0, 1, 2}, {0, 3, 4}}, fan{{0, 1, 2}, {0, 2, 3}};
  for (const auto &[faces, one_fan] : {std::make_pair(bow_tie, false), std::make_pair(fan, true)}) {
    Rings r;
    r.vertex_count = 5;
    detail::facesAroundVertices(5, faces, r);
    EXPECT_EQ(detail::facesFormOneFan(0, r, faces), one_fan);
    EXPECT_TRUE(detail::facesFormOneFan(1, r, faces)); // a single face is one fan
  }
}

TEST(RingsStages, TwoRingSkipsTheVertexAndDoesNotExpandNonManifoldNeighbours) {
  const MeshArrays grid = test_meshes::heightField(7, 0, 1, 0, 1, [](double, double) { return 0; });
  Rings r = computeRings(49, grid.faces, /*with_two_rings=*/false);
  const int centre = 3 * 7 + 3;
  std::vector<int> two;
  detail::mergedTwoRing(centre, r, two);
  EXPECT_EQ(two.size(), 18u); // valence 6: 6 + 12
  EXPECT_TRUE(std::is_sorted(two.begin(), two.end()));
  EXPECT_EQ(std::count(two.begin(), two.end(), centre), 0);
  // (4, 3), a neighbour, made non-manifold: (5, 3), which only it reaches, leaves the 2-ring.
  EXPECT_EQ(std::count(two.begin(), two.end(), centre + 2), 1);
  r.nonmanifold[centre + 1] = 1;
  two.clear();
  detail::mergedTwoRing(centre, r, two);
  EXPECT_EQ(std::count(two.begin(), two.end(), centre + 2), 0);
  EXPECT_EQ(std::count(two.begin(), two.end(), centre + 1), 1); // still in, as a neighbour
  EXPECT_LT(two.size(), 18u);
}
