// The board as it looks with nothing in front of it (a "clean plate"),
// learned online in tank coordinates, and per frame the mask of pixels where
// something real (a hand, a sleeve, a cup) stands between the camera and the
// board: the pixels the AR composite must leave to the video.
//
// Model, per plate texel (the board plane z = 0, tank frame): a background
// colour with the frames of evidence behind it and one challenger colour
// (two-candidate background, after Stauffer & Grimson's mixture kept to two
// modes). An observation that matches the background refines it; one that
// does not feeds the challenger, which replaces the background once it has
// been seen for longer and for at least `takeover_frames`. So a board
// revealed by a hand that was there when tracking began takes over after
// `takeover_frames` (or as many frames as the hand stayed, if more), a hand
// passing over the board never becomes board, and one resting there for
// longer than `evidence_cap_frames` does. Colours are stored relative to a
// global gain (the camera's exposure and white balance drift; the gain of each
// frame is the ratio of frame to plate that most of the board agrees on: the
// peak of the ratios' histogram, which a hand entering over the board does
// not move as it moves their median).
//
// Per frame, on the plate texels the tank's box hides from the camera:
//   1. the frame (undistorted to the ideal pinhole, the renderer's output)
//      is warped onto the plate by the board's homography;
//   2. a texel differs when its colour lies off the segment between the
//      darkest and brightest colours of the plate's 3x3 neighbourhood (times
//      the gain) by more than a threshold: the segment holds the mixtures a
//      texel of registration error at a printed edge can show, and nothing
//      else; a darkening by a common factor that keeps the plate's
//      chromaticity is a shadow, not an occluder (Horprasert et al. 1999's
//      brightness/chromaticity split);
//   3. hysteresis: differing regions (low threshold) are kept when they hold
//      a strong texel (high threshold) or were foreground in the last frame
//      (in tank coordinates, so a moving camera keeps them); small blobs are
//      dropped and the mask is closed by one texel;
//   4. the mask is warped back into the window (ideal-pinhole pixels) and
//      grown by `grow_px`;
//   5. a known object of one colour (the pen's shaft, `object`) has a
//      colour model of its own; its pixels far from it are occluders in
//      front of it (a hand holding the pen), and the gap the coarse texels
//      leave between the mask and the object is closed;
//   6. the plate learns from the frame, except where `exclude` says a known
//      object is (the pen) and next to the mask.
// The printed board is known (`SetBoardPrior`: the sheet's design as the
// frame would show it under white light): where the plate has not learned a
// texel yet, a pixel is compared with the design instead (times a
// per-channel gain, within an illumination tolerance), a texel learns only
// colours the design allows, and a challenger the design does not allow never
// becomes background. So a hand present when tracking starts is foreground
// from the first frame, and no hand is ever learned as board.
// Shortcomings, by design: an occluder of the board's own colour (or a grey
// one over white paper, which reads as shadow) is not seen; without a prior,
// texels never observed free of a known object stay unknown (not
// foreground).
#ifndef RIPPLE_TRACKING_CLEAN_PLATE_H_
#define RIPPLE_TRACKING_CLEAN_PLATE_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "tracking/camera.h"
#include "tracking/pose.h"

namespace ripple::tracking {

struct CleanPlateOptions {
  double texel_m = 0.0015;  // plate texel edge, metres
  // Board around the tank's inner outline that the plate covers, metres:
  // what the walls show of the board behind them (a 40 mm wall seen from
  // 30 degrees above the board shows 69 mm behind it).
  double margin_m = 0.08;
  // Board around the tank's inner outline where occluders are looked for
  // too, metres (at most margin_m): the renderer changes it (the tank's
  // shadow, the light its glass sends down), so a hand over it must be
  // known. 0: only the board the tank's box hides.
  double surround_m = 0.0;
  // Colour difference beyond the plate's neighbourhood range, 8-bit levels
  // of the frame's encoding (largest over the channels): seeds of a region,
  // and the level its pixels must reach.
  double high_threshold = 30;
  double low_threshold = 14;
  // A pixel at this fraction of the plate's brightness or more, with the
  // plate's chromaticity (within `shadow_chroma_tolerance` of its
  // brightness), is shadowed board.
  double shadow_min_ratio = 0.4;
  double shadow_chroma_tolerance = 0.08;
  // Frames of evidence a background colour can hold; a challenger seen for
  // longer replaces it.
  int evidence_cap_frames = 150;
  // Frames a challenger must be seen before it can replace the background.
  int takeover_frames = 45;
  // Where the printed design stands in for the plate: the light may vary
  // over the board by these factors around the frame's gain.
  double illumination_low = 0.7;
  double illumination_high = 1.35;
  // Weight of a matching observation in the background colour.
  double learn_rate = 0.08;
  // Foreground regions smaller than this are dropped as noise, texels.
  int min_region_texels = 12;
  // The mask in the image is grown by this: an occluder's edge pixels,
  // half board and half hand, read as the hand's edge in the video, and
  // the plate's texels are coarser than the pixels close to the camera.
  int grow_px = 0;

