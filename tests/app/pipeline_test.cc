// The AR pipeline commands end to end: demo outputs, replay determinism,
// truncated and mismatched inputs. Headless (EGL); skipped without a GL
// context unless CI=true.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "tests/app/cli_test.h"

namespace ripple {
namespace {

using ::testing::HasSubstr;
using testing::RunRipple;

std::string Temp(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "ripple_pipeline_" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Poses CSV without the ms column (tracking time differs run to run).
std::string PosesWithoutMs(const std::string& path) {
  std::ifstream in(path);
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    clip_ = new std::string(Temp("clip"));
    // A short synthetic clip with a pen in the water, as a lossless video.
    const auto r =
        RunRipple("synth --out " + *clip_ +
                  " --frames 24 --size 320x240 --preset demo --video " +
                  *clip_ + "/clip.mkv");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // Probe once for a headless GL context.
    const std::string dir = Temp("probe");
    probe_ = new testing::CommandResult(RunRipple(
        "demo --out " + dir + " --frames 10 --idle-frames 1 --camera " +
        *clip_ + "/camera.yml"));
  }
  void SetUp() override {
    if (probe_->exit_code != 0 &&
        probe_->output.find("EGL") != std::string::npos) {
      const char* ci = std::getenv("CI");
      if (ci && std::string(ci) == "true")
        FAIL() << "no GL context under CI: " << probe_->output;
      GTEST_SKIP() << "no headless GL context: " << probe_->output;
    }
    ASSERT_EQ(probe_->exit_code, 0) << probe_->output;
  }
  static std::string* clip_;
  static testing::CommandResult* probe_;
};
std::string* PipelineTest::clip_ = nullptr;
testing::CommandResult* PipelineTest::probe_ = nullptr;

TEST_F(PipelineTest, DemoWritesVideoFrameTableAndPoses) {
  const std::string dir = Temp("demo");
  const auto r =
      RunRipple("demo --out " + dir + " --frames 12 --idle-frames 4 --camera " +
                *clip_ + "/camera.yml");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("active: pen in the water (12 frames, ms)"));
  EXPECT_THAT(r.output,
              HasSubstr("idle: water at rest, pen away (4 frames, ms)"));
  for (const char* c : {"cap", "det", "pose", "occ", "drw", "sim", "caustics",
                        "shadow", "total"})
    EXPECT_THAT(r.output, HasSubstr(c));
  cv::VideoCapture video(dir + "/demo.mp4");
  ASSERT_TRUE(video.isOpened());
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_COUNT), 16);
  const cv::Mat frame = cv::imread(dir + "/demo_frame.png");
  EXPECT_EQ(frame.cols, 320);
  EXPECT_TRUE(std::filesystem::exists(dir + "/timing.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/demo_poses.csv"));
}

TEST_F(PipelineTest, ReplayIsDeterministic) {
  const std::string a = Temp("a"), b = Temp("b");
  for (const std::string& dir : {a, b}) {
    const auto r = RunRipple(
        "replay --headless --input " + *clip_ + "/clip.mkv --camera " + *clip_ +
        "/camera.yml --rig " + *clip_ + "/rig.yml --out " + dir +
        "/ar.mp4 --poses " + dir + "/poses.csv --snapshot " + dir +
        "/snap.png --snapshot-frame 15");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("tank tracked in 24/24 frames"));
  }
  EXPECT_EQ(PosesWithoutMs(a + "/poses.csv"), PosesWithoutMs(b + "/poses.csv"));
  const cv::Mat sa = cv::imread(a + "/snap.png"),
                sb = cv::imread(b + "/snap.png");
  ASSERT_FALSE(sa.empty());
  EXPECT_EQ(cv::norm(sa, sb, cv::NORM_INF), 0.0);
  // The water was drawn: the composite differs from the input frame.
  cv::VideoCapture in(*clip_ + "/clip.mkv");
  cv::Mat original;
  for (int i = 0; i <= 15; ++i) in.read(original);
  EXPECT_GT(cv::norm(sa, original, cv::NORM_L1) / sa.total(), 1.0);
}

TEST_F(PipelineTest, ReplayToAFolderWritesLosslessFrames) {
  const std::string dir = Temp("frames");
  const auto r =
      RunRipple("replay --headless --input " + *clip_ + "/clip.mkv --camera " +
                *clip_ + "/camera.yml --rig " + *clip_ + "/rig.yml --out " +
                dir + "/png/ --snapshot " + dir +
                "/snap.png "
                "--snapshot-frame 15");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/png")) {
    EXPECT_EQ(e.path().extension(), ".png");
    ++n;
  }
  EXPECT_EQ(n, 24);
  const cv::Mat frame = cv::imread(dir + "/png/000015.png");
  const cv::Mat snap = cv::imread(dir + "/snap.png");
  ASSERT_FALSE(frame.empty());
  EXPECT_EQ(cv::norm(frame, snap, cv::NORM_INF), 0.0);
}

