// The tracking figures: the benchmark's median tip error against median run
// time (one numbered point per setting, log-scaled axes, a legend on the
// right), and `ripple eval`'s errors over frames.
#ifndef RIPPLE_BENCH_TRACKING_PLOT_H_
#define RIPPLE_BENCH_TRACKING_PLOT_H_

#include <memory>
#include <string>
#include <vector>

#include "bench/pose_errors.h"
#include "bench/tracking_bench.h"

namespace ripple::bench {

// Writes the PNG to `path`; nothing when no setting has both a time and a
// tip error. False when the file cannot be written.
bool PlotTipErrorAgainstTime(
    const std::vector<std::unique_ptr<TrackingSetting>>& settings,
    const std::string& title, const std::string& path);

// Errors over frames: three stacked panels (tank rotation in degrees, pen
// rotation in degrees, tip in millimetres) on log-scaled axes, one dot per
// frame with an estimate (red: a flip), a red tick under the panel where the
// truth has the quantity and the estimate not, and the static segments
// shaded. `frames` are the frame numbers of `errors`. False when the file
// cannot be written.
bool PlotErrorsOverFrames(const std::vector<int>& frames,
                          const std::vector<FrameErrors>& errors,
                          const std::vector<bool>& pen_in_truth,
                          const PoseErrorSummary& summary,
                          const std::string& title, const std::string& path);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_TRACKING_PLOT_H_
