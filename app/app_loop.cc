#include "app/app_loop.h"

#include "bench/stats.h"

namespace ripple::app {

bool ReadSourceFrame(FrameSource* source, SourceFrame* frame) {
  const bench::Stopwatch watch;
  const bool ok = source->Read(&frame->bgr, &frame->time_s);
  frame->cap_ms = watch.ElapsedMs();
  return ok;
}

void RunFrameLoop(const FrameLoopHooks& hooks, FrameSource* source,
                  const SourceFrame* first, Pipeline* pipeline,
                  const std::vector<FrameSink*>& sinks,
                  FrameLoopSummary* summary) {
  *summary = FrameLoopSummary();
  SourceFrame frame;
  bool have_frame = true;
  if (first) {
    frame = *first;
  } else {
    have_frame = ReadSourceFrame(source, &frame);
  }
  while (have_frame) {
    const bool paused = hooks.paused && hooks.paused();
    if (!paused) {
      const int index = summary->frames;
      if (hooks.before_frame) hooks.before_frame(index);
      bool read_back = false;
      for (const FrameSink* sink : sinks)
        read_back = read_back || sink->WantsComposite(index);
      const FrameReport report =
          pipeline->Process(frame.bgr, frame.time_s, frame.cap_ms, read_back);
      ++summary->frames;
      LoopFrame loop_frame;
      loop_frame.index = index;
      loop_frame.input = &frame;
      loop_frame.report = &report;
      loop_frame.pipeline = pipeline;
      for (FrameSink* sink : sinks) {
        if (!sink->Consume(loop_frame, &summary->stop)) {
          summary->stopped = true;
          break;
        }
      }
      if (summary->stopped) break;
    } else if (hooks.while_paused) {
      hooks.while_paused();
    }
    if (hooks.after_turn && !hooks.after_turn(&summary->stop)) {
      summary->stopped = true;
      break;
    }
    if (hooks.paused && hooks.paused()) continue;
    have_frame = ReadSourceFrame(source, &frame);
  }
  if (!summary->stopped) summary->source_error = source->error();
  for (FrameSink* sink : sinks) {
    LoopStop close_stop;
    if (!sink->Close(&close_stop) && !summary->stopped) {
      summary->stopped = true;
      summary->stop = close_stop;
    }
  }
}

}  // namespace ripple::app
