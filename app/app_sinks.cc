#include "app/app_sinks.h"

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "app/command.h"

namespace ripple::app {

bool WindowSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  frame.pipeline->renderer().Present();
  return !frame.pipeline->context().ShouldClose();
}

bool VideoSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  if (video_.is_open()) video_.Write(frame.pipeline->composite());
  return true;
}

bool PngSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  if (frame.index != options_.frame) return true;
  if (cv::imwrite(options_.path, frame.pipeline->composite())) return true;
  stop->exit_code = options_.exit_code;
  stop->message = "cannot write " +
                  (options_.label.empty() ? "" : options_.label + " ") + "'" +
                  options_.path + "'";
  return false;
}

bool PngFolderSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  char name[32];
  std::snprintf(name, sizeof(name), "/%06d.png", frame.index);
  const std::string path = folder_ + name;
  // Fastest zlib level: lossless all the same.
  if (cv::imwrite(path, frame.pipeline->composite(),
                  {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    ++written_;
    return true;
  }
  stop->exit_code = kExitRuntime;
  stop->message = "cannot write '" + path + "' (" + std::to_string(written_) +
                  " frames written before it)";
  return false;
}

bool PoseCsvSink::Open(const std::string& path, std::string* error) {
  path_ = path;
  return writer_.Open(path, error);
}

bool PoseCsvSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  for (const tracking::PoseRow& row :
       frame.pipeline->tracker().ToPoseRows(frame.report->tracking)) {
    if (!writer_.Write(row)) {
      stop->exit_code = kExitRuntime;
      stop->message = "cannot write '" + path_ + "' (video finalized)";
      return false;
    }
  }
  return true;
}

bool RawSink::Consume(const LoopFrame& frame, LoopStop* stop) {
  if (!raw_.is_open()) return true;
  if (raw_.Write(frame.input->bgr, frame.input->time_s, &stop->message))
    return true;
  stop->exit_code = kExitRuntime;
  if (stop->message.empty())
    stop->message = "cannot write '" + raw_.dir() + "/timestamps.csv'";
  return false;
}

}  // namespace ripple::app
