// libFuzzer: the pose CSV reader (tracking/pose_csv.h) on arbitrary bytes.
#include <string>

#include "tests/fuzz/fuzz_input.h"
#include "tracking/pose_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ripple::fuzz::WriteInput("poses.csv", data, size);
  std::string error;
  const auto rows = ripple::tracking::ReadPoseCsv(path, &error);
  if (!rows && error.find(path) == std::string::npos) __builtin_trap();
  return 0;
}
