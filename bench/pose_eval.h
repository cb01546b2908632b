// Pairs a ground-truth pose CSV (`ripple synth`) with an estimate in the same
// format (`ripple track`, or any tracker that writes it) frame by frame, for
// the error statistics of bench/pose_errors.h (`ripple eval`).
#ifndef RIPPLE_BENCH_POSE_EVAL_H_
#define RIPPLE_BENCH_POSE_EVAL_H_

#include <string>
#include <vector>

#include "bench/pose_errors.h"
#include "tracking/pose_csv.h"

namespace ripple::bench {

// Truth and estimate of the same frames, in frame order.
struct PairedPoses {
  std::vector<TruthFrame> truth;
  std::vector<EstimateFrame> estimates;
  // Pen rows of the estimate without tip columns whose tip was made from
  // its tank and pen poses and the truth's tip in the pen frame.
  int derived_tips = 0;
};

// Pairs `truth` (rows read from `truth_name`) with `estimate` (from
// `estimate_name`). Both must hold the same frames with the same objects,
// each (frame, object) once; every truth row needs a pose, and a truth pen
// row its tip. In the estimate, rows that are lost (no pose) count as no
// estimate, held ones as an estimate that is not tracked. A pen row without
// the tip columns but with both poses gets the tip from them: the tip in the
// pen frame is the truth's (cam_from_pen^-1 * cam_from_tank * tip_in_tank),
// so the rig file is not needed. False with one line in `error` (naming the
// file and frame) on any mismatch.
bool PairPoseRows(const std::vector<tracking::PoseRow>& truth,
                  const std::string& truth_name,
                  const std::vector<tracking::PoseRow>& estimate,
                  const std::string& estimate_name, PairedPoses* out,
                  std::string* error);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_POSE_EVAL_H_
