// libFuzzer targets for Ripple's file readers take paths, as the program
// does: each input is written to one scratch file (in /dev/shm when there
// is one) and the reader is called on it.
#ifndef RIPPLE_TESTS_FUZZ_FUZZ_INPUT_H_
#define RIPPLE_TESTS_FUZZ_FUZZ_INPUT_H_

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace ripple::fuzz {

// The scratch file `name` holding exactly `data`; its path.
inline std::string WriteInput(const char* name, const uint8_t* data,
                              size_t size) {
  static const std::string dir =
      access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path =
      dir + "/ripple_fuzz_" + std::to_string(getpid()) + "_" + name;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace ripple::fuzz

#endif  // RIPPLE_TESTS_FUZZ_FUZZ_INPUT_H_
