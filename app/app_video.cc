#include "app/app_video.h"

#include <cstdio>
#include <filesystem>
#include <iterator>
#include <opencv2/videoio.hpp>

namespace ripple::app {

VideoOut::VideoOut() = default;
VideoOut::~VideoOut() { Close(); }

bool VideoOut::Open(const std::string& path, double fps, cv::Size size,
                    std::string* error) {
  Close();
  const std::string ext = std::filesystem::path(path).extension().string();
  struct Choice {
    const char* fourcc;
    const char* name;
  };
  static const Choice kMp4[] = {{"avc1", "H.264"}, {"mp4v", "MPEG-4"}};
  static const Choice kLossless[] = {{"FFV1", "FFV1 (lossless)"}};
  const Choice* begin = nullptr;
  const Choice* end = nullptr;
  if (ext == ".mp4" || ext == ".mov") {
    begin = std::begin(kMp4);
    end = std::end(kMp4);
  } else if (ext == ".mkv" || ext == ".avi") {
    begin = std::begin(kLossless);
    end = std::end(kLossless);
  } else {
    if (error)
      *error = "video output '" + path + "': use .mp4, .mov, .mkv or .avi";
    return false;
  }
  for (const Choice* c = begin; c != end; ++c) {
    auto w = std::make_unique<cv::VideoWriter>();
    try {
      const int fourcc = cv::VideoWriter::fourcc(c->fourcc[0], c->fourcc[1],
                                                 c->fourcc[2], c->fourcc[3]);
      if (w->open(path, cv::CAP_FFMPEG, fourcc, fps, size, true) &&
          w->isOpened()) {
        writer_ = std::move(w);
        codec_ = c->name;
        return true;
      }
    } catch (const cv::Exception&) {
    }
  }
  if (error) *error = "cannot open video output '" + path + "' for writing";
  return false;
}

bool VideoOut::Write(const cv::Mat& bgr) {
  if (!writer_) return false;
  writer_->write(bgr);
  return true;
}

void VideoOut::Close() {
  if (writer_) writer_->release();
  writer_.reset();
}

bool VideoOut::is_open() const { return writer_ != nullptr; }

}  // namespace ripple::app
