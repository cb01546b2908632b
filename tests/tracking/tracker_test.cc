#include "tracking/tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "tests/shipped_data.h"
#include "tests/tracking/tag_scene.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFps = 30.0;

using test_data::DefaultRig;

Pose BoardView(double yaw = 0.0) {
  const Eigen::Vector3d eye(0.3 * std::sin(yaw), -0.3 * std::cos(yaw), 0.35);
  return LookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1))
      .Inverse();
}

Pose TankFromPen(double t) {
  return Pose(Eigen::Quaterniond(Eigen::AngleAxisd(
                  0.4 + 0.1 * t, Eigen::Vector3d(1, 1, 0).normalized())),
              Eigen::Vector3d(0.02 * std::cos(t), 0.01, 0.15));
}

std::vector<TagDetection> Concat(std::vector<TagDetection> a,
                                 const std::vector<TagDetection>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(TrackerTest, TracksBothObjectsAndTheTip) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  Tracker tracker(camera, rig, TrackerOptions{});
  std::mt19937 rng(1);
  for (int f = 0; f < 20; ++f) {
    const double t = f / kFps;
    const Pose cam_from_tank = BoardView(0.01 * f);
    const Pose tank_from_pen = TankFromPen(t);
    const Pose cam_from_pen = cam_from_tank * tank_from_pen;
    const auto dets =
        Concat(testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank,
                                          0.1, &rng),
               testing::ProjectDetections(camera, rig.pen->faces, cam_from_pen,
                                          0.1, &rng));
    const FrameResult r = tracker.TrackDetections(dets, t);
    EXPECT_EQ(r.frame, f);
    ASSERT_EQ(r.tank.status, TrackStatus::kTracked);
    ASSERT_EQ(r.pen.status, TrackStatus::kTracked);
    EXPECT_EQ(r.tank.reinitialized, f == 0);
    EXPECT_LT(RotationDistance(*r.tank.cam_from_object, cam_from_tank),
              0.1 * kDeg);
    ASSERT_TRUE(r.tip_in_tank);
    const Eigen::Vector3d tip = tank_from_pen * rig.pen->tip_in_pen;
    EXPECT_LT((*r.tip_in_tank - tip).norm(), 0.001) << "frame " << f;
    EXPECT_GE(r.pen.tags.size(), 2u);
    const auto rows = tracker.ToPoseRows(r);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].object, "tank");
    EXPECT_TRUE(rows[1].tip_in_tank);
  }
}

TEST(TrackerTest, BestFaceModesUseOneFace) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  for (FaceSelection selection :
       {FaceSelection::kLeastUncertain, FaceSelection::kMostFrontal}) {
    TrackerOptions options;
    options.pen_mode = PenMode::kBestFace;
    options.face_selection = selection;
    Tracker tracker(camera, rig, options);
    std::mt19937 rng(2);
    const Pose cam_from_tank = BoardView();
    const Pose cam_from_pen = cam_from_tank * TankFromPen(0);
    const auto dets =
        Concat(testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank,
                                          0.0, &rng),
               testing::ProjectDetections(camera, rig.pen->faces, cam_from_pen,
                                          0.0, &rng));
    const FrameResult r = tracker.TrackDetections(dets, 0.0);
    ASSERT_EQ(r.pen.status, TrackStatus::kTracked);
    EXPECT_EQ(r.pen.tags.size(), 1u);
    EXPECT_LT(TranslationDistance(*r.pen.cam_from_object, cam_from_pen), 1e-6);
  }
}

// A lone face seen almost frontally from afar has two poses that explain
// its corners nearly equally well. Feeding the corners of the wrong branch
// must not flip the reported pose.
TEST(TrackerTest, RejectsAFlipToTheOtherBranch) {
  Rig rig = DefaultRig();
  rig.pen->faces.resize(1);  // the +z face only
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TrackerOptions options;
  Tracker tracker(camera, rig, options);
  std::mt19937 rng(3);
  // Face +z looking at the camera, tilted by 12 degrees, 0.6 m away.
  const Pose cam_from_face(Eigen::Quaterniond(Eigen::AngleAxisd(
                               12 * kDeg, Eigen::Vector3d::UnitX())),
                           Eigen::Vector3d(0.01, 0.0, 0.6));
  const Pose cam_from_pen =
      cam_from_face * rig.pen->faces[0].object_from_tag.Inverse();
  const auto exact =
      testing::ProjectDetections(camera, rig.pen->faces, cam_from_pen, 0, &rng);
  const auto obs = MatchObservations(camera, rig.pen->faces, exact);
  ASSERT_EQ(obs.size(), 1u);
  Pose flipped_pen;
  bool found = false;
  for (const Pose& cam_from_tag : IppeSquare(obs[0], obs[0].edge_m)) {
    const Pose candidate = cam_from_tag * obs[0].object_from_tag.Inverse();
    if (RotationDistance(candidate, cam_from_pen) > 10 * kDeg) {
      flipped_pen = candidate;
      found = true;
    }
  }
  ASSERT_TRUE(found);
  for (int f = 0; f < 12; ++f) {
    const Pose shown = f == 8 ? flipped_pen : cam_from_pen;
    const auto dets =
        Concat(testing::ProjectDetections(camera, rig.tank_tags, BoardView(),
                                          0.05, &rng),
               testing::ProjectDetections(camera, rig.pen->faces, shown,
                                          f == 8 ? 0.0 : 0.05, &rng));
    const FrameResult r = tracker.TrackDetections(dets, f / kFps);
    ASSERT_TRUE(r.pen.has_pose()) << "frame " << f;
    EXPECT_LT(RotationDistance(*r.pen.cam_from_object, cam_from_pen), 5 * kDeg)
        << "frame " << f;
    EXPECT_FALSE(r.cut);
    if (f == 8) {
      EXPECT_TRUE(r.pen.flip_rejected);
    }
  }
}

