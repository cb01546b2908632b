#include "app/app_raw.h"

#include <opencv2/imgcodecs.hpp>

#include "app/app_common.h"

namespace ripple::app {

bool RawRecorder::Open(const std::string& dir, std::string* error) {
  Close();
  if (!MakeDirectories(dir, error)) return false;
  file_ = std::fopen((dir + "/timestamps.csv").c_str(), "w");
  if (!file_) {
    if (error) *error = "cannot write '" + dir + "/timestamps.csv'";
    return false;
  }
  std::fprintf(file_, "frame,time_s\n");
  dir_ = dir;
  frames_ = 0;
  return true;
}

bool RawRecorder::Write(const cv::Mat& bgr, double time_s, std::string* error) {
  if (!file_) return false;
  char name[32];
  std::snprintf(name, sizeof(name), "/%06d.png", frames_);
  if (!cv::imwrite(dir_ + name, bgr, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    if (error) *error = "cannot write '" + dir_ + name + "'";
    return false;
  }
  std::fprintf(file_, "%d,%.6f\n", frames_, time_s);
  std::fflush(file_);
  ++frames_;
  return std::ferror(file_) == 0;
}

void RawRecorder::Close() {
  if (file_) std::fclose(file_);
  file_ = nullptr;
}

}  // namespace ripple::app
