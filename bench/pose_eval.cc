#include "bench/pose_eval.h"

#include <map>
#include <utility>

namespace ripple::bench {
namespace {

using tracking::PoseRow;

// Rows of one frame by object.
struct FrameRows {
  const PoseRow* tank = nullptr;
  const PoseRow* pen = nullptr;
};

bool Index(const std::vector<PoseRow>& rows, const std::string& name,
           std::map<int, FrameRows>* frames, std::string* error) {
  if (rows.empty()) {
    *error = "pose file '" + name + "': no rows after the header";
    return false;
  }
  for (const PoseRow& r : rows) {
    FrameRows& f = (*frames)[r.frame];
    const PoseRow** slot = r.object == "tank" ? &f.tank : &f.pen;
    if (*slot) {
      *error = "pose file '" + name + "' frame " + std::to_string(r.frame) +
               ": two " + r.object + " rows";
      return false;
    }
    *slot = &r;
  }
  return true;
}

}  // namespace

bool PairPoseRows(const std::vector<PoseRow>& truth,
                  const std::string& truth_name,
                  const std::vector<PoseRow>& estimate,
                  const std::string& estimate_name, PairedPoses* out,
                  std::string* error) {
  *out = PairedPoses();
  std::map<int, FrameRows> t, e;
  if (!Index(truth, truth_name, &t, error) ||
      !Index(estimate, estimate_name, &e, error))
    return false;
  auto fail = [&](const std::string& name, int frame, const std::string& what) {
    *error =
        "pose file '" + name + "' frame " + std::to_string(frame) + ": " + what;
    return false;
  };
  for (const auto& [frame, rows] : e)
    if (!t.count(frame))
      return fail(estimate_name, frame,
                  "not in the ground truth '" + truth_name + "'");
  for (const auto& [frame, rows] : t) {
    const auto it = e.find(frame);
    if (it == e.end())
      return fail(truth_name, frame,
                  "not in the estimates '" + estimate_name + "'");
    const FrameRows& est = it->second;
    if (!rows.tank) return fail(truth_name, frame, "no tank row");
    if (!rows.tank->cam_from_object)
      return fail(truth_name, frame, "the ground-truth tank row has no pose");
    if (rows.pen && (!rows.pen->cam_from_object || !rows.pen->tip_in_tank))
      return fail(truth_name, frame,
                  "the ground-truth pen row lacks its pose or tip");
    for (const char* object : {"tank", "pen"}) {
      const bool in_truth = object[0] == 't' ? rows.tank : rows.pen;
      const bool in_estimate = object[0] == 't' ? est.tank : est.pen;
      if (in_truth != in_estimate)
        return fail(in_estimate ? estimate_name : truth_name, frame,
                    std::string("has a ") + object + " row, '" +
                        (in_estimate ? truth_name : estimate_name) +
                        "' has none (mismatched objects)");
    }
    TruthFrame tf;
    tf.frame = frame;
    tf.cam_from_tank = *rows.tank->cam_from_object;
    tf.tank_visible = !rows.tank->faces.empty();
    EstimateFrame ef;
    ef.cam_from_tank = est.tank->cam_from_object;
    ef.tank_tracked = est.tank->status == tracking::TrackStatus::kTracked &&
                      ef.cam_from_tank.has_value();
    if (rows.pen) {
      tf.cam_from_pen = *rows.pen->cam_from_object;
      tf.tip_in_tank = *rows.pen->tip_in_tank;
      tf.pen_visible = !rows.pen->faces.empty();
      ef.cam_from_pen = est.pen->cam_from_object;
      ef.pen_tracked = est.pen->status == tracking::TrackStatus::kTracked &&
                       ef.cam_from_pen.has_value();
      ef.tip_in_tank = est.pen->tip_in_tank;
      if (!ef.tip_in_tank && ef.cam_from_tank && ef.cam_from_pen) {
        const Eigen::Vector3d tip_in_pen =
            tf.cam_from_pen->Inverse() * (tf.cam_from_tank * *tf.tip_in_tank);
        ef.tip_in_tank =
            ef.cam_from_tank->Inverse() * (*ef.cam_from_pen * tip_in_pen);
        ++out->derived_tips;
      }
    }
    out->truth.push_back(std::move(tf));
    out->estimates.push_back(std::move(ef));
  }
  return true;
}

}  // namespace ripple::bench
