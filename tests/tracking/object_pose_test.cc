#include "tracking/object_pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/shipped_data.h"
#include "tests/tracking/tag_scene.h"
#include "tracking/baselines.h"

namespace ripple::tracking {
namespace {

constexpr double kDeg = M_PI / 180.0;

using test_data::DefaultRig;

Camera DistortedCamera() {
  Camera c = MakeIdealCamera(640, 480, 60.0);
  c.dist = {-0.12, 0.05, 0.001, -0.0005, 0.0, 0, 0, 0};
  return c;
}

// Camera 0.45 m from the board, looking down at it obliquely.
Pose BoardView() {
  const Pose tank_from_cam =
      LookAt(Eigen::Vector3d(0.05, -0.3, 0.35), Eigen::Vector3d(0, 0, 0),
             Eigen::Vector3d(0, 0, 1));
  return tank_from_cam.Inverse();
}

// The pen held above the board, tilted.
Pose PenView(const Pose& cam_from_tank) {
  const Pose tank_from_pen(Eigen::Quaterniond(Eigen::AngleAxisd(
                               0.5, Eigen::Vector3d(1, 1, 0).normalized())),
                           Eigen::Vector3d(0.02, 0.01, 0.15));
  return cam_from_tank * tank_from_pen;
}

::testing::AssertionResult PoseNear(const Pose& actual, const Pose& expected,
                                    double rot_deg, double trans_m) {
  const double r = RotationDistance(actual, expected) / kDeg;
  const double t = TranslationDistance(actual, expected);
  if (r <= rot_deg && t <= trans_m) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "rotation error " << r << " deg (max " << rot_deg
         << "), translation error " << t * 1000 << " mm (max " << trans_m * 1000
         << ")";
}

TEST(PoseMathTest, ComposeInverseAndCanonicalSign) {
  const Pose a = Pose::FromAxisAngle(Eigen::Vector3d(0.3, -0.2, 1.1),
                                     Eigen::Vector3d(0.1, 0.2, 0.3));
  const Pose b = Pose::FromAxisAngle(Eigen::Vector3d(-1.0, 0.4, 0.2),
                                     Eigen::Vector3d(-0.4, 0.0, 1.0));
  EXPECT_TRUE(PoseNear(a * a.Inverse(), Pose::Identity(), 1e-9, 1e-12));
  const Eigen::Vector3d p(0.3, -0.7, 2.0);
  EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
  EXPECT_LT(((a.Matrix() * p.homogeneous()).head<3>() - a * p).norm(), 1e-12);
  EXPECT_GE(a.CanonicalRotation().w(), 0.0);
}

TEST(ObjectPoseTest, ExactCornersGiveExactPoseThroughDistortion) {
  const Rig rig = DefaultRig();
  const Camera camera = DistortedCamera();
  std::mt19937 rng(1);
  const Pose cam_from_tank = BoardView();
  const Pose cam_from_pen = PenView(cam_from_tank);
  for (const auto& [tags, truth] :
       {std::make_pair(rig.tank_tags, cam_from_tank),
        std::make_pair(rig.pen->faces, cam_from_pen)}) {
    const auto detections =
        testing::ProjectDetections(camera, tags, truth, 0.0, &rng);
    ASSERT_FALSE(detections.empty());
    const auto obs = MatchObservations(camera, tags, detections);
    ObjectPose pose;
    ASSERT_TRUE(EstimateObjectPose({}, camera, obs, {}, &pose));
    EXPECT_TRUE(PoseNear(pose.cam_from_object, truth, 1e-6, 1e-8));
    EXPECT_LT(pose.rmse_px, 1e-5);
    EXPECT_EQ(pose.tag_ids.size(), detections.size());
  }
}

TEST(ObjectPoseTest, NoisyBoardIsAccurateAndRefinementHelps) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  std::mt19937 rng(2);
  const Pose truth = BoardView();
  double refined_sum = 0, ippe_sum = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto obs = MatchObservations(
        camera, rig.tank_tags,
        testing::ProjectDetections(camera, rig.tank_tags, truth, 0.2, &rng));
    ObjectPose refined, ippe;
    PoseEstimatorOptions no_refine;
    no_refine.refine = false;
    ASSERT_TRUE(EstimateObjectPose({}, camera, obs, {}, &refined));
    ASSERT_TRUE(EstimateObjectPose(no_refine, camera, obs, {}, &ippe));
    EXPECT_TRUE(PoseNear(refined.cam_from_object, truth, 0.2, 0.001));
    refined_sum += RotationDistance(refined.cam_from_object, truth);
    ippe_sum += RotationDistance(ippe.cam_from_object, truth);
    EXPECT_NEAR(refined.rmse_px, 0.2 * std::sqrt(2.0), 0.1);
  }
  EXPECT_LT(refined_sum, 0.5 * ippe_sum);
}

