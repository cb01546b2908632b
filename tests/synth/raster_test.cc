#include "tracking/synth/raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ripple::synth {
namespace {

using Eigen::Vector2d;

// Coverage of one pixel square by a polygon, by clipping (the reference).
double PixelCoverage(const std::vector<Vector2d>& poly, int u, int v) {
  return std::abs(
      PolygonArea(ClipToRect(poly, u - 0.5, v - 0.5, u + 0.5, v + 0.5)));
}

TEST(QuadRectAreaTest, MatchesClippingForRandomQuads) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-2, 2);
  for (int trial = 0; trial < 2000; ++trial) {
    // A convex quad: four points on a random ellipse, in angular order.
    const Vector2d c(d(rng), d(rng));
    const double a = 0.2 + std::abs(d(rng)), b = 0.2 + std::abs(d(rng)),
                 phase = d(rng);
    Vector2d quad[4];
    for (int k = 0; k < 4; ++k) {
      const double t = phase + k * M_PI / 2 + 0.3 * d(rng) / 2;
      quad[k] = c + Vector2d(a * std::cos(t), b * std::sin(t));
    }
    const std::vector<Vector2d> poly(quad, quad + 4);
    const double x0 = d(rng), y0 = d(rng), x1 = x0 + std::abs(d(rng)),
                 y1 = y0 + std::abs(d(rng));
    const double expected =
        std::abs(PolygonArea(ClipToRect(poly, x0, y0, x1, y1)));
    EXPECT_NEAR(QuadRectArea(quad, x0, y0, x1, y1), expected, 1e-12);
  }
}

TEST(QuadRectAreaTest, AxisAlignedSquareIsExact) {
  const Vector2d quad[4] = {
      {0.25, 0.25}, {1.75, 0.25}, {1.75, 1.75}, {0.25, 1.75}};
  EXPECT_NEAR(QuadRectArea(quad, 0, 0, 1, 1), 0.75 * 0.75, 1e-15);
  EXPECT_NEAR(QuadRectArea(quad, 1, 0, 2, 1), 0.75 * 0.75, 1e-15);
  EXPECT_NEAR(QuadRectArea(quad, -5, -5, 5, 5), 1.5 * 1.5, 1e-15);
  EXPECT_EQ(QuadRectArea(quad, 2, 2, 3, 3), 0.0);
}

TEST(RasterizePolygonTest, MatchesPerPixelClippingOnConcavePolygons) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(0, 1);
  const int w = 40, h = 30;
  for (int trial = 0; trial < 30; ++trial) {
    // A star-shaped (concave) polygon partly outside the image.
    std::vector<Vector2d> poly;
    const Vector2d c(-5 + 50 * d(rng), -5 + 40 * d(rng));
    const int n = 5 + int(10 * d(rng));
    for (int k = 0; k < n; ++k) {
      const double r = (k % 2 ? 3 : 12) * (0.5 + d(rng));
      const double t = 2 * M_PI * k / n;
      poly.push_back(c + r * Vector2d(std::cos(t), std::sin(t)));
    }
    if (trial % 2) std::reverse(poly.begin(), poly.end());  // both windings
    cv::Mat cov;
    cv::Rect roi;
    if (!RasterizePolygon(poly, w, h, &cov, &roi)) continue;
    double max_err = 0;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const double got = roi.contains(cv::Point(u, v))
                               ? cov.at<float>(v - roi.y, u - roi.x)
                               : 0.0;
        max_err = std::max(max_err, std::abs(got - PixelCoverage(poly, u, v)));
      }
    }
    EXPECT_LT(max_err, 1e-5) << "trial " << trial;
  }
}

TEST(RasterizePolygonTest, TotalCoverageEqualsArea) {
  const std::vector<Vector2d> tri = {{3.3, 2.1}, {17.8, 5.4}, {8.2, 19.9}};
  cv::Mat cov;
  cv::Rect roi;
  ASSERT_TRUE(RasterizePolygon(tri, 32, 32, &cov, &roi));
  EXPECT_NEAR(cv::sum(cov)[0], std::abs(PolygonArea(tri)), 1e-4);
}

TEST(RasterizePolygonTest, MissesImageEntirely) {
  const std::vector<Vector2d> tri = {{-30, -30}, {-20, -30}, {-25, -20}};
  cv::Mat cov;
  cv::Rect roi;
  EXPECT_FALSE(RasterizePolygon(tri, 32, 32, &cov, &roi));
}

}  // namespace
}  // namespace ripple::synth
