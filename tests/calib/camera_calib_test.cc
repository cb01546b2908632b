// Camera intrinsics from synthetic chessboard views (0.2 px corner noise),
// the view selector (blur, duplicates) and the blur measure on rendered
// frames.
#include "calib/camera_calib.h"

#include <gtest/gtest.h>

#include "tests/calib/calib_scene.h"
#include "tracking/synth/synth.h"

namespace ripple::calib {
namespace {

using tracking::Camera;
using tracking::Pose;

Camera TrueCamera() {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.fx = 600;
  c.fy = 602;
  c.cx = 327;
  c.cy = 236;
  c.dist = {-0.25, 0.08, 0.001, -0.0005, 0, 0, 0, 0};
  return c;
}

std::vector<CalibView> ChessboardViews(const Camera& camera, int n,
                                       std::mt19937* rng) {
  std::normal_distribution<double> noise(0, 0.2);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<CalibView> views;
  while (static_cast<int>(views.size()) < n) {
    // A 9x6 board of 25 mm squares, 0.3-0.5 m away, tilted up to ~40 deg,
    // anywhere in the image.
    const Eigen::Vector3d centre(0.1 * u(*rng), 0.08 * u(*rng),
                                 0.4 + 0.1 * u(*rng));
    const Pose board_in_cam =
        Pose(Eigen::Quaterniond(
                 Eigen::AngleAxisd(0.6 * u(*rng), Eigen::Vector3d::UnitX()) *
                 Eigen::AngleAxisd(0.6 * u(*rng), Eigen::Vector3d::UnitY()) *
                 Eigen::AngleAxisd(0.3 * u(*rng), Eigen::Vector3d::UnitZ())),
             centre - Eigen::Vector3d(0.1, 0.0625, 0));
    CalibView v;
    v.frame = static_cast<int>(views.size());
    v.edge_width_px = 1.0;
    bool inside = true;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 9; ++c) {
        const Eigen::Vector3d p(0.025 * c, 0.025 * r, 0);
        const Eigen::Vector2d px = camera.Project(board_in_cam * p) +
                                   Eigen::Vector2d(noise(*rng), noise(*rng));
        inside =
            inside && px.x() > 0 && px.x() < 639 && px.y() > 0 && px.y() < 479;
        v.point_ids.push_back(r * 9 + c);
        v.points_in_target.push_back(p);
        v.pixels.push_back(px);
      }
    if (inside) views.push_back(v);
  }
  return views;
}

TEST(CameraCalibTest, RecoversIntrinsicsAndDistortion) {
  const Camera truth = TrueCamera();
  std::mt19937 rng(2);
  const auto views = ChessboardViews(truth, 25, &rng);
  Camera camera;
  CameraCalibSummary summary;
  std::string error;
  ASSERT_TRUE(CalibrateCamera(CameraCalibOptions(), views, 640, 480, &camera,
                              &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  EXPECT_NEAR(camera.fx, truth.fx, 0.005 * truth.fx);
  EXPECT_NEAR(camera.fy, truth.fy, 0.005 * truth.fy);
  EXPECT_NEAR(camera.cx, truth.cx, 2.0);
  EXPECT_NEAR(camera.cy, truth.cy, 2.0);
  EXPECT_NEAR(camera.dist[0], truth.dist[0], 0.02);
  // OpenCV's RMS is per point (2-D): 0.2 px per axis -> 0.28 px.
  EXPECT_NEAR(summary.rms_px, 0.2 * std::sqrt(2.0), 0.03);
  EXPECT_EQ(summary.view_rms_px.size(), 25u);
  EXPECT_GT(summary.grid_coverage, 0.3);
  // k3 = 0 in the lens: the choice keeps the simpler model.
  EXPECT_EQ(summary.model, DistortionModel::kK1K2);
  EXPECT_TRUE(summary.model_chosen);
  EXPECT_EQ(camera.dist[4], 0.0);
}

// A strongly distorting lens with k3 (OpenCV's sample camera: k1 = -0.27,
// k3 = 0.25), and the same lens without k3.
Camera StrongLens(bool with_k3) {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.fx = 536;
  c.fy = 536;
  c.cx = 342;
  c.cy = 235;
  c.dist = {-0.265,
            with_k3 ? -0.047 : 0.09,
            0.0018,
            -0.0003,
            with_k3 ? 0.252 : 0.0,
            0,
            0,
            0};
  return c;
}

CameraCalibSummary Calibrate(const std::vector<CalibView>& views,
                             DistortionModel model, Camera* camera) {
  CameraCalibOptions options;
  options.distortion = model;
  CameraCalibSummary summary;
  std::string error;
  EXPECT_TRUE(
      CalibrateCamera(options, views, 640, 480, camera, &summary, &error))
      << error;
  return summary;
}

TEST(CameraCalibTest, ChoosesK3WhenTheLensHasIt) {
  const Camera truth = StrongLens(true);
  std::mt19937 rng(11);
  const auto views = ChessboardViews(truth, 20, &rng);
  Camera chosen, fixed;
  const CameraCalibSummary summary =
      Calibrate(views, DistortionModel::kAuto, &chosen);
  std::printf("%s", summary.ModelReport().c_str());
  EXPECT_EQ(summary.model, DistortionModel::kK1K2K3);
  EXPECT_NEAR(chosen.fx, truth.fx, 0.002 * truth.fx);
  EXPECT_NEAR(chosen.fy, truth.fy, 0.002 * truth.fy);
  EXPECT_NEAR(chosen.dist[4], truth.dist[4], 0.05);
  // Every candidate is scored; k3 = 0 predicts the held-out views worse and
  // moves the focal length further.
  ASSERT_EQ(summary.models.size(), 3u);
  const DistortionScore& k1k2 = summary.models[0];
  const DistortionScore& k1k2k3 = summary.models[1];
  EXPECT_TRUE(k1k2.ok && k1k2k3.ok);
  EXPECT_GT(k1k2.heldout_rms_px, k1k2k3.heldout_rms_px);
  const CameraCalibSummary forced =
      Calibrate(views, DistortionModel::kK1K2, &fixed);
  EXPECT_FALSE(forced.model_chosen);
  EXPECT_EQ(forced.model, DistortionModel::kK1K2);
  EXPECT_EQ(fixed.dist[4], 0.0);
  EXPECT_DOUBLE_EQ(fixed.fx, k1k2.fx);
  EXPECT_GT(std::abs(fixed.fx - truth.fx), 2 * std::abs(chosen.fx - truth.fx));
}

TEST(CameraCalibTest, KeepsK1K2WhenTheLensHasNoK3) {
  const Camera truth = StrongLens(false);
  for (int seed : {12, 13}) {
    std::mt19937 rng(seed);
    const auto views = ChessboardViews(truth, 20, &rng);
    Camera camera;
    const CameraCalibSummary summary =
        Calibrate(views, DistortionModel::kAuto, &camera);
    EXPECT_EQ(summary.model, DistortionModel::kK1K2) << "seed " << seed << "\n"
                                                     << summary.ModelReport();
    // Within three of OpenCV's standard deviations.
    EXPECT_NEAR(camera.fx, truth.fx, 3 * summary.std_fx) << "seed " << seed;
  }
}

TEST(CameraCalibTest, DistortionModelNames) {
  for (DistortionModel m :
       {DistortionModel::kAuto, DistortionModel::kK1K2,
        DistortionModel::kK1K2K3, DistortionModel::kRational})
    EXPECT_EQ(ParseDistortionModel(ToString(m)), m);
  EXPECT_FALSE(ParseDistortionModel("k1"));
}

TEST(CameraCalibTest, TooFewViews) {
  std::mt19937 rng(3);
  const auto views = ChessboardViews(TrueCamera(), 4, &rng);
  Camera camera;
  CameraCalibSummary summary;
  std::string error;
  EXPECT_FALSE(CalibrateCamera(CameraCalibOptions(), views, 640, 480, &camera,
                               &summary, &error));
  EXPECT_NE(error.find("too few views"), std::string::npos) << error;
}

TEST(CameraCalibTest, SelectorRejectsBlurredAndDuplicateViews) {
  std::mt19937 rng(4);
  auto views = ChessboardViews(TrueCamera(), 3, &rng);
  ViewSelector selector(ViewSelectionOptions(), 640, 480);
  EXPECT_EQ(selector.Offer(views[0]), ViewSelector::Verdict::kAccepted);
  CalibView nudged = views[0];  // moved by 2 px: the same view
  for (auto& p : nudged.pixels) p += Eigen::Vector2d(2, 0);
  EXPECT_EQ(selector.Offer(nudged), ViewSelector::Verdict::kDuplicate);
  CalibView blurred = views[1];
  blurred.edge_width_px = 6;
  EXPECT_EQ(selector.Offer(blurred), ViewSelector::Verdict::kBlurred);
  EXPECT_EQ(selector.Offer(views[2]), ViewSelector::Verdict::kAccepted);
  EXPECT_EQ(selector.accepted().size(), 2u);
}

TEST(CameraCalibTest, BlurMeasureOnRenderedBoard) {
  std::string error;
  const auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  const synth::SceneRenderer renderer(camera, *rig);
  synth::SceneState scene;
  scene.cam_from_tank =
      tracking::LookAt({0.0, -0.1, 0.35}, {0, 0, 0}, {0, 1, 0}).Inverse();
  tracking::TagDetector detector{tracking::TagDetectorOptions()};
  double width[2];
  for (int blur = 0; blur < 2; ++blur) {
    synth::ImagingOptions imaging;
    imaging.defocus_sigma_px = blur ? 2.0 : 0.3;
    const cv::Mat image = renderer.Render(scene, imaging, 1).image;
    cv::Mat gray;
    cv::extractChannel(image, gray, 1);
    CalibView view;
    ASSERT_TRUE(TagTargetView(gray, rig->tank_tags, detector.Detect(gray), 8, 2,
                              &view));
    width[blur] = view.edge_width_px;
  }
  std::printf("edge width: sharp %.2f px, defocus 2 px: %.2f px\n", width[0],
              width[1]);
  EXPECT_LT(width[0], 2.0);
  EXPECT_GT(width[1], ViewSelectionOptions().max_edge_width_px);
}

}  // namespace
}  // namespace ripple::calib
