// The `ripple` binary: dispatches to the registered subcommands.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>

#include "app/command.h"

int main(int argc, char** argv) {
  using namespace ripple::app;
  // OpenCV's backend chatter (GStreamer, V4L2 probing) is not for users; our
  // own messages say what failed.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  // FFmpeg's own lines ("moov atom not found", ...) beside ours likewise;
  // OPENCV_FFMPEG_LOGLEVEL set by the user (e.g. 24, warnings) wins.
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", /*overwrite=*/0);
  CLI::App app{
      "Ripple: marker-tracked tabletop AR water.\n"
      "Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input "
      "file."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ripple 0.1.0");
  std::vector<CommandInfo> commands = CommandRegistry();
  std::sort(commands.begin(), commands.end(),
            [](const CommandInfo& a, const CommandInfo& b) {
              return a.name < b.name;
            });
  std::vector<std::pair<CLI::App*, CommandAction>> actions;
  for (const CommandInfo& info : commands) {
    CLI::App* sub = app.add_subcommand(info.name, info.description);
    actions.emplace_back(sub, info.setup(sub));
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0 in CLI11.
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    for (auto& [sub, action] : actions) {
      if (sub->parsed()) return action();
    }
  } catch (const std::exception& e) {
    return Fail(kExitRuntime, std::string("unexpected error: ") + e.what());
  }
  return Fail(kExitBadInput, "no subcommand given (see ripple --help)");
}
