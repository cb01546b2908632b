// What the tracker reports per frame and per object (tracking/tracker.h):
// the track status, the object's pose and quality, stage timings.
#ifndef RIPPLE_TRACKING_TRACK_RESULT_H_
#define RIPPLE_TRACKING_TRACK_RESULT_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "tracking/pose.h"
#include "tracking/tag_detector.h"
#include "tracking/track_status.h"

namespace ripple::tracking {

struct ObjectTrack {
  TrackStatus status = TrackStatus::kLost;
  std::optional<Pose> cam_from_object;  // set iff tracked or held
  double rmse_px = 0;          // of this frame's estimate (0 when not tracked)
  std::vector<int> tags;       // tags (pen faces) used this frame
  bool reinitialized = false;  // first pose after being lost, or after a cut
  bool flip_rejected = false;  // a >flip_angle jump was resolved back
  bool jumped = false;  // a >flip_angle jump was accepted (clearly lower error)
  // Two branches of an ambiguous view are both alive (pen only); the pose is
  // the one that explains the corners better so far, and may still switch.
  bool ambiguous = false;

  bool has_pose() const { return cam_from_object.has_value(); }
};

struct FrameTimings {
  double detect_ms = 0;  // grey conversion + detection (all searches)
  double pose_ms = 0;    // pose estimation and temporal logic
  double dense_ms = 0;   // of which the pen's dense and shaft refinements
  double total_ms = 0;
  bool full_search = true;  // the whole frame was searched
};

struct FrameResult {
  int frame = 0;  // index since construction or Reset()
  double time_s = 0;
  ObjectTrack tank;
  ObjectTrack pen;  // always kLost for a rig without a pen
  // Pen tip in the tank frame: tank_from_cam * cam_from_pen * tip_in_pen,
  // when both objects have a pose.
  std::optional<Eigen::Vector3d> tip_in_tank;
  bool cut = false;                      // a cut was detected in this frame
  std::vector<TagDetection> detections;  // all detected tags, corrected
  FrameTimings timings;
};

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_TRACK_RESULT_H_
