// libFuzzer: the Matroska integrity check (app/app_matroska.h) on arbitrary
// bytes: it walks a container's element headers and CRC-32s itself.
#include <string>

#include "app/app_matroska.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ripple::fuzz::WriteInput("video.mkv", data, size);
  ripple::app::CheckMatroska(path);
  return 0;
}
