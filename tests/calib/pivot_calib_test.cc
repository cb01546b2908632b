// Pivot calibration: pen poses estimated from noisy corners (0.2 px) of the
// cube while the tip (5 mm off the rig's nominal) stays in a dimple.
#include "calib/pivot_calib.h"

#include <gtest/gtest.h>

#include "tests/calib/calib_scene.h"
#include "tracking/object_pose.h"

namespace ripple::calib {
namespace {

using tracking::Camera;
using tracking::Pose;

constexpr double kDeg = M_PI / 180;

struct PivotData {
  std::vector<Pose> cam_from_pen;
  Eigen::Vector3d tip_truth;
};

// `tilt_deg` about the two axes across the pen, `spin_deg` about its own.
PivotData MakePivotData(int n, double tilt_deg, double spin_deg,
                        bool single_axis, uint32_t seed) {
  std::string error;
  const auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  EXPECT_TRUE(rig) << error;
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::mt19937 rng(seed);
  PivotData data;
  data.tip_truth = rig->pen->tip_in_pen + 0.005 * testing::RandomUnit(&rng);
  const Eigen::Vector3d pivot_in_cam(0.0, 0.06, 0.36);
  // Pen +z (away from the tip) towards the camera and up the image.
  const Eigen::Quaterniond base = Eigen::Quaterniond::FromTwoVectors(
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, -0.6, -1).normalized());
  std::uniform_real_distribution<double> u(-1, 1);
  while (static_cast<int>(data.cam_from_pen.size()) < n) {
    const Eigen::Quaterniond tilt =
        Eigen::AngleAxisd(tilt_deg * kDeg * u(rng), Eigen::Vector3d::UnitX()) *
        Eigen::AngleAxisd(single_axis ? 0.0 : tilt_deg * kDeg * u(rng),
                          Eigen::Vector3d::UnitY());
    const Eigen::Quaterniond spin(
        Eigen::AngleAxisd(spin_deg * kDeg * u(rng), Eigen::Vector3d::UnitZ()));
    const Eigen::Quaterniond r = base * tilt * spin;
    const Pose truth(r, pivot_in_cam - r * data.tip_truth);
    const auto detections =
        testing::ProjectTags(camera, rig->pen->faces, truth, 0.2, &rng);
    const auto obs =
        tracking::MatchObservations(camera, rig->pen->faces, detections);
    if (obs.empty()) continue;
    tracking::ObjectPose pose;
    if (!tracking::EstimateObjectPose(tracking::PoseEstimatorOptions(), camera,
                                      obs, {}, &pose))
      continue;
    data.cam_from_pen.push_back(pose.cam_from_object);
  }
  return data;
}

TEST(PivotCalibTest, RecoversTipWithinThreeTenthsOfAMillimetre) {
  const PivotData data = MakePivotData(60, 30, 90, false, 3);
  PivotSummary summary;
  std::string error;
  ASSERT_TRUE(
      CalibratePivot(PivotOptions(), data.cam_from_pen, &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  const double err = (summary.tip_in_pen - data.tip_truth).norm();
  std::printf("tip error %.3f mm\n", 1e3 * err);
  EXPECT_LT(err, 0.3e-3);
  EXPECT_NEAR(summary.pivot_in_ref.z(), 0.36, 0.5e-3);
  EXPECT_LT(summary.rms_m, 2e-3);
}

// The calibration refuses `data` with a message containing `reason`.
void ExpectRefused(const PivotData& data, const std::string& reason) {
  PivotSummary summary;
  std::string error;
  EXPECT_FALSE(
      CalibratePivot(PivotOptions(), data.cam_from_pen, &summary, &error));
  EXPECT_NE(error.find(reason), std::string::npos) << error;
}

TEST(PivotCalibTest, SpinningWithoutTiltIsDegenerate) {
  ExpectRefused(MakePivotData(40, 0, 90, false, 4), "degenerate motion");
}

TEST(PivotCalibTest, RotationAboutOneAxisIsDegenerate) {
  ExpectRefused(MakePivotData(40, 30, 0, true, 5), "degenerate motion");
}

TEST(PivotCalibTest, TooFewViews) {
  ExpectRefused(MakePivotData(5, 30, 90, false, 6), "too few views");
}

}  // namespace
}  // namespace ripple::calib
