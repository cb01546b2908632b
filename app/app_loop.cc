#include "app/app_loop.h"

#include <utility>

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
  // Reading ahead: the frame after `frame`, read before `frame` is
  // processed (its own buffer: a source may reuse the last one).
  const bool overlap = pipeline->overlap_tracking() && !hooks.paused;
  SourceFrame frame, next;
  bool have_frame = true, have_next = false;
  bool tracked_ahead = false;  // `frame` was tracked during the last one
  double last_total_ms = 0;
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
      if (overlap) {
        next.bgr = cv::Mat();  // a fresh buffer, not frame's
        have_next = ReadSourceFrame(source, &next);
      }
      FrameReport report =
          pipeline->Process(frame.bgr, frame.time_s, frame.cap_ms, read_back,
                            have_next ? &next.bgr : nullptr, next.time_s);
      // A frame tracked during the last one waited for it as well (the
      // loop's own reads and sinks are not the pipeline's latency).
      if (tracked_ahead) report.times.lat += last_total_ms;
      tracked_ahead = have_next;
      last_total_ms = report.times.total;
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
    if (overlap) {
      have_frame = have_next;
      std::swap(frame, next);
    } else {
      have_frame = ReadSourceFrame(source, &frame);
    }
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
