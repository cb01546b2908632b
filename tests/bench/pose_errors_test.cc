// The pose error statistics on synthetic truth and estimates with known
// errors: a known rotation offset is measured exactly, a flip is counted,
// static segments are found where the truth stands still and the jitter of
// known noise comes back; and the pairing of two pose CSVs' rows.
#include "bench/pose_errors.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "bench/pose_eval.h"

namespace ripple::bench {
namespace {

using ::testing::HasSubstr;
using tracking::Pose;
constexpr double kDeg = M_PI / 180.0;

const Eigen::Vector3d kTipInPen(0, 0, 0.14);

Pose Rotation(const Eigen::Vector3d& axis, double angle_rad) {
  return Pose(
      Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, axis.normalized())),
      Eigen::Vector3d::Zero());
}

// A camera circling the board and a pen moving over it; frames in
// [still_begin, still_end) hold the whole scene still.
TruthFrame MovingTruth(int frame, int still_begin = -1, int still_end = -1) {
  const double t =
      frame >= still_begin && frame < still_end ? still_begin : frame;
  TruthFrame f;
  f.frame = frame;
  f.cam_from_tank = tracking::LookAt({0.3 * std::cos(0.01 * t),
                                      0.3 * std::sin(0.01 * t), 0.4},
                                     {0, 0, 0}, {0, 0, 1})
                        .Inverse();
  const Pose tank_from_pen(Eigen::Quaterniond(Eigen::AngleAxisd(
                               0.3 + 0.02 * t, Eigen::Vector3d::UnitX())),
                           Eigen::Vector3d(0.001 * t, -0.02, 0.15));
  f.cam_from_pen = f.cam_from_tank * tank_from_pen;
  f.tip_in_tank = tank_from_pen * kTipInPen;
  f.tank_visible = f.pen_visible = true;
  return f;
}

EstimateFrame Exact(const TruthFrame& t) {
  EstimateFrame e;
  e.cam_from_tank = t.cam_from_tank;
  e.cam_from_pen = t.cam_from_pen;
  e.tip_in_tank = t.tip_in_tank;
  e.tank_tracked = e.pen_tracked = true;
  return e;
}

TEST(PoseErrorsTest, KnownRotationAndTranslationOffsetsAreMeasuredExactly) {
  PoseErrorAccumulator acc;
  for (int i = 0; i < 50; ++i) {
    const TruthFrame t = MovingTruth(i);
    EstimateFrame e = Exact(t);
    // Tank: 0.25 degrees about a skew axis in the tank frame, no translation
    // error; pen: 2 mm along camera x, no rotation error.
    e.cam_from_tank = *e.cam_from_tank * Rotation({1, 2, 3}, 0.25 * kDeg);
    e.cam_from_pen->translation += Eigen::Vector3d(0.002, 0, 0);
    acc.Add(t, e);
  }
  const PoseErrorSummary s = acc.Summarize();
  EXPECT_NEAR(s.tank_rot_deg.median, 0.25, 1e-9);
  EXPECT_NEAR(s.tank_rot_deg.p95, 0.25, 1e-9);
  EXPECT_NEAR(s.tank_mm.median, 0.0, 1e-9);
  EXPECT_NEAR(s.pen_rot_deg.median, 0.0, 1e-6);
  EXPECT_NEAR(s.pen_mm.median, 2.0, 1e-9);
  // The tip estimate here is the exact one.
  EXPECT_NEAR(s.tip_mm.median, 0.0, 1e-9);
  EXPECT_EQ(s.flips, 0);
  EXPECT_DOUBLE_EQ(s.tank_tracked_share(), 1.0);
}

