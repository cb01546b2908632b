// The status of a tracked object in a frame, as the tracker reports it and
// the pose CSV stores it.
#ifndef RIPPLE_TRACKING_TRACK_STATUS_H_
#define RIPPLE_TRACKING_TRACK_STATUS_H_

#include <optional>
#include <string>

namespace ripple::tracking {

// kTracked: estimated in this frame; kHeld: not found, the last pose kept
// for a short hold time; kLost: no pose.
enum class TrackStatus { kTracked, kHeld, kLost };
const char* ToString(TrackStatus s);  // tracked, held, lost
std::optional<TrackStatus> ParseTrackStatus(const std::string& s);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_TRACK_STATUS_H_