TEST(ObjectPoseTest, SingleTagEvaluatesBothIppeBranches) {
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TagPlacement tag;
  tag.id = 0;
  tag.edge_m = 0.024;
  // A small, nearly frontal tag far away: the classic ambiguous view.
  const Pose truth(Eigen::Quaterniond(Eigen::AngleAxisd(
                       0.25, Eigen::Vector3d(1, 0.3, 0).normalized())),
                   Eigen::Vector3d(0.02, -0.01, 0.6));
  std::mt19937 rng(3);
  const auto obs = MatchObservations(
      camera, {tag}, testing::ProjectDetections(camera, {tag}, truth, 0, &rng));
  ASSERT_EQ(obs.size(), 1u);
  const std::vector<Pose> branches = IppeSquare(obs[0], tag.edge_m);
  ASSERT_EQ(branches.size(), 2u);
  EXPECT_GT(RotationDistance(branches[0], branches[1]), 10 * kDeg);
  ObjectPose pose;
  ASSERT_TRUE(EstimateObjectPose({}, camera, obs, {}, &pose));
  EXPECT_TRUE(PoseNear(pose.cam_from_object, truth, 1e-4, 1e-6));
  EXPECT_TRUE(std::isfinite(pose.alternative_rmse_px));
  EXPECT_LT(pose.alternative_rmse_px, 2.0);  // genuinely ambiguous
}

TEST(ObjectPoseTest, RobustLossDiscountsAnOutlierTag) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  std::mt19937 rng(4);
  const Pose truth = BoardView();
  auto detections =
      testing::ProjectDetections(camera, rig.tank_tags, truth, 0.1, &rng);
  ASSERT_GE(detections.size(), 6u);
  // One corner badly off (an occluding finger on an edge).
  detections[2].corners[1] += Eigen::Vector2d(6.0, -4.0);
  const auto obs = MatchObservations(camera, rig.tank_tags, detections);
  PoseEstimatorOptions plain;
  plain.loss = RobustLoss::kNone;
  ObjectPose robust, least_squares;
  ASSERT_TRUE(EstimateObjectPose({}, camera, obs, {}, &robust));
  ASSERT_TRUE(EstimateObjectPose(plain, camera, obs, {}, &least_squares));
  EXPECT_LT(TranslationDistance(robust.cam_from_object, truth),
            TranslationDistance(least_squares.cam_from_object, truth));
  EXPECT_TRUE(PoseNear(robust.cam_from_object, truth, 0.1, 0.001));
}

// A pen face whose corner lies under a finger: the detector's outline
// follows the finger there (TagDetection::corner_occluded). Left out, the
// three other corners still fix the pose; used, it pulls the pose away.
TEST(ObjectPoseTest, HiddenCornersAreLeftOut) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  const Pose truth = PenView(BoardView());
  std::mt19937 rng(5);
  auto detections =
      testing::ProjectDetections(camera, rig.pen->faces, truth, 0.0, &rng);
  ASSERT_FALSE(detections.empty());
  detections.resize(1);  // a single face
  detections[0].corners[2] += Eigen::Vector2d(2.0, 1.5);
  ObjectPose used, left_out;
  ASSERT_TRUE(EstimateObjectPose(
      {}, camera, MatchObservations(camera, rig.pen->faces, detections), {},
      &used));
  detections[0].corner_occluded[2] = true;
  const auto obs = MatchObservations(camera, rig.pen->faces, detections);
  ASSERT_TRUE(obs[0].occluded[2]);
  ASSERT_TRUE(EstimateObjectPose({}, camera, obs, {}, &left_out));
  EXPECT_EQ(left_out.num_corners, 3);
  EXPECT_LT(left_out.rmse_px, 1e-6);
  EXPECT_TRUE(PoseNear(left_out.cam_from_object, truth, 0.01, 1e-5));
  EXPECT_FALSE(PoseNear(used.cam_from_object, truth, 0.5, 0.001));

  // With fewer than three corners left every corner is used again: two
  // corners cannot fix a pose.
  detections[0].corner_occluded = {true, true, true, false};
  const auto few = MatchObservations(camera, rig.pen->faces, detections);
  for (int k = 0; k < 4; ++k) EXPECT_FALSE(few[0].occluded[k]);
}

