// Third-party log output (FFmpeg, libpng and the other codecs OpenCV calls,
// OpenCV itself) kept off the user's terminal: the user sees our one line,
// and `--verbose` shows the detail.
//
//   InitThirdPartyLogs(verbose);                 // once, in main
//   { StderrCapture quiet;  cv::imread(...); }   // libpng's own prints
//   FfmpegErrorCount();                          // errors FFmpeg reported
#ifndef RIPPLE_APP_APP_THIRD_PARTY_LOG_H_
#define RIPPLE_APP_APP_THIRD_PARTY_LOG_H_

#include <string>

namespace ripple::app {

// OpenCV's log level (errors only; info with `verbose`) and FFmpeg's log
// callback: FFmpeg's lines are counted and dropped, or printed with an
// "ffmpeg: " prefix when `verbose`. An OPENCV_FFMPEG_LOGLEVEL set by the
// user makes OpenCV install its own FFmpeg logger instead (its choice wins).
void InitThirdPartyLogs(bool verbose);
bool VerboseLogs();

// FFmpeg messages at error level or worse since start, and the last one.
int FfmpegErrorCount();
std::string LastFfmpegError();

// While alive, whatever third-party code writes to stderr (file descriptor
// 2) goes to a scratch file; at destruction it is printed with a "detail: "
// prefix when verbose, and otherwise kept in text(). Not thread-safe: for
// calls on the main thread (image decoding).
class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  // Stops capturing now; returns what was captured.
  const std::string& Finish();

 private:
  int saved_fd_ = -1;
  std::string text_;
  bool finished_ = false;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_THIRD_PARTY_LOG_H_