// The benchmark's hard case: a pen far away (face 10 about 18 px wide) seen
// through that single face, where corner noise can make the wrong IPPE
// branch reproject better than the right one.
struct SmallFaceScene {
  Rig rig = DefaultRig();
  Camera camera = MakeIdealCamera(640, 480, 60.0);
  // Face 10 towards the camera, tilted 15 deg about x and `yaw` about y,
  // 0.75 m away.
  Pose CamFromPen(double yaw) const {
    const Pose cam_from_face(
        Eigen::Quaterniond(
            Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(15 * kDeg, Eigen::Vector3d::UnitX())),
        Eigen::Vector3d(0.02, 0.01, 0.75));
    return cam_from_face * rig.pen->faces[0].object_from_tag.Inverse();
  }
  // Detections of the given pen faces only.
  std::vector<TagDetection> Faces(const Pose& cam_from_pen, double noise_px,
                                  std::mt19937* rng,
                                  const std::vector<int>& ids) const {
    std::vector<TagDetection> out;
    for (const TagDetection& d : testing::ProjectDetections(
             camera, rig.pen->faces, cam_from_pen, noise_px, rng))
      if (std::find(ids.begin(), ids.end(), d.id) != ids.end())
        out.push_back(d);
    return out;
  }
  // The other IPPE branch of face 10's corners at `cam_from_pen`.
  Pose Flipped(const Pose& cam_from_pen) const {
    std::mt19937 rng(0);
    const auto obs = MatchObservations(camera, rig.pen->faces,
                                       Faces(cam_from_pen, 0, &rng, {10}));
    EXPECT_EQ(obs.size(), 1u);
    for (const Pose& cam_from_tag : IppeSquare(obs[0], obs[0].edge_m)) {
      const Pose candidate = cam_from_tag * obs[0].object_from_tag.Inverse();
      if (RotationDistance(candidate, cam_from_pen) > 10 * kDeg)
        return candidate;
    }
    ADD_FAILURE() << "no second branch";
    return cam_from_pen;
  }
};

// Tracked through two faces, hidden for three frames, then re-acquired
// through the single small face with corners that the wrong branch explains
// best: the branch nearer the pose before the gap is reported, and the
// other is kept (ambiguous) instead of being locked in or out.
TEST(TrackerTest, SmallSingleFaceReacquiredWithoutAFlip) {
  const SmallFaceScene scene;
  Tracker tracker(scene.camera, scene.rig, TrackerOptions{});
  std::mt19937 rng(5);
  const double yaw0 = 25 * kDeg;  // faces 10 and 11 visible
  const double yaw1 = 0.0;        // face 10 nearly alone
  bool ambiguous_seen = false;
  for (int f = 0; f < 30; ++f) {
    const double yaw = f < 5 ? yaw0 : yaw1 + 0.2 * kDeg * (f - 8);
    const Pose truth = scene.CamFromPen(yaw);
    std::vector<TagDetection> dets;
    if (f < 5) {
      dets = scene.Faces(truth, 0.1, &rng, {10, 11});
      ASSERT_EQ(dets.size(), 2u);
    } else if (f == 8) {
      dets = scene.Faces(scene.Flipped(truth), 0.05, &rng, {10});
      // The scene is the hard case: alone, these corners pose the pen on
      // the wrong branch, the right one a close second.
      ObjectPose alone;
      ASSERT_TRUE(EstimateObjectPose(
          PoseEstimatorOptions{}, scene.camera,
          MatchObservations(scene.camera, scene.rig.pen->faces, dets), {},
          &alone));
      EXPECT_GT(RotationDistance(alone.cam_from_object, truth), 10 * kDeg);
      EXPECT_LT(alone.alternative_rmse_px, alone.rmse_px + 1.0);
    } else if (f > 8) {
      dets = scene.Faces(truth, 0.15, &rng, {10});
    }
    const FrameResult r = tracker.TrackDetections(dets, f / kFps);
    if (f >= 5 && f < 8) {
      EXPECT_EQ(r.pen.status, TrackStatus::kLost);
      continue;
    }
    ASSERT_TRUE(r.pen.has_pose()) << "frame " << f;
    EXPECT_LT(RotationDistance(*r.pen.cam_from_object, truth), 10 * kDeg)
        << "frame " << f;
    ambiguous_seen = ambiguous_seen || r.pen.ambiguous;
  }
  EXPECT_TRUE(ambiguous_seen);
}

