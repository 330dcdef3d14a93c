// vcg_ext/methods/organic/fold_repair.h: a vertex slid past its neighbours (a folded star) goes back to its ring's
// barycentre; unfolded stars, a cube's corners and edges included, stay exactly where they are.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/methods/organic/fold_repair.h>

using namespace vcg_ext;

namespace {

long foldedStars(const std::vector<Vec3> &points, const MeshArrays &m, const Rings &rings) {
  long count = 0;
  for (int v = 0; v < int(points.size()); ++v)
    count += !rings.boundary[v] && detail::starFolded(v, points, m.faces, rings);
  return count;
}

FoldRepairParams rounds(int r) {
  FoldRepairParams p;
  p.max_rounds = r;
  return p;
}

} // namespace

TEST(FoldRepair, AVertexSlidPastItsNeighboursGoesBackToItsRingBarycentre) {
  const MeshArrays grid =
      test_meshes::heightField(11, -1, 1, -1, 1, [](double, double) { return 0.0; });
  const Rings rings = computeRings(int(grid.points.size()), grid.faces);
  const std::vector<std::uint8_t> fixed(grid.points.size(), 0);
  const int v = test_meshes::nearestVertex(grid, 0, 0);
  std::vector<Vec3> points = grid.points;
  // Along the surface by 1.5 edge lengths (0.2): past its neighbour, as scanner noise moves a
  // vertex along a grazing view ray.
  points[v] += Vec3(0.3, 0.0, 0.0);
  ASSERT_GT(foldedStars(points, grid, rings), 0);

  EXPECT_EQ(repairFolds(points, grid.faces, rings, fixed, rounds(0)), 0); // no rounds: no moves
  const long moves = repairFolds(points, grid.faces, rings, fixed, rounds(5));
  EXPECT_GE(moves, 1);
  EXPECT_EQ(foldedStars(points, grid, rings), 0);
  // The folded vertex is back at its ring's barycentre, the grid point it came from.
  EXPECT_LT((points[v] - grid.points[v]).norm(), 1e-12);
  // Only stars that were folded moved: the vertices two rings away are untouched.
  for (int u = 0; u < int(points.size()); ++u)
    if ((grid.points[u] - grid.points[v]).norm() > 0.45)
      EXPECT_EQ(points[u], grid.points[u]) << u;
}

TEST(FoldRepair, CleanCreasesCornersAndFixedVerticesStay) {
  const MeshArrays cube = test_meshes::box(1, 1, 1, 4);
  const Rings rings = computeRings(int(cube.points.size()), cube.faces);
  std::vector<Vec3> points = cube.points;
  EXPECT_EQ(repairFolds(points, cube.faces, rings, std::vector<std::uint8_t>(points.size(), 0),
                        rounds(5)),
            0);
  EXPECT_EQ(points, cube.points);

  // A folded vertex that may not move (frozen, or outside the selection) stays folded.
  const MeshArrays grid =
      test_meshes::heightField(11, -1, 1, -1, 1, [](double, double) { return 0.0; });
  const Rings grid_rings = computeRings(int(grid.points.size()), grid.faces);
  const int v = test_meshes::nearestVertex(grid, 0, 0);
  std::vector<Vec3> moved = grid.points;
  moved[v] += Vec3(0.3, 0.0, 0.0);
  std::vector<std::uint8_t> fixed(grid.points.size(), 0);
  fixed[v] = 1;
  const Vec3 before = moved[v];
  repairFolds(moved, grid.faces, grid_rings, fixed, rounds(5));
  EXPECT_EQ(moved[v], before);
}
