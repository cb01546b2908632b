// `ripple eval` end to end: known errors in its table and files, synth's
// truth against track's poses, and one line with exit 2 for each kind of bad
// input.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/cli_test.h"
#include "tracking/pose_csv.h"

namespace ripple::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using tracking::Pose;
using tracking::PoseRow;

constexpr double kDeg = M_PI / 180.0;

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("ripple_eval_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// Frames 0-19 hold the scene still; from 20 the camera moves.
std::vector<PoseRow> TruthRows(int frames) {
  std::vector<PoseRow> rows;
  for (int i = 0; i < frames; ++i) {
    const double t = i < 20 ? 0 : i - 19;
    PoseRow tank;
    tank.frame = i;
    tank.time_s = i / 30.0;
    tank.object = "tank";
    tank.status = tracking::TrackStatus::kTracked;
    tank.cam_from_object =
        tracking::LookAt({0.05 * t * 0.01, -0.25, 0.35}, {0, 0, 0}, {0, 0, 1})
            .Inverse();
    tank.faces = {0, 1, 2};
    const Pose tank_from_pen(Eigen::Quaterniond::Identity(),
                             Eigen::Vector3d(0.01, 0.0, 0.17));
    PoseRow pen = tank;
    pen.object = "pen";
    pen.cam_from_object = *tank.cam_from_object * tank_from_pen;
    pen.tip_in_tank = tank_from_pen * Eigen::Vector3d(0, 0, -0.14);
    pen.faces = {10};
    rows.push_back(tank);
    rows.push_back(pen);
  }
  return rows;
}

void Write(const std::vector<PoseRow>& rows, const std::string& path) {
  tracking::PoseCsvWriter w;
  std::string error;
  ASSERT_TRUE(w.Open(path, &error)) << error;
  for (const PoseRow& r : rows) ASSERT_TRUE(w.Write(r));
  ASSERT_TRUE(w.Close());
}

int Lines(const std::string& s) {
  return static_cast<int>(std::count(s.begin(), s.end(), '\n'));
}

TEST(EvalCliTest, TableAndReportOfKnownErrors) {
  const std::string dir = TempDir("known");
  const std::vector<PoseRow> truth = TruthRows(30);
  std::vector<PoseRow> estimate = truth;
  for (PoseRow& r : estimate) {
    r.faces.clear();
    if (r.object == "tank")  // 0.5 degrees off on every frame
      r.cam_from_object =
          *r.cam_from_object * Pose(Eigen::Quaterniond(Eigen::AngleAxisd(
                                        0.5 * kDeg, Eigen::Vector3d::UnitY())),
                                    Eigen::Vector3d::Zero());
    if (r.object == "pen" && r.frame == 25)  // one flip of the pen
      r.cam_from_object =
          *r.cam_from_object * Pose(Eigen::Quaterniond(Eigen::AngleAxisd(
                                        30 * kDeg, Eigen::Vector3d::UnitX())),
                                    Eigen::Vector3d::Zero());
    if (r.object == "pen" && r.frame == 27) {  // lost
      r.status = tracking::TrackStatus::kLost;
      r.cam_from_object.reset();
      r.tip_in_tank.reset();
    }
  }
  Write(truth, dir + "/groundtruth.csv");
  Write(estimate, dir + "/theirs.csv");
  const CommandResult r =
      RunRipple("eval --truth " + dir + "/groundtruth.csv --poses " + dir +
                "/theirs.csv --out " + dir + "/report");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("30 frames (0 to 29)"));
  EXPECT_THAT(r.output, HasSubstr("| theirs.csv | 0.500 / 0.500 |"));
  EXPECT_THAT(r.output, HasSubstr("| 1 | 100.0% / 96.7% |"));  // 29 of 30
  // The first 20 frames are static: a segment for each quantity; the tank's
  // constant offset is no jitter.
  EXPECT_THAT(r.output, HasSubstr("tank 1 (20 frames), pen 1 (20 frames)"));
  EXPECT_THAT(r.output, HasSubstr("| 0.0000 / 0.0000 / 0.000 |"));

  std::ifstream frames(dir + "/report/eval_frames.csv");
  std::stringstream text;
  text << frames.rdbuf();
  EXPECT_EQ(Lines(text.str()), 31);
  EXPECT_THAT(text.str(), HasSubstr("frame,tank_rot_deg,tank_mm"));
  EXPECT_THAT(text.str(), HasSubstr("\n27,0.5,0,nan,nan,nan,0,1,0,0,0,0\n"));
  std::ifstream summary(dir + "/report/eval_summary.csv");
  std::stringstream summary_text;
  summary_text << summary.rdbuf();
  EXPECT_EQ(Lines(summary_text.str()), 2);
  EXPECT_GT(fs::file_size(dir + "/report/eval_errors.png"), 1000u);
}

