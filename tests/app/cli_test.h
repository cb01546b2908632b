// Runs the `ripple` binary in tests and captures its exit code and output.
#ifndef RIPPLE_TESTS_APP_CLI_TEST_H_
#define RIPPLE_TESTS_APP_CLI_TEST_H_

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace ripple::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs `ripple <args>` through the shell (args are shell words).
inline CommandResult RunRipple(const std::string& args) {
  CommandResult r;
  const std::string cmd = std::string(RIPPLE_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
    r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace ripple::testing

#endif  // RIPPLE_TESTS_APP_CLI_TEST_H_
