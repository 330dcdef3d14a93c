#include <gtest/gtest.h>
#include <vcg_ext/core/small_ldlt.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

using namespace vcg_ext;

namespace {
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

void lowerOf(const Mat9 &M, double L[9][9]) {
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) L[i][j] = j <= i ? M(i, j) : 12345.0; // upper: never read
}
} // namespace

TEST(SmallLdlt, SolvesAPositiveDefiniteSystemAsEigensPivotedLdltDoes) {
  std::srand(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Mat9 A = Mat9::Random();
    const Mat9 M = A * A.transpose() + 0.1 * Mat9::Identity();
    const Vec9 b = Vec9::Random();
    double L[9][9];
    lowerOf(M, L);
    ASSERT_TRUE(detail::ldlt9(L, 1e-10)) << trial;
    Vec9 x;
    detail::ldlt9Solve<1>(L, b.data(), x.data());
    const Vec9 reference = M.ldlt().solve(b);
    EXPECT_LT((x - reference).norm(), 1e-10 * reference.norm()) << trial;
    EXPECT_LT((M * x - b).norm(), 1e-10 * b.norm()) << trial;
    // Three right-hand sides at once (the Bezier fit's coordinates): each column as alone.
    const Eigen::Matrix<double, 9, 3, Eigen::RowMajor> B = Eigen::Matrix<double, 9, 3>::Random();
    Eigen::Matrix<double, 9, 3, Eigen::RowMajor> X3;
    detail::ldlt9Solve<3>(L, B.data(), X3.data());
    for (int r = 0; r < 3; ++r) {
      const Vec9 column = B.col(r);
      Vec9 alone;
      detail::ldlt9Solve<1>(L, column.data(), alone.data());
      EXPECT_EQ(Vec9(X3.col(r)), alone) << trial << " " << r;
      EXPECT_LT((M * alone - column).norm(), 1e-10 * column.norm()) << trial;
    }
    // D on the diagonal: the product of the pivots is the determinant.
    double det = 1;
    for (int k = 0; k < 9; ++k) det *= L[k][k];
    EXPECT_NEAR(det / M.determinant(), 1.0, 1e-9) << trial;
  }
}

TEST(SmallLdlt, RefusesSingularAndIllConditionedMatrices) {
  // Rank 8: the ninth pivot is rounding only.
  Eigen::Matrix<double, 9, 8> B = Eigen::Matrix<double, 9, 8>::Random();
  double L[9][9];
  lowerOf(B * B.transpose(), L);
  EXPECT_FALSE(detail::ldlt9(L, 1e-10));
  // Positive definite, but its smallest pivot below the ratio asked for.
  Mat9 D = Mat9::Identity();
  D(4, 4) = 1e-11;
  lowerOf(D, L);
  EXPECT_FALSE(detail::ldlt9(L, 1e-10));
  lowerOf(D, L);
  EXPECT_TRUE(detail::ldlt9(L, 1e-12));
  // Not a number, or nothing at all.
  lowerOf(Mat9::Zero(), L);
  EXPECT_FALSE(detail::ldlt9(L, 1e-10));
  Mat9 nan = Mat9::Identity();
  nan(3, 1) = NAN;
  lowerOf(nan, L);
  EXPECT_FALSE(detail::ldlt9(L, 1e-10));
}
