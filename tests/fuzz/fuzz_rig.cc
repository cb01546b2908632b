// libFuzzer: the rig loader (tracking/rig.h) on arbitrary bytes. A crash,
// hang, leak or sanitizer report is a finding; a rejected file is not.
#include <string>

#include "tests/fuzz/fuzz_input.h"
#include "tracking/rig.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ripple::fuzz::WriteInput("rig.yml", data, size);
  std::string error;
  const auto rig = ripple::tracking::LoadRig(path, &error);
  // Every failure names the file.
  if (!rig && error.find(path) == std::string::npos) __builtin_trap();
  return 0;
}
