// The tracking benchmark behind `ripple bench tracking`: run time against
// error of the tracker's settings and of three baselines on synth's
// benchmark preset, rendered in memory.
//
// Frames are rendered once and every setting runs on each frame in turn.
// Settings without region search share one full-frame detection per
// decimation (timed once per frame and charged to each of them); settings
// with region search detect on their own. The baselines get the corrected
// corners of the default decimation's detection and are charged its time.
#ifndef RIPPLE_BENCH_TRACKING_BENCH_H_
#define RIPPLE_BENCH_TRACKING_BENCH_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "bench/pose_errors.h"
#include "tracking/camera.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/tracker.h"

namespace ripple::bench {

// Pose methods compared against the tracker (tracking/baselines.h).
enum class Baseline {
  kNone,     // the tracker with the setting's options
  kPaper,    // frontal face, apriltag's estimate_tag_pose
  kIppe,     // OpenCV IPPE_SQUARE on the best-posed face
  kSqpnpLm,  // OpenCV SQPNP + LM on all corners
  // The plain method: OpenCV SQPNP + LM on all corners of libapriltag's own
  // detections, moved by -0.5 px into OpenCV's convention and nothing else
  // (no edge re-fit, no outward shift), at TrackingSetting::plain_decimate.
  kPlainSqpnpLm,
};

// Which settings a run compares.
enum class Sweep {
  kFull,     // decimation x refinement x pen mode x region search
  kShort,    // one factor at a time around the default
  kDefault,  // the default setting only, no baselines
  // The corner pipeline's suspects, one at a time against the default:
  // no edge re-fit, no outward edge shift, other loss scales, no view-angle
  // weights, no dense refinement, no shaft refinement, and the shaft step's
  // parts (one profile per sample, the corners' prior, the dense prior at
  // full weight); with the plain baselines.
  kSuspects,
  // Smoothing off against the default smoothing and a grid around it.
  kSmoothing,
};

// One setting under test and its per-frame samples.
struct TrackingSetting {
  std::string name;  // "d2 joint ceres roi dense [default]", ...
  Baseline baseline = Baseline::kNone;
  double plain_decimate = 2.0;       // kPlainSqpnpLm only
  tracking::TrackerOptions options;  // kNone only
  std::unique_ptr<tracking::Tracker> tracker;
  std::vector<double> ms;       // per frame, milliseconds
  PoseErrorAccumulator errors;  // per frame, against synth's truth
  // Jitter on the static sequence (TrackingBenchOptions::static_frames):
  // per static segment the RMS deviation of the tip from its mean (mm) and
  // of the pen's and the tank's rotation from their mean rotation (degrees).
  std::vector<double> jitter_tip_mm, jitter_pen_rot_deg, jitter_tank_rot_deg;

  bool is_default() const;
};

// The settings of `sweep` (trackers not yet built), detector threads set.
// `smoothing_grid` replaces the smoothing sweep's built-in grid when not
// empty.
std::vector<std::unique_ptr<TrackingSetting>> MakeTrackingSettings(
    Sweep sweep, int threads,
    const std::vector<tracking::SmoothingOptions>& smoothing_grid = {});

struct TrackingBenchOptions {
  Sweep sweep = Sweep::kShort;
  int frames = 500;  // frames of the benchmark preset
  int first = 0;     // frames before this are neither rendered nor tracked
  int threads = 1;   // detector threads
  uint64_t seed = 1;
  synth::FloorPattern floor;  // the tank floor drawn in the frames
  // How the frames are formed and imaged (synth/variant.h): "exact",
  // "supersampled", "webcam". The camera given to RunTrackingBench is the
  // base; the variant's lens replaces its distortion.
  std::string variant = "exact";
  // Frames of synth's static preset (segments of 30, nothing moving, only
  // the noise changing) tracked after the benchmark frames for the jitter
  // columns, each segment by fresh trackers; 0: none.
  int static_frames = 0;
  int static_segment_frames = 30;  // frames per static segment
  // Sweep::kSmoothing: the smoothing settings tried beside off and the
  // default (empty: a built-in grid).
  std::vector<tracking::SmoothingOptions> smoothing_grid;
};

// Per-frame errors of one setting: a row of the frames CSV.
struct TrackingFrameRow {
  int frame = 0;
  std::string setting;
  double tank_rot_deg = 0, pen_rot_deg = 0, tip_mm = 0;  // NaN when absent
  // The tip's error split along the true tip's line of sight (signed, + away
  // from the camera) and across it, mm; NaN when absent.
  double tip_los_mm = 0, tip_across_mm = 0;
  bool flip = false;
  int pen_faces_visible = 0;  // ground truth
  double pen_face_px = 0;     // largest detected pen face, pixels
  std::string pen_status;     // tracker's, empty for baselines
  std::string pen_tags;       // faces used, '+'-separated
  bool pen_flip_rejected = false, pen_jumped = false, pen_ambiguous = false;
  // The frame's imaging (ground truth): motion blur and defocus (pixels),
  // occluders in the scene.
  double motion_blur_px = 0, defocus_px = 0;
  int occluders = 0;
  bool is_static = false;  // a frame of the static sequence (jitter only)
};

struct TrackingBenchResult {
  std::vector<std::unique_ptr<TrackingSetting>> settings;
  std::vector<TrackingFrameRow> frame_rows;  // only when asked for
  double render_s = 0;                       // synthesising the frames
  double tracking_s = 0;                     // everything else
};

// Runs every setting on the frames of `camera` (already at the benchmark's
// size). `keep_frame_rows` fills result->frame_rows; `progress(done, total)`
// is called every 50 frames. False with `error` when the sequence cannot be
// made.
bool RunTrackingBench(const TrackingBenchOptions& options,
                      const tracking::Camera& camera, const tracking::Rig& rig,
                      bool keep_frame_rows,
                      const std::function<void(int, int)>& progress,
                      TrackingBenchResult* result, std::string* error);

// The markdown table printed per size: heading line, header and one row per
// setting.
std::string FormatTrackingTable(const TrackingBenchOptions& options,
                                const std::string& size,
                                const TrackingBenchResult& result);

// Header of the summary CSV (bench_tracking.csv), then one row per setting.
void WriteTrackingCsvHeader(std::ostream* csv);
void WriteTrackingCsvRows(const TrackingBenchOptions& options,
                          const std::string& size,
                          const TrackingBenchResult& result, std::ostream* csv);
// Header of the per-frame CSV (bench_tracking_frames.csv), then its rows.
void WriteTrackingFramesCsvHeader(std::ostream* csv);
void WriteTrackingFramesCsvRows(const std::string& size,
                                const TrackingBenchResult& result,
                                std::ostream* csv);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_TRACKING_BENCH_H_
