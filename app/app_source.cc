#include "app/app_source.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "app/app_matroska.h"
#include "app/app_third_party_log.h"
#include "app/command.h"
#include "bench/stats.h"
#include "tracking/camera.h"

namespace ripple::app {
namespace {

namespace fs = std::filesystem;

cv::Mat ToBgr(const cv::Mat& image) {
  cv::Mat bgr;
  if (image.channels() == 1)
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  else if (image.channels() == 4)
    cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
  else
    bgr = image;
  if (bgr.depth() != CV_8U) bgr.convertTo(bgr, CV_8U, 255.0 / 65535.0);
  return bgr;
}

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff",
                        ".pgm", ".ppm", ".webp"})
    if (ext == e) return true;
  return false;
}

class FolderSource : public FrameSource {
 public:
  FolderSource(const std::string& spec, std::vector<std::string> files,
               double fps, std::vector<double> times)
      : FrameSource(Kind::kFolder, spec),
        files_(std::move(files)),
        fps_(fps),
        times_(std::move(times)) {}

  bool Read(cv::Mat* bgr, double* time_s) override {
    if (!error_.empty() || next_ >= files_.size()) return false;
    cv::Mat image;
    std::string why;
    {
      // libpng and libtiff print their complaints themselves; the detail
      // goes to --verbose, our line says what failed.
      StderrCapture quiet;
      try {
        image = cv::imread(files_[next_], cv::IMREAD_UNCHANGED);
      } catch (const cv::Exception& e) {
        // OpenCV's size limits (set in main from tracking::kMaxImageSide)
        // are checked on the header, before the pixels are allocated.
        why = e.err.find("CV_IO_MAX_IMAGE") != std::string::npos
                  ? ": its header states a size over " +
                        std::to_string(tracking::kMaxImageSide) +
                        " pixels per side"
                  : ": " + e.err;
      } catch (const std::exception& e) {
        why = std::string(": ") + e.what();
      }
      const std::string& detail = quiet.Finish();
      if (why.empty() && image.empty() && !detail.empty())
        why = ": " + detail.substr(0, detail.find('\n'));
    }
    if (image.empty()) {
      error_ = "cannot read image '" + files_[next_] + "'" + why + " (read " +
               std::to_string(frames_read_) + " of " +
               std::to_string(files_.size()) + " frames)";
      return false;
    }
    *bgr = ToBgr(image);
    if (size_.area() == 0) size_ = bgr->size();
    if (bgr->size() != size_) {
      error_ = "image '" + files_[next_] +
               "' has a different size from the "
               "first image of '" +
               spec_ + "'";
      return false;
    }
    *time_s = times_.empty() ? next_ / fps_ : times_[next_];
    ++next_;
    ++frames_read_;
    return true;
  }
  int frame_count() const override { return static_cast<int>(files_.size()); }

 private:
  std::vector<std::string> files_;
  double fps_;
  std::vector<double> times_;  // from timestamps.csv, or empty
  size_t next_ = 0;
};

}  // namespace

bool ReadFolderTimestamps(const std::string& dir, size_t frames,
                          std::vector<double>* times, std::string* error) {
  const std::string path = dir + "/timestamps.csv";
  std::error_code ec;
  if (!fs::exists(path, ec)) return true;
  // "frame,time_s" rows are a few dozen bytes each: bound the file before
  // reading it.
  const uintmax_t bytes = fs::file_size(path, ec);
  if (ec || bytes > 4096 + 128 * static_cast<uintmax_t>(frames)) {
    *error = "'" + path + "': " +
             (ec ? std::string("cannot be read")
                 : std::to_string(bytes) + " bytes is too large for " +
                       std::to_string(frames) + " frames");
    return false;
  }
  std::ifstream in(path);
  if (!in) {
    *error = "'" + path + "': cannot be read";
    return false;
  }
  std::string line;
  std::getline(in, line);
  if (line != "frame,time_s") {
    *error = "'" + path + "': expected the header frame,time_s";
    return false;
  }
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    int frame = -1;
    double t = 0;
    char comma = 0;
    std::istringstream row(line);
    // Nothing may follow the time: an extra column is another format.
    if (!(row >> frame >> comma >> t) || comma != ',' ||
        !(row >> std::ws).eof() || !std::isfinite(t) ||
        frame != static_cast<int>(times->size()) ||
        (!times->empty() && t < times->back())) {
      *error = "'" + path + "' line " + std::to_string(n) + ": expected \"" +
               std::to_string(times->size()) +
               ",<time_s>\" (frame, then a finite non-decreasing time)";
      return false;
    }
    times->push_back(t);
  }
  if (times->size() != frames) {
    *error = "'" + path + "' has " + std::to_string(times->size()) +
             " rows for " + std::to_string(frames) + " images";
    return false;
  }
  return true;
}

