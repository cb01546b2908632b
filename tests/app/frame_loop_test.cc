// The frame loop on a scripted source: every frame reaches every sink in
// order, sinks are asked about read-back and closed however the loop ends,
// and a sink, a hook or the source can end it. Also the pipeline's options
// that follow the camera's size.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "app/app_loop.h"
#include "app/app_synth_source.h"
#include "tests/shipped_data.h"

namespace ripple::app {
namespace {

using ::testing::ElementsAre;

// `frames` grey frames 1/30 s apart; fails after them when `fail` is set.
class ScriptedSource : public FrameSource {
 public:
  ScriptedSource(cv::Size size, int frames, bool fail)
      : FrameSource(Kind::kSynthetic, "scripted"),
        frames_(frames),
        fail_(fail) {
    size_ = size;
  }
  bool Read(cv::Mat* bgr, double* time_s) override {
    if (frames_read_ == frames_) {
      if (fail_) error_ = "scripted failure";
      return false;
    }
    *bgr = cv::Mat(size_, CV_8UC3, cv::Scalar(128, 128, 128));
    *time_s = frames_read_ / 30.0;
    ++frames_read_;
    return true;
  }

 private:
  int frames_;
  bool fail_;
};

// Records what it saw; stops the loop at frame `stop_at` (-1: never).
class RecordingSink : public FrameSink {
 public:
  explicit RecordingSink(int stop_at = -1) : stop_at_(stop_at) {}
  bool WantsComposite(int index) const override { return index == 1; }
  bool Consume(const LoopFrame& frame, LoopStop* stop) override {
    indices.push_back(frame.index);
    times.push_back(frame.input->time_s);
    if (frame.index == stop_at_) {
      stop->exit_code = 1;
      stop->message = "stopped";
      return false;
    }
    return true;
  }
  bool Close(LoopStop*) override {
    ++closed;
    return true;
  }
  std::vector<int> indices;
  std::vector<double> times;
  int closed = 0;

