// The interactive side of `ripple live`: one key table (key, help text,
// action) that both handles the keys and prints the help, the HUD, the
// composite and raw recordings, and the loop hooks and sink that plug the
// session into the frame loop (app/app_loop.h).
#ifndef RIPPLE_APP_APP_LIVE_SESSION_H_
#define RIPPLE_APP_APP_LIVE_SESSION_H_

#include <functional>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "app/app_loop.h"
#include "app/app_pipeline.h"
#include "app/app_sinks.h"
#include "bench/stage_table.h"
#include "bench/stats.h"

namespace ripple::app {

struct LiveSessionOptions {
  std::string out_dir = ".";   // screenshots and recordings started by keys
  double fps = 30;             // frame rate of composite recordings
  cv::Size frame_size;         // camera frames, pixels
  double hud_period_s = 0.25;  // HUD redrawn this often, seconds
  int hud_frames = 30;         // HUD figures: median of the last frames
};

// One row of the key table.
struct KeyBinding {
  std::vector<int> keys;  // the keys (ASCII; 27 is Esc)
  std::string help;       // what they do, for the help lines
  std::function<void(int key)> action;
};

class LiveSession : public FrameSink {
 public:
  // `pipeline` outlives the session. `raw` is the raw recording sink (opened
  // by --record-raw or the `k` key).
  LiveSession(const LiveSessionOptions& options, Pipeline* pipeline,
              RawSink* raw);

  const std::vector<KeyBinding>& keys() const { return keys_; }
  // "h  this help", "v/V  viscosity down/up", ...: one line per binding.
  std::vector<std::string> HelpLines() const;
  // Runs the binding of `key`; false when no binding has it.
  bool HandleKey(int key);

  // The loop's hooks: pause, event polling while paused, and once per turn
  // the HUD, Present() and the keys; the turn hook ends the loop on quit or
  // when the window is closed.
  FrameLoopHooks Hooks();
  // The sinks in loop order: the session itself (stage table, HUD figures,
  // video-only frames when the tank is not seen), raw recording, composite
  // recording.
  std::vector<FrameSink*> Sinks();

  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
  const bench::StageTable& table() const { return table_; }
  VideoSink& video() { return video_; }

  // The HUD's text lines (status, stage medians, water, effects, help).
  std::vector<std::string> HudLines() const;

 private:
  void BuildKeyTable();
  void ChangeWater(const std::function<void(sim::WaterModelOptions*)>& change);
  void AddObstacle();
  void Screenshot();
  void ToggleVideo();
  void ToggleRaw();
  void UpdateHud();
  bool Turn(LoopStop* stop);

  LiveSessionOptions options_;
  Pipeline* pipeline_;
  RawSink* raw_;
  VideoSink video_;
  std::vector<KeyBinding> keys_;
  bench::StageTable table_;
  std::vector<double> frame_times_s_;  // the last hud_frames frames' times
  FrameReport last_;
  bool paused_ = false, help_ = false, quit_ = false;
  int shots_ = 0, videos_ = 0, raws_ = 0;
  std::string status_line_;
  std::mt19937 rng_{1};
  bench::Stopwatch hud_clock_;
  bool hud_drawn_ = false;
};

// HUD drawing: BGRA lines of white text on translucent black, each line
// fitting `max_width_px` (a line too wide is broken at spaces).
std::vector<std::string> FitHudLines(const std::vector<std::string>& lines,
                                     int max_width_px);
cv::Mat DrawHud(const std::vector<std::string>& lines, int max_width_px);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_LIVE_SESSION_H_
