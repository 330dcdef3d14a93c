#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <vcg_ext/analysis/curvature.h>

using namespace vcg_ext;

namespace {

CurvatureField curvatureOf(const MeshArrays &m, Rings *rings_out = nullptr) {
  const Rings r = computeRings(int(m.points.size()), m.faces);
  CurvatureField c;
  computeCurvature(m.points, m.faces, r, c);
  if (rings_out) *rings_out = r;
  return c;
}

void expectOrthonormalFrame(const CurvatureField &c, int v) {
  EXPECT_NEAR(c.dir1[v].norm(), 1.0, 1e-12);
  EXPECT_NEAR(c.dir2[v].norm(), 1.0, 1e-12);
  EXPECT_NEAR(c.dir1[v].dot(c.dir2[v]), 0.0, 1e-12);
  EXPECT_NEAR(c.dir1[v].dot(c.normal[v]), 0.0, 1e-12);
  EXPECT_NEAR(c.dir2[v].dot(c.normal[v]), 0.0, 1e-12);
}

} // namespace

TEST(Curvature, SphereHasPrincipalCurvaturesOneOverRadiusAndRadialNormals) {
  const double r = 2.0;
  const auto m = test_meshes::icosphere(r, 5); // 10242 vertices
  const CurvatureField c = curvatureOf(m);
  double max_k_error = 0, max_angle = 0, area_sum = 0;
  for (int v = 0; v < int(m.points.size()); ++v) {
    max_k_error = std::max({max_k_error, std::abs(c.k1[v] * r - 1), std::abs(c.k2[v] * r - 1)});
    EXPECT_NEAR(c.mean[v] * r, 1.0, 0.02) << v;
    EXPECT_NEAR(c.gauss[v] * r * r, 1.0, 0.03) << v;
    EXPECT_GE(c.k1[v], c.k2[v]);
    const double cosine = std::min(1.0, c.normal[v].dot(m.points[v].normalized()));
    max_angle = std::max(max_angle, std::acos(cosine) * 180 / M_PI);
    expectOrthonormalFrame(c, v);
    area_sum += c.area[v];
  }
  EXPECT_LT(max_k_error, 0.02);
  EXPECT_LT(max_angle, 1.0);
  // Mixed areas tile the surface: their sum is the polyhedron's area, a bit below 4πr².
  EXPECT_NEAR(area_sum / (4 * M_PI * r * r), 1.0, 0.005);
  std::printf("sphere r=2, 10242 vertices: max |k r - 1| = %.2e, max normal angle = %.3f deg\n",
              max_k_error, max_angle);
}

TEST(Curvature, CylinderInteriorHasCurvatureAroundAndZeroAlongTheAxis) {
  const double r = 1.0;
  const auto m = test_meshes::cylinder(r, 4.0, 64, 48);
  const CurvatureField c = curvatureOf(m);
  int checked = 0;
  double max_k1_error = 0, max_k2 = 0;
  for (int v = 0; v < int(m.points.size()); ++v) {
    const Vec3 &p = m.points[v];
    if (std::abs(p.z()) > 1.0) continue; // away from the rims
    const Vec3 radial = Vec3(p.x(), p.y(), 0).normalized();
    const Vec3 around = Vec3::UnitZ().cross(radial);
    max_k1_error = std::max(max_k1_error, std::abs(c.k1[v] * r - 1));
    max_k2 = std::max(max_k2, std::abs(c.k2[v] * r));
    EXPECT_GT(c.normal[v].dot(radial), std::cos(M_PI / 180)) << v;
    EXPECT_GT(std::abs(c.dir1[v].dot(around)), 0.99) << v;
    EXPECT_GT(std::abs(c.dir2[v].z()), 0.99) << v;
    expectOrthonormalFrame(c, v);
    ++checked;
  }
  EXPECT_GT(checked, 64 * 20);
  EXPECT_LT(max_k1_error, 0.03);
  EXPECT_LT(max_k2, 0.05);
  std::printf("cylinder r=1: max |k1 r - 1| = %.2e, max |k2 r| = %.2e over %d vertices\n",
              max_k1_error, max_k2, checked);
}

