#include "bench/tracking_bench.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>

#include "tests/shipped_data.h"

namespace ripple::bench {
namespace {

using ::testing::HasSubstr;

int CountDefaults(const std::vector<std::unique_ptr<TrackingSetting>>& s) {
  int n = 0;
  for (const auto& setting : s) n += setting->is_default();
  return n;
}

TEST(TrackingBenchTest, SweepsHaveOneDefaultAndTheBaselines) {
  const auto only = MakeTrackingSettings(Sweep::kDefault, 2);
  ASSERT_EQ(only.size(), 1u);
  EXPECT_TRUE(only[0]->is_default());
  EXPECT_THAT(only[0]->name, HasSubstr("[default]"));
  EXPECT_EQ(only[0]->options.detector.threads, 2);

  const auto short_sweep = MakeTrackingSettings(Sweep::kShort, 1);
  const auto full_sweep = MakeTrackingSettings(Sweep::kFull, 1);
  EXPECT_EQ(CountDefaults(short_sweep), 1);
  EXPECT_EQ(CountDefaults(full_sweep), 1);
  // 4 decimations x 2 refinements x 2 pen modes x 2 searches, the frontal
  // face selection and five baselines (paper, IPPE, SQPNP+LM on the
  // corrected corners, the plain SQPNP+LM at decimation 2 and 1).
  EXPECT_EQ(full_sweep.size(), 32u + 1 + 5);
  int baselines = 0;
  for (const auto& s : short_sweep) baselines += s->baseline != Baseline::kNone;
  EXPECT_EQ(baselines, 5);
  // The suspects: the default, ten changes to the corner pipeline and the
  // pose, four to the shaft step's parts, three baselines.
  const auto suspects = MakeTrackingSettings(Sweep::kSuspects, 1);
  EXPECT_EQ(CountDefaults(suspects), 1);
  EXPECT_EQ(suspects.size(), 11u + 4 + 3);
  std::set<std::string> names;
  for (const auto& s : suspects) names.insert(s->name);
  EXPECT_EQ(names.size(), suspects.size());  // every setting named apart
}

TEST(TrackingBenchTest, DefaultSettingTracksTheBenchmarkFrames) {
  const tracking::Camera camera = test_data::DefaultCamera();
  const tracking::Rig rig = test_data::DefaultRig();
  std::string error;
  TrackingBenchOptions options;
  options.sweep = Sweep::kDefault;
  options.frames = 6;
  TrackingBenchResult result;
  int progress_calls = 0;
  ASSERT_TRUE(RunTrackingBench(
      options, camera.Scaled(320, 240), rig, true,
      [&](int, int) { ++progress_calls; }, &result, &error))
      << error;
  ASSERT_EQ(result.settings.size(), 1u);
  const TrackingSetting& s = *result.settings[0];
  EXPECT_EQ(s.ms.size(), 6u);
  EXPECT_EQ(result.frame_rows.size(), 6u);
  EXPECT_EQ(progress_calls, 0);  // every 50 frames
  EXPECT_GT(s.errors.Summarize().tank_visible, 0);

  const std::string table = FormatTrackingTable(options, "320x240", result);
  EXPECT_THAT(table, HasSubstr("### 320x240, exact frames, 6 frames"));
  EXPECT_THAT(table, HasSubstr(s.name));
  std::ostringstream csv, frames;
  WriteTrackingCsvHeader(&csv);
  WriteTrackingCsvRows(options, "320x240", result, &csv);
  EXPECT_THAT(csv.str(), HasSubstr("size,frames,setting,ms_median"));
  EXPECT_THAT(csv.str(), HasSubstr("320x240,6,\"" + s.name + "\","));
  WriteTrackingFramesCsvRows("320x240", result, &frames);
  EXPECT_THAT(frames.str(), HasSubstr("320x240,0,\""));
}

// The static sequence fills the jitter columns: per static segment the
// default's tip and rotation scatter, small against the pen's size.
TEST(TrackingBenchTest, StaticFramesGiveJitterOnEveryVariant) {
  const tracking::Camera camera = test_data::DefaultCamera();
  const tracking::Rig rig = test_data::DefaultRig();
  for (const char* variant : {"exact", "webcam"}) {
    std::string error;
    TrackingBenchOptions options;
    options.sweep = Sweep::kDefault;
    options.frames = 2;
    options.static_frames = 8;
    options.variant = variant;
    TrackingBenchResult result;
    ASSERT_TRUE(
        RunTrackingBench(options, camera, rig, false, nullptr, &result, &error))
        << error;
    const TrackingSetting& s = *result.settings[0];
    EXPECT_EQ(s.ms.size(), 2u) << variant;  // static frames are not errors
    ASSERT_EQ(s.jitter_tank_rot_deg.size(), 1u) << variant;
    EXPECT_GT(s.jitter_tank_rot_deg[0], 0.0) << variant;  // noise moves it
    EXPECT_LT(s.jitter_tank_rot_deg[0], 0.5) << variant;
    const std::string table = FormatTrackingTable(options, "640x480", result);
    EXPECT_THAT(table, HasSubstr(std::string(variant) + " frames"));
  }
  TrackingBenchOptions bad;
  bad.variant = "ideal";
  TrackingBenchResult result;
  std::string error;
  EXPECT_FALSE(RunTrackingBench(bad, camera.Scaled(320, 240), rig, false,
                                nullptr, &result, &error));
  EXPECT_THAT(error, HasSubstr("ideal"));
}

}  // namespace
}  // namespace ripple::bench