// A hand over a face's margin near one corner pulls libapriltag's outline
// onto the hand there: that corner moves along the tag's edge, and the four
// corners are no longer the image of a square. Posed alone they put the tip
// centimetres off; the tracker does not report such a single face, while
// the same face with its corners only noisy is tracked.
TEST(TrackerTest, SingleFaceWhoseCornersAreNotASquareIsNotReported) {
  const SmallFaceScene scene;
  // Face 10 alone, about 30 px wide (the benchmark's covered faces are
  // 24-33 px).
  Pose truth = scene.CamFromPen(0.0);
  truth.translation *= 0.45 / 0.75;
  const Eigen::Vector3d tip = truth * scene.rig.pen->tip_in_pen;
  Tracker tracker(scene.camera, scene.rig, TrackerOptions{});
  constexpr int kTrials = 8;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::mt19937 rng(40 + trial);
    const std::vector<TagDetection> noisy =
        scene.Faces(truth, 0.05, &rng, {10});
    ASSERT_EQ(noisy.size(), 1u);
    // The top-right corner drawn 0.8 cells towards the top-left one (the
    // tag's edge is 8 cells): a parallelogram's fit leaves 0.8 / 4 = 0.2
    // cells RMS (0.16-0.17 here, perspective takes up some of it), above
    // the 0.12 allowed.
    std::vector<TagDetection> bent = noisy;
    auto& c = bent[0].corners;
    c[1] += 0.1 * (c[0] - c[1]);
    ObjectPose alone;
    ASSERT_TRUE(EstimateObjectPose(
        PoseEstimatorOptions{}, scene.camera,
        MatchObservations(scene.camera, scene.rig.pen->faces, bent), {},
        &alone));
    EXPECT_GT((alone.cam_from_object * scene.rig.pen->tip_in_pen - tip).norm(),
              0.01)
        << trial;

    tracker.Reset();
    const FrameResult r = tracker.TrackDetections(noisy, 0.0);
    ASSERT_EQ(r.pen.status, TrackStatus::kTracked) << trial;
    // A single 29 px face: 0.5-2.8 mm over these draws.
    EXPECT_LT((*r.pen.cam_from_object * scene.rig.pen->tip_in_pen - tip).norm(),
              0.004)
        << trial;
    tracker.Reset();
    EXPECT_EQ(tracker.TrackDetections(bent, 0.0).pen.status, TrackStatus::kLost)
        << trial;
  }
}

// Acquired on the wrong branch with no history to go by, the track stays
// ambiguous (flip rejection does not hold the wrong branch) and settles on
// the right one as soon as a second face comes into view.
TEST(TrackerTest, AmbiguousAcquisitionResolvedByASecondFace) {
  const SmallFaceScene scene;
  Tracker tracker(scene.camera, scene.rig, TrackerOptions{});
  std::mt19937 rng(7);
  for (int f = 0; f < 20; ++f) {
    const double yaw = f < 8 ? 0.0 : 25 * kDeg + 0.2 * kDeg * (f - 8);
    const Pose truth = scene.CamFromPen(yaw);
    std::vector<TagDetection> dets;
    if (f == 0) {
      dets = scene.Faces(scene.Flipped(truth), 0.05, &rng, {10});
    } else if (f < 8) {
      dets = scene.Faces(truth, 0.15, &rng, {10});
    } else {
      dets = scene.Faces(truth, 0.15, &rng, {10, 11});
      ASSERT_EQ(dets.size(), 2u);
    }
    const FrameResult r = tracker.TrackDetections(dets, f / kFps);
    ASSERT_TRUE(r.pen.has_pose()) << "frame " << f;
    if (f == 0) {
      EXPECT_TRUE(r.pen.ambiguous);
    }
    if (f < 8) {
      EXPECT_FALSE(r.pen.flip_rejected) << "frame " << f;
    } else {
      EXPECT_LT(RotationDistance(*r.pen.cam_from_object, truth), 3 * kDeg)
          << "frame " << f;
      EXPECT_FALSE(r.pen.ambiguous) << "frame " << f;
    }
  }
}