TEST(Curvature, PlaneIsFlatEverywhereIncludingTheBoundary) {
  const auto m = test_meshes::heightField(9, -1, 1, -1, 1, [](double, double) { return 0.0; });
  const CurvatureField c = curvatureOf(m);
  for (int v = 0; v < int(m.points.size()); ++v) {
    EXPECT_NEAR(c.mean[v], 0.0, 1e-12);
    EXPECT_NEAR(c.gauss[v], 0.0, 1e-12);
    EXPECT_NEAR(c.k1[v], 0.0, 1e-12);
    EXPECT_NEAR(c.k2[v], 0.0, 1e-12);
    EXPECT_NEAR((c.normal[v] - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    expectOrthonormalFrame(c, v);
  }
  // Interior mixed area of a regular grid vertex is one grid cell (0.25²).
  EXPECT_NEAR(c.area[4 * 9 + 4], 0.0625, 1e-12);
}

TEST(Curvature, SaddleAtOriginHasCurvaturesPlusMinusTwoAlongTheAxes) {
  // z = x² − y² with the upward normal: curving away from the normal along y (+2), towards it
  // along x (−2), as a sphere seen from outside curves away from its normal (+1/r).
  const auto m = test_meshes::heightField(41, -0.2, 0.2, -0.2, 0.2,
                                          [](double x, double y) { return x * x - y * y; });
  const CurvatureField c = curvatureOf(m);
  const int o = test_meshes::nearestVertex(m, 0, 0);
  ASSERT_NEAR(m.points[o].norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.k1[o], 2.0, 0.1);
  EXPECT_NEAR(c.k2[o], -2.0, 0.1);
  EXPECT_NEAR(c.mean[o], 0.0, 0.05);
  EXPECT_NEAR(c.gauss[o], -4.0, 0.2);
  EXPECT_GT(std::abs(c.dir1[o].y()), 0.999);
  EXPECT_GT(std::abs(c.dir2[o].x()), 0.999);
  expectOrthonormalFrame(c, o);
  std::printf("saddle: k1 = %.4f, k2 = %.4f, H = %.2e, K = %.4f\n", c.k1[o], c.k2[o], c.mean[o],
              c.gauss[o]);
}

TEST(Curvature, RotatedQuadricDirectionsFollowTheSurfaceNotTheGrid) {
  // z = 1.5 u² − 0.5 w² with (u, w) the axes turned by 30°: normal curvatures −3 along u, +1 along
  // w, neither along a grid edge.
  const double angle = M_PI / 6;
  const Vec3 u(std::cos(angle), std::sin(angle), 0), w(-std::sin(angle), std::cos(angle), 0);
  const auto m = test_meshes::heightField(41, -0.2, 0.2, -0.2, 0.2, [&](double x, double y) {
    const double a = x * u.x() + y * u.y(), b = x * w.x() + y * w.y();
    return 1.5 * a * a - 0.5 * b * b;
  });
  const CurvatureField c = curvatureOf(m);
  const int o = test_meshes::nearestVertex(m, 0, 0);
  EXPECT_NEAR(c.k1[o], 1.0, 0.05);
  EXPECT_NEAR(c.k2[o], -3.0, 0.15);
  EXPECT_NEAR(c.mean[o], -1.0, 0.05);
  EXPECT_GT(std::abs(c.dir1[o].dot(w)), 0.995);
  EXPECT_GT(std::abs(c.dir2[o].dot(u)), 0.995);
  std::printf("rotated quadric: k1 = %.4f (1), k2 = %.4f (-3), |dir1.w| = %.5f\n", c.k1[o], c.k2[o],
              std::abs(c.dir1[o].dot(w)));
}

TEST(Curvature, BoundaryVerticesAverageTheirInteriorNeighbours) {
  const auto m = test_meshes::cylinder(1.0, 2.0, 32, 12);
  Rings r;
  const CurvatureField c = curvatureOf(m, &r);
  int boundary_count = 0;
  for (int v = 0; v < r.vertex_count; ++v) {
    if (!r.boundary[v]) continue;
    ++boundary_count;
    double k1 = 0, k2 = 0, H = 0, K = 0;
    int count = 0;
    for (const int *w = r.ring1Begin(v); w != r.ring1End(v); ++w)
      if (!r.boundary[*w]) k1 += c.k1[*w], k2 += c.k2[*w], H += c.mean[*w], K += c.gauss[*w], ++count;
    ASSERT_GT(count, 0);
    EXPECT_NEAR(c.k1[v], k1 / count, 1e-12);
    EXPECT_NEAR(c.k2[v], k2 / count, 1e-12);
    EXPECT_NEAR(c.mean[v], H / count, 1e-12);
    EXPECT_NEAR(c.gauss[v], K / count, 1e-12);
    EXPECT_NEAR(c.k1[v], 1.0, 0.05);
    EXPECT_GT(std::abs(c.dir2[v].z()), 0.99) << v; // inherits "along the axis"
    expectOrthonormalFrame(c, v);
  }
  EXPECT_EQ(boundary_count, 64);
}

TEST(Curvature, DegenerateNonManifoldAndIsolatedVerticesGetZerosNotNaN) {
  // 0–4: a bow-tie at 0; 5–7: a zero-area triangle (collinear); 8: isolated.
  std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},  {-1, 0, 0.3}, {0, -1, 0.2},
                         {2, 2, 2}, {3, 3, 3}, {4, 4, 4}, {9, 9, 9}};
  std::vector<Face> f = {{0, 1, 2}, {0, 3, 4}, {5, 6, 7}};
  const Rings r = computeRings(int(p.size()), f);
  CurvatureField c;
  computeCurvature(p, f, r, c);
  for (int v = 0; v < int(p.size()); ++v) {
    for (double x : {c.mean[v], c.gauss[v], c.k1[v], c.k2[v], c.area[v]}) EXPECT_TRUE(std::isfinite(x));
    EXPECT_TRUE(c.normal[v].allFinite() && c.dir1[v].allFinite() && c.dir2[v].allFinite());
  }
  for (int v : {0, 5, 6, 7, 8}) {
    EXPECT_EQ(c.mean[v], 0.0) << v;
    EXPECT_EQ(c.gauss[v], 0.0) << v;
    EXPECT_EQ(c.k1[v], 0.0) << v;
    EXPECT_EQ(c.k2[v], 0.0) << v;
  }
  EXPECT_EQ(c.normal[8], Vec3::Zero());
  EXPECT_NEAR((c.normal[1] - Vec3::UnitZ()).norm(), 0.0, 1e-12); // a single face's normal
}