namespace {

class CaptureSource : public FrameSource {
 public:
  CaptureSource(Kind kind, const std::string& spec,
                std::unique_ptr<cv::VideoCapture> capture, int retries,
                std::string damage = "")
      : FrameSource(kind, spec),
        capture_(std::move(capture)),
        retries_(retries),
        damage_(std::move(damage)),
        ffmpeg_errors_at_open_(FfmpegErrorCount()) {
    if (kind == Kind::kVideo) {
      const double n = capture_->get(cv::CAP_PROP_FRAME_COUNT);
      count_ = n > 0 ? static_cast<int>(n) : -1;
    }
    if (kind == Kind::kCamera) fps_ = capture_->get(cv::CAP_PROP_FPS);
  }

  bool Read(cv::Mat* bgr, double* time_s) override {
    if (!error_.empty() || ended_) return false;
    cv::Mat frame;
    bool got = capture_->read(frame) && !frame.empty();
    for (int retry = 0; !got && retry < retries_; ++retry) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      got = capture_->read(frame) && !frame.empty();
    }
    if (!got) {
      ended_ = true;
      if (kind_ == Kind::kCamera && retries_ > 0) {
        error_ = "camera '" + spec_ + "' lost (no frame for " +
                 std::to_string(retries_ + 1) + " reads)";
      } else if (kind_ == Kind::kCamera) {
        error_ = "camera '" + spec_ + "' stopped delivering frames";
      } else if (!damage_.empty()) {
        error_ = "video '" + spec_ + "' is " + damage_ + ": read " +
                 std::to_string(frames_read_) + " of " +
                 (count_ > 0 ? std::to_string(count_) : std::string("?")) +
                 " frames";
      } else if (count_ > 0 && frames_read_ < count_ - 1) {
        // Containers' counts can be off by one; more missing is a cut.
        error_ = "video '" + spec_ + "' is truncated: read " +
                 std::to_string(frames_read_) + " of " +
                 std::to_string(count_) + " frames";
      } else if (FfmpegErrorCount() > ffmpeg_errors_at_open_) {
        error_ = "video '" + spec_ + "' has frames that failed to decode (" +
                 LastFfmpegError() + "): read " + std::to_string(frames_read_) +
                 " of " +
                 (count_ > 0 ? std::to_string(count_) : std::string("?")) +
                 " frames";
      }
      return false;
    }
    *bgr = ToBgr(frame);
    if (size_.area() == 0) size_ = bgr->size();
    if (kind_ == Kind::kCamera && bgr->size() != size_) {
      ended_ = true;
      error_ = "camera '" + spec_ + "' changed its frame size mid-run";
      return false;
    }
    if (kind_ == Kind::kVideo) {
      const double ms = capture_->get(cv::CAP_PROP_POS_MSEC);
      if (frames_read_ == 0) t0_ms_ = ms;
      *time_s = (ms - t0_ms_) * 1e-3;
    } else {
      *time_s = clock_.ElapsedS();
    }
    ++frames_read_;
    return true;
  }
  int frame_count() const override { return count_; }
  double reported_fps() const override { return fps_ > 0 ? fps_ : 0; }

 private:
  std::unique_ptr<cv::VideoCapture> capture_;
  int retries_ = 0;
  std::string damage_;  // what CheckMatroska found, or empty
  int ffmpeg_errors_at_open_ = 0;
  int count_ = -1;
  double fps_ = 0;
  bool ended_ = false;
  double t0_ms_ = 0;
  bench::Stopwatch clock_;  // camera timestamps
};