// Hands over the tank stay in front of the water: of the hand pixels the
// water and walls cover without the clean plate, the share still covered
// with it (the composite differing from the input by more than 3 levels).
TEST_F(PipelineTest, HandsOverTheTankStayInFrontOfTheWater) {
  const std::string dir = Temp("hands");
  auto r = RunRipple("synth --out " + dir +
                     " --frames 40 --segment 40 --size 640x480 --preset hands "
                     "--seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // As the pipeline runs by default at 640x480 (with the tank's shadow on
  // the board around the tank, where the clean plate then looks for hands
  // too), and without that shadow.
  for (const std::string extra : {"", " --tank-shadow off"}) {
    const std::string common =
        "replay --headless --input " + dir + "/frames --camera " + dir +
        "/camera.yml --rig " + dir + "/rig.yml --fps 30" + extra + " --out ";
    r = RunRipple(common + dir + "/with/");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = RunRipple(common + dir + "/without/ --no-occluders");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    long long over_tank = 0, covered = 0;
    for (int i = 5; i < 40; ++i) {
      char name[32];
      std::snprintf(name, sizeof(name), "/%06d.png", i);
      const cv::Mat input = cv::imread(dir + "/frames" + name);
      const cv::Mat labels =
          cv::imread(dir + "/occluders" + name, cv::IMREAD_GRAYSCALE);
      const cv::Mat with = cv::imread(dir + "/with" + name);
      const cv::Mat without = cv::imread(dir + "/without" + name);
      ASSERT_FALSE(input.empty() || labels.empty() || with.empty() ||
                   without.empty())
          << name;
      for (int y = 0; y < input.rows; ++y) {
        for (int x = 0; x < input.cols; ++x) {
          if (labels.at<std::uint8_t>(y, x) != 255) continue;
          const cv::Vec3b a = input.at<cv::Vec3b>(y, x);
          auto differs = [&](const cv::Mat& m) {
            const cv::Vec3b b = m.at<cv::Vec3b>(y, x);
            return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]),
                             std::abs(a[2] - b[2])}) > 3;
          };
          if (!differs(without)) continue;
          ++over_tank;
          covered += differs(with);
        }
      }
    }
    ASSERT_GT(over_tank, 5000) << "the sequence must put hands over the tank";
    const double share = double(covered) / over_tank;
    std::printf(
        "hand pixels over the tank covered by water%s: %.2f%% of %lld\n",
        extra.c_str(), 100 * share, over_tank);
    // Measured 0.62%, 0.47% with the tank's shadow (the mask then grown by
    // a pixel; the target is 1%): the hand's edge pixels, and slivers along
    // the shaft's outline.
    EXPECT_LT(share, 0.01) << extra;
  }
}

TEST_F(PipelineTest, TruncatedVideoExits1AndKeepsAPlayableOutput) {
  const std::string dir = Temp("trunc");
  {
    std::ifstream in(*clip_ + "/clip.mkv", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    const std::string bytes = s.str();
    std::ofstream(dir + "/cut.mkv", std::ios::binary)
        << bytes.substr(0, bytes.size() / 2);
  }
  const auto r = RunRipple(
      "replay --headless --input " + dir + "/cut.mkv --camera " + *clip_ +
      "/camera.yml --rig " + *clip_ + "/rig.yml --out " + dir + "/ar.mp4");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("truncated"));
  cv::VideoCapture out(dir + "/ar.mp4");
  ASSERT_TRUE(out.isOpened());
  cv::Mat f;
  int frames = 0;
  while (out.read(f)) ++frames;
  EXPECT_GT(frames, 0);
}

TEST_F(PipelineTest, BadInputsExit2WithOneMessage) {
  auto r = RunRipple("replay --headless --input /nonexistent/clip.mp4");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/nonexistent/clip.mp4"));
  // 320x240 frames against a 640x360 calibration: another aspect ratio.
  const std::string dir = Temp("size");
  std::ofstream(dir + "/cam.yml")
      << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 360\ncamera_matrix: "
         "!!opencv-matrix\n"
         "   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 319.5, 0., "
         "500., 179.5, 0., 0., 1. ]\n"
         "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   "
         "dt: d\n"
         "   data: [ 0., 0., 0., 0., 0. ]\n";
  r = RunRipple("replay --headless --input " + *clip_ + "/clip.mkv --camera " +
                dir + "/cam.yml --rig " + *clip_ + "/rig.yml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("calibrated at 640x360"));
  r = RunRipple("replay --headless --input " + *clip_ + "/clip.mkv --camera " +
                *clip_ + "/camera.yml --rig " + *clip_ + "/rig.yml --out " +
                dir + "/x.gif");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("x.gif"));
  r = RunRipple("live --input 97 --gl egl");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("no camera at '97'"));
}

}  // namespace
}  // namespace ripple
