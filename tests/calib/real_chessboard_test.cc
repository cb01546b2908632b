// Real data: OpenCV's own chessboard sample photos (left01..left14.jpg, 9x6
// inner corners, 640x480, a lens with k1 about -0.3), shipped by Debian's
// opencv-doc package in /usr/share/doc/opencv-doc/examples/data (or a folder
// named by $RIPPLE_CHESSBOARD_DIR). Skips when the photos are absent: they
// are not the project's and are never copied into it.
//
// What it checks: every distortion candidate fits and is cross-validated,
// the choice obeys its rule, and on these photos the focal length hardly
// depends on the model (with our corners, k3 moves fx by far less than its
// standard deviation).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "calib/camera_calib.h"

namespace ripple::calib {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SamplePhotos() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("RIPPLE_CHESSBOARD_DIR"))
    dirs.push_back(env);
  dirs.push_back("/usr/share/doc/opencv-doc/examples/data");
  for (const std::string& dir : dirs) {
    std::vector<std::string> photos;
    for (int i = 1; i <= 14; ++i) {
      char name[32];
      std::snprintf(name, sizeof(name), "/left%02d.jpg", i);
      if (fs::exists(dir + name)) photos.push_back(dir + name);
    }
    if (photos.size() >= 10) return photos;
  }
  return {};
}

TEST(RealChessboardTest, DistortionModelFromOpenCvSamplePhotos) {
  const std::vector<std::string> photos = SamplePhotos();
  if (photos.empty())
    GTEST_SKIP() << "OpenCV's left*.jpg sample photos not found (apt-get "
                    "install opencv-doc, or set RIPPLE_CHESSBOARD_DIR)";
  ViewSelector selector(ViewSelectionOptions(), 640, 480);
  for (size_t i = 0; i < photos.size(); ++i) {
    const cv::Mat gray = cv::imread(photos[i], cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(gray.size(), cv::Size(640, 480)) << photos[i];
    CalibView view;
    ASSERT_TRUE(DetectChessboardView(gray, 9, 6, 0.025, &view)) << photos[i];
    view.frame = static_cast<int>(i);
    selector.Offer(std::move(view));
  }
  CameraCalibOptions options;
  options.min_views = 8;
  tracking::Camera camera;
  CameraCalibSummary summary;
  std::string error;
  ASSERT_TRUE(CalibrateCamera(options, selector.accepted(), 640, 480, &camera,
                              &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  EXPECT_LT(summary.rms_px, 0.35);
  EXPECT_NEAR(camera.dist[0], -0.3, 0.05);  // the strongly distorting lens
  ASSERT_EQ(summary.models.size(), 3u);
  double lowest = 1e9;
  for (const DistortionScore& m : summary.models) {
    EXPECT_TRUE(m.ok) << ToString(m.model);
    lowest = std::min(lowest, m.heldout_mse_px2);
    // The models agree on fx within 2 standard deviations.
    EXPECT_NEAR(m.fx, camera.fx, 2 * summary.std_fx) << ToString(m.model);
  }
  // The choice is the simplest within one standard error of the lowest.
  EXPECT_TRUE(summary.model_chosen);
  for (const DistortionScore& m : summary.models) {
    if (m.model == summary.model) break;
    EXPECT_GT(m.heldout_mse_px2, summary.choice_limit_mse_px2)
        << ToString(m.model) << " is simpler and within the bound";
  }
  const auto& chosen = summary.models[static_cast<int>(summary.model) - 1];
  EXPECT_LE(chosen.heldout_mse_px2, summary.choice_limit_mse_px2);
  EXPECT_GT(summary.choice_limit_mse_px2, lowest);
}

}  // namespace
}  // namespace ripple::calib