// A pen first seen through a single face near grazing (65-80 degrees from
// the line of sight; its other faces hidden, by a hand say), the board in
// view: the two branches of the square's pose are close in error there, so
// the first frame must either pose it right, or say it is ambiguous, or not
// report it; never a confident flip.
TEST(TrackerTest, GrazingSingleFaceFirstFrameIsNotAConfidentFlip) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0, 1);
  int trials = 0, flips = 0, ambiguous = 0, right = 0, unreported = 0;
  for (int attempt = 0; attempt < 4000 && trials < 40; ++attempt) {
    const Pose cam_from_tank = BoardView(2 * M_PI * u01(rng));
    const Eigen::Vector3d tip(0.14 * (u01(rng) - 0.5), 0.08 * (u01(rng) - 0.5),
                              0.01 + 0.04 * u01(rng));
    const Eigen::Matrix3d r =
        (Eigen::AngleAxisd(2 * M_PI * u01(rng), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(60 * kDeg * u01(rng), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(2 * M_PI * u01(rng), Eigen::Vector3d::UnitZ()))
            .toRotationMatrix();
    const Pose tank_from_pen =
        Pose::FromMatrix(r, tip - r * rig.pen->tip_in_pen);
    const Pose cam_from_pen = cam_from_tank * tank_from_pen;
    // The face seen: the most oblique one between 65 and 80 degrees.
    const TagPlacement* seen = nullptr;
    double seen_deg = 0;
    for (const TagPlacement& f : rig.pen->faces) {
      const Pose cam_from_tag = cam_from_pen * f.object_from_tag;
      const double c =
          cam_from_tag.R().col(2).dot(cam_from_tag.translation.normalized());
      const double deg = std::acos(std::clamp(c, -1.0, 1.0)) / kDeg;
      if (deg > 65 && deg < 80 && deg > seen_deg) {
        seen = &f;
        seen_deg = deg;
      }
    }
    if (!seen) continue;
    auto pen_dets =
        testing::ProjectDetections(camera, {*seen}, cam_from_pen, 0.15, &rng);
    auto tank_dets = testing::ProjectDetections(camera, rig.tank_tags,
                                                cam_from_tank, 0.1, &rng);
    if (pen_dets.size() != 1 || tank_dets.size() < 4) continue;
    ++trials;
    Tracker tracker(camera, rig, TrackerOptions{});
    const FrameResult res =
        tracker.TrackDetections(Concat(tank_dets, pen_dets), 0.0);
    if (!res.pen.has_pose() || res.pen.status != TrackStatus::kTracked) {
      ++unreported;
      continue;
    }
    const double err = RotationDistance(*res.pen.cam_from_object, cam_from_pen);
    if (err < 10 * kDeg) {
      ++right;
    } else if (res.pen.ambiguous) {
      ++ambiguous;
    } else {
      ++flips;
      ADD_FAILURE() << "confident flip of " << err / kDeg << " deg, face "
                    << seen->id << " at " << seen_deg << " deg";
    }
  }
  std::printf(
      "grazing single face: %d trials, %d right, %d ambiguous, %d "
      "not reported, %d flips\n",
      trials, right, ambiguous, unreported, flips);
  EXPECT_GE(trials, 30);
  EXPECT_EQ(flips, 0);
}

TEST(TrackerTest, ReinitialisesOnACut) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TrackerOptions options;
  options.smoothing.enabled = true;
  Tracker tracker(camera, rig, options);
  std::mt19937 rng(4);
  const Pose before = BoardView(0.0);
  // After the cut the camera looks from the other side, 80 degrees away.
  const Pose after = BoardView(80 * kDeg);
  for (int f = 0; f < 16; ++f) {
    const Pose truth = f < 10 ? before : after;
    const FrameResult r = tracker.TrackDetections(
        testing::ProjectDetections(camera, rig.tank_tags, truth, 0.1, &rng),
        f / kFps);
    ASSERT_EQ(r.tank.status, TrackStatus::kTracked);
    EXPECT_EQ(r.cut, f == 10) << "frame " << f;
    EXPECT_EQ(r.tank.reinitialized, f == 0 || f == 10);
    EXPECT_FALSE(r.tank.flip_rejected);
    // No smoothing across the cut: the new pose is reported at once.
    EXPECT_LT(RotationDistance(*r.tank.cam_from_object, truth), 0.2 * kDeg)
        << "frame " << f;
  }
}

