// The frame loop's output sinks (app/app_loop.h): the window, a video file,
// PNG snapshots, the pose CSV and the raw camera recording. Each one writes
// what it is given and finalizes its file on Close(), so whatever ended the
// loop leaves playable and complete outputs.
#ifndef RIPPLE_APP_APP_SINKS_H_
#define RIPPLE_APP_APP_SINKS_H_

#include <string>

#include "app/app_loop.h"
#include "app/app_raw.h"
#include "app/app_video.h"
#include "app/command.h"
#include "tracking/pose_csv.h"

namespace ripple::app {

// Shows each finished frame in the pipeline's window; stops the loop
// (normally) when the window is closed.
class WindowSink : public FrameSink {
 public:
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
};

// The composite frames as a video (app/app_video.h); writes nothing while
// closed, so live can start and stop recordings.
class VideoSink : public FrameSink {
 public:
  bool Open(const std::string& path, double fps, cv::Size size,
            std::string* error) {
    return video_.Open(path, fps, size, error);
  }
  bool is_open() const { return video_.is_open(); }
  const std::string& codec() const { return video_.codec(); }
  bool WantsComposite(int) const override { return video_.is_open(); }
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
  bool Close(LoopStop* stop) override {
    if (video_.Close(&stop->message)) return true;
    stop->exit_code = kExitRuntime;
    return false;
  }

 private:
  VideoOut video_;
};

// Writes the composite of one frame as PNG. A failed write stops the loop
// with `exit_code` and "cannot write [<label> ]'<path>'".
class PngSink : public FrameSink {
 public:
  struct Options {
    std::string path;
    int frame = 0;      // index of the frame to write
    std::string label;  // names the file in the error ("snapshot"), or empty
    int exit_code = 1;  // on a failed write
  };
  explicit PngSink(Options options) : options_(std::move(options)) {}
  bool WantsComposite(int index) const override {
    return index == options_.frame;
  }
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;

 private:
  Options options_;
};

// Writes every composite frame as a lossless PNG, <folder>/<index>.png
// (six digits, from 000000), so composites compare pixel by pixel. A failed
// write stops the loop with exit code 1 and the file's name.
class PngFolderSink : public FrameSink {
 public:
  explicit PngFolderSink(std::string folder) : folder_(std::move(folder)) {}
  bool WantsComposite(int) const override { return true; }
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
  int written() const { return written_; }

 private:
  std::string folder_;
  int written_ = 0;
};

// The tracked poses of every frame (tracking/pose_csv.h). A failed write
// stops the loop with exit code 1.
class PoseCsvSink : public FrameSink {
 public:
  bool Open(const std::string& path, std::string* error);
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
  bool Close(LoopStop*) override {
    writer_.Close();
    return true;
  }

 private:
  std::string path_;
  tracking::PoseCsvWriter writer_;
};

// The raw input frames, losslessly, with their timestamps (app/app_raw.h);
// writes nothing while closed. A failed write stops the loop with exit
// code 1.
class RawSink : public FrameSink {
 public:
  RawRecorder& recorder() { return raw_; }
  bool Consume(const LoopFrame& frame, LoopStop* stop) override;
  bool Close(LoopStop*) override {
    raw_.Close();
    return true;
  }

 private:
  RawRecorder raw_;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_SINKS_H_
