#include "tracking/track_status.h"

namespace ripple::tracking {

const char* ToString(TrackStatus s) {
  switch (s) {
    case TrackStatus::kTracked:
      return "tracked";
    case TrackStatus::kHeld:
      return "held";
    case TrackStatus::kLost:
      return "lost";
  }
  return "lost";
}

std::optional<TrackStatus> ParseTrackStatus(const std::string& s) {
  if (s == "tracked") return TrackStatus::kTracked;
  if (s == "held") return TrackStatus::kHeld;
  if (s == "lost") return TrackStatus::kLost;
  return std::nullopt;
}

}  // namespace ripple::tracking