  bool IsValid(std::string* error) const;
};

// What the last Process() found.
struct CleanPlateSummary {
  int foreground_px = 0;   // mask pixels set
  int known_texels = 0;    // plate texels with a background colour
  int learned_texels = 0;  // texels this frame updated
  int visited_texels = 0;  // plate texels the tank's box hides
  double gain = 1.0;       // frame / plate brightness
  bool plate_changed = false;
  // Share of the sheet's paper samples the printed design allows (-1: not
  // measured); below 0.6 for 5 frames the design is dropped.
  double design_agreement = -1;
};

class CleanPlate {
 public:
  // `camera`: the tracker's camera (its distortion is undone for the mask);
  // the tank's box: inner size and the height of what is drawn over the
  // board (walls, water), metres. Only the board the box hides is
  // processed.
  CleanPlate(const Camera& camera, double tank_size_x_m, double tank_size_y_m,
             double box_top_m,
             const CleanPlateOptions& options = CleanPlateOptions());

  // One frame: `bgr` (CV_8UC3, the camera's size, as captured), the board's
  // pose, `exclude` (CV_8U of the camera's size in ideal-pinhole pixels, or
  // empty): known objects' pixels, neither learned nor reported. The mask
  // covers the tank box's window (TankWindow, 4 px of margin). Returns the
  // summary; the mask is foreground().
  //
  // `object` (same layout, inside `exclude`, or empty): a known object of
  // one colour (the pen's shaft), by levels: kObjectLearn (255) where its
  // colour is learned (where no hand is likely: the shaft's lower half),
  // from the pixels no occluder is next to (per-channel median and spread,
  // blended over frames); kObjectBody (128) the rest of the object;
  // kObjectMargin (64) a margin round it for its pose's error, where the
  // board may show. Its own pixels (128 and up) a pixel inside its outline
  // that differ from its colour by more than max(high_threshold, 4
  // spreads) are occluders in front of it (a hand holding the pen), in the
  // mask; so are the outline's and the margin's pixels that differ from it
  // within kObjectMarginPx of an occluder, near one more than a line thin.
  static constexpr std::uint8_t kObjectLearn = 255, kObjectBody = 128,
                                kObjectMargin = 64;
  static constexpr int kObjectMarginPx = 3;
  const CleanPlateSummary& Process(const cv::Mat& bgr,
                                   const Pose& cam_from_tank,
                                   const cv::Mat& exclude,
                                   const cv::Mat& object = cv::Mat());

  // CV_8U, the camera's size, ideal-pinhole pixels: 255 where something real
  // is in front of the board; 0 elsewhere and outside foreground_window().
  const cv::Mat& foreground() const { return foreground_; }
  cv::Rect foreground_window() const { return window_; }

  // The plate as 8-bit BGRA (alpha 255 where known, else 0), in the
  // frame's encoding: the centre of texel (column i, row j) is the tank
  // point (x, y) = plate_origin_m() + texel_m() * (i + 0.5, j + 0.5), so
  // row 0 is the smallest y. Colours are relative to the gain (times
  // summary().gain: this frame's exposure).
  const cv::Mat& plate() const { return plate_bgra_; }
  cv::Point2d plate_origin_m() const { return origin_m_; }
  double texel_m() const { return options_.texel_m; }
  // Bumped whenever plate() changed.
  std::uint64_t plate_counter() const { return plate_counter_; }

  // The board as a renderer should show it behind what hides it, in
  // plate()'s layout and units: plate() where a texel is known; where it is
  // not but the printed design is (SetBoardPrior), the design as the last
  // frame's light shows it (its per-channel gain over the plate's), alpha
  // 255 too; alpha 0 elsewhere. So the board under a pen that has not moved
  // since tracking began is known from the print. Without a design (or once
  // it is dropped), plate() itself. Recomposed in Process() when the plate
  // changes or the design's gain moves by more than
  // `kShownDesignGainStep` of itself.
  const cv::Mat& shown_plate() const { return shown_; }
  // Bumped whenever shown_plate() changed.
  std::uint64_t shown_plate_counter() const { return shown_counter_; }
  static constexpr double kShownDesignGainStep = 0.01;
  const CleanPlateSummary& summary() const { return summary_; }

  // The printed board's design on the plate's grid (plate_size(), texel
  // centres as in plate()): CV_32FC3 in 8-bit levels of the frame's encoding
  // as the board would show under white light with paper at 255; `valid`
  // CV_8U, nonzero where the design is known (the sheet, not the table).
  // False (nothing changed) on a size or type mismatch.
  bool SetBoardPrior(const cv::Mat& design_levels, const cv::Mat& valid);
  cv::Size plate_size() const { return {plate_w_, plate_h_}; }
  // The design as set, 8-bit BGRA on the plate's grid (alpha 255 where
  // valid); empty without a prior.
  const cv::Mat& board_prior() const { return prior_; }
  // True once the design was dropped as not matching the camera's view.
  bool design_dropped() const { return design_dropped_; }

  // Forgets the plate (a new board or a cut); the prior stays.
  void Reset();