bool IsCameraIndex(const std::string& s) {
  return !s.empty() && s.size() <= 3 &&
         std::all_of(s.begin(), s.end(),
                     [](unsigned char c) { return std::isdigit(c); });
}

}  // namespace

std::unique_ptr<FrameSource> FrameSource::Open(const std::string& spec,
                                               std::string* error,
                                               double folder_fps) {
  FrameSourceOptions options;
  options.folder_fps = folder_fps;
  return Open(spec, options, error);
}

std::unique_ptr<FrameSource> FrameSource::Open(
    const std::string& spec, const FrameSourceOptions& options,
    std::string* error) {
  const double folder_fps = options.folder_fps;
  std::error_code ec;
  if (spec.empty()) {
    *error = "--input is empty";
    return nullptr;
  }
  if (fs::is_directory(spec, ec)) {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(spec, ec))
      if (entry.is_regular_file() && IsImageFile(entry.path()))
        files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) {
      *error = "input folder '" + spec + "' holds no image files";
      return nullptr;
    }
    std::vector<double> times;
    if (!ReadFolderTimestamps(spec, files.size(), &times, error))
      return nullptr;
    return std::make_unique<FolderSource>(spec, std::move(files),
                                          folder_fps > 0 ? folder_fps : 30.0,
                                          std::move(times));
  }
  const bool is_device = IsCameraIndex(spec) || spec.rfind("/dev/", 0) == 0;
  if (!is_device) {
    if (!fs::exists(spec, ec)) {
      *error = "input '" + spec + "' does not exist";
      return nullptr;
    }
    auto capture = std::make_unique<cv::VideoCapture>();
    try {
      capture->open(spec, cv::CAP_FFMPEG);
    } catch (const cv::Exception&) {
    }
    if (!capture->isOpened()) {
      *error = "cannot open video '" + spec + "' (not a video OpenCV can read)";
      return nullptr;
    }
    // The stream's size from the container header, before any frame is
    // decoded (and allocated).
    const double w = capture->get(cv::CAP_PROP_FRAME_WIDTH);
    const double h = capture->get(cv::CAP_PROP_FRAME_HEIGHT);
    if (!(w <= tracking::kMaxImageSide && h <= tracking::kMaxImageSide)) {
      *error = "video '" + spec + "' is " + std::to_string(w) + "x" +
               std::to_string(h) + " pixels, over " +
               std::to_string(tracking::kMaxImageSide) + " per side";
      return nullptr;
    }
    return std::make_unique<CaptureSource>(
        Kind::kVideo, spec, std::move(capture), 0, CheckMatroska(spec));
  }
  auto capture = std::make_unique<cv::VideoCapture>();
  try {
    // An index opens through V4L2 as a device path does: CAP_ANY would
    // also probe gphoto2, which scans the USB bus and leaks its port
    // plugin's allocations (LeakSanitizer, after the plugin is unloaded).
    if (IsCameraIndex(spec))
      capture->open(std::stoi(spec), cv::CAP_V4L2);
    else
      capture->open(spec, cv::CAP_V4L2);
  } catch (const cv::Exception&) {
  }
  if (!capture->isOpened()) {
    *error = "cannot open camera '" + spec + "'";
    return nullptr;
  }
  if (options.camera_newest_frame) capture->set(cv::CAP_PROP_BUFFERSIZE, 1);
  if (options.camera_width > 0)
    capture->set(cv::CAP_PROP_FRAME_WIDTH, options.camera_width);
  if (options.camera_height > 0)
    capture->set(cv::CAP_PROP_FRAME_HEIGHT, options.camera_height);
  if (options.camera_fps > 0)
    capture->set(cv::CAP_PROP_FPS, options.camera_fps);
  return std::make_unique<CaptureSource>(
      Kind::kCamera, spec, std::move(capture), options.camera_retries);
}

bool ReadFirstFrame(FrameSource* source, cv::Mat* bgr, double* time_s,
                    int* exit_code, std::string* error) {
  if (source->Read(bgr, time_s)) return true;
  if (source->error().empty()) {
    *exit_code = kExitBadInput;
    *error = "input '" + source->spec() + "' has no frames";
  } else {
    *exit_code = kExitRuntime;
    *error = source->error();
  }
  return false;
}

}  // namespace ripple::app