 private:
  int stop_at_;
};

class FrameLoopTest : public ::testing::Test {
 protected:
  void SetUp() override {
    camera_ = test_data::DefaultCamera().Scaled(160, 120);
    PipelineOptions options;
    options.backend = render::Backend::kEgl;
    std::string error;
    pipeline_ =
        Pipeline::Create(camera_, test_data::DefaultRig(), options, &error);
    if (!pipeline_) GTEST_SKIP() << "no headless GL context: " << error;
  }
  cv::Size size() const { return {camera_.width, camera_.height}; }
  tracking::Camera camera_;
  std::unique_ptr<Pipeline> pipeline_;
};

TEST_F(FrameLoopTest, EveryFrameReachesEverySinkAndSinksAreClosed) {
  ScriptedSource source(size(), 4, false);
  RecordingSink a, b;
  std::vector<int> before;
  FrameLoopHooks hooks;
  hooks.before_frame = [&](int index) { before.push_back(index); };
  FrameLoopSummary summary;
  RunFrameLoop(hooks, &source, nullptr, pipeline_.get(), {&a, &b}, &summary);
  EXPECT_EQ(summary.frames, 4);
  EXPECT_FALSE(summary.stopped);
  EXPECT_TRUE(summary.source_error.empty());
  EXPECT_THAT(a.indices, ElementsAre(0, 1, 2, 3));
  EXPECT_THAT(b.indices, ElementsAre(0, 1, 2, 3));
  EXPECT_THAT(before, ElementsAre(0, 1, 2, 3));
  EXPECT_DOUBLE_EQ(a.times[3], 3 / 30.0);
  EXPECT_EQ(a.closed, 1);
  EXPECT_EQ(b.closed, 1);
}

TEST_F(FrameLoopTest, AFirstFrameReadBeforeTheLoopIsProcessedFirst) {
  ScriptedSource source(size(), 3, false);
  SourceFrame first;
  ASSERT_TRUE(ReadSourceFrame(&source, &first));
  EXPECT_GE(first.cap_ms, 0.0);
  RecordingSink sink;
  FrameLoopSummary summary;
  RunFrameLoop(FrameLoopHooks(), &source, &first, pipeline_.get(), {&sink},
               &summary);
  EXPECT_EQ(summary.frames, 3);
  EXPECT_THAT(sink.times, ElementsAre(0.0, 1 / 30.0, 2 / 30.0));
}

TEST_F(FrameLoopTest, ASinkStopsTheLoopAndLaterSinksMissThatFrame) {
  ScriptedSource source(size(), 10, true);
  RecordingSink stopper(2), after;
  FrameLoopSummary summary;
  RunFrameLoop(FrameLoopHooks(), &source, nullptr, pipeline_.get(),
               {&stopper, &after}, &summary);
  EXPECT_TRUE(summary.stopped);
  EXPECT_EQ(summary.stop.exit_code, 1);
  EXPECT_EQ(summary.stop.message, "stopped");
  EXPECT_TRUE(summary.source_error.empty());  // it never got there
  EXPECT_THAT(after.indices, ElementsAre(0, 1));
  EXPECT_EQ(after.closed, 1);
}

TEST_F(FrameLoopTest, SourceFailureIsReportedAfterTheFramesBeforeIt) {
  ScriptedSource source(size(), 2, true);
  RecordingSink sink;
  FrameLoopSummary summary;
  RunFrameLoop(FrameLoopHooks(), &source, nullptr, pipeline_.get(), {&sink},
               &summary);
  EXPECT_EQ(summary.frames, 2);
  EXPECT_EQ(summary.source_error, "scripted failure");
  EXPECT_EQ(sink.closed, 1);
}

// The tank's shadow on the board follows the camera's width unless the
// options set it: on up to 640 columns, off above (where it would cost the
// frame more than its budget leaves), on at any width when asked for.
TEST(PipelineOptionsTest, TheTanksShadowFollowsTheCamerasWidth) {
  const tracking::Rig rig = test_data::DefaultRig();
  std::string error;
  auto shadow_at = [&](int width, int height, bool by_resolution,
                       bool on) -> std::optional<bool> {
    PipelineOptions options;
    options.backend = render::Backend::kEgl;
    options.tank_shadow_by_resolution = by_resolution;
    options.effects.tank_shadow = on;
    auto p = Pipeline::Create(test_data::DefaultCamera().Scaled(width, height),
                              rig, options, &error);
    if (!p) return std::nullopt;
    return p->effects().tank_shadow;
  };
  // Whether a pipeline (a headless GL context) can be made at all.
  const auto vga = shadow_at(640, 480, true, false);
  if (!vga) GTEST_SKIP() << "no headless GL context: " << error;
  EXPECT_TRUE(*vga);
  EXPECT_EQ(shadow_at(1280, 720, true, true), std::optional<bool>(false));
  EXPECT_EQ(shadow_at(1280, 720, false, true), std::optional<bool>(true));
  EXPECT_EQ(shadow_at(640, 480, false, false), std::optional<bool>(false));
}

// Tracking frame n + 1 and advancing its water beside frame n's render
// changes nothing but the timing: the same poses, the same water and the
// same composites as doing each frame's work in turn, and each frame's
// latency adds the frame it was tracked during.
TEST(FrameLoopOverlapTest, SameFramesAsTrackingEachFrameFirst) {
  const tracking::Camera camera = test_data::DefaultCamera().Scaled(320, 240);
  const tracking::Rig rig = test_data::DefaultRig();
  synth::SequenceOptions seq;
  seq.preset = "demo";
  seq.frames = 12;
  std::vector<synth::FrameSpec> specs;
  std::string error;
  ASSERT_TRUE(synth::MakeSequence(camera, rig, seq, &specs, &error)) << error;
  struct Run {
    std::vector<tracking::FrameResult> tracking;
    std::vector<cv::Mat> composites;
    std::vector<bench::StageTimes> times;
    std::vector<sim::AdvanceStats> water;
    int prepared = 0;  // frames whose real objects and caustics were ahead
  };
  // Whether a pipeline (a headless GL context) can be made at all.
  {
    PipelineOptions options;
    options.backend = render::Backend::kEgl;
    std::string error;
    if (!Pipeline::Create(camera, rig, options, &error))
      GTEST_SKIP() << "no headless GL context: " << error;
  }
  auto run = [&](bool overlap, bool ahead, Run* out) {
    PipelineOptions options;
    options.backend = render::Backend::kEgl;
    options.overlap_tracking = overlap;
    options.prepare_ahead = ahead;
    // The light estimate runs on its own schedule: fixed here.
    options.fixed_light = Eigen::Vector3d(0.3, 0.2, 0.9).normalized();
    std::string error;
    auto pipeline = Pipeline::Create(camera, rig, options, &error);
    EXPECT_NE(pipeline, nullptr) << error;
    if (!pipeline) return false;
    SynthSource source(camera, rig, specs);
    FunctionSink sink([&](const LoopFrame& f, LoopStop*) {
      out->tracking.push_back(f.report->tracking);
      out->composites.push_back(f.pipeline->composite().clone());
      out->times.push_back(f.report->times);
      out->water.push_back(f.report->water);
      out->prepared += f.report->prepared_ahead;
      return true;
    });
    struct ReadBack : FrameSink {
      bool WantsComposite(int) const override { return true; }
      bool Consume(const LoopFrame&, LoopStop*) override { return true; }
    } read_back;
    FrameLoopSummary summary;
    RunFrameLoop(FrameLoopHooks(), &source, nullptr, pipeline.get(),
                 {&read_back, &sink}, &summary);
    return summary.frames == seq.frames && !summary.stopped;
  };
  Run first;
  ASSERT_TRUE(run(false, true, &first));
  EXPECT_EQ(first.prepared, 0);
  // The next frame's real objects and caustics prepared beside the render
  // (every frame after the first) or at each frame's start.
  for (const bool ahead : {true, false}) {
    SCOPED_TRACE(ahead);
    Run beside;
    ASSERT_TRUE(run(true, ahead, &beside));
    EXPECT_EQ(beside.prepared, ahead ? seq.frames - 1 : 0);
    int tracked = 0, pushed = 0;
    for (int i = 0; i < seq.frames; ++i) {
      SCOPED_TRACE(i);
      const tracking::FrameResult &a = first.tracking[i],
                                  &b = beside.tracking[i];
      ASSERT_EQ(a.tank.has_pose(), b.tank.has_pose());
      ASSERT_EQ(a.pen.has_pose(), b.pen.has_pose());
      if (a.tank.has_pose()) {
        EXPECT_EQ(a.tank.cam_from_object->translation,
                  b.tank.cam_from_object->translation);
        ++tracked;
      }
      if (a.pen.has_pose()) {
        EXPECT_EQ(a.pen.cam_from_object->translation,
                  b.pen.cam_from_object->translation);
      }
      const sim::AdvanceStats &wa = first.water[i], &wb = beside.water[i];
      EXPECT_EQ(wa.counter, wb.counter);
      EXPECT_EQ(wa.pen_touched, wb.pen_touched);
      EXPECT_EQ(wa.volume_m3, wb.volume_m3);
      EXPECT_EQ(wa.max_abs_height_m, wb.max_abs_height_m);
      if (wa.pen_touched) ++pushed;
      EXPECT_EQ(
          cv::norm(first.composites[i], beside.composites[i], cv::NORM_INF),
          0.0);
      EXPECT_DOUBLE_EQ(first.times[i].lat, first.times[i].total);
      const double before = i > 0 ? beside.times[i - 1].total : 0.0;
      EXPECT_DOUBLE_EQ(beside.times[i].lat, beside.times[i].total + before);
    }
    EXPECT_GT(tracked, seq.frames / 2);
    // The water's step is compared with the pen in it.
    EXPECT_GT(pushed, 0);
  }
}

// The detector's decimation follows the webcam's mode.
TEST(QuadDecimateTest, OneStepPer240RowsNeverBelowTheSetting) {
  EXPECT_EQ(QuadDecimateForHeight(480, 2.0), 2.0);
  EXPECT_EQ(QuadDecimateForHeight(720, 2.0), 3.0);
  EXPECT_EQ(QuadDecimateForHeight(1080, 2.0), 4.0);
  EXPECT_EQ(QuadDecimateForHeight(240, 2.0), 2.0);
  EXPECT_EQ(QuadDecimateForHeight(120, 1.0), 1.0);
  EXPECT_EQ(QuadDecimateForHeight(720, 1.5), 3.0);
  EXPECT_EQ(QuadDecimateForHeight(100000, 2.0), 8.0);
}

TEST_F(FrameLoopTest, PausedTurnsNeitherReadNorProcess) {
  ScriptedSource source(size(), 3, false);
  RecordingSink sink;
  int turns = 0, idle = 0;
  FrameLoopHooks hooks;
  // Paused for turns 2 to 4 (after the first frame).
  hooks.paused = [&] { return turns >= 1 && turns < 4; };
  hooks.while_paused = [&] { ++idle; };
  hooks.after_turn = [&](LoopStop*) {
    ++turns;
    return true;
  };
  FrameLoopSummary summary;
  RunFrameLoop(hooks, &source, nullptr, pipeline_.get(), {&sink}, &summary);
  EXPECT_EQ(summary.frames, 3);
  EXPECT_EQ(idle, 3);
  EXPECT_EQ(turns, 6);
  EXPECT_THAT(sink.indices, ElementsAre(0, 1, 2));
}

TEST_F(FrameLoopTest, AfterTurnEndsTheLoop) {
  ScriptedSource source(size(), 10, false);
  RecordingSink sink;
  FrameLoopHooks hooks;
  hooks.after_turn = [&](LoopStop*) { return sink.indices.size() < 2; };
  FrameLoopSummary summary;
  RunFrameLoop(hooks, &source, nullptr, pipeline_.get(), {&sink}, &summary);
  EXPECT_TRUE(summary.stopped);
  EXPECT_EQ(summary.stop.exit_code, 0);
  EXPECT_EQ(summary.frames, 2);
}

}  // namespace
}  // namespace ripple::app
