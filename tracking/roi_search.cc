#include "tracking/roi_search.h"

#include <algorithm>
#include <cmath>

namespace ripple::tracking {
namespace {

// Merges overlapping rectangles until none overlap.
std::vector<cv::Rect> MergeRects(std::vector<cv::Rect> rects) {
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t i = 0; i < rects.size() && !merged; ++i) {
      for (size_t j = i + 1; j < rects.size(); ++j) {
        if ((rects[i] & rects[j]).area() > 0) {
          rects[i] = rects[i] | rects[j];
          rects.erase(rects.begin() + j);
          merged = true;
          break;
        }
      }
    }
  }
  return rects;
}

}  // namespace

bool RoiSearchOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (full_search_period < 1) return fail("full_search_period must be >= 1");
  if (!(margin_fraction >= 0 && margin_px >= 0))
    return fail("roi margins must be >= 0");
  if (!(recent_loss_s >= 0)) return fail("recent_loss_s must be >= 0");
  return true;
}

std::vector<cv::Rect> PredictTagRois(const RoiSearchOptions& options,
                                     const Camera& camera,
                                     const std::vector<RoiObject>& objects) {
  std::vector<cv::Rect> rects;
  for (const RoiObject& object : objects) {
    if (!object.cam_from_object) continue;
    const Pose& pose = *object.cam_from_object;
    for (const TagPlacement& tag : *object.tags) {
      // Skip faces turned well away from the camera.
      if (FacingCosine(pose, tag.object_from_tag) < -0.2) continue;
      double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
      bool ok = true;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p = pose * tag.CornerInObject(k);
        if (p.z() <= 1e-3) {
          ok = false;
          break;
        }
        const Eigen::Vector2d uv = camera.Project(p);
        x0 = std::min(x0, uv.x());
        y0 = std::min(y0, uv.y());
        x1 = std::max(x1, uv.x());
        y1 = std::max(y1, uv.y());
      }
      if (!ok) continue;
      const double m = options.margin_fraction * std::max(x1 - x0, y1 - y0) +
                       options.margin_px;
      x0 = std::max(x0 - m, -1.0);
      y0 = std::max(y0 - m, -1.0);
      x1 = std::min(x1 + m, double(camera.width));
      y1 = std::min(y1 + m, double(camera.height));
      if (x1 <= x0 || y1 <= y0) continue;
      const int ix0 = static_cast<int>(std::floor(x0)),
                iy0 = static_cast<int>(std::floor(y0));
      rects.emplace_back(ix0, iy0, static_cast<int>(std::ceil(x1)) - ix0,
                         static_cast<int>(std::ceil(y1)) - iy0);
    }
  }
  return MergeRects(rects);
}

std::vector<TagDetection> RoiSearch::Detect(
    TagDetector* detector, const cv::Mat& gray, const Camera& camera,
    const std::vector<RoiObject>& objects, bool* full_out) {
  bool any_tracked = false;
  for (const RoiObject& o : objects)
    any_tracked = any_tracked || (o.cam_from_object && !o.lost);
  bool full = !options_.enabled || !any_tracked ||
              frames_since_full_ + 1 >= options_.full_search_period;
  std::vector<TagDetection> detections;
  auto found = [&detections](const std::vector<TagPlacement>& tags) {
    for (const TagDetection& d : detections)
      for (const TagPlacement& t : tags)
        if (t.id == d.id) return true;
    return false;
  };
  // Detections of `object`'s tags only, out of `more`.
  auto take = [&detections](const RoiObject& object,
                            const std::vector<TagDetection>& more) {
    for (const TagDetection& d : more) {
      for (const TagPlacement& t : *object.tags) {
        if (t.id == d.id) {
          detections.push_back(d);
          break;
        }
      }
    }
  };
  if (!full) {
    const std::vector<cv::Rect> rois =
        PredictTagRois(options_, camera, objects);
    if (rois.empty()) {
      full = true;
    } else {
      detections = detector->Detect(gray, rois);
      // An object none of whose tags was found: its own regions again, at
      // full resolution; only its tags are taken from there.
      if (options_.retry_full_resolution &&
          detector->options().quad_decimate > 1.0) {
        for (const RoiObject& o : objects) {
          if (!o.cam_from_object || found(*o.tags)) continue;
          const std::vector<cv::Rect> own =
              PredictTagRois(options_, camera, {o});
          if (own.empty()) continue;
          take(o, detector->Detect(gray, own, 1.0));
        }
      }
      // Fall back to the whole frame when a tracked object went missing.
      for (const RoiObject& o : objects)
        if (o.cam_from_object && !o.lost && !found(*o.tags)) full = true;
    }
  }
  if (full) {
    detections = detector->Detect(gray);
    frames_since_full_ = 0;
    // Objects not yet acquired that the decimated whole frame missed: the
    // whole frame once more at a finer decimation, their tags only.
    const double decimate = detector->options().quad_decimate;
    std::vector<const RoiObject*> missing;
    if (options_.acquire_finer && any_tracked && decimate > 1.0)
      for (const RoiObject& o : objects)
        if (!o.cam_from_object && !found(*o.tags)) missing.push_back(&o);
    if (!missing.empty()) {
      const std::vector<TagDetection> finer =
          detector->Detect(gray, {}, std::max(1.0, decimate / 2));
      for (const RoiObject* o : missing) take(*o, finer);
    }
  } else {
    ++frames_since_full_;
  }
  if (full_out) *full_out = full;
  return detections;
}

}  // namespace ripple::tracking
