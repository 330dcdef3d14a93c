#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/mesh_metrics.h>

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import.h>

#include <fstream>
#include <random>
#include <string>

using namespace vcg_ext;

namespace {

double deg(double radians) { return radians * 180.0 / M_PI; }

// Rotates `p` about the axis through `centre` along unit `axis` by `angle` radians.
Vec3 rotated(const Vec3 &p, const Vec3 &centre, const Vec3 &axis, double angle) {
  return centre + Eigen::AngleAxisd(angle, axis) * (p - centre);
}

// A flat 5x5 grid plus one separate triangle (faces 0..31 grid, 32 the triangle).
MeshArrays gridWithLooseTriangle() {
  MeshArrays m = test_meshes::heightField(5, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const int base = int(m.points.size());
  m.points.push_back({2.0, 0.0, 0.0});
  m.points.push_back({3.0, 0.0, 0.0});
  m.points.push_back({2.5, 0.8, 0.0});
  m.faces.push_back({base, base + 1, base + 2});
  return m;
}

MeshArrays unitCube() {
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  // Counter-clockwise seen from outside.
  std::vector<Face> f = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                         {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return test_meshes::fromArrays(std::move(p), std::move(f));
}

// Disk of n rim vertices around a centre vertex: a regular n-gon boundary.
MeshArrays regularFan(int n) {
  std::vector<Vec3> p = {{0, 0, 0}};
  std::vector<Face> f;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    p.emplace_back(std::cos(a), std::sin(a), 0.0);
    f.push_back({0, 1 + i, 1 + (i + 1) % n});
  }
  return test_meshes::fromArrays(std::move(p), std::move(f));
}

class LoadVertex;
class LoadFace;
struct LoadTypes : vcg::UsedTypes<vcg::Use<LoadVertex>::AsVertexType, vcg::Use<LoadFace>::AsFaceType> {};
class LoadVertex : public vcg::Vertex<LoadTypes, vcg::vertex::Coord3d, vcg::vertex::BitFlags> {};
class LoadFace : public vcg::Face<LoadTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
class LoadMesh : public vcg::tri::TriMesh<std::vector<LoadVertex>, std::vector<LoadFace>> {};

// The shared benchmark data, found next to the repository (tests/unit -> ../../../shared).
std::string sharedData(const std::string &relative) {
  std::string here = __FILE__;
  here = here.substr(0, here.find_last_of('/'));
  return here + "/../../../shared/data/" + relative;
}

bool loadMesh(const std::string &path, MeshArrays &out) {
  if (!std::ifstream(path).good()) return false;
  LoadMesh mesh;
  if (vcg::tri::io::Importer<LoadMesh>::Open(mesh, path.c_str()) != 0) return false;
  out = extractArrays(mesh);
  return true;
}

} // namespace

TEST(MeshMetrics, IdenticalMeshesScoreZero) {
  const MeshArrays m = test_meshes::icosphere(2.0, 3);
  const MeshComparison c = compareMeshes(m.points, m.points, m.faces);
  EXPECT_EQ(c.normals.theta_deg, 0.0);
  EXPECT_EQ(c.normals.flipped_faces, 0);
  EXPECT_EQ(c.ev, 0.0);
  EXPECT_EQ(c.volume_ratio, 1.0);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(std::isnan(c.boundary_drift_edges)); // closed: not applicable
}

TEST(MeshMetrics, OneTiltedFaceGivesItsAngleOverTheFaceCount) {
  const MeshArrays reference = gridWithLooseTriangle();
  const int nf = int(reference.faces.size()); // 33
  const Face loose = reference.faces.back();
  const Vec3 centre =
      (reference.points[loose[0]] + reference.points[loose[1]] + reference.points[loose[2]]) / 3;
  const EdgeTable edges = buildEdgeTable(reference.faces);
  for (const double tilt_deg : {25.0, 150.0}) {
    MeshArrays result = reference;
    for (int k : loose)
      result.points[k] = rotated(reference.points[k], centre, Vec3::UnitX(), tilt_deg * M_PI / 180);
    const NormalDeviation d = normalDeviation(result.points, reference.points, reference.faces, edges);
    EXPECT_NEAR(d.theta_deg, tilt_deg / nf, 1e-10);
    EXPECT_EQ(d.flipped_faces, tilt_deg > 90 ? 1 : 0);
    EXPECT_EQ(d.sharp_faces, 0);
    EXPECT_TRUE(std::isnan(d.theta_sharp_deg));
  }
}

TEST(MeshMetrics, SharpFacesAreTheTwoRowsAlongACrease) {
  // Roof z = k|x| on a 9x9 grid: the crease x = 0 is a grid line, one face on each side per row.
  const int n = 9;
  const auto roof = [](double k) {
    return test_meshes::heightField(n, -1, 1, 0, 1, [k](double x, double) { return k * std::abs(x); });
  };
  const MeshArrays steep = roof(std::tan(20 * M_PI / 180)); // dihedral 40° > 30°
  const MeshArrays shallow = roof(std::tan(10 * M_PI / 180)); // dihedral 20°
  const MeshArrays flat = roof(0.0);
  const EdgeTable edges = buildEdgeTable(steep.faces);
  const NormalDeviation d = normalDeviation(flat.points, steep.points, steep.faces, edges);
  EXPECT_EQ(d.sharp_faces, 2 * (n - 1));
  EXPECT_NEAR(d.theta_deg, 20.0, 1e-10); // every face normal is tilted by atan(k)
  EXPECT_NEAR(d.theta_sharp_deg, 20.0, 1e-10);
  EXPECT_EQ(normalDeviation(flat.points, shallow.points, shallow.faces, edges).sharp_faces, 0);
}

TEST(MeshMetrics, EvOfPlaneShiftedAlongNormalIsShiftOverDiagonal) {
  const MeshArrays reference =
      test_meshes::heightField(21, 0, 2, 0, 1, [](double, double) { return 0.0; });
  MeshArrays result = reference;
  const double d = 0.03;
  for (Vec3 &p : result.points) p.z() += d;
  EXPECT_NEAR(evError(result.points, result.faces, reference.points, reference.faces),
              d / std::sqrt(5.0), 1e-12);
}

TEST(MeshMetrics, EvOfInflatedIcosphereIsRadialOffsetOverDiagonal) {
  // A vertex pushed radially out of an inscribed convex polyhedron is nearest to itself.
  const MeshArrays reference = test_meshes::icosphere(1.0, 3);
  MeshArrays result = reference;
  for (Vec3 &p : result.points) p *= 1.02;
  EXPECT_NEAR(evError(result.points, result.faces, reference.points, reference.faces),
              0.02 / boundingBoxDiagonal(reference.points), 1e-12);
}

TEST(MeshMetrics, EvWeightsVerticesByTheResultsAreas) {
  // Two separate coplanar triangles of areas 1/2 and 2, lifted by d1 and d2 in the result.
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {7, 0, 0}, {5, 2, 0}};
  const MeshArrays reference = test_meshes::fromArrays(p, {{0, 1, 2}, {3, 4, 5}});
  MeshArrays result = reference;
  const double d1 = 0.1, d2 = 0.4;
  for (int v = 0; v < 3; ++v) result.points[v].z() += d1;
  for (int v = 3; v < 6; ++v) result.points[v].z() += d2;
  const double rms = std::sqrt((0.5 * d1 * d1 + 2.0 * d2 * d2) / 2.5);
  EXPECT_NEAR(surfaceDistanceRms(result.points, result.faces, reference.points, reference.faces),
              rms, 1e-12);
  EXPECT_NEAR(evError(result.points, result.faces, reference.points, reference.faces),
              rms / std::sqrt(49.0 + 4.0), 1e-12);
}

