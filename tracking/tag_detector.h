// AprilTag detection with libapriltag, corners in OpenCV's pixel convention.
//
// libapriltag's corners are biased against OpenCV's convention (integer
// coordinates = pixel centres): they sit +0.5 px in x and y (DESIGN.md, "What
// the tracker can count on"), and its edge refinement places each edge
// slightly inside the black square. The detector removes both: it subtracts
// `pixel_offset_px` and moves every edge line outward by `edge_outward_px`
// (the corrected corner is the intersection of the shifted edge lines).
// tests/tracking/tag_detector_test.cc measures the remaining bias on
// ray-cast frames (docs/tracking.md, "Corner bias").
#ifndef RIPPLE_TRACKING_TAG_DETECTOR_H_
#define RIPPLE_TRACKING_TAG_DETECTOR_H_

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {

// One detected tag. Corners are in the order top-left, top-right,
// bottom-right, bottom-left of the tag image as the family draws it (the
// order of TagPlacement::CornerInObject), in distorted image pixels (OpenCV
// convention, as observed: not undistorted).
struct TagDetection {
  int id = -1;
  std::array<Eigen::Vector2d, 4> corners;
  double decision_margin = 0;  // libapriltag's decoding margin (higher: surer)
  int hamming = 0;             // bits corrected
  // Corner k is hidden: the white margin beside it is covered (a hand, the
  // pen, the image's border) and its two edges could not place it, so its
  // position is libapriltag's outline of what is visible, not the tag's
  // corner (FitTagEdges). Poses leave such corners out.
  std::array<bool, 4> corner_occluded{false, false, false, false};
  // Mean edge length, pixels.
  double SizePx() const;
};

// What the edge fit may trust (FitTagEdges).
struct EdgeFitLimits {
  // A fitted corner further than this from libapriltag's is not trusted.
  double max_shift_px = 1.5;
  // A profile whose white end is below this share of the tag's white (the
  // upper quartile of every profile's white end) is not on the white
  // margin: a hand, the pen or its shadow covers it. It is left out of the
  // line fit. On synth's benchmark preset the margin beside a tank tag's
  // corner reads 0.94-1.0 of the tag's white, a hand over it 0.67-0.84;
  // a pen face's margin, 1.1 cells wide and foreshortened on a turned
  // face, can read lower where the profile's white end reaches the cube's
  // edge: at 0.8 and above such profiles were dropped and the static pen's
  // jitter doubled (docs/tracking.md, "Occluded corners").
  double margin_share = 0.75;
  // A corner with covered profiles beside it is where libapriltag's outline
  // follows the occluder, not the tag (2-5 px off on the benchmark): the
  // intersection of its edges' lines, fitted on the uncovered profiles, may
  // move it up to this many cells.
  double max_occluded_shift_cells = 2.4;

  bool IsValid(std::string* error) const;
};

struct TagDetectorOptions {
  std::string family = "tag36h11";
  // Quad finding runs on an image decimated by this factor (>= 1); corners
  // are refined at full resolution when refine_edges is on.
  double quad_decimate = 2.0;
  double quad_sigma = 0.0;  // Gaussian blur before quad finding, pixels
  int threads = 1;          // libapriltag worker threads
  bool refine_edges = true;
  double decode_sharpening = 0.25;
  // libapriltag marks a 4x4-pixel tile (of the decimated image) as
  // unknown, and skips it, when its grey range is below this (DN). Its own
  // default, 5, lets sensor noise (2-4 DN read noise plus shot noise)
  // through: flat paper then breaks into thousands of tiny segments that
  // are clustered and fitted as quad candidates, which took 80% of the
  // detector's time on the benchmark preset (docs/tracking.md, "Detector
  // time"). Printed tags have 100+ DN between black and white.
  int min_white_black_diff = 25;
  int max_hamming = 1;                // reject detections with more bit errors
  double min_decision_margin = 15.0;  // reject weaker decodes
  // Bias correction (see the file comment). Pixels.
  double pixel_offset_px = 0.5;
  // With the edge fit and the border's own black (below), the remaining
  // outward bias is +0.00..+0.05 px on the synthetic variants, sharp or
  // blurred, linear or sRGB (docs/tracking.md, "Detection and corner
  // bias"): no correction. The former per-profile dark level sat
  // +0.03..+0.10 px outward under blur and took -0.015 px here.
  double edge_outward_px = 0.0;
  // Ripple's own edge fit after libapriltag's: along each edge, the
  // sub-pixel crossing of the mid level between the black border and the
  // white margin (unbiased under any symmetric blur), a robust line fit per
  // edge, and corners at the intersections of adjacent lines.
  bool edge_fit = true;
  // The edge fit's dark level: the black border's own, read where the
  // decoded tag has a black cell inside the border and taken as a share of
  // the white beside each profile (FitTagEdges), on tags whose cells are
  // 2.4-7 px (where a white cell inside the one-cell border lifts the
  // border's level under blur); off, or outside that range: each
  // profile's dark end.
  bool edge_fit_border_black = true;
  // The edge fit's limits (EdgeFitLimits).
  EdgeFitLimits edge_fit_limits;
  // How the image's 8-bit values encode light (the camera file's
  // `transfer`). Blur mixes light, not encoded values: a blurred edge of an
  // sRGB-encoded image crosses its encoded mid level on the dark side,
  // about 0.5 px inside the black square at the benchmark preset's blur
  // (tests/tracking/synth_track_test.cc), and small black cells blurred
  // into white paper look lighter than in linear light, so libapriltag's
  // mid-range threshold loses them. kSrgb frames are decoded (IEC
  // 61966-2-1, to 8-bit linear values) before detection and the edge fit.
  geometry::Transfer transfer = geometry::Transfer::kLinear;
  // The camera's lens. A tag's edges are straight in the world and through
  // a pinhole, not in a distorted image: with a lens that distorts, the
  // edge fit's lines are fitted in undistorted pixels (a straight line
  // fitted to a barrel-distorted edge 200-300 px from the centre put the
  // corners 0.05 px outward, docs/tracking.md). Empty: fitted in the image
  // as it is. The tracker sets it from its camera.
  std::optional<geometry::CameraModel> lens;

  bool IsValid(std::string* error) const;
};

// Stateful wrapper around one libapriltag detector. Not thread-safe (one
// detector per thread); movable, not copyable.
class TagDetector {
 public:
  // CHECKs options.IsValid().
  explicit TagDetector(const TagDetectorOptions& options);
  ~TagDetector();
  TagDetector(TagDetector&&) noexcept;
  TagDetector& operator=(TagDetector&&) noexcept;

  // Images and regions narrower or lower than this (pixels) are not
  // searched: no tag fits, and libapriltag reads past their edges.
  static constexpr int kMinImageSide = 8;

  // Detects tags in an 8-bit image (CV_8UC1, or CV_8UC3 BGR which is
  // converted). With `rois` non-empty only those rectangles (clipped to the
  // image) are searched, without copying pixels; a tag must lie wholly inside
  // one of them. Duplicate ids keep the detection with the larger margin.
  // `quad_decimate` (>= 1) replaces the options' for this call.
  std::vector<TagDetection> Detect(
      const cv::Mat& image, const std::vector<cv::Rect>& rois = {},
      std::optional<double> quad_decimate = std::nullopt);

  const TagDetectorOptions& options() const { return options_; }

 private:
  struct Impl;
  TagDetectorOptions options_;
  std::unique_ptr<Impl> impl_;
};

// Fits the four edge lines of a tag around `corners` (TL, TR, BR, BL,
// OpenCV convention) in an 8-bit grey image and returns their
// intersections; `cell_px` is the size of one tag cell in pixels (it bounds
// the profile so that it stays on the black border and the white margin).
// Each edge point is the crossing of the mid level between the black border
// and the white margin; with the tag's `bitmap` (its cells as decoded, TL
// corner first) the border's black is read only where the cell inside the
// border is black (TagDetectorOptions::edge_fit_border_black).
// Profiles whose white end is darker than the tag's margin
// (limits.margin_share) or that leave the image are left out; a corner next
// to them may move further (limits.max_occluded_shift_cells), and is
// reported hidden when its edges cannot place it.
// Corners whose edges cannot be fitted keep their input value.
struct EdgeFit {
  std::array<Eigen::Vector2d, 4> corners;
  std::array<bool, 4> occluded{false, false, false, false};
};
// A distorting lens's pixels and its undistorted (ideal pinhole) pixels,
// where a tag's edges are straight. Undistorting is iterative (about
// 0.15 us a point) and the edge fit maps thousands of points a frame, so
// image pixels are undistorted by bilinear interpolation in a table
// computed once, every `kStepPx` pixels over the image and a margin
// around it (the map's curvature makes that under 0.005 px off in the
// image's corners under the `lens` variant's k1 -0.28, 0.017 px at 8 px),
// and exactly outside it. Distorting is the camera model's closed form.
class LensPixels {
 public:
  static constexpr int kStepPx = 4;
  static constexpr int kMarginPx = 32;
  explicit LensPixels(const geometry::CameraModel& lens);
  Eigen::Vector2d ToIdeal(const Eigen::Vector2d& pixel) const;
  Eigen::Vector2d ToImage(const Eigen::Vector2d& ideal) const;

 private:
  Eigen::Vector2d ToIdealExact(const Eigen::Vector2d& pixel) const;
  geometry::CameraModel lens_;
  int cols_ = 0, rows_ = 0;
  std::vector<Eigen::Vector2d> table_;  // ideal pixel at each node
};

// With `lens` the lines are fitted in its undistorted pixels and the
// corners mapped back into the image.
EdgeFit FitTagEdges(const cv::Mat& gray,
                    const std::array<Eigen::Vector2d, 4>& corners,
                    double cell_px, const EdgeFitLimits& limits,
                    const TagBitmap* bitmap = nullptr,
                    const LensPixels* lens = nullptr);

// A cv::LUT table (1 x 256, CV_8U) from 8-bit values of `transfer` to 8-bit
// values linear in light (identity for kLinear).
cv::Mat DecodeToLinearLut(geometry::Transfer transfer);

// Applies the detector's bias correction to libapriltag's raw corners
// (already in TL, TR, BR, BL order). Exposed for tests and benchmarks.
std::array<Eigen::Vector2d, 4> CorrectCorners(
    const std::array<Eigen::Vector2d, 4>& raw, double pixel_offset_px,
    double edge_outward_px);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_TAG_DETECTOR_H_
