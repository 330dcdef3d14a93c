#include <gtest/gtest.h>
#include <vcg_ext/methods/paper/uniform_curvature.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

using namespace vcg_ext;

namespace {

// A vertex whose principal frame is (x, y, z) rotated by `frame`.
VertexCurvature vertexIn(const Eigen::Matrix3d &frame, double k1, double k2) {
  return {k1, k2, frame.col(0), frame.col(1), frame.col(2)};
}

// The vertex's principal directions turned by phi about its normal.
VertexCurvature turned(const VertexCurvature &self, double phi, double k1, double k2) {
  const Vec3 d1 = std::cos(phi) * self.dir1 + std::sin(phi) * self.dir2;
  const Vec3 d2 = -std::sin(phi) * self.dir1 + std::cos(phi) * self.dir2;
  return {k1, k2, d1, d2, self.normal};
}

const UniformCurvatureVariant kBoth[] = {UniformCurvatureVariant::Paper, UniformCurvatureVariant::Neighbour};

} // namespace

TEST(UniformCurvature, NeighboursLikeSelfGiveSelfCurvatures) {
  const Eigen::Matrix3d frame = Eigen::AngleAxisd(1.1, Vec3(0.3, -1, 2).normalized()).toRotationMatrix();
  const VertexCurvature self = vertexIn(frame, 1.7, -0.4);
  VertexCurvature ring[5] = {self, self, self, self, self};
  ring[2].dir1 = -ring[2].dir1; // direction signs carry no information
  ring[3].dir2 = -ring[3].dir2;
  const double saliency[5] = {0.1, 0.9, 0.3, 0.0, 0.5};
  for (auto variant : kBoth) {
    double k1, k2;
    uniformPrincipalCurvature(self, ring, saliency, 5, variant, k1, k2);
    EXPECT_NEAR(k1, 1.7, 1e-14);
    EXPECT_NEAR(k2, -0.4, 1e-14);
  }
}

TEST(UniformCurvature, PaperVariantKeepsMeanCurvatureWhenDirectionsAreOrthogonal) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), curvature(-2, 2), unit(0, 1);
  const VertexCurvature self = vertexIn(Eigen::Matrix3d::Identity(), 1.3, 0.2);
  VertexCurvature ring[7];
  double saliency[7];
  double expected1 = 0, expected2 = 0, weight_sum = 0;
  for (int j = 0; j < 7; ++j) {
    const double phi = angle(rng);
    ring[j] = turned(self, phi, curvature(rng), curvature(rng)); // neighbours' own k do not enter
    saliency[j] = unit(rng);
    const double c = std::cos(phi), s = std::sin(phi);
    expected1 += saliency[j] * (1.3 * c * c + 0.2 * s * s);
    expected2 += saliency[j] * (1.3 * s * s + 0.2 * c * c); // θ2 = θ1 + 90°
    weight_sum += saliency[j];
  }
  double k1, k2;
  uniformPrincipalCurvature(self, ring, saliency, 7, UniformCurvatureVariant::Paper, k1, k2);
  EXPECT_NEAR(k1, expected1 / weight_sum, 1e-14);
  EXPECT_NEAR(k2, expected2 / weight_sum, 1e-14);
  EXPECT_NEAR(k1 + k2, 1.3 + 0.2, 1e-14); // the finding of ALGORITHM.md: H never changes
  EXPECT_GT(std::abs(k1 - 1.3), 0.05);    // while k1, k2 themselves do
}