TEST(TrackerTest, FollowsAFastGenuineRotation) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  Tracker tracker(camera, rig, TrackerOptions{});
  std::mt19937 rng(5);
  const Pose cam_from_tank = BoardView();
  for (int f = 0; f < 8; ++f) {
    // The pen spins 15 degrees per frame about its axis.
    const Pose tank_from_pen =
        TankFromPen(0) * Pose(Eigen::Quaterniond(Eigen::AngleAxisd(
                                  15 * kDeg * f, Eigen::Vector3d::UnitZ())),
                              Eigen::Vector3d::Zero());
    const Pose cam_from_pen = cam_from_tank * tank_from_pen;
    const auto dets =
        Concat(testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank,
                                          0.1, &rng),
               testing::ProjectDetections(camera, rig.pen->faces, cam_from_pen,
                                          0.1, &rng));
    const FrameResult r = tracker.TrackDetections(dets, f / kFps);
    ASSERT_TRUE(r.pen.has_pose());
    EXPECT_LT(RotationDistance(*r.pen.cam_from_object, cam_from_pen), 1 * kDeg)
        << "frame " << f;
  }
}

TEST(TrackerTest, HoldsAnOccludedBoardThenLosesIt) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TrackerOptions options;
  options.tank_hold_s = 0.5;
  options.pen_hold_s = 0.0;
  Tracker tracker(camera, rig, options);
  std::mt19937 rng(6);
  const Pose cam_from_tank = BoardView();
  const Pose cam_from_pen = cam_from_tank * TankFromPen(0);
  for (int f = 0; f < 30; ++f) {
    const double t = f / kFps;
    std::vector<TagDetection> dets;
    const bool visible = f < 5 || f >= 25;
    if (visible) {
      dets = Concat(testing::ProjectDetections(camera, rig.tank_tags,
                                               cam_from_tank, 0.1, &rng),
                    testing::ProjectDetections(camera, rig.pen->faces,
                                               cam_from_pen, 0.1, &rng));
    }
    const FrameResult r = tracker.TrackDetections(dets, t);
    if (visible) {
      EXPECT_EQ(r.tank.status, TrackStatus::kTracked) << f;
      EXPECT_EQ(r.pen.status, TrackStatus::kTracked) << f;
      EXPECT_EQ(r.tank.reinitialized, f == 0 || f == 25) << f;
    } else if (t - 4 / kFps <= 0.5 + 1e-9) {
      EXPECT_EQ(r.tank.status, TrackStatus::kHeld) << f;
      ASSERT_TRUE(r.tank.has_pose());
      EXPECT_LT(RotationDistance(*r.tank.cam_from_object, cam_from_tank),
                0.2 * kDeg);
      EXPECT_EQ(r.pen.status, TrackStatus::kLost) << f;
      EXPECT_FALSE(r.pen.has_pose());
      EXPECT_FALSE(r.tip_in_tank);
    } else {
      EXPECT_EQ(r.tank.status, TrackStatus::kLost) << f;
      EXPECT_FALSE(r.tank.has_pose());
      EXPECT_FALSE(r.pen.has_pose());
      const auto rows = tracker.ToPoseRows(r);
      EXPECT_FALSE(rows[0].cam_from_object);
    }
  }
}

// A board seen through one 22 px tag with a hidden corner (a hand over its
// margin), and a hand's edge pulling a second corner by 0.8 cells: three
// corners fit a pose exactly whatever their errors, so neither the RMS
// bound nor the single tag's square test can catch it, and the pose is off
// by degrees. The tracker holds the last pose instead of reporting it; the
// same tag's four clean corners are reported.
TEST(TrackerTest, ThreeCornersAreNotReported) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  Pose cam_from_tank = BoardView();
  cam_from_tank.translation *= 1.3;
  const TagPlacement& tag = rig.tank_tags[0];
  std::mt19937 rng(9);
  double min_deg = 180;
  int held = 0, tracked_four = 0;
  constexpr int kTrials = 20;
  for (int trial = 0; trial < kTrials; ++trial) {
    Tracker tracker(camera, rig, TrackerOptions{});
    const FrameResult first = tracker.TrackDetections(
        testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank, 0.2,
                                   &rng),
        0.0);
    ASSERT_EQ(first.tank.status, TrackStatus::kTracked);
    const std::vector<TagDetection> one =
        testing::ProjectDetections(camera, {tag}, cam_from_tank, 0.2, &rng);
    ASSERT_EQ(one.size(), 1u);
    ASSERT_NEAR(one[0].SizePx(), 22, 3);
    std::vector<TagDetection> three = one;
    three[0].corner_occluded[1] = true;
    auto& c = three[0].corners;
    c[0] += 0.1 * (c[3] - c[0]);
    ObjectPose pose;
    ASSERT_TRUE(EstimateObjectPose(
        PoseEstimatorOptions{}, camera,
        MatchObservations(camera, rig.tank_tags, three), {}, &pose));
    EXPECT_LT(pose.rmse_px, 1e-3) << "an exact fit: nothing to check";
    min_deg = std::min(
        min_deg, RotationDistance(pose.cam_from_object, cam_from_tank) / kDeg);
    const FrameResult r = tracker.TrackDetections(three, 1 / kFps);
    held += r.tank.status == TrackStatus::kHeld;
    if (r.tank.has_pose()) {
      EXPECT_LT(RotationDistance(*r.tank.cam_from_object, cam_from_tank),
                0.5 * kDeg)
          << trial;
    }
    tracked_four += tracker.TrackDetections(one, 2 / kFps).tank.status ==
                    TrackStatus::kTracked;
  }
  std::printf(
      "three corners, one pulled 0.8 cells: rotation error >= %.1f "
      "deg; held %d of %d\n",
      min_deg, held, kTrials);
  EXPECT_GT(min_deg, 4.0);
  EXPECT_EQ(held, kTrials);
  EXPECT_EQ(tracked_four, kTrials);
}

