// Tag-layout bundle adjustment on synthetic views: the default rig's cube
// faces and board tags perturbed by up to 2 mm and 3 degrees, corners with
// 0.2 px Gaussian noise; recovery within 0.2 mm and 0.2 degrees per tag.
//
// Cube faces are compared in the calibration's own gauge (the reference face
// at its nominal pose). Board tags are compared after the best rigid
// alignment of the whole layout: on a 25 cm board the reference tag's own
// orientation noise (~0.1 degree for a 30 mm tag) swings the far tags by
// ~0.3 mm, which moves the frame, not the layout.
#include "calib/rig_calib.h"

#include <gtest/gtest.h>

#include "tests/calib/calib_scene.h"
#include "tests/shipped_data.h"

namespace ripple::calib {
namespace {

using testing::Perturbed;
using testing::ProjectTags;
using testing::Regauged;
using tracking::Camera;
using tracking::TagPlacement;

constexpr double kDeg = M_PI / 180;
const double kNoise = getenv("NOISE") ? atof(getenv("NOISE")) : 0.2;

using test_data::DefaultRig;

// Views of the pen cube from random directions, >= 2 faces each.
std::vector<std::vector<tracking::TagDetection>> PenViews(
    const Camera& camera, const std::vector<TagPlacement>& truth, int n,
    double noise_px, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::vector<tracking::TagDetection>> views;
  while (static_cast<int>(views.size()) < n) {
    const Pose cam_from_pen(
        testing::RandomRotation(rng),
        Eigen::Vector3d(0.03 * u(*rng), 0.02 * u(*rng), 0.18 + 0.03 * u(*rng)));
    auto d = ProjectTags(camera, truth, cam_from_pen, noise_px, rng);
    if (d.size() >= 2) views.push_back(d);
  }
  return views;
}

void ExpectRecovered(const std::vector<TagPlacement>& truth,
                     const std::vector<TagPlacement>& calibrated, double max_m,
                     double max_rad) {
  ASSERT_EQ(truth.size(), calibrated.size());
  double worst_m = 0, worst_rad = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double dm = tracking::TranslationDistance(
        truth[i].object_from_tag, calibrated[i].object_from_tag);
    const double dr = tracking::RotationDistance(truth[i].object_from_tag,
                                                 calibrated[i].object_from_tag);
    EXPECT_LT(dm, max_m) << "tag " << truth[i].id;
    EXPECT_LT(dr, max_rad) << "tag " << truth[i].id;
    worst_m = std::max(worst_m, dm);
    worst_rad = std::max(worst_rad, dr);
  }
  std::printf("worst tag error: %.3f mm, %.3f deg\n", 1e3 * worst_m,
              worst_rad / kDeg);
}

TEST(RigCalibTest, RecoversPerturbedCubeFaces) {
  const tracking::Rig rig = DefaultRig();
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::mt19937 rng(7);
  const auto& nominal = rig.pen->faces;
  const auto truth = Perturbed(nominal, &rng, 0.002, 3 * kDeg);
  const auto views = PenViews(camera, truth, 100, kNoise, &rng);

  RigCalibOptions options;
  options.reference_id = 10;
  std::vector<TagPlacement> calibrated;
  RigCalibSummary summary;
  std::string error;
  ASSERT_TRUE(CalibrateTagLayout(options, camera, nominal, views, &calibrated,
                                 &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  EXPECT_EQ(summary.views_used, 100);
  EXPECT_GT(summary.rms_before_px, 1.0);
  EXPECT_LT(summary.rms_after_px, 0.3);  // ~ the 0.2 px noise
  ExpectRecovered(Regauged(truth, nominal, 10), calibrated, 0.2e-3, 0.2 * kDeg);
}

TEST(RigCalibTest, RecoversPerturbedBoardTags) {
  const tracking::Rig rig = DefaultRig();
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::mt19937 rng(11);
  const auto& nominal = rig.tank_tags;
  const auto truth = Perturbed(nominal, &rng, 0.002, 3 * kDeg);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::vector<tracking::TagDetection>> views;
  while (views.size() < 80) {
    // Looking at the board centre from 0.35-0.5 m, up to 45 degrees off.
    const Eigen::Vector3d eye =
        (Eigen::Vector3d(u(rng), u(rng), 1.0).normalized()) *
        (0.425 + 0.075 * u(rng));
    const Pose tank_from_cam =
        tracking::LookAt(eye, Eigen::Vector3d(0.02 * u(rng), 0.02 * u(rng), 0),
                         Eigen::Vector3d(0, 1, 0));
    auto d = ProjectTags(camera, truth, tank_from_cam.Inverse(), kNoise, &rng);
    if (d.size() >= 4) views.push_back(d);
  }
  RigCalibOptions options;
  std::vector<TagPlacement> calibrated;
  RigCalibSummary summary;
  std::string error;
  ASSERT_TRUE(CalibrateTagLayout(options, camera, nominal, views, &calibrated,
                                 &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  ExpectRecovered(truth, testing::AlignedTo(calibrated, truth), 0.2e-3,
                  0.2 * kDeg);
}

TEST(RigCalibTest, InPlaneOnlyKeepsTagsInTheirPlane) {
  const tracking::Rig rig = DefaultRig();
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::mt19937 rng(3);
  auto truth = rig.tank_tags;
  std::uniform_real_distribution<double> v(-1, 1);
  for (auto& t : truth)  // in-plane errors only: shifts and yaw
    t.object_from_tag =
        t.object_from_tag *
        Pose::FromAxisAngle(
            Eigen::Vector3d(0, 0, 3 * kDeg * v(rng)),
            Eigen::Vector3d(0.0014 * v(rng), 0.0014 * v(rng), 0));
  std::vector<std::vector<tracking::TagDetection>> views;
  std::uniform_real_distribution<double> u(-1, 1);
  while (views.size() < 15) {
    const Eigen::Vector3d eye =
        Eigen::Vector3d(0.25 * u(rng), 0.25 * u(rng), 0.45);
    const Pose tank_from_cam =
        tracking::LookAt(eye, Eigen::Vector3d::Zero(), {0, 1, 0});
    auto d = ProjectTags(camera, truth, tank_from_cam.Inverse(), kNoise, &rng);
    if (d.size() >= 4) views.push_back(d);
  }
  RigCalibOptions options;
  options.in_plane_only = true;
  options.reference_id = 0;
  std::vector<TagPlacement> calibrated;
  RigCalibSummary summary;
  std::string error;
  ASSERT_TRUE(CalibrateTagLayout(options, camera, rig.tank_tags, views,
                                 &calibrated, &summary, &error))
      << error;
  for (const auto& t : calibrated) {
    EXPECT_NEAR(t.object_from_tag.translation.z(), 0, 1e-12);
    EXPECT_NEAR(std::abs(t.object_from_tag.R()(2, 2)), 1, 1e-12);
  }
  ExpectRecovered(truth, testing::AlignedTo(calibrated, truth), 0.2e-3,
                  0.2 * kDeg);
}

TEST(RigCalibTest, TooFewViewsIsAnError) {
  const tracking::Rig rig = DefaultRig();
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::mt19937 rng(5);
  const auto views = PenViews(camera, rig.pen->faces, 4, 0.2, &rng);
  std::vector<TagPlacement> calibrated;
  RigCalibSummary summary;
  std::string error;
  EXPECT_FALSE(CalibrateTagLayout(RigCalibOptions(), camera, rig.pen->faces,
                                  views, &calibrated, &summary, &error));
  EXPECT_NE(error.find("too few views"), std::string::npos) << error;
}

TEST(RigCalibTest, NoTargetIsAnError) {
  const tracking::Rig rig = DefaultRig();
  const Camera camera = tracking::MakeIdealCamera(640, 480, 60);
  std::vector<std::vector<tracking::TagDetection>> views(20);
  std::vector<TagPlacement> calibrated;
  RigCalibSummary summary;
  std::string error;
  EXPECT_FALSE(CalibrateTagLayout(RigCalibOptions(), camera, rig.pen->faces,
                                  views, &calibrated, &summary, &error));
  EXPECT_NE(error.find("no target found"), std::string::npos) << error;
  std::mt19937 rng(1);
  RigCalibOptions bad;
  bad.reference_id = 99;
  const auto some = PenViews(camera, rig.pen->faces, 12, 0.2, &rng);
  EXPECT_FALSE(CalibrateTagLayout(bad, camera, rig.pen->faces, some,
                                  &calibrated, &summary, &error));
  EXPECT_NE(error.find("reference tag 99"), std::string::npos) << error;
}

// Views of detections, each listing tag ids seen together.
std::vector<std::vector<tracking::TagDetection>> ViewsOf(
    const std::vector<std::vector<int>>& ids_per_view) {
  std::vector<std::vector<tracking::TagDetection>> views;
  for (const auto& ids : ids_per_view) {
    views.emplace_back();
    for (int id : ids) {
      tracking::TagDetection d;
      d.id = id;
      for (auto& c : d.corners) c.setZero();
      views.back().push_back(d);
    }
  }
  return views;
}

TEST(LayoutChoiceTest, PicksTheObjectWhoseTagsAreSeenTogetherMore) {
  const tracking::Rig rig = DefaultRig();
  ASSERT_TRUE(rig.pen);
  ASSERT_GE(rig.pen->faces.size(), 2u);
  ASSERT_GE(rig.tank_tags.size(), 2u);
  const int p0 = rig.pen->faces[0].id, p1 = rig.pen->faces[1].id;
  const int t0 = rig.tank_tags[0].id, t1 = rig.tank_tags[1].id;
  const auto pen_views = ViewsOf({{p0, p1}, {p0, p1, t0}, {t0, t1}});
  EXPECT_EQ(ViewsWithTwoTags(rig.pen->faces, pen_views), 2);
  EXPECT_EQ(ViewsWithTwoTags(rig.tank_tags, pen_views), 1);
  EXPECT_EQ(ChooseLayoutObject(rig, pen_views), LayoutObject::kPen);
  const auto board_views = ViewsOf({{t0, t1}, {t0, t1, p0}, {p0}});
  EXPECT_EQ(ChooseLayoutObject(rig, board_views), LayoutObject::kTank);
  // A tie goes to the pen; a rig without a pen is always the board.
  EXPECT_EQ(ChooseLayoutObject(rig, ViewsOf({{p0, p1}, {t0, t1}})),
            LayoutObject::kPen);
  tracking::Rig no_pen = rig;
  no_pen.pen.reset();
  EXPECT_EQ(ChooseLayoutObject(no_pen, pen_views), LayoutObject::kTank);
}

}  // namespace
}  // namespace ripple::calib
