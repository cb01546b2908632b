// `ripple calib` end to end: frames rendered by the synth library (exact
// geometry, defocus, sensor noise) go through the real detector; bad input
// ends with a clear message, a non-zero exit code and no output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "tests/app/cli_test.h"
#include "tests/calib/calib_scene.h"
#include "tests/shipped_data.h"
#include "tracking/synth/synth.h"

namespace ripple::calib {
namespace {

namespace fs = std::filesystem;
using tracking::Pose;

constexpr double kDeg = M_PI / 180;

std::string Dir(const std::string& name) {
  const std::string d = ::testing::TempDir() + "/ripple_calib_cli/" + name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

using test_data::DefaultRig;

// Renders `n` frames of the pen in front of the camera (the board further
// away) into `dir`; `pose(i)` gives cam_from_pen.
void RenderPenFrames(const tracking::Camera& camera, const tracking::Rig& rig,
                     int n, const std::function<Pose(int)>& pose,
                     const std::string& dir) {
  const synth::SceneRenderer renderer(camera, rig);
  const Pose cam_from_tank =
      tracking::LookAt({0, -0.3, 0.6}, {0, 0, 0}, {0, 1, 0}).Inverse();
  synth::ImagingOptions imaging;
  imaging.defocus_sigma_px = 0.6;
  imaging.read_noise_dn = 2.0;
  for (int i = 0; i < n; ++i) {
    synth::SceneState scene;
    scene.cam_from_tank = cam_from_tank;
    scene.tank_from_pen = cam_from_tank.Inverse() * pose(i);
    const auto frame = renderer.Render(scene, imaging, 100 + i);
    char name[32];
    std::snprintf(name, sizeof(name), "/%04d.png", i);
    ASSERT_TRUE(cv::imwrite(dir + name, frame.image));
  }
}

void WriteCamera(const tracking::Camera& camera, const std::string& path) {
  std::string error;
  ASSERT_TRUE(tracking::SaveCamera(camera, path, &error)) << error;
}

TEST(CalibCliTest, RigFromRenderedFramesRecoversCubeFaces) {
  const tracking::Rig nominal = DefaultRig();
  tracking::Rig truth = nominal;
  std::mt19937 rng(21);
  truth.pen->faces =
      testing::Perturbed(nominal.pen->faces, &rng, 0.002, 3 * kDeg);
  const tracking::Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  const std::string dir = Dir("rig_frames");
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Pose> poses;
  while (poses.size() < 40) {  // random views showing >= 2 faces
    const Pose p(
        testing::RandomRotation(&rng),
        Eigen::Vector3d(0.03 * u(rng), 0.02 * u(rng), 0.17 + 0.02 * u(rng)));
    if (testing::ProjectTags(camera, truth.pen->faces, p, 0, &rng, 65).size() >=
        2)
      poses.push_back(p);
  }
  RenderPenFrames(
      camera, truth, 40, [&](int i) { return poses[i]; }, dir + "/");
  WriteCamera(camera, dir + "/../camera.yml");
  const std::string out = dir + "/../refined.yml";
  fs::remove(out);
  const auto r = ripple::testing::RunRipple(
      "calib rig --input " + dir + " --camera " + dir + "/../camera.yml" +
      " --rig " RIPPLE_SOURCE_DIR
      "/data/rig/default.yml --object pen "
      "--reference 10 --out " +
      out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::printf("%s", r.output.c_str());
  std::string error;
  const auto refined = tracking::LoadRig(out, &error);
  ASSERT_TRUE(refined) << error;
  const auto expected =
      testing::Regauged(truth.pen->faces, nominal.pen->faces, 10);
  double worst_m = 0, worst_rad = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    worst_m = std::max(worst_m, tracking::TranslationDistance(
                                    expected[i].object_from_tag,
                                    refined->pen->faces[i].object_from_tag));
    worst_rad = std::max(
        worst_rad,
        tracking::RotationDistance(expected[i].object_from_tag,
                                   refined->pen->faces[i].object_from_tag));
  }
  std::printf("rendered + detector: worst face error %.3f mm, %.3f deg\n",
              1e3 * worst_m, worst_rad / kDeg);
  // The synth renderer trims each printed tag to its cube face (a sticker
  // glued 2 mm off-centre loses part of its white margin at the edge rather
  // than overhanging the neighbouring face), so the truth is physical.
  EXPECT_LT(worst_m, 0.2e-3);
  EXPECT_LT(worst_rad, 0.2 * kDeg);
}

TEST(CalibCliTest, PivotWithoutRotationIsDegenerate) {
  const tracking::Rig rig = DefaultRig();
  const tracking::Camera camera = tracking::MakeIdealCamera(320, 240, 60);
  const std::string dir = Dir("spin_frames");
  // Spinning about the shaft only: the tip along the shaft is unknown.
  const Eigen::Quaterniond base = Eigen::Quaterniond::FromTwoVectors(
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, -0.6, -1).normalized());
  RenderPenFrames(
      camera, rig, 12,
      [&](int i) {
        const Eigen::Quaterniond r =
            base * Eigen::AngleAxisd(i * 5 * kDeg, Eigen::Vector3d::UnitZ());
        return Pose(r, Eigen::Vector3d(0, 0.06, 0.3) - r * rig.pen->tip_in_pen);
      },
      dir);
  WriteCamera(camera, dir + "/../camera_small.yml");
  const std::string out = dir + "/../pen.yml";
  fs::remove(out);
  const auto r = ripple::testing::RunRipple(
      "calib pen --input " + dir + " --camera " + dir +
      "/../camera_small.yml --min-views 10 --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("degenerate motion"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
  // The same 12 frames are too few for the default (15 views).
  const auto few =
      ripple::testing::RunRipple("calib pen --input " + dir + " --camera " +
                                 dir + "/../camera_small.yml --out " + out);
  EXPECT_EQ(few.exit_code, 1) << few.output;
  EXPECT_NE(few.output.find("too few views"), std::string::npos) << few.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CalibCliTest, NoTargetMissingInputAndTruncatedVideo) {
  const std::string dir = Dir("blank");
  const cv::Mat blank(480, 640, CV_8UC3, cv::Scalar(200, 200, 200));
  for (int i = 0; i < 5; ++i)
    cv::imwrite(dir + "/" + std::to_string(i) + ".png", blank);
  const std::string out = dir + "/../out.yml";
  fs::remove(out);
  for (const char* cmd : {"calib rig", "calib pen", "calib camera"}) {
    const auto r = ripple::testing::RunRipple(std::string(cmd) + " --input " +
                                              dir + " --out " + out);
    EXPECT_EQ(r.exit_code, 1) << cmd << ": " << r.output;
    EXPECT_NE(r.output.find("no target found"), std::string::npos)
        << cmd << ": " << r.output;
    EXPECT_FALSE(fs::exists(out));
  }
  const auto missing = ripple::testing::RunRipple(
      "calib rig --input " + dir + "/nothing_here.mp4 --out " + out);
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("does not exist"), std::string::npos);
  // A video cut in the middle: exit 1 once the frames run out early.
  const std::string video = dir + "/../cut.avi";
  {
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                           30, blank.size());
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 60; ++i) {
      cv::Mat f = blank.clone();
      f(cv::Rect(10 * (i % 50), 100, 40, 40)).setTo(cv::Scalar(20, 20, 20));
      writer.write(f);
    }
  }
  fs::resize_file(video, fs::file_size(video) / 2);
  const auto cut = ripple::testing::RunRipple("calib rig --input " + video +
                                              " --out " + out);
  EXPECT_EQ(cut.exit_code, 1) << cut.output;
  EXPECT_NE(cut.output.find("truncated"), std::string::npos) << cut.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CalibCliTest, MarkersWritesEverySheet) {
  const std::string dir = Dir("markers");
  const auto r =
      ripple::testing::RunRipple("markers --out " + dir + " --dpi 72");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* sheet : {"board", "cube_net", "chessboard"})
    for (const char* paper : {"a4", "letter"})
      for (const char* ext : {".pdf", ".svg", ".png"})
        EXPECT_TRUE(fs::exists(dir + "/" + sheet + "_" + paper + ext))
            << sheet << "_" << paper << ext;
}

}  // namespace
}  // namespace ripple::calib
