// libFuzzer: a raw recording's timestamps.csv (app/app_source.h) on
// arbitrary bytes, for a folder of 3 images.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <string>
#include <vector>

#include "app/app_source.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path =
      ripple::fuzz::WriteInput("timestamps.csv", data, size);
  // The reader takes the folder; the scratch file is DIR/timestamps.csv
  // through a per-process folder holding a link to it.
  static const std::string dir = [&] {
    const std::string d = "/tmp/ripple_fuzz_ts_" + std::to_string(getpid());
    mkdir(d.c_str(), 0700);
    unlink((d + "/timestamps.csv").c_str());
    if (symlink(path.c_str(), (d + "/timestamps.csv").c_str()) != 0)
      __builtin_trap();
    return d;
  }();
  std::vector<double> times;
  std::string error;
  if (ripple::app::ReadFolderTimestamps(dir, 3, &times, &error)) {
    // Accepted: one finite, non-decreasing time per image.
    if (times.size() != 3) __builtin_trap();
    for (size_t i = 0; i < times.size(); ++i)
      if (!std::isfinite(times[i]) || (i > 0 && times[i] < times[i - 1]))
        __builtin_trap();
  } else if (error.find("timestamps.csv") == std::string::npos) {
    __builtin_trap();
  }
  return 0;
}
