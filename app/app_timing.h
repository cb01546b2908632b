// The per-stage timing table printed at the end of live, replay and demo,
// with the columns of Tawara & Ono's Table 1: cap, det, pose, drw, sim,
// caustics, shadow, total (milliseconds; median and p95 over the frames).
// `total` is everything after capture up to a finished frame in memory; it
// excludes video encoding.
#ifndef RIPPLE_APP_APP_TIMING_H_
#define RIPPLE_APP_APP_TIMING_H_

#include <string>
#include <vector>

namespace ripple::app {

struct StageTimes {
  double cap = 0;       // capture: read / decode / synthesise the frame
  double det = 0;       // tag detection
  double pose = 0;      // pose estimation and temporal logic
  double sim = 0;       // water simulation
  double caustics = 0;  // caustics map (0 when skipped)
  double shadow = 0;    // shadow map pass (0 when skipped)
  double drw = 0;       // uploads, main pass and readback into memory
  double total = 0;     // det + pose + sim + render + readback, wall clock
};

class StageTable {
 public:
  void Add(const StageTimes& t) { rows_.push_back(t); }
  size_t size() const { return rows_.size(); }
  // A table: one row per statistic (median, p95), one column per stage,
  // titled with `label` and the frame count.
  std::string Format(const std::string& label) const;
  // Appends rows "label,stat,cap,...,total,frames" to a CSV file.
  bool AppendCsv(const std::string& path, const std::string& label, bool header,
                 std::string* error) const;

 private:
  std::vector<StageTimes> rows_;
};

// Median and p95 (nearest rank) of a sample; 0 for an empty one.
double Percentile(std::vector<double> v, double p);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_TIMING_H_
