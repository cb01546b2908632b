// Region-of-interest scheduling for the tracker: detect tags only in boxes
// around where the last poses put them, with a whole-frame search every
// full_search_period frames, whenever nothing is being tracked, and as a
// fallback in a frame where a tracked object is not found in its regions.
// An object lost a moment ago is still looked for around its last pose, so
// that a pen missed for a frame (blur, a hand, a face at the detector's
// limit) is found again at once rather than at the next whole-frame search;
// its absence there forces no whole-frame search. An object missing from
// its regions is looked for there once more at full resolution first, and
// an object not yet acquired is looked for in the whole frame at a finer
// decimation when the periodic whole-frame search misses it.
#ifndef RIPPLE_TRACKING_ROI_SEARCH_H_
#define RIPPLE_TRACKING_ROI_SEARCH_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"

namespace ripple::tracking {

struct RoiSearchOptions {
  // Off: every frame is searched whole.
  bool enabled = true;
  int full_search_period = 10;   // frames between whole-frame searches
  double margin_fraction = 0.5;  // box margin, fraction of the tag's size
  double margin_px = 12.0;       // box margin added to that, pixels
  // How long a lost object's last pose still places regions (seconds).
  double recent_loss_s = 0.5;
  // An object none of whose tags the (decimated) search found in the
  // regions is searched for again in its own regions at full resolution,
  // before any whole-frame search: a face at the detector's limit (under
  // about 20 px at decimation 2) that the decimated quad search loses.
  bool retry_full_resolution = true;
  // A whole-frame search made while something else is tracked (the
  // periodic one, or the fallback below) that did not find an object with
  // no pose to place regions from searches the whole frame again at half
  // the detector's decimation (at least 1); only that object's tags are
  // taken from there. A face at the detector's limit is otherwise acquired
  // only when the decimated search finds it by chance, and the region retry
  // above needs a pose. Off while nothing is tracked, where every frame is a
  // whole-frame search.
  bool acquire_finer = true;

  bool IsValid(std::string* error) const;
};

// An object whose tags the region search looks for. Not owned.
struct RoiObject {
  const Pose* cam_from_object = nullptr;  // null: no pose, no regions
  const std::vector<TagPlacement>* tags = nullptr;
  // The pose is the object's last one before a recent loss: its regions
  // are searched, but missing from them is no reason to search the whole
  // frame, and it alone does not count as something tracked.
  bool lost = false;
};

// Pixel boxes around the predicted tags of `objects` (faces turned well away
// from the camera skipped), margins added, clipped to the image and merged
// until none overlap.
std::vector<cv::Rect> PredictTagRois(const RoiSearchOptions& options,
                                     const Camera& camera,
                                     const std::vector<RoiObject>& objects);

// Decides per frame whether to search regions or the whole frame; counts
// frames since the last whole-frame search.
class RoiSearch {
 public:
  explicit RoiSearch(const RoiSearchOptions& options = {})
      : options_(options) {}

  // This frame's detections in `gray` (CV_8UC1): in the regions of
  // `objects` when allowed, else (or when a tracked object is missing from
  // its regions) in the whole frame. `full` (may be null) tells which.
  std::vector<TagDetection> Detect(TagDetector* detector, const cv::Mat& gray,
                                   const Camera& camera,
                                   const std::vector<RoiObject>& objects,
                                   bool* full);
  // The next frame starts a new period (a new video).
  void Reset() { frames_since_full_ = 0; }

  const RoiSearchOptions& options() const { return options_; }

 private:
  RoiSearchOptions options_;
  int frames_since_full_ = 0;
};

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_ROI_SEARCH_H_
