// libFuzzer: the voxel obstacle reader (sim/obstacle.h) on arbitrary bytes.
#include <string>

#include "sim/obstacle.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = ripple::fuzz::WriteInput("obstacle.vox", data, size);
  ripple::sim::VoxelVolume volume;
  std::string error;
  if (ripple::sim::LoadVoxelVolume(path, 0.002, &volume, &error)) {
    if (!volume.IsValid(&error)) __builtin_trap();
  } else if (error.find(path) == std::string::npos) {
    __builtin_trap();
  }
  return 0;
}
