#include "bench/flip_budget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "tests/bench/synth_photo.h"

namespace ripple::bench {
namespace {

// `image` with the linear light inside `mask` times `gain` (sRGB in and out).
cv::Mat Brightened(const cv::Mat& image, const cv::Mat& mask, double gain) {
  cv::Mat out = image.clone();
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      if (!mask.at<uchar>(y, x)) continue;
      for (int c = 0; c < 3; ++c) {
        const double e = image.at<cv::Vec3b>(y, x)[c] / 255.0;
        double l =
            e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
        l = std::min(1.0, l * gain);
        const double s =
            l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
        out.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(255.0 * s);
      }
    }
  }
  return out;
}

cv::Mat CentreMask(const cv::Size& size) {
  cv::Mat mask(size, CV_8U, cv::Scalar(0));
  cv::rectangle(mask, {size.width / 4, size.height / 4},
                {3 * size.width / 4, 3 * size.height / 4}, cv::Scalar(255),
                cv::FILLED);
  return mask;
}

// A test image 4% too bright inside the region: the fit finds the gain that
// undoes it (to the 8-bit rounding of the brightened copy) and takes away
// most of the FLIP.
TEST(FlipBudgetTest, UniformGainUndoesABrightnessBias) {
  const cv::Mat photo = testing::SynthesizePhoto(160, 120, 3);
  const cv::Mat mask = CentreMask(photo.size());
  const cv::Mat bright = Brightened(photo, mask, 1.04);
  UniformGainFit fit;
  std::string error;
  ASSERT_TRUE(FitUniformGain(FlipOptions(), photo, bright, mask, 0.1, 1e-3,
                             &fit, &error))
      << error;
  EXPECT_NEAR(fit.gain, 1.0 / 1.04, 0.004);
  EXPECT_GT(fit.flip_at_one, 0.02);
  EXPECT_LT(fit.flip, 0.25 * fit.flip_at_one);
  // An unbiased image keeps gain 1 and its FLIP.
  ASSERT_TRUE(FitUniformGain(FlipOptions(), photo, photo, mask, 0.1, 1e-3, &fit,
                             &error));
  EXPECT_DOUBLE_EQ(fit.flip_at_one, 0.0);
  EXPECT_DOUBLE_EQ(fit.flip, 0.0);
  EXPECT_DOUBLE_EQ(fit.gain, 1.0);
}

// Reading the image at a coarser resolution costs nothing at 1 and more the
// coarser it gets.
TEST(FlipBudgetTest, ResolutionLossGrowsWithMagnification) {
  const cv::Mat photo = testing::SynthesizePhoto(160, 120, 5);
  const cv::Mat mask = CentreMask(photo.size());
  std::string error;
  double at1 = -1, at133 = -1, at2 = -1;
  ASSERT_TRUE(
      ResolutionLossFlip(FlipOptions(), photo, mask, 1.0, &at1, &error));
  ASSERT_TRUE(
      ResolutionLossFlip(FlipOptions(), photo, mask, 1.333, &at133, &error));
  ASSERT_TRUE(ResolutionLossFlip(FlipOptions(), photo, mask, 2.0, &at2, &error))
      << error;
  EXPECT_DOUBLE_EQ(at1, 0.0);
  EXPECT_GT(at133, 0.01);
  EXPECT_GT(at2, at133);
}

TEST(FlipBudgetTest, RefusesBadInputs) {
  const cv::Mat photo = testing::SynthesizePhoto(64, 48, 1);
  const cv::Mat mask = CentreMask(photo.size());
  UniformGainFit fit;
  double flip = 0;
  std::string error;
  EXPECT_FALSE(FitUniformGain(FlipOptions(), photo, photo,
                              cv::Mat(photo.size(), CV_8U, cv::Scalar(0)), 0.1,
                              1e-3, &fit, &error));
  EXPECT_NE(error.find("mask"), std::string::npos);
  EXPECT_FALSE(FitUniformGain(FlipOptions(), photo,
                              photo(cv::Rect(0, 0, 32, 24)), mask, 0.1, 1e-3,
                              &fit, &error));
  EXPECT_FALSE(FitUniformGain(FlipOptions(), photo, photo, mask, 1.5, 1e-3,
                              &fit, &error));
  EXPECT_FALSE(FitUniformGain(FlipOptions(), photo, photo, mask, 0.1, 0.2, &fit,
                              &error));
  EXPECT_FALSE(
      ResolutionLossFlip(FlipOptions(), photo, mask, 0.5, &flip, &error));
  EXPECT_NE(error.find("magnification"), std::string::npos);
}

}  // namespace
}  // namespace ripple::bench