TEST(TrackerTest, PartlyOccludedBoardStaysAccurate) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  Tracker tracker(camera, rig, TrackerOptions{});
  std::mt19937 rng(7);
  const Pose truth = BoardView();
  for (int keep = 10; keep >= 1; --keep) {
    auto dets =
        testing::ProjectDetections(camera, rig.tank_tags, truth, 0.1, &rng);
    dets.resize(std::min<size_t>(dets.size(), keep));
    const FrameResult r = tracker.TrackDetections(dets, keep / kFps);
    ASSERT_EQ(r.tank.status, TrackStatus::kTracked);
    EXPECT_EQ(r.tank.tags.size(), dets.size());
    EXPECT_LT(RotationDistance(*r.tank.cam_from_object, truth),
              (keep > 2 ? 0.2 : 1.0) * kDeg)
        << keep << " tags";
  }
}

TEST(TrackerTest, UnknownTagsAreIgnored) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  Tracker tracker(camera, rig, TrackerOptions{});
  TagDetection stray;
  stray.id = 200;
  stray.corners = {Eigen::Vector2d(10, 10), Eigen::Vector2d(40, 10),
                   Eigen::Vector2d(40, 40), Eigen::Vector2d(10, 40)};
  const FrameResult r = tracker.TrackDetections({stray}, 0.0);
  EXPECT_EQ(r.tank.status, TrackStatus::kLost);
  EXPECT_EQ(r.pen.status, TrackStatus::kLost);
}

TEST(TrackerTest, RegionSearchOnRenderedFrames) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  auto family = TagFamily::Create(rig.family);
  TrackerOptions roi_options, full_options;
  roi_options.roi.full_search_period = 4;
  full_options.roi.enabled = false;
  Tracker roi(camera, rig, roi_options), full(camera, rig, full_options);
  int roi_frames = 0;
  for (int f = 0; f < 8; ++f) {
    const Pose cam_from_tank = BoardView(0.01 * f);
    const Pose cam_from_pen = cam_from_tank * TankFromPen(f / kFps);
    auto placed = testing::PlaceObjectTags(rig.tank_tags, cam_from_tank);
    for (const auto& p : testing::PlaceObjectTags(rig.pen->faces, cam_from_pen))
      if (p.cam_from_tag.R().col(2).dot(p.cam_from_tag.translation) > 0)
        placed.push_back(p);
    const cv::Mat image = testing::RenderTags(camera, *family, placed, 3);
    const FrameResult a = roi.Track(image, f / kFps);
    const FrameResult b = full.Track(image, f / kFps);
    ASSERT_EQ(a.tank.status, TrackStatus::kTracked);
    ASSERT_EQ(b.tank.status, TrackStatus::kTracked);
    ASSERT_TRUE(a.tip_in_tank && b.tip_in_tank);
    EXPECT_EQ(a.detections.size(), b.detections.size());
    const Eigen::Vector3d tip = TankFromPen(f / kFps) * rig.pen->tip_in_pen;
    EXPECT_LT((*a.tip_in_tank - tip).norm(), 0.002);
    EXPECT_LT((*a.tip_in_tank - *b.tip_in_tank).norm(), 0.001);
    EXPECT_GT(a.timings.total_ms, 0.0);
    if (!a.timings.full_search) ++roi_frames;
  }
  EXPECT_GE(roi_frames, 4);
}