TEST(Curvature, IndependentOfVertexOrderAndThreadCount) {
  auto m = test_meshes::icosphere(1.0, 4);
  test_meshes::addNoise(m, 0.005, 7);
  const CurvatureField a = curvatureOf(m);
  const auto perm = test_meshes::shuffledPermutation(int(m.points.size()), 3);
  const CurvatureField b = curvatureOf(test_meshes::permuted(m, perm));
  for (int v = 0; v < int(m.points.size()); ++v) {
    ASSERT_TRUE(std::isfinite(a.k1[v]) && std::isfinite(a.k2[v]) && a.dir1[v].allFinite());
    EXPECT_GE(a.k1[v], a.k2[v]);
    const int w = perm[v];
    EXPECT_NEAR(a.mean[v], b.mean[w], 1e-12);
    EXPECT_NEAR(a.gauss[v], b.gauss[w], 1e-12);
    EXPECT_NEAR(a.k1[v], b.k1[w], 1e-12);
    EXPECT_NEAR(a.k2[v], b.k2[w], 1e-12);
    EXPECT_NEAR(a.area[v], b.area[w], 1e-15);
    EXPECT_NEAR((a.normal[v] - b.normal[w]).norm(), 0.0, 1e-12);
    // A direction is a line: its sign may flip where the fit is nearly isotropic.
    EXPECT_NEAR(std::abs(a.dir1[v].dot(b.dir1[w])), 1.0, 1e-9);
  }

  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const CurvatureField one = curvatureOf(m);
  omp_set_num_threads(2);
  const CurvatureField two = curvatureOf(m);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.k1, two.k1);
  EXPECT_EQ(one.k2, two.k2);
  EXPECT_EQ(one.mean, two.mean);
  EXPECT_EQ(one.dir1, two.dir1);
  EXPECT_EQ(one.normal, two.normal);
}

// The vertex normals are the area-weighted sums of their faces' cross products in face-list order,
// normalised: the same bits as summing a per-face array of cross products (how they were computed
// before), for interior and boundary vertices alike, with a zero normal where the faces have no
// area; computeBoundaryVertexNormals gives the boundary's the same and leaves the others.
TEST(VertexNormals, AreaWeightedSumsOfTheFacesCrossProducts) {
  MeshArrays m = test_meshes::cylinder(1.0, 2.0, 24, 12); // open: two boundary curves
  test_meshes::addNoise(m, 0.02, 3);
  m.points.push_back(Vec3(5, 5, 5)); // isolated
  const int n = int(m.points.size());
  const Rings rings = computeRings(n, m.faces);
  std::vector<Vec3> cross(m.faces.size()), expected(n, Vec3::Zero());
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const Face &t = m.faces[f];
    cross[f] = (m.points[t[1]] - m.points[t[0]]).cross(m.points[t[2]] - m.points[t[0]]);
  }
  for (int v = 0; v < n; ++v) {
    Vec3 sum = Vec3::Zero();
    for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f) sum += cross[*f];
    if (sum.norm() > 0) expected[v] = sum / sum.norm();
  }
  std::vector<Vec3> normals;
  computeVertexNormals(m.points, m.faces, rings, normals);
  ASSERT_EQ(normals.size(), size_t(n));
  EXPECT_EQ(normals, expected);
  EXPECT_EQ(normals[n - 1], Vec3::Zero());
  // An outward normal on the cylinder's side: along the radius.
  EXPECT_GT(normals[0].dot(Vec3(m.points[0].x(), m.points[0].y(), 0).normalized()), 0.9);
  std::vector<Vec3> boundary(n, Vec3::Constant(7));
  computeBoundaryVertexNormals(m.points, m.faces, rings, boundary);
  int boundary_count = 0;
  for (int v = 0; v < n; ++v) {
    EXPECT_EQ(boundary[v], rings.boundary[v] ? expected[v] : Vec3::Constant(7)) << v;
    boundary_count += rings.boundary[v];
  }
  EXPECT_EQ(boundary_count, 48);
}

