// The `ripple` binary: dispatches to the registered subcommands.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "app/app_third_party_log.h"
#include "app/command.h"
#include "tracking/camera.h"

int main(int argc, char** argv) {
  using namespace ripple::app;
  // Third-party lines (FFmpeg's "moov atom not found", libpng's "Read
  // Error", OpenCV's backend probing) stay off the terminal unless
  // --verbose (app/app_third_party_log.h); our own line says what failed.
  bool verbose = false;
  for (int i = 1; i < argc; ++i)
    verbose = verbose || std::string(argv[i]) == "--verbose";
  InitThirdPartyLogs(verbose);
  // OpenCV checks image headers against these before decoding (and
  // allocating): no image larger than a camera file may state.
  const std::string side = std::to_string(ripple::tracking::kMaxImageSide);
  setenv("OPENCV_IO_MAX_IMAGE_WIDTH", side.c_str(), /*overwrite=*/0);
  setenv("OPENCV_IO_MAX_IMAGE_HEIGHT", side.c_str(), 0);
  const std::string pixels =
      std::to_string(static_cast<long long>(ripple::tracking::kMaxImageSide) *
                     ripple::tracking::kMaxImageSide);
  setenv("OPENCV_IO_MAX_IMAGE_PIXELS", pixels.c_str(), 0);
  CLI::App app{
      "Ripple: marker-tracked tabletop AR water.\n"
      "Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input "
      "file."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ripple 0.1.0");
  // Read above (before any library is used); declared so CLI11 accepts it
  // before or after the subcommand.
  app.add_flag("--verbose",
               "Show third-party libraries' log lines (FFmpeg, "
               "libpng, OpenCV) as well as ours");
  app.fallthrough();
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
  } catch (const std::bad_alloc&) {
    return Fail(kExitRuntime, "out of memory");
  } catch (const std::exception& e) {
    return Fail(kExitRuntime, std::string("unexpected error: ") + e.what());
  }
  return Fail(kExitBadInput, "no subcommand given (see ripple --help)");
}
