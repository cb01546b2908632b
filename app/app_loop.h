// The one frame loop of live, replay and demo (DESIGN.md, "One frame"):
//
//   source -> Pipeline::Process -> sinks (window, video, PNG, pose CSV, raw
//   recording, the command's own tables)
//
// The commands differ only in their source, their sinks and the loop hooks
// (the demo resets the water before its idle tail; live pauses, draws its
// HUD and reads keys between frames).
#ifndef RIPPLE_APP_APP_LOOP_H_
#define RIPPLE_APP_APP_LOOP_H_

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "app/app_pipeline.h"
#include "app/app_source.h"

namespace ripple::app {

// A frame read from a source, with the time the read took.
struct SourceFrame {
  cv::Mat bgr;
  double time_s = 0;  // the source's timestamp, seconds
  double cap_ms = 0;  // reading / decoding / synthesising it, milliseconds
};

// Reads the next frame of `source` into `frame`, timing the read; false at
// the end of the input or on a read failure (source->error()).
bool ReadSourceFrame(FrameSource* source, SourceFrame* frame);

// One processed frame as the sinks see it.
struct LoopFrame {
  int index = 0;  // 0-based among the frames processed
  const SourceFrame* input = nullptr;
  const FrameReport* report = nullptr;
  // composite() holds the finished frame when some sink wanted it read back.
  Pipeline* pipeline = nullptr;
};

// Why a loop ended before its source did: a sink's failure (exit_code
// kExitRuntime or kExitBadInput, with the one-line message) or a normal stop
// (kExitOk: the window was closed, the user quit).
struct LoopStop {
  int exit_code = 0;
  std::string message;
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Whether frame `index` must be read back into Pipeline::composite().
  virtual bool WantsComposite(int index) const { return false; }
  // Takes one processed frame; false ends the loop, with `stop` saying why.
  virtual bool Consume(const LoopFrame& frame, LoopStop* stop) = 0;
  // Finalizes what was written (idempotent); the loop calls it at its end,
  // whatever ended it. False, with `stop` saying why, if what was written
  // is incomplete.
  virtual bool Close(LoopStop* stop) { return true; }
};

// A sink made of a function (timing tables, counters, progress lines).
class FunctionSink : public FrameSink {
 public:
  using Function = std::function<bool(const LoopFrame&, LoopStop*)>;
  explicit FunctionSink(Function function) : function_(std::move(function)) {}
  bool Consume(const LoopFrame& frame, LoopStop* stop) override {
    return function_(frame, stop);
  }

 private:
  Function function_;
};

struct FrameLoopHooks {
  // Before frame `index` is processed.
  std::function<void(int index)> before_frame;
  // While true, no frame is read or processed; while_paused runs instead.
  std::function<bool()> paused;
  std::function<void()> while_paused;
  // Once per turn, after the sinks (or while_paused); false ends the loop.
  std::function<bool(LoopStop*)> after_turn;
};

struct FrameLoopSummary {
  int frames = 0;            // frames processed
  bool stopped = false;      // a sink or after_turn ended the loop
  LoopStop stop;             // why, when stopped
  std::string source_error;  // the source failed (the caller exits with 1)
};

// Processes `first` (already read, e.g. to size the pipeline; nullptr: the
// loop reads it) and every further frame of `source` until it ends, a sink
// or a hook stops the loop. Closes every sink before returning. With the
// pipeline's overlap_tracking and no pause hook, frame n + 1 is read
// before frame n is processed, so that its tracking overlaps n's render.
void RunFrameLoop(const FrameLoopHooks& hooks, FrameSource* source,
                  const SourceFrame* first, Pipeline* pipeline,
                  const std::vector<FrameSink*>& sinks,
                  FrameLoopSummary* summary);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_LOOP_H_