// computeCurvature's stages one by one: a vertex's fan sums, the interior values from them, and
// what a boundary vertex borrows.
namespace {
// A vertex at the origin with six neighbours on the unit circle at height z (a hexagon fan).
MeshArrays hexagonFan(double z) {
  std::vector<Vec3> points{Vec3::Zero()};
  std::vector<Face> faces;
  for (int k = 0; k < 6; ++k) {
    points.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), z);
    faces.push_back(Face{0, 1 + k, 1 + (k + 1) % 6});
  }
  return test_meshes::fromArrays(points, faces);
}
} // namespace

TEST(CurvatureStages, FlatHexagonFanSumsToItsVoronoiAreaAndFullAngle) {
  const MeshArrays m = hexagonFan(0.0);
  detail::FanSums sums;
  for (const Face &t : m.faces)
    ASSERT_TRUE(detail::addFanCorner(0, t, m.points, Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY(),
                                     true, sums));
  EXPECT_NEAR(sums.angle_sum, 2 * M_PI, 1e-12);
  EXPECT_NEAR(sums.mixed_area, std::sqrt(3.0) / 2, 1e-12); // a third of six equilateral faces
  EXPECT_NEAR(sums.laplacian.norm(), 0.0, 1e-12);
  CurvatureField out;
  out.normal = {Vec3::UnitZ()};
  out.mean = out.gauss = out.k1 = out.k2 = {7.0};
  detail::storeInteriorCurvature(0, sums, Vec3::UnitX(), Vec3::UnitY(), false, out);
  EXPECT_NEAR(out.mean[0], 0.0, 1e-12);
  EXPECT_NEAR(out.gauss[0], 0.0, 1e-12);
}

TEST(CurvatureStages, EdgeRowsOfABowlGiveItsNormalCurvatureInEveryDirection) {
  // Neighbours half a unit below the tangent plane at distance sqrt(1.25): every edge's normal
  // curvature is 2 * 0.5 / 1.25 = 0.8, so the fitted tensor is 0.8 times the identity.
  const MeshArrays m = hexagonFan(-0.5);
  detail::FanSums sums;
  for (const Face &t : m.faces)
    ASSERT_TRUE(detail::addFanCorner(0, t, m.points, Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY(),
                                     true, sums));
  Eigen::Matrix3d M = sums.normal_matrix.selfadjointView<Eigen::Upper>();
  const Eigen::Vector3d tensor = detail::solveTensorFit(M, sums.rhs);
  EXPECT_NEAR(tensor[0], 0.8, 1e-12);
  EXPECT_NEAR(tensor[1], 0.0, 1e-12);
  EXPECT_NEAR(tensor[2], 0.8, 1e-12);
  // A face with its three corners on a line adds nothing and says so.
  detail::FanSums other;
  const std::vector<Vec3> line{Vec3::Zero(), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_FALSE(detail::addFanCorner(0, Face{0, 1, 2}, line, Vec3::UnitZ(), Vec3::UnitX(),
                                    Vec3::UnitY(), true, other));
  EXPECT_EQ(other.mixed_area, 0.0);
}

TEST(CurvatureStages, BoundaryVertexBorrowsTheMeanOfItsInteriorNeighbours) {
  const MeshArrays m = hexagonFan(0.0);
  const Rings rings = computeRings(7, m.faces);
  CurvatureField out;
  out.normal.assign(7, Vec3::UnitZ());
  out.mean.assign(7, 0.0);
  out.gauss = out.k1 = out.k2 = out.mean;
  std::vector<std::uint8_t> interior_valid(7, 0);
  // Vertex 1 (on the rim) has neighbours 0, 2 and 6; only 0 and 2 count as interior here.
  interior_valid[0] = interior_valid[2] = 1;
  out.mean[0] = 1, out.mean[2] = 3, out.mean[6] = 100;
  out.k1[0] = 2, out.k1[2] = 4;
  detail::borrowBoundaryCurvature(1, rings, interior_valid, false, out);
  EXPECT_EQ(out.mean[1], 2.0);
  EXPECT_EQ(out.k1[1], 3.0);
  EXPECT_EQ(out.gauss[1], 0.0);
}
