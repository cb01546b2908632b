// The tracking benchmark's figure: median tip error against median run time,
// one numbered point per setting, log-scaled axes, a legend on the right.
#ifndef RIPPLE_BENCH_TRACKING_PLOT_H_
#define RIPPLE_BENCH_TRACKING_PLOT_H_

#include <memory>
#include <string>
#include <vector>

#include "bench/tracking_bench.h"

namespace ripple::bench {

// Writes the PNG to `path`; nothing when no setting has both a time and a
// tip error. False when the file cannot be written.
bool PlotTipErrorAgainstTime(
    const std::vector<std::unique_ptr<TrackingSetting>>& settings,
    const std::string& title, const std::string& path);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_TRACKING_PLOT_H_
