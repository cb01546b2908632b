// Lossless raw recording of the camera stream: DIR/NNNNNN.png plus
// DIR/timestamps.csv ("frame,time_s"), which `ripple replay --input DIR`
// (FrameSource) reads back so that a replay reproduces the session's timing
// exactly.
#ifndef RIPPLE_APP_APP_RAW_H_
#define RIPPLE_APP_APP_RAW_H_

#include <cstdio>
#include <opencv2/core.hpp>
#include <string>

namespace ripple::app {

class RawRecorder {
 public:
  ~RawRecorder() { Close(); }
  bool Open(const std::string& dir, std::string* error);
  // Writes one frame and its timestamp (seconds); false on a write error.
  bool Write(const cv::Mat& bgr, double time_s, std::string* error);
  void Close();
  bool is_open() const { return file_ != nullptr; }
  const std::string& dir() const { return dir_; }
  int frames() const { return frames_; }

 private:
  std::string dir_;
  std::FILE* file_ = nullptr;
  int frames_ = 0;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_RAW_H_