 private:
  void Undistort(const cv::Mat& bgr, const cv::Rect& window, cv::Mat* out);
  // Per-frame gains from the frame against the plate and the design.
  void EstimateGains(const cv::Mat& bgr, const Pose& cam_from_tank,
                     const cv::Mat& exclude);
  // The foreground texels of `roi` (CV_8U 255) from the frame on the plate,
  // against the learned plate or else the design.
  void Classify(const cv::Mat& seen, const cv::Rect& roi, cv::Mat* mask);
  // Whether `o` (levels) may be the printed design `p` (levels) under this
  // frame's light.
  bool PriorAllows(const cv::Vec3f& o, const cv::Vec3f& p) const;
  // `seen`: the frame on the plate's `roi`, alpha 255 where it may teach,
  // 128 where it only feeds challengers, 0 where it says nothing.
  void Learn(const cv::Mat& seen, const cv::Rect& roi);

  Camera camera_;
  CleanPlateOptions options_;
  double size_x_m_ = 0, size_y_m_ = 0, box_top_m_ = 0;
  cv::Point2d origin_m_;
  int plate_w_ = 0, plate_h_ = 0;
  // Per texel: background and challenger colours (gain-relative, 8-bit
  // levels), their evidence in frames.
  cv::Mat background_, challenger_;      // CV_32FC3
  cv::Mat background_n_, challenger_n_;  // CV_16U
  int known_texels_ = 0;                 // nonzero in background_n_
  cv::Mat plate_bgra_;
  // The design (levels) and its 3x3 darkest and brightest, CV_8UC4, alpha
  // 255 where valid.
  cv::Mat prior_, prior_lo_, prior_hi_;
  int design_strikes_ = 0;
  bool design_dropped_ = false;
  std::uint64_t plate_counter_ = 0;
  // Ideal-pinhole pixel -> captured pixel, for cameras with distortion.
  cv::Mat undistort_x_, undistort_y_;
  cv::Mat foreground_;
  // Per-frame buffers, kept so that frames do not reallocate them.
  cv::Mat frame_bgra_, full_, grown_, seen_, mask_, in_window_, near_fg_;
  cv::Mat both_, weak_, strong_, labels_, stats_, centroids_, plo_, phi_;
  cv::Mat plate_foreground_;  // CV_8U, plate-sized: the last mask on the plate
  cv::Rect last_roi_;         // where plate_foreground_ may be nonzero
  cv::Rect window_;
  // The known object's colour (8-bit levels) and spread; no model before
  // `object_frames_` > 0.
  cv::Vec3f object_colour_{0, 0, 0}, object_spread_{0, 0, 0};
  int object_frames_ = 0;
  // ClassifyObject's buffers.
  cv::Mat object_inner_, object_core_, object_hand_near_, object_near_mask_;
  void ClassifyObject(const cv::Mat& frame, const cv::Mat& object_in_window,
                      cv::Mat* mask_in_window);
  double gain_ = 1.0;
  cv::Vec3f prior_gain_{1.0f, 1.0f, 1.0f};  // frame / design, per channel
  CleanPlateSummary summary_;
  // shown_plate(): the composition, and what it was composed from.
  void ComposeShownPlate();
  cv::Mat shown_;
  std::uint64_t shown_counter_ = 0;
  std::uint64_t shown_from_plate_ = ~std::uint64_t{0};
  cv::Vec3f shown_scale_{0.0f, 0.0f, 0.0f};  // design to plate units
};

// The ideal-pinhole pixel window of the tank's box (inner size, floor to
// `top_m`) grown by `pad_px`, clipped to the image; the whole image when a
// corner is behind the camera.
cv::Rect TankWindow(const Camera& camera, const Pose& cam_from_tank,
                    double size_x_m, double size_y_m, double top_m, int pad_px);

// Pixels (CV_8U 255, the camera's size, ideal-pinhole) covered by a pen of
// the rig's geometry at `cam_from_pen`: the shaft cylinder and the cube,
// grown by `grow_px`. `mask` is (re)allocated and cleared.
void DrawPenSilhouette(const Camera& camera, const Pose& cam_from_pen,
                       double cube_edge_m, double shaft_radius_m,
                       const Eigen::Vector3d& tip_in_pen, double grow_px,
                       cv::Mat* mask, bool with_cube = true,
                       double shaft_share = 1.0);

// The pen's masks for CleanPlate::Process (`exclude` and `object`), grown
// by `margin_m` at the pen's depth as the renderer grows the pen's phantom,
// so that what the plate leaves out is what the phantom decides: `exclude`
// the shaft and the cube (255); `object` the shaft alone in CleanPlate's
// levels: its lower half at its own size kObjectLearn (where its colour is
// learned: a hand holding the pen is rarely there), the rest at its size
// kObjectBody, the growth kObjectMargin (where the board shows beside a
// well-tracked shaft).
void DrawPenPlateMasks(const Camera& camera, const Pose& cam_from_pen,
                       double cube_edge_m, double shaft_radius_m,
                       const Eigen::Vector3d& tip_in_pen, double margin_m,
                       cv::Mat* exclude, cv::Mat* object);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_CLEAN_PLATE_H_
