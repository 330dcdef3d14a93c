// vcg_ext/core/trimmed_mean.h (band_shrink.h and noise_amplitude.h read it): the trimmed mean
// keeps the values below the quantile (at least one); the Gaussian's trimmed mean square against
// its closed form and against samples.
#include <gtest/gtest.h>
#include <vcg_ext/core/trimmed_mean.h>

#include <random>

using namespace vcg_ext;

TEST(TrimmedMean, KeepsTheValuesBelowTheQuantile) {
  std::vector<double> x = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(trimmedMean(x, 0.6), 2.0); // 1, 2, 3
  x = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(trimmedMean(x, 1.0), 3.0);
  x = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(trimmedMean(x, 0.01), 1.0);
  x.clear();
  EXPECT_DOUBLE_EQ(trimmedMean(x, 0.5), 0.0);
}

TEST(TrimmedMean, GaussianTrimmedSquareMatchesItsClosedFormAndSamples) {
  EXPECT_DOUBLE_EQ(gaussianTrimmedSquare(1.0), 1.0);
  EXPECT_DOUBLE_EQ(gaussianTrimmedSquare(0.0), 0.0);
  // q = 0.5: a = 0.67449 (the quartile of |x|), (q - 2 a φ(a)) / q.
  EXPECT_NEAR(gaussianTrimmedSquare(0.5), 0.14265, 1e-4);
  EXPECT_NEAR(gaussianTrimmedSquare(0.75), 0.36852, 1e-4);
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::vector<double> squares(200000);
  for (double &s : squares) {
    const double x = g(rng);
    s = x * x;
  }
  EXPECT_NEAR(trimmedMean(squares, 0.75), gaussianTrimmedSquare(0.75), 0.01);
}