TEST(UniformCurvature, NeighbourVariantFollowsEulersFormula) {
  const Eigen::Matrix3d frame = Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  const VertexCurvature self = vertexIn(frame, 5.0, 4.0); // own curvatures must not enter
  const double one[1] = {1.0};
  double k1, k2;
  // Turned by 90°: the neighbour's k1 lies along q_i's y axis, so the two swap.
  VertexCurvature ring[1] = {turned(self, M_PI / 2, 0.9, -0.3)};
  uniformPrincipalCurvature(self, ring, one, 1, UniformCurvatureVariant::Neighbour, k1, k2);
  EXPECT_NEAR(k1, -0.3, 1e-14);
  EXPECT_NEAR(k2, 0.9, 1e-14);
  // Any angle: normal curvature along x and y of the neighbour's quadratic form.
  const double phi = 0.6;
  ring[0] = turned(self, phi, 0.9, -0.3);
  uniformPrincipalCurvature(self, ring, one, 1, UniformCurvatureVariant::Neighbour, k1, k2);
  const double c2 = std::cos(phi) * std::cos(phi), s2 = std::sin(phi) * std::sin(phi);
  EXPECT_NEAR(k1, 0.9 * c2 - 0.3 * s2, 1e-14);
  EXPECT_NEAR(k2, 0.9 * s2 - 0.3 * c2, 1e-14);
  EXPECT_NEAR(k1 + k2, 0.9 - 0.3, 1e-14);
  // Directions tilted out of q_i's tangent plane count by their projection.
  ring[0].dir1 += 0.8 * self.normal;
  ring[0].dir2 -= 0.5 * self.normal;
  ring[0].normal = (ring[0].normal + 0.3 * self.dir1).normalized();
  uniformPrincipalCurvature(self, ring, one, 1, UniformCurvatureVariant::Neighbour, k1, k2);
  EXPECT_NEAR(k1, 0.9 * c2 - 0.3 * s2, 1e-14);
  EXPECT_NEAR(k2, 0.9 * s2 - 0.3 * c2, 1e-14);
}

TEST(UniformCurvature, SaliencyWeightsActAsWeights) {
  const VertexCurvature self = vertexIn(Eigen::Matrix3d::Identity(), 2.0, -1.0);
  // Neighbour curvatures along x: 2 (aligned), -1 (turned 90°), 0.5 (turned 45°).
  VertexCurvature ring[3] = {turned(self, 0, 2.0, -1.0), turned(self, M_PI / 2, 2.0, -1.0),
                             turned(self, M_PI / 4, 2.0, -1.0)};
  double k1, k2;
  const double weights[3] = {3.0, 1.0, 0.0};
  for (auto variant : kBoth) {
    uniformPrincipalCurvature(self, ring, weights, 3, variant, k1, k2);
    EXPECT_NEAR(k1, (3 * 2.0 + 1 * -1.0) / 4, 1e-14);
    EXPECT_NEAR(k2, (3 * -1.0 + 1 * 2.0) / 4, 1e-14);
    // The zero-weight neighbour has no effect: the same as leaving it out.
    double k1_two, k2_two;
    uniformPrincipalCurvature(self, ring, weights, 2, variant, k1_two, k2_two);
    EXPECT_EQ(k1, k1_two);
    EXPECT_EQ(k2, k2_two);
  }
  // All saliencies ~0: plain mean.
  const double zeros[3] = {0.0, 1e-13, 0.0};
  uniformPrincipalCurvature(self, ring, zeros, 3, UniformCurvatureVariant::Neighbour, k1, k2);
  EXPECT_NEAR(k1, (2.0 - 1.0 + 0.5) / 3, 1e-14);
  EXPECT_NEAR(k2, (-1.0 + 2.0 + 0.5) / 3, 1e-14);
  // No neighbour: the vertex's own curvatures.
  uniformPrincipalCurvature(self, ring, zeros, 0, UniformCurvatureVariant::Neighbour, k1, k2);
  EXPECT_EQ(k1, 2.0);
  EXPECT_EQ(k2, -1.0);
}

TEST(UniformCurvature, DirectionAlongTheNormalFallsBackToTheOtherDirection) {
  const VertexCurvature self = vertexIn(Eigen::Matrix3d::Identity(), 1.0, 0.0);
  // Neighbour's dir1 is q_i's normal; its dir2 lies along q_i's x axis: θ2 = 0, θ1 = 90°.
  VertexCurvature ring[1] = {{3.0, 1.0, Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0)}};
  const double one[1] = {1.0};
  double k1, k2;
  uniformPrincipalCurvature(self, ring, one, 1, UniformCurvatureVariant::Paper, k1, k2);
  EXPECT_NEAR(k1, 0.0, 1e-14); // k1 cos²90° + k2 sin²90°
  EXPECT_NEAR(k2, 1.0, 1e-14);
  uniformPrincipalCurvature(self, ring, one, 1, UniformCurvatureVariant::Neighbour, k1, k2);
  EXPECT_NEAR(k1, 1.0, 1e-14);
  EXPECT_NEAR(k2, 3.0, 1e-14);
}