TEST(EvalCliTest, SynthTruthAgainstTrackPoses) {
  const std::string dir = TempDir("synth");
  CommandResult r = RunRipple("synth --out " + dir +
                              "/seq --frames 6 --size 320x240 --preset clean");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunRipple("track --input " + dir + "/seq/frames --camera " + dir +
                "/seq/camera.yml --rig " + dir + "/seq/rig.yml --out " + dir +
                "/poses.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunRipple("eval --truth " + dir + "/seq/groundtruth.csv --poses " + dir +
                "/poses.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("6 frames (0 to 5)"));
  EXPECT_THAT(r.output, HasSubstr("| poses.csv | "));
  EXPECT_THAT(r.output, HasSubstr(" | 0 | 100.0% / "));  // no flips
  // The truth against itself: every error zero.
  r = RunRipple("eval --truth " + dir + "/seq/groundtruth.csv --poses " + dir +
                "/seq/groundtruth.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("| 0.000 / 0.000 | 0.00 / 0.00 | 0.00 / "
                                  "0.00 | 0.00 / 0.00 | 0 | 100.0% / "));
}

TEST(EvalCliTest, BadInputIsOneLineAndExit2) {
  const std::string dir = TempDir("bad");
  const std::vector<PoseRow> truth = TruthRows(5);
  Write(truth, dir + "/gt.csv");
  std::vector<PoseRow> fewer(truth.begin(), truth.end() - 2);
  Write(fewer, dir + "/fewer.csv");
  std::vector<PoseRow> more = TruthRows(6);
  Write(more, dir + "/more.csv");
  std::vector<PoseRow> tank_only;
  for (const PoseRow& row : truth)
    if (row.object == "tank") tank_only.push_back(row);
  Write(tank_only, dir + "/tank_only.csv");
  Write({}, dir + "/header_only.csv");
  std::ofstream(dir + "/empty.csv");
  {
    std::ofstream bad(dir + "/malformed.csv");
    bad << tracking::kPoseCsvHeader << "\n"
        << tracking::FormatPoseRow(truth[0]) << "\n"
        << "1,0.03,tank,tracked,0.1,abc,0.3,1,0,0,0,,,,,0,0\n";
  }
  const std::string gt = dir + "/gt.csv";
  const struct {
    std::string args, message;
  } cases[] = {
      {"--truth " + dir + "/nope.csv --poses " + gt, "cannot open file"},
      {"--truth " + gt + " --poses " + dir + "/nope.csv", "--poses"},
      {"--truth " + gt + " --poses " + dir + "/malformed.csv",
       "line 3: pose columns"},
      {"--truth " + gt + " --poses " + dir + "/fewer.csv",
       "frame 4: not in the estimates"},
      {"--truth " + gt + " --poses " + dir + "/more.csv",
       "frame 5: not in the ground truth"},
      {"--truth " + gt + " --poses " + dir + "/tank_only.csv",
       "mismatched objects"},
      {"--truth " + dir + "/empty.csv --poses " + gt, "empty file"},
      {"--truth " + gt + " --poses " + dir + "/header_only.csv",
       "no rows after the header"},
  };
  for (const auto& c : cases) {
    const CommandResult r = RunRipple("eval " + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(c.message)) << c.args;
    EXPECT_EQ(Lines(r.output), 1) << c.args << "\n" << r.output;
  }
  // Usage errors (CLI11's message and its --help hint).
  CommandResult r = RunRipple("eval --truth " + gt);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--poses is required"));
  r = RunRipple("eval --truth " + gt + " --poses " + gt + " --static-frames 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--static-frames"));
}

}  // namespace
}  // namespace ripple::testing
