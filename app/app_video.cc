#include "app/app_video.h"

#include <cstdio>
#include <filesystem>
#include <iterator>
#include <opencv2/videoio.hpp>

namespace ripple::app {

bool VerifyVideo(const std::string& path, int expected, std::string* error) {
  cv::VideoCapture check;
  int frames = -1;
  try {
    if (check.open(path, cv::CAP_FFMPEG)) {
      frames = static_cast<int>(check.get(cv::CAP_PROP_FRAME_COUNT));
    }
  } catch (const cv::Exception&) {
  }
  if (frames >= expected) return true;
  if (error) {
    *error = frames < 0
                 ? "video '" + path +
                       "' cannot be read back after writing (disk "
                       "full or not writable?)"
                 : "video '" + path + "' holds " + std::to_string(frames) +
                       " of the " + std::to_string(expected) +
                       " frames written (disk full?)";
  }
  return false;
}

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
        path_ = path;
        frames_ = 0;
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
  ++frames_;
  return true;
}

bool VideoOut::Close(std::string* error) {
  if (!writer_) return true;
  writer_->release();
  writer_.reset();
  // cv::VideoWriter reports no write errors: read the result back.
  return VerifyVideo(path_, frames_, error);
}

bool VideoOut::is_open() const { return writer_ != nullptr; }

}  // namespace ripple::app