TEST(PoseErrorsTest, FlipsAreRotationErrorsOverTheThreshold) {
  PoseErrorAccumulator acc;
  const double angles_deg[] = {0.1, 9.9, 10.1, 78.0, 0.2, 180.0};
  for (int i = 0; i < 6; ++i) {
    const TruthFrame t = MovingTruth(i);
    EstimateFrame e = Exact(t);
    e.cam_from_pen =
        *e.cam_from_pen * Rotation({0, 1, 0}, angles_deg[i] * kDeg);
    const FrameErrors fe = acc.Add(t, e);
    EXPECT_NEAR(fe.pen_rot_deg, angles_deg[i], 1e-6);
    EXPECT_EQ(fe.flip, angles_deg[i] > 10) << angles_deg[i];
  }
  EXPECT_EQ(acc.Summarize().flips, 3);
  // A tank flip in a frame where the pen is fine counts too; one flip per
  // frame however many objects flipped.
  TruthFrame t = MovingTruth(6);
  EstimateFrame e = Exact(t);
  e.cam_from_tank = *e.cam_from_tank * Rotation({1, 0, 0}, 20 * kDeg);
  e.cam_from_pen = *e.cam_from_pen * Rotation({1, 0, 0}, 20 * kDeg);
  acc.Add(t, e);
  EXPECT_EQ(acc.Summarize().flips, 4);
}

TEST(PoseErrorsTest, TrackedShareCountsTrackedFramesWithTheObjectInView) {
  PoseErrorAccumulator acc;
  for (int i = 0; i < 10; ++i) {
    TruthFrame t = MovingTruth(i);
    t.pen_visible = i < 8;  // the pen leaves the view for two frames
    EstimateFrame e = Exact(t);
    e.pen_tracked = i % 2 == 0;  // held every other frame
    if (i == 3) e.tank_tracked = false, e.cam_from_tank.reset();
    acc.Add(t, e);
  }
  const PoseErrorSummary s = acc.Summarize();
  EXPECT_EQ(s.tank_visible, 10);
  EXPECT_EQ(s.tank_tracked, 9);
  EXPECT_EQ(s.pen_visible, 8);
  EXPECT_EQ(s.pen_tracked, 4);  // frames 0, 2, 4, 6
  EXPECT_DOUBLE_EQ(s.pen_tracked_share(), 0.5);
  // Frame 3 has no tank estimate: no tank error and no tip.
  EXPECT_TRUE(std::isnan(acc.frame_errors()[3].tank_rot_deg));
  EXPECT_EQ(acc.tank_rot_deg().size(), 9u);
}

TEST(PoseErrorsTest, StaticSegmentsAreFoundInTheTruth) {
  PoseErrorAccumulator acc;
  for (int i = 0; i < 200; ++i) {
    const TruthFrame t = MovingTruth(i, 60, 140);
    acc.Add(t, Exact(t));
  }
  const PoseErrorSummary s = acc.Summarize();
  ASSERT_EQ(s.tank_static.size(), 1u);
  EXPECT_EQ(s.tank_static[0].begin, 60);
  EXPECT_EQ(s.tank_static[0].end, 140);
  ASSERT_EQ(s.pen_static.size(), 1u);
  ASSERT_EQ(s.tip_static.size(), 1u);
  EXPECT_EQ(s.tip_static[0].begin, 60);
  // Exact estimates: no jitter.
  EXPECT_NEAR(s.tip_jitter_mm.std, 0.0, 1e-9);
  EXPECT_NEAR(s.pen_jitter_deg.std, 0.0, 1e-6);
  EXPECT_EQ(s.tip_jitter_mm.samples, 80);

  // A moving sequence has none, and no jitter to report.
  PoseErrorAccumulator moving;
  for (int i = 0; i < 50; ++i)
    moving.Add(MovingTruth(i), Exact(MovingTruth(i)));
  const PoseErrorSummary m = moving.Summarize();
  EXPECT_TRUE(m.tank_static.empty());
  EXPECT_TRUE(m.pen_static.empty());
  EXPECT_TRUE(std::isnan(m.tip_jitter_mm.std));
  EXPECT_EQ(m.tip_jitter_mm.segments, 0);
}