// A pen missing from one frame is looked for around its last pose in the
// next: it is found there by the region search, without waiting for the
// next whole-frame search.
TEST(TrackerTest, RegionSearchFindsAPenMissingForAFrame) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  auto family = TagFamily::Create(rig.family);
  TrackerOptions options;
  options.roi.full_search_period = 10;
  Tracker tracker(camera, rig, options);
  for (int f = 0; f < 8; ++f) {
    const Pose cam_from_tank = BoardView(0.01 * f);
    const Pose cam_from_pen = cam_from_tank * TankFromPen(f / kFps);
    auto placed = testing::PlaceObjectTags(rig.tank_tags, cam_from_tank);
    const bool hidden = f == 5;
    if (!hidden)
      for (const auto& p :
           testing::PlaceObjectTags(rig.pen->faces, cam_from_pen))
        if (p.cam_from_tag.R().col(2).dot(p.cam_from_tag.translation) > 0)
          placed.push_back(p);
    const cv::Mat image = testing::RenderTags(camera, *family, placed, 3);
    const FrameResult r = tracker.Track(image, f / kFps);
    ASSERT_EQ(r.tank.status, TrackStatus::kTracked) << f;
    if (hidden) {
      EXPECT_EQ(r.pen.status, TrackStatus::kLost);
      continue;
    }
    ASSERT_EQ(r.pen.status, TrackStatus::kTracked) << f;
    // Frame 0 searches the whole frame; the pen's loss in frame 5 does too
    // (a tracked object missing from its regions). Frame 6 need not.
    if (f == 6) {
      EXPECT_FALSE(r.timings.full_search);
    }
  }
}

TEST(TrackerTest, SmoothingLowersStaticJitterAndFollowsTheTipInTheTank) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TrackerOptions on;
  on.smoothing.enabled = true;
  TrackerOptions off = on;
  off.smoothing.enabled = false;
  Tracker smooth(camera, rig, on), raw(camera, rig, off);
  std::mt19937 rng(11);
  const Pose tank_from_pen = TankFromPen(0);
  const Eigen::Vector3d tip = tank_from_pen * rig.pen->tip_in_pen;
  double ss_on = 0, ss_off = 0;
  for (int f = 0; f < 90; ++f) {
    // The camera moves (the tank in the camera frame with it); the pen rests
    // on the board: its tip in the tank does not move.
    const Pose cam_from_tank = BoardView(0.004 * f);
    const auto dets = Concat(
        testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank, 0.05,
                                   &rng),
        testing::ProjectDetections(camera, rig.pen->faces,
                                   cam_from_tank * tank_from_pen, 0.05, &rng));
    const FrameResult a = smooth.TrackDetections(dets, f / kFps);
    const FrameResult b = raw.TrackDetections(dets, f / kFps);
    ASSERT_TRUE(a.tip_in_tank && b.tip_in_tank);
    // The reported pen pose and the tip agree.
    EXPECT_LT((a.tank.cam_from_object->Inverse() *
                   (*a.pen.cam_from_object * rig.pen->tip_in_pen) -
               *a.tip_in_tank)
                  .norm(),
              1e-9);
    if (f < 30) continue;
    ss_on += (*a.tip_in_tank - tip).squaredNorm();
    ss_off += (*b.tip_in_tank - tip).squaredNorm();
  }
  const double rms_on = std::sqrt(ss_on / 60), rms_off = std::sqrt(ss_off / 60);
  std::printf("static tip: RMS error %.3f mm raw, %.3f mm smoothed\n",
              1e3 * rms_off, 1e3 * rms_on);
  EXPECT_LT(rms_on, 0.6 * rms_off);
}