TEST(MeshMetrics, GridDistanceMatchesBruteForceInsideAndFarOutside) {
  MeshArrays sphere = test_meshes::icosphere(1.0, 3);
  test_meshes::addNoise(sphere, 0.01, 7);
  const TriangleGrid grid(sphere.points, sphere.faces);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    // Scales from deep inside to 20 radii out, where the search must still stop early and be exact.
    const double scale = i < 100 ? 1.2 : i < 200 ? 3.0 : 20.0;
    const Vec3 p(scale * u(rng), scale * u(rng), scale * u(rng));
    double brute = INFINITY;
    for (const Face &f : sphere.faces)
      brute = std::min(brute, (closestPointOnTriangle(p, sphere.points[f[0]], sphere.points[f[1]],
                                                      sphere.points[f[2]]) - p).squaredNorm());
    EXPECT_NEAR(grid.squaredDistance(p), brute, 1e-12 * (1 + brute));
  }
}

TEST(MeshMetrics, ClosestPointOnTriangleRegions) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  EXPECT_TRUE(closestPointOnTriangle({0.5, 0.5, 3}, a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(closestPointOnTriangle({-1, -1, 1}, a, b, c).isApprox(Vec3(0, 0, 0)));
  EXPECT_TRUE(closestPointOnTriangle({1, -3, 0}, a, b, c).isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(closestPointOnTriangle({2, 2, 0}, a, b, c).isApprox(Vec3(1, 1, 0)));
  // Degenerate (collinear) triangle: nearest point of its longest edge.
  EXPECT_TRUE(closestPointOnTriangle({1, 1, 0}, a, b, Vec3(1, 0, 0)).isApprox(Vec3(1, 0, 0)));
}

TEST(MeshMetrics, CubeVolumeIsOneAndIcosphereIsBetweenItsInAndCircumscribedBalls) {
  MeshArrays cube = unitCube();
  EXPECT_NEAR(signedVolume(cube.points, cube.faces), 1.0, 1e-15);
  EXPECT_TRUE(isClosed(buildEdgeTable(cube.faces)));
  for (Vec3 &p : cube.points) p += Vec3(3, -2, 7);
  EXPECT_NEAR(signedVolume(cube.points, cube.faces), 1.0, 1e-13); // closed: origin-independent
  auto inverted = cube.faces;
  for (Face &f : inverted) std::swap(f[1], f[2]);
  EXPECT_NEAR(signedVolume(cube.points, inverted), -1.0, 1e-13);
  auto open = cube.faces;
  open.pop_back();
  EXPECT_FALSE(isClosed(buildEdgeTable(open)));

  const double r = 1.5;
  const MeshArrays ico = test_meshes::icosphere(r, 4);
  double inradius = r;
  for (const Face &f : ico.faces)
    inradius = std::min(inradius, std::abs(ico.points[f[0]].dot(
                                      faceAreaVector(ico.points, f).normalized())));
  const double v = signedVolume(ico.points, ico.faces);
  EXPECT_LT(v, 4.0 / 3.0 * M_PI * r * r * r);
  EXPECT_GT(v, 4.0 / 3.0 * M_PI * inradius * inradius * inradius);
  EXPECT_NEAR(v / (4.0 / 3.0 * M_PI * r * r * r), 1.0, 3e-3);
}

TEST(MeshMetrics, BoundaryTurningOfRegularPolygonAndSquareGrid) {
  for (const int n : {6, 12, 40}) {
    const MeshArrays fan = regularFan(n);
    const auto loops = boundaryLoops(int(fan.points.size()), fan.faces, buildEdgeTable(fan.faces));
    ASSERT_EQ(loops.size(), 1u);
    EXPECT_EQ(int(loops[0].size()), n);
    EXPECT_NEAR(boundaryTurningDeg(fan.points, loops), 360.0 / n, 1e-10);
  }
  // A 7x7 grid: 24 boundary vertices, four 90° corners, straight elsewhere.
  const MeshArrays grid = test_meshes::heightField(7, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const auto loops = boundaryLoops(int(grid.points.size()), grid.faces, buildEdgeTable(grid.faces));
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 24u);
  EXPECT_NEAR(boundaryTurningDeg(grid.points, loops), 4 * 90.0 / 24, 1e-10);
}

TEST(MeshMetrics, BoundaryDriftCountsInwardMovesInMeanEdgeLengths) {
  const int n = 9;
  const MeshArrays reference =
      test_meshes::heightField(n, 0, 1, 0, 1, [](double, double) { return 0.0; });
  const EdgeTable edges = buildEdgeTable(reference.faces);
  const double edge = meanEdgeLength(reference.points, edges);
  // Inward direction by hand: away from each side the vertex lies on (corners: the diagonal).
  const auto inward = [](const Vec3 &p) {
    Vec3 d = Vec3::Zero();
    if (p.x() == 0) d.x() += 1;
    if (p.x() == 1) d.x() -= 1;
    if (p.y() == 0) d.y() += 1;
    if (p.y() == 1) d.y() -= 1;
    return d.normalized();
  };
  for (const double amount : {0.5, -0.25}) {
    MeshArrays result = reference;
    for (Vec3 &p : result.points) {
      if (p.x() == 0 || p.x() == 1 || p.y() == 0 || p.y() == 1) p += amount * edge * inward(p);
      else p.z() += 0.3; // interior moves do not count
    }
    EXPECT_NEAR(boundaryInwardDrift(result.points, reference.points, reference.faces, edges),
                amount, 1e-12);
  }
  // Sliding along the boundary is no drift.
  MeshArrays slid = reference;
  for (Vec3 &p : slid.points)
    if ((p.y() == 0 || p.y() == 1) && p.x() > 0 && p.x() < 1) p.x() += 0.3 * edge;
  EXPECT_NEAR(boundaryInwardDrift(slid.points, reference.points, reference.faces, edges), 0.0, 1e-12);
}

TEST(MeshMetrics, Fandisk03NoisyMatchesThePublishedScores) {
  MeshArrays noisy, clean;
  if (!loadMesh(sharedData("benchmark/Fandisk0.3/noisy.ply"), noisy) ||
      !loadMesh(sharedData("benchmark/Fandisk0.3/clean.ply"), clean))
    GTEST_SKIP() << "shared data not found at " << sharedData("benchmark/Fandisk0.3");
  ASSERT_EQ(noisy.points.size(), 6475u);
  ASSERT_EQ(noisy.faces, clean.faces);
  const MeshComparison c = compareMeshes(noisy.points, clean.points, clean.faces);
  EXPECT_NEAR(c.normals.theta_deg, 28.42, 0.05);
  EXPECT_NEAR(c.ev * 1e3, 4.37, 0.05); // exact point-to-triangle Ev, the authors' evaluator
  EXPECT_TRUE(c.closed);
}
