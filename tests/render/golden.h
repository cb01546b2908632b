// Golden-image comparison for the GL tests: tests/render/golden/<name>.png.
// RIPPLE_UPDATE_GOLDEN=1 rewrites the stored image instead of comparing.
#ifndef RIPPLE_TESTS_RENDER_GOLDEN_H_
#define RIPPLE_TESTS_RENDER_GOLDEN_H_

#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "render/renderer.h"

namespace ripple::render::testing {

// Renders `in` and reads the frame back as BGR8 (test failures on GL errors).
inline cv::Mat RenderScene(Renderer* r, const SceneInputs& in) {
  EXPECT_TRUE(r->Render(in));
  cv::Mat out(r->intrinsics().height, r->intrinsics().width, CV_8UC3);
  EXPECT_TRUE(r->ReadBgr(out.data, static_cast<int>(out.step)));
  return out;
}

inline std::string GoldenPath(const std::string& name) {
  return std::string(RIPPLE_SOURCE_DIR) + "/tests/render/golden/" + name +
         ".png";
}

// Compares `actual` with the stored image: per-channel absolute difference
// at most `max_diff` everywhere and at most `mean_diff` on average. The
// actual image is written next to the test binary for inspection.
inline ::testing::AssertionResult MatchesGolden(const cv::Mat& actual,
                                                const std::string& name,
                                                double max_diff = 64,
                                                double mean_diff = 0.8) {
  cv::imwrite(name + "_actual.png", actual);
  const char* update = std::getenv("RIPPLE_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    cv::imwrite(GoldenPath(name), actual);
    return ::testing::AssertionSuccess() << "updated " << GoldenPath(name);
  }
  const cv::Mat golden = cv::imread(GoldenPath(name), cv::IMREAD_COLOR);
  if (golden.empty()) {
    return ::testing::AssertionFailure()
           << "no golden image " << GoldenPath(name)
           << " (run with RIPPLE_UPDATE_GOLDEN=1 to create it)";
  }
  if (golden.size() != actual.size() || golden.type() != actual.type()) {
    return ::testing::AssertionFailure()
           << "golden " << name << " is " << golden.cols << "x" << golden.rows;
  }
  cv::Mat diff;
  cv::absdiff(actual, golden, diff);
  double max_value = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &max_value);
  const cv::Scalar mean = cv::mean(diff);
  const double mean_value = (mean[0] + mean[1] + mean[2]) / 3.0;
  if (max_value > max_diff || mean_value > mean_diff) {
    return ::testing::AssertionFailure()
           << name << ": max diff " << max_value << " (limit " << max_diff
           << "), mean " << mean_value << " (limit " << mean_diff << "); see "
           << name << "_actual.png";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace ripple::render::testing

#endif  // RIPPLE_TESTS_RENDER_GOLDEN_H_
