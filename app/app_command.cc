// The subcommand registries and the one-line failure report (app/command.h).
#include <cstdio>

#include "app/command.h"

namespace ripple::app {

std::vector<CommandInfo>& CommandRegistry() {
  static std::vector<CommandInfo> registry;
  return registry;
}

int Fail(int code, const std::string& message) {
  std::fprintf(stderr, "ripple: %s\n", message.c_str());
  return code;
}

}  // namespace ripple::app