// A pen at rest that drops out of detection for a few frames comes back
// through its filter (SmoothingOptions::bridge_loss_s), not restarted at
// one raw pose; a pen that moved while hidden is reported where it is.
TEST(TrackerTest, SmoothingBridgesAShortLossOfAPenAtRest) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  const Pose cam_from_tank = BoardView();
  TrackerOptions bridged;
  TrackerOptions restarted = bridged;
  restarted.smoothing.bridge_loss_s = 0;
  for (const bool moved : {false, true}) {
    // The reported tip's jump from the last frame before the loss to the
    // first after it, over several noise draws.
    double ss_a = 0, ss_b = 0;
    constexpr int kTrials = 6;
    for (int trial = 0; trial < kTrials; ++trial) {
      Tracker a(camera, rig, bridged), b(camera, rig, restarted);
      std::mt19937 rng(13 + trial);
      Pose tank_from_pen = TankFromPen(0);
      Eigen::Vector3d before_a = Eigen::Vector3d::Zero();
      Eigen::Vector3d before_b = Eigen::Vector3d::Zero();
      for (int f = 0; f < 15; ++f) {
        // Hidden for frames 12-13; moved 5 mm meanwhile when `moved`.
        const bool hidden = f == 12 || f == 13;
        if (moved && f == 13) tank_from_pen.translation.x() += 0.005;
        std::vector<TagDetection> dets = testing::ProjectDetections(
            camera, rig.tank_tags, cam_from_tank, 0.05, &rng);
        if (!hidden)
          dets = Concat(dets, testing::ProjectDetections(
                                  camera, rig.pen->faces,
                                  cam_from_tank * tank_from_pen, 0.1, &rng));
        const FrameResult ra = a.TrackDetections(dets, f / kFps);
        const FrameResult rb = b.TrackDetections(dets, f / kFps);
        if (hidden) {
          EXPECT_FALSE(ra.pen.has_pose()) << f;  // pen_hold_s is 0
          continue;
        }
        ASSERT_TRUE(ra.tip_in_tank && rb.tip_in_tank) << f;
        if (f == 11) {
          before_a = *ra.tip_in_tank;
          before_b = *rb.tip_in_tank;
        }
        if (f < 14) continue;
        const Eigen::Vector3d tip = tank_from_pen * rig.pen->tip_in_pen;
        if (moved) {
          // Beyond the filter's 1 mm bound: reported at once, as the raw
          // pose is.
          EXPECT_LT((*ra.tip_in_tank - *rb.tip_in_tank).norm(), 1e-9);
          EXPECT_LT((*ra.tip_in_tank - tip).norm(), 1e-3);
        }
        ss_a += (*ra.tip_in_tank - before_a).squaredNorm();
        ss_b += (*rb.tip_in_tank - before_b).squaredNorm();
      }
    }
    const double jump_a = std::sqrt(ss_a / kTrials),
                 jump_b = std::sqrt(ss_b / kTrials);
    std::printf(
        "%s: the tip's jump over the loss, RMS %.3f mm bridged, %.3f mm "
        "restarted\n",
        moved ? "moved 5 mm while hidden" : "at rest", 1e3 * jump_a,
        1e3 * jump_b);
    // Measured: 0.55 mm bridged, 0.78 mm restarted. The two missing frames
    // fade the filter's memory (weight 0.25 on the new pose), and a
    // re-acquired pose beyond the 1 mm bound still restarts it.
    if (!moved) {
      EXPECT_LT(jump_a, 0.8 * jump_b);
    }
  }
}

TEST(TrackerTest, SmoothingDoesNotSmearAFastTurn) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  TrackerOptions options;
  options.smoothing.enabled = true;
  Tracker tracker(camera, rig, options);
  std::mt19937 rng(12);
  const Pose cam_from_tank = BoardView();
  for (int f = 0; f < 12; ++f) {
    // The pen turns 30 degrees at frame 6 (a genuine fast turn, beyond the
    // filter's reset bound): reported at once.
    Pose tank_from_pen = TankFromPen(0);
    if (f >= 6)
      tank_from_pen.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(
                                   30 * kDeg, Eigen::Vector3d::UnitZ())) *
                               tank_from_pen.rotation;
    const auto dets = Concat(
        testing::ProjectDetections(camera, rig.tank_tags, cam_from_tank, 0.05,
                                   &rng),
        testing::ProjectDetections(camera, rig.pen->faces,
                                   cam_from_tank * tank_from_pen, 0.05, &rng));
    const FrameResult r = tracker.TrackDetections(dets, f / kFps);
    ASSERT_EQ(r.pen.status, TrackStatus::kTracked);
    const Pose truth = cam_from_tank * tank_from_pen;
    EXPECT_LT(RotationDistance(*r.pen.cam_from_object, truth), 0.5 * kDeg)
        << "frame " << f;
  }
}

TEST(TrackerOptionsTest, Validates) {
  TrackerOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.detector.quad_decimate = 0.5;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("quad_decimate"), std::string::npos);
  options = TrackerOptions{};
  options.roi.full_search_period = 0;
  EXPECT_FALSE(options.IsValid(&error));
  options = TrackerOptions{};
  options.roi.recent_loss_s = -0.1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("recent_loss_s"), std::string::npos);
  options = TrackerOptions{};
  options.max_single_tag_rmse_cells = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_single_tag_rmse_cells"), std::string::npos);
  options = TrackerOptions{};
  options.pen_rest_iterations = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("pen_rest_iterations"), std::string::npos);
  options = TrackerOptions{};
  options.pen_rest_motion_px = NAN;
  EXPECT_FALSE(options.IsValid(&error));
  for (const double ratio : {-0.1, 1.0, double(NAN)}) {
    options = TrackerOptions{};
    options.pen_shaft_resolve_ratio = ratio;
    EXPECT_FALSE(options.IsValid(&error)) << ratio;
    EXPECT_NE(error.find("pen_shaft_resolve_ratio"), std::string::npos);
    options = TrackerOptions{};
    options.pen_shaft_turn_ratio = ratio;
    EXPECT_FALSE(options.IsValid(&error)) << ratio;
    EXPECT_NE(error.find("pen_shaft_turn_ratio"), std::string::npos);
  }
  EXPECT_EQ(ParsePenMode("best-face"), PenMode::kBestFace);
  EXPECT_FALSE(ParsePenMode("best"));
}

}  // namespace
}  // namespace ripple::tracking
