// The per-stage timing table printed at the end of live, replay and demo,
// with the columns of Tawara & Ono's Table 1: cap, det, pose, drw, sim,
// caustics, shadow, total (milliseconds; median and p95 over the frames),
// and lat. `total` is the frame loop's time per frame after capture up to a
// finished frame in memory (it excludes video encoding); `lat` is the
// latency from the end of a frame's capture to that frame finished. They
// are equal unless tracking overlaps the previous frame's render
// (PipelineOptions::overlap_tracking): then det and pose ran beside it, and
// lat grows by the time the frame waited.
#ifndef RIPPLE_BENCH_STAGE_TABLE_H_
#define RIPPLE_BENCH_STAGE_TABLE_H_

#include <string>
#include <vector>

namespace ripple::bench {

struct StageTimes {
  double cap = 0;       // capture: read / decode / synthesise the frame
  double det = 0;       // tag detection
  double pose = 0;      // pose estimation and temporal logic
  double occ = 0;       // occluder mask and clean plate
  double sim = 0;       // water simulation
  double caustics = 0;  // caustics map (0 when skipped)
  double shadow = 0;    // shadow map pass (0 when skipped)
  double drw = 0;       // uploads, main pass and readback into memory
  double total = 0;     // det + pose + sim + render + readback, wall clock
  double lat = 0;       // capture done -> frame done, wall clock
};

class StageTable {
 public:
  void Add(const StageTimes& t) { rows_.push_back(t); }
  size_t size() const { return rows_.size(); }
  // Per-stage median of the last `last` rows (all when fewer): the live
  // HUD's steady figures.
  StageTimes RecentMedian(size_t last) const;
  // A table: one row per statistic (median, p95, nearest rank), one column
  // per stage,
  // titled with `label` and the frame count.
  std::string Format(const std::string& label) const;
  // Appends rows "label,stat,cap,...,total,frames" to a CSV file.
  bool AppendCsv(const std::string& path, const std::string& label, bool header,
                 std::string* error) const;

 private:
  std::vector<StageTimes> rows_;
};

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_STAGE_TABLE_H_
