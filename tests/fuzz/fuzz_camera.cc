// libFuzzer: the camera loader (tracking/camera.h) on arbitrary bytes.
#include <string>

#include "tests/fuzz/fuzz_input.h"
#include "tracking/camera.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ripple::fuzz::WriteInput("camera.yml", data, size);
  std::string error;
  const auto camera = ripple::tracking::LoadCamera(path, &error);
  if (!camera && error.find(path) == std::string::npos) __builtin_trap();
  // What loads is usable: the size within the bounds the file reader states.
  if (camera && (camera->width < ripple::tracking::kMinImageSide ||
                 camera->width > ripple::tracking::kMaxImageSide ||
                 camera->height < ripple::tracking::kMinImageSide ||
                 camera->height > ripple::tracking::kMaxImageSide))
    __builtin_trap();
  return 0;
}
