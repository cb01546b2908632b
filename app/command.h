// Subcommand registry for the single `ripple` binary. Each subcommand lives in
// its own file (COLMAP style) and registers itself at static-init time:
//
//   int RunSynth(const SynthArgs& args);
//   RIPPLE_REGISTER_COMMAND(synth, "Render ground-truth frames", SetupSynth);
//
// where SetupSynth(CLI::App* sub) adds the options and returns the action to
// run after parsing. Exit codes (DESIGN.md): 0 success, 1 runtime failure,
// 2 bad usage or a bad input file.
#ifndef RIPPLE_APP_COMMAND_H_
#define RIPPLE_APP_COMMAND_H_

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace ripple::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitRuntime = 1;
inline constexpr int kExitBadInput = 2;

using CommandAction = std::function<int()>;
using CommandSetup = std::function<CommandAction(CLI::App* sub)>;

struct CommandInfo {
  std::string name;
  std::string description;
  CommandSetup setup;
};

std::vector<CommandInfo>& CommandRegistry();

struct CommandRegistrar {
  CommandRegistrar(const char* name, const char* description,
                   CommandSetup setup) {
    CommandRegistry().push_back({name, description, std::move(setup)});
  }
};

#define RIPPLE_REGISTER_COMMAND(name, description, setup)       \
  static ::ripple::app::CommandRegistrar ripple_command_##name( \
      #name, description, setup)

// Prints "ripple: <message>" on stderr and returns `code`; the one clear line
// every failure ends with.
int Fail(int code, const std::string& message);

}  // namespace ripple::app

#endif  // RIPPLE_APP_COMMAND_H_
