// Video output through OpenCV's FFmpeg backend, with the codec chosen by the
// file extension, and always finalized (the destructor releases the writer so
// whatever was written stays playable).
#ifndef RIPPLE_APP_APP_VIDEO_H_
#define RIPPLE_APP_APP_VIDEO_H_

#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace cv {
class VideoWriter;
}

namespace ripple::app {

// Opens `path` and reads its frame count: false with `error` (may be null)
// if it cannot be opened or holds fewer than `frames` frames.
bool VerifyVideo(const std::string& path, int frames, std::string* error);

class VideoOut {
 public:
  VideoOut();
  ~VideoOut();
  VideoOut(const VideoOut&) = delete;
  VideoOut& operator=(const VideoOut&) = delete;

  // .mp4: H.264 (falls back to MPEG-4 part 2 if the FFmpeg build lacks an
  // H.264 encoder, and says so); .mkv/.avi: lossless FFV1. False with `error`
  // if the file can't be opened for writing.
  bool Open(const std::string& path, double fps, cv::Size size,
            std::string* error);
  bool Write(const cv::Mat& bgr);
  // Finalizes the file, then reads its index back: false with `error` (may
  // be null) if it cannot be opened or holds fewer frames than were written
  // (a full disk leaves an MP4 without its index, or a short file).
  // Idempotent; a second call returns true.
  bool Close(std::string* error = nullptr);  // VerifyVideo on the file
  bool is_open() const;
  const std::string& codec() const { return codec_; }
  int frames_written() const { return frames_; }

 private:
  std::unique_ptr<cv::VideoWriter> writer_;
  std::string codec_, path_;
  int frames_ = 0;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_VIDEO_H_
