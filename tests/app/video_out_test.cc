// VideoOut reads back what it wrote: a complete file passes, one that the
// disk cut short is reported, not silent.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "app/app_video.h"

namespace ripple::app {
namespace {

std::string TempDir(const std::string& name) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("ripple_video_out_" + name))
          .string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(VideoOutTest, ACompleteFilePassesTheReadBack) {
  const std::string dir = TempDir("ok");
  VideoOut v;
  std::string error;
  ASSERT_TRUE(v.Open(dir + "/a.mkv", 30, {64, 48}, &error)) << error;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(v.Write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(i * 40, 0, 0))));
  }
  EXPECT_EQ(v.frames_written(), 5);
  EXPECT_TRUE(v.Close(&error)) << error;
  EXPECT_TRUE(v.Close(&error));  // idempotent
}

// What a full disk leaves: the same MP4 cut short (its index, written last,
// is missing) is reported with the file's name, the whole one passes.
TEST(VideoOutTest, ATruncatedFileIsReported) {
  const std::string dir = TempDir("cut");
  VideoOut v;
  std::string error;
  ASSERT_TRUE(v.Open(dir + "/a.mp4", 30, {64, 48}, &error)) << error;
  for (int i = 0; i < 30; ++i) {
    v.Write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(i * 8, 255 - i * 8, 0)));
  }
  ASSERT_TRUE(v.Close(&error)) << error;
  EXPECT_TRUE(VerifyVideo(dir + "/a.mp4", 30, &error)) << error;
  EXPECT_FALSE(VerifyVideo(dir + "/a.mp4", 31, &error));
  EXPECT_NE(error.find("holds 30 of the 31"), std::string::npos) << error;
  const auto size = std::filesystem::file_size(dir + "/a.mp4");
  std::filesystem::copy_file(dir + "/a.mp4", dir + "/cut.mp4");
  std::filesystem::resize_file(dir + "/cut.mp4", size / 2);
  EXPECT_FALSE(VerifyVideo(dir + "/cut.mp4", 30, &error));
  EXPECT_NE(error.find("cut.mp4"), std::string::npos) << error;
}

}  // namespace
}  // namespace ripple::app
