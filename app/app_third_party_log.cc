#include "app/app_third_party_log.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <opencv2/core/utils/logger.hpp>

extern "C" {
#include <libavutil/log.h>
}

namespace ripple::app {
namespace {

std::atomic<bool> g_verbose{false};
std::atomic<int> g_ffmpeg_errors{0};
std::mutex g_last_mutex;
std::string g_last_error;

// FFmpeg calls this from its decoding threads too.
void FfmpegLog(void* avcl, int level, const char* fmt, va_list args) {
  if (level > AV_LOG_INFO && !g_verbose) return;
  char line[1024];
  int prefix = 1;
  av_log_format_line(avcl, level, fmt, args, line, sizeof(line), &prefix);
  if (level <= AV_LOG_ERROR) {
    ++g_ffmpeg_errors;
    std::lock_guard<std::mutex> lock(g_last_mutex);
    g_last_error = line;
    while (!g_last_error.empty() && g_last_error.back() == '\n')
      g_last_error.pop_back();
  }
  if (g_verbose) std::fprintf(stderr, "ffmpeg: %s", line);
}

// One scratch file for every capture (opened once, truncated each time).
int ScratchFd() {
  static int fd = [] {
    char name[] = "/tmp/ripple_stderr.XXXXXX";
    const int f = mkstemp(name);
    if (f >= 0) unlink(name);
    return f;
  }();
  return fd;
}

}  // namespace

void InitThirdPartyLogs(bool verbose) {
  g_verbose = verbose;
  // OpenCV's backend chatter (GStreamer, V4L2 probing) is not for users;
  // our own messages say what failed.
  cv::utils::logging::setLogLevel(verbose
                                      ? cv::utils::logging::LOG_LEVEL_INFO
                                      : cv::utils::logging::LOG_LEVEL_ERROR);
  if (std::getenv("OPENCV_FFMPEG_LOGLEVEL") == nullptr) {
    av_log_set_level(verbose ? AV_LOG_VERBOSE : AV_LOG_ERROR);
    av_log_set_callback(FfmpegLog);
  }
}

bool VerboseLogs() { return g_verbose; }

int FfmpegErrorCount() { return g_ffmpeg_errors; }

std::string LastFfmpegError() {
  std::lock_guard<std::mutex> lock(g_last_mutex);
  return g_last_error;
}

StderrCapture::StderrCapture() {
  const int scratch = ScratchFd();
  if (scratch < 0) return;
  std::fflush(stderr);
  if (ftruncate(scratch, 0) != 0 || lseek(scratch, 0, SEEK_SET) != 0) return;
  saved_fd_ = dup(STDERR_FILENO);
  if (saved_fd_ >= 0 && dup2(scratch, STDERR_FILENO) < 0) {
    close(saved_fd_);
    saved_fd_ = -1;
  }
}

const std::string& StderrCapture::Finish() {
  if (finished_ || saved_fd_ < 0) return text_;
  finished_ = true;
  std::fflush(stderr);
  dup2(saved_fd_, STDERR_FILENO);
  close(saved_fd_);
  const int scratch = ScratchFd();
  const off_t size = lseek(scratch, 0, SEEK_END);
  if (size > 0) {
    text_.resize(static_cast<size_t>(std::min<off_t>(size, 1 << 16)));
    const ssize_t got = pread(scratch, text_.data(), text_.size(), 0);
    text_.resize(got > 0 ? static_cast<size_t>(got) : 0);
  }
  if (g_verbose && !text_.empty()) {
    size_t start = 0;
    while (start < text_.size()) {
      size_t end = text_.find('\n', start);
      if (end == std::string::npos) end = text_.size();
      std::fprintf(stderr, "detail: %.*s\n", static_cast<int>(end - start),
                   text_.data() + start);
      start = end + 1;
    }
  }
  return text_;
}

StderrCapture::~StderrCapture() { Finish(); }

}  // namespace ripple::app