TEST(PoseErrorsTest, JitterOfKnownNoiseOnStaticSegments) {
  // Two static segments with different poses, each with a constant bias
  // (which jitter must ignore) and Gaussian noise: tip sigma 0.05 mm per
  // axis (3-D spread 0.05 * sqrt(3) mm), pen rotation sigma 0.01 degrees
  // per axis of the rotation vector (angle spread 0.01 * sqrt(3) degrees).
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 1);
  const double tip_sigma_m = 0.05e-3, rot_sigma = 0.01 * kDeg;
  PoseErrorAccumulator acc;
  for (int i = 0; i < 2000; ++i) {
    // Frames 0-999 still at frame 0's pose, 1000-1999 at frame 1000's.
    const TruthFrame t =
        MovingTruth(i, i < 1000 ? 0 : 1000, i < 1000 ? 1000 : 2000);
    EstimateFrame e = Exact(t);
    const Eigen::Vector3d bias(0.001, -0.002, 0.0005);
    *e.tip_in_tank +=
        bias +
        tip_sigma_m * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const Eigen::Vector3d w =
        rot_sigma * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    e.cam_from_pen =
        *e.cam_from_pen * Rotation({0, 0, 1}, 2 * kDeg) * Rotation(w, w.norm());
    acc.Add(t, e);
  }
  const PoseErrorSummary s = acc.Summarize();
  ASSERT_EQ(s.tip_static.size(), 2u);
  EXPECT_EQ(s.tip_jitter_mm.segments, 2);
  EXPECT_EQ(s.tip_jitter_mm.samples, 2000);
  // 1998 degrees of freedom x 3 axes: the spread's relative standard error
  // is about 1 / sqrt(2 * 5994) = 0.9 %.
  EXPECT_NEAR(s.tip_jitter_mm.std, 0.05 * std::sqrt(3.0), 0.04 * 0.0866);
  EXPECT_NEAR(s.pen_jitter_deg.std, 0.01 * std::sqrt(3.0), 0.04 * 0.0173);
  // The bias is an error, not jitter.
  EXPECT_NEAR(s.tip_mm.median,
              1000 * Eigen::Vector3d(0.001, -0.002, 0.0005).norm(), 0.05);
  EXPECT_NEAR(s.pen_rot_deg.median, 2.0, 0.05);
  // The tank was estimated exactly.
  EXPECT_NEAR(s.tank_jitter_deg.std, 0.0, 1e-6);
}

TEST(PoseErrorsTest, TableAndCsvCells) {
  PoseErrorAccumulator acc;
  const TruthFrame t = MovingTruth(0);
  EstimateFrame e = Exact(t);
  e.cam_from_pen.reset();
  e.tip_in_tank.reset();
  e.pen_tracked = false;
  acc.Add(t, e);
  const PoseErrorSummary s = acc.Summarize();
  const std::string cells = ErrorTableCells(s);
  EXPECT_THAT(cells, HasSubstr("| 0.000 / 0.000 |"));
  EXPECT_THAT(cells, HasSubstr("| - / - |"));  // pen never estimated
  EXPECT_THAT(cells, HasSubstr("| 100.0% / 0.0% |"));
  EXPECT_THAT(cells, HasSubstr("- / - / -"));  // no static segments
  // Header and cells have the same number of columns.
  auto count = [](const std::string& x) {
    return std::count(x.begin(), x.end(), '|');
  };
  EXPECT_EQ(count(ErrorTableHeaderCells()), count(cells));
  EXPECT_EQ(count(ErrorTableSeparatorCells()), count(cells));
  const std::string header = ErrorCsvHeader(), fields = ErrorCsvFields(s);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','),
            std::count(fields.begin(), fields.end(), ','));
}

// Pose CSV rows of a truth frame, or of an estimate of it.
std::vector<tracking::PoseRow> Rows(const TruthFrame& t, bool truth,
                                    bool with_tip = true) {
  tracking::PoseRow tank;
  tank.frame = t.frame;
  tank.object = "tank";
  tank.status = tracking::TrackStatus::kTracked;
  tank.cam_from_object = t.cam_from_tank;
  if (truth) tank.faces = {1, 2};
  tracking::PoseRow pen = tank;
  pen.object = "pen";
  pen.cam_from_object = t.cam_from_pen;
  if (with_tip) pen.tip_in_tank = t.tip_in_tank;
  return {tank, pen};
}

