// The pose CSV shared by `ripple synth` (ground truth) and `ripple track`
// (estimates): one row per object per frame, header
//   frame,time_s,object,status,tx,ty,tz,qw,qx,qy,qz,tip_x,tip_y,tip_z,
//   faces,reproj_rmse_px,ms
// The pose is cam_from_object (metres, unit quaternion with qw >= 0), empty
// when lost; tip is the pen tip in the tank frame, set only on pen rows when
// both objects have a pose; faces are tag ids joined by ';'.
#ifndef RIPPLE_TRACKING_POSE_CSV_H_
#define RIPPLE_TRACKING_POSE_CSV_H_

#include <Eigen/Core>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "tracking/pose.h"
#include "tracking/track_status.h"

namespace ripple::tracking {

struct PoseRow {
  int frame = 0;
  double time_s = 0;
  std::string object;  // "tank" or "pen"
  TrackStatus status = TrackStatus::kLost;
  std::optional<Pose> cam_from_object;
  std::optional<Eigen::Vector3d> tip_in_tank;
  std::vector<int> faces;
  double reproj_rmse_px = 0;
  double ms = 0;
};

extern const char kPoseCsvHeader[];

// Streams rows to a file; flushes each frame so a crash leaves a valid prefix.
class PoseCsvWriter {
 public:
  PoseCsvWriter() = default;
  ~PoseCsvWriter();
  PoseCsvWriter(const PoseCsvWriter&) = delete;
  PoseCsvWriter& operator=(const PoseCsvWriter&) = delete;

  bool Open(const std::string& path, std::string* error);
  bool Write(const PoseRow& row);
  bool Close();

 private:
  std::FILE* file_ = nullptr;
};

std::string FormatPoseRow(const PoseRow& row);
// Reads a pose CSV; nullopt with `error` (file, line, column) on bad input.
std::optional<std::vector<PoseRow>> ReadPoseCsv(const std::string& path,
                                                std::string* error);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_POSE_CSV_H_