TEST(ObjectPoseTest, RefineConvergesFromAPerturbedStart) {
  const Rig rig = DefaultRig();
  const Camera camera = DistortedCamera();
  std::mt19937 rng(5);
  const Pose truth = BoardView();
  const auto obs = MatchObservations(
      camera, rig.tank_tags,
      testing::ProjectDetections(camera, rig.tank_tags, truth, 0.0, &rng));
  const Pose start = Pose::FromAxisAngle(Eigen::Vector3d(0.1, -0.05, 0.08),
                                         Eigen::Vector3d(0.01, -0.02, 0.03)) *
                     truth;
  ObjectPose pose;
  ASSERT_TRUE(RefineObjectPose({}, camera, obs, start, &pose));
  EXPECT_TRUE(PoseNear(pose.cam_from_object, truth, 1e-5, 1e-7));
  EXPECT_GT(pose.iterations, 1);
}

TEST(ObjectPoseTest, TipUncertaintyShrinksWithMoreFaces) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  std::mt19937 rng(6);
  const Pose truth = PenView(BoardView());
  const auto obs = MatchObservations(
      camera, rig.pen->faces,
      testing::ProjectDetections(camera, rig.pen->faces, truth, 0.0, &rng));
  ASSERT_GE(obs.size(), 2u);
  const double all = PointUncertainty(camera, obs, truth, rig.pen->tip_in_pen);
  for (const TagObservation& o : obs) {
    const double one =
        PointUncertainty(camera, {o}, truth, rig.pen->tip_in_pen);
    EXPECT_GT(one, all);
  }
  EXPECT_GT(all, 0.0);
  EXPECT_LT(all, 0.01);  // metres per pixel of corner noise
}

TEST(BaselinesTest, AllMethodsRecoverExactPoses) {
  const Rig rig = DefaultRig();
  const Camera camera = DistortedCamera();
  std::mt19937 rng(7);
  const Pose cam_from_tank = BoardView();
  const Pose cam_from_pen = PenView(cam_from_tank);
  const auto tank_obs =
      MatchObservations(camera, rig.tank_tags,
                        testing::ProjectDetections(camera, rig.tank_tags,
                                                   cam_from_tank, 0, &rng));
  const auto pen_obs =
      MatchObservations(camera, rig.pen->faces,
                        testing::ProjectDetections(camera, rig.pen->faces,
                                                   cam_from_pen, 0, &rng));
  auto paper = PaperFrontalTagPose(camera, tank_obs);
  ASSERT_TRUE(paper);
  EXPECT_TRUE(PoseNear(*paper, cam_from_tank, 0.01, 1e-4));
  paper = PaperFrontalTagPose(camera, pen_obs);
  ASSERT_TRUE(paper);
  EXPECT_TRUE(PoseNear(*paper, cam_from_pen, 0.01, 1e-4));
  auto ippe = OpenCvIppeBestTagPose(camera, pen_obs, rig.pen->tip_in_pen);
  ASSERT_TRUE(ippe);
  EXPECT_TRUE(PoseNear(*ippe, cam_from_pen, 0.01, 1e-4));
  auto sqpnp = SqpnpLmPose(camera, tank_obs);
  ASSERT_TRUE(sqpnp);
  EXPECT_TRUE(PoseNear(*sqpnp, cam_from_tank, 0.01, 1e-4));
  sqpnp = SqpnpLmPose(camera, pen_obs);
  ASSERT_TRUE(sqpnp);
  EXPECT_TRUE(PoseNear(*sqpnp, cam_from_pen, 0.01, 1e-4));
}

}  // namespace
}  // namespace ripple::tracking