TEST(PoseEvalTest, PairsFramesAndDerivesMissingTips) {
  std::vector<tracking::PoseRow> truth, estimate;
  for (int i = 0; i < 5; ++i) {
    const auto t = Rows(MovingTruth(i), true);
    truth.insert(truth.end(), t.begin(), t.end());
    const auto e = Rows(MovingTruth(i), false, /*with_tip=*/false);
    estimate.insert(estimate.end(), e.rbegin(), e.rend());  // pen first
  }
  estimate[2].status = tracking::TrackStatus::kHeld;  // frame 1's pen
  PairedPoses pairs;
  std::string error;
  ASSERT_TRUE(
      PairPoseRows(truth, "gt.csv", estimate, "est.csv", &pairs, &error))
      << error;
  ASSERT_EQ(pairs.truth.size(), 5u);
  EXPECT_EQ(pairs.derived_tips, 5);
  EXPECT_TRUE(pairs.truth[0].tank_visible);
  EXPECT_FALSE(pairs.estimates[1].pen_tracked);
  EXPECT_TRUE(pairs.estimates[2].pen_tracked);
  for (size_t i = 0; i < 5; ++i) {
    ASSERT_TRUE(pairs.estimates[i].tip_in_tank);
    EXPECT_NEAR(
        (*pairs.estimates[i].tip_in_tank - *pairs.truth[i].tip_in_tank).norm(),
        0, 1e-12);
  }
}

TEST(PoseEvalTest, MismatchesAreOneLineErrors) {
  std::vector<tracking::PoseRow> truth;
  for (int i = 0; i < 3; ++i) {
    const auto t = Rows(MovingTruth(i), true);
    truth.insert(truth.end(), t.begin(), t.end());
  }
  PairedPoses pairs;
  std::string error;
  auto fails = [&](std::vector<tracking::PoseRow> t,
                   std::vector<tracking::PoseRow> e) {
    error.clear();
    return !PairPoseRows(t, "gt.csv", e, "est.csv", &pairs, &error);
  };
  // A frame only in the truth, then only in the estimates.
  std::vector<tracking::PoseRow> short_estimate(truth.begin(), truth.end() - 2);
  EXPECT_TRUE(fails(truth, short_estimate));
  EXPECT_THAT(error, HasSubstr("'gt.csv' frame 2: not in the estimates"));
  std::vector<tracking::PoseRow> long_estimate = truth;
  for (auto r : Rows(MovingTruth(3), false)) long_estimate.push_back(r);
  EXPECT_TRUE(fails(truth, long_estimate));
  EXPECT_THAT(error, HasSubstr("'est.csv' frame 3: not in the ground truth"));
  // A pen row where the truth has none.
  std::vector<tracking::PoseRow> no_pen_truth = truth;
  no_pen_truth.erase(no_pen_truth.begin() + 1);
  EXPECT_TRUE(fails(no_pen_truth, truth));
  EXPECT_THAT(error, HasSubstr("mismatched objects"));
  // Duplicates, empty files, truth without poses.
  std::vector<tracking::PoseRow> dup = truth;
  dup.push_back(truth[0]);
  EXPECT_TRUE(fails(truth, dup));
  EXPECT_THAT(error, HasSubstr("frame 0: two tank rows"));
  EXPECT_TRUE(fails({}, truth));
  EXPECT_THAT(error, HasSubstr("'gt.csv': no rows"));
  std::vector<tracking::PoseRow> lost_truth = truth;
  lost_truth[2].cam_from_object.reset();
  EXPECT_TRUE(fails(lost_truth, truth));
  EXPECT_THAT(error,
              HasSubstr("frame 1: the ground-truth tank row has no pose"));
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace ripple::bench
