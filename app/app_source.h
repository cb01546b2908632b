// Frame sources for `--input`: a video file, a folder of images, or a camera
// (index "0" or a device path such as /dev/video0). Shared by every command
// that reads frames (calib, track, replay, live); the demo's synthetic frames
// come through the same interface (app/app_synth_source.h).
//
//   std::string error;
//   auto source = FrameSource::Open(args.input, &error);
//   if (!source) return Fail(kExitBadInput, error);       // missing/unreadable
//   cv::Mat bgr; double t;
//   while (source->Read(&bgr, &t)) { ... }
//   if (!source->error().empty()) return Fail(kExitRuntime, source->error());
#ifndef RIPPLE_APP_APP_SOURCE_H_
#define RIPPLE_APP_APP_SOURCE_H_

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ripple::app {

// What to ask of a camera, and how folder frames are timed.
struct FrameSourceOptions {
  // Timestamps of folder frames without a timestamps.csv, frames per second.
  double folder_fps = 30.0;
  // Camera capture size and rate (0: the driver's default). The driver may
  // deliver something else; compare with size() and reported_fps().
  int camera_width = 0, camera_height = 0;  // pixels
  double camera_fps = 0;                    // frames per second
  // A one-frame driver buffer, so that every read returns the newest frame
  // (live latency).
  bool camera_newest_frame = false;
  // Failed camera reads retried (10 ms apart) before the camera counts as
  // lost; 0: the first failure ends the input.
  int camera_retries = 0;
};

class FrameSource {
 public:
  enum class Kind { kVideo, kFolder, kCamera, kSynthetic };

  // Opens `spec`: an existing folder (its image files: png, jpg, jpeg, bmp,
  // tif, tiff, pgm, ppm, webp, sorted by name), an existing file (a video),
  // or a camera (a number, or a path under /dev). nullptr with one line in
  // `error` naming the input when it does not exist, is empty or cannot be
  // decoded. `folder_fps` sets the timestamps of folder frames, unless the
  // folder holds a raw recording's timestamps.csv ("frame,time_s"), whose
  // times are used as they are (an inconsistent one is an error).
  static std::unique_ptr<FrameSource> Open(const std::string& spec,
                                           std::string* error,
                                           double folder_fps = 30.0);
  // As above, with camera requests. A camera that changes its frame size
  // mid-run ends the input with an error.
  static std::unique_ptr<FrameSource> Open(const std::string& spec,
                                           const FrameSourceOptions& options,
                                           std::string* error);
  virtual ~FrameSource() = default;

  // Next frame as 8-bit BGR and its time in seconds from the first frame
  // (video: the container's timestamps; folder: index / fps; camera: the
  // steady clock). False at the end of the input, or on a read failure, in
  // which case error() is non-empty (a truncated video or an unreadable
  // image in a folder: the caller exits with 1).
  virtual bool Read(cv::Mat* bgr, double* time_s) = 0;

  const std::string& error() const { return error_; }
  Kind kind() const { return kind_; }
  const std::string& spec() const { return spec_; }
  // Frames read so far.
  int frames_read() const { return frames_read_; }
  // Expected frame count (video: the container's; folder: the files);
  // -1 when unknown (cameras).
  virtual int frame_count() const { return -1; }
  // Frame size (0 x 0 when not yet known).
  cv::Size size() const { return size_; }
  // The frame rate the camera driver reports (0 when unknown or not a
  // camera).
  virtual double reported_fps() const { return 0; }

 protected:
  FrameSource(Kind kind, std::string spec)
      : kind_(kind), spec_(std::move(spec)) {}
  Kind kind_;
  std::string spec_;
  std::string error_;
  int frames_read_ = 0;
  cv::Size size_;
};

// Reads the first frame of a freshly opened source. False with one line in
// `error` and the exit code in `exit_code`: kExitBadInput for an input
// without frames, kExitRuntime for a read failure.
bool ReadFirstFrame(FrameSource* source, cv::Mat* bgr, double* time_s,
                    int* exit_code, std::string* error);

// A raw recording's DIR/timestamps.csv ("frame,time_s", one row per image
// in name order; `ripple live --record-raw` writes it), for `frames` images.
// Absent: empty and true. Present but inconsistent (a row out of order, an
// extra column, a time that is not finite or decreases, a row count other
// than `frames`, a file far larger than those rows): false with one line in
// `error` naming the file and the line.
bool ReadFolderTimestamps(const std::string& dir, size_t frames,
                          std::vector<double>* times, std::string* error);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_SOURCE_H_
