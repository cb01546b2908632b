// `ripple sim`: the .npy height export users check dispersion with, released
// drops, the slope report, and one clear line with exit 2 for every bad
// water option.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "tests/app/cli_test.h"

namespace ripple {
namespace {

using ::testing::HasSubstr;
using testing::RunRipple;

std::string Temp(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "ripple_sim_" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

// Reads a float32 C-order 2-D .npy as NumPy writes and reads it.
bool ReadNpy(const std::string& path, int* rows, int* cols,
             std::vector<float>* data) {
  std::ifstream in(path, std::ios::binary);
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "\x93NUMPY\x01\x00", 8) != 0)
    return false;
  unsigned char len[2];
  in.read(reinterpret_cast<char*>(len), 2);
  std::string header(len[0] | (len[1] << 8), ' ');
  in.read(header.data(), header.size());
  if ((10 + header.size()) % 64 != 0 || header.back() != '\n') return false;
  if (header.find("'descr': '<f4'") == std::string::npos ||
      header.find("'fortran_order': False") == std::string::npos)
    return false;
  if (std::sscanf(header.c_str() + header.find("'shape': (") + 10, "%d, %d",
                  rows, cols) != 2)
    return false;
  data->resize(static_cast<std::size_t>(*rows) * *cols);
  in.read(reinterpret_cast<char*>(data->data()), data->size() * 4);
  return static_cast<std::size_t>(in.gcount()) == data->size() * 4 &&
         in.peek() == EOF;
}

TEST(SimCliTest, NpyFramesOfAReleasedDrop) {
  const std::string dir = Temp("npy");
  const auto r = RunRipple(
      "sim --duration 0.2 --fps 30 --out " + dir +
      " --format npy --impulse 0.0,0.0,0.0,0.0005,0.003 --obstacles off");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("capillary-gravity"));
  // frames.csv: one row per frame, the pen out (empty tip).
  std::ifstream csv(dir + "/frames.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,time_s,tip_x_m,tip_y_m,tip_z_m");
  int rows_in_csv = 0;
  while (std::getline(csv, line)) {
    EXPECT_THAT(line, ::testing::EndsWith(",,,"));
    ++rows_in_csv;
  }
  EXPECT_EQ(rows_in_csv, 7);
  int ny = 0, nx = 0;
  std::vector<float> h0, h6;
  ASSERT_TRUE(ReadNpy(dir + "/frame_000000.npy", &ny, &nx, &h0));
  EXPECT_GE(nx, 256);  // the default grid resolves 4 mm ripples
  EXPECT_NEAR(ny * 0.17 / nx, 0.11, 0.5 * 0.17 / nx);
  // Frame 0 is the drop itself: its peak at the tank centre.
  const float peak = *std::max_element(h0.begin(), h0.end());
  EXPECT_NEAR(peak, 0.0005, 0.0001);
  // The drop spreads out: by 0.2 s the centre has fallen and rings stand
  // around it.
  ASSERT_TRUE(ReadNpy(dir + "/frame_000006.npy", &ny, &nx, &h6));
  const float centre = h6[static_cast<std::size_t>(ny / 2) * nx + nx / 2];
  EXPECT_LT(std::abs(centre), 0.5 * peak);
}

TEST(SimCliTest, StrokesReportSurfaceSlopes) {
  const auto r = RunRipple("sim --duration 1.2 --fps 30");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("surface slope while the pen acts"));
}

TEST(SimCliTest, BadWaterOptionsAreOneLineExit2) {
  for (const char* bad :
       {"--waves nope", "--pen nope", "--waves paper --pen displace",
        "--viscosity -1", "--viscosity nan", "--waves paper --viscosity 1e-6",
        "--damping 1", "--wave-speed 0.3", "--radius 0", "--sim-cells 1",
        "--walls soft", "--impulse 1,2,3", "--impulse 0,0,-1,0.001,0.002",
        "--impulse 0,0,0,0.001,0", "--format npy", "--out x.mp4 --format npy",
        "--format tiff --out d", "--obstacles zero", "--courant 0.3"}) {
    const auto r = RunRipple(std::string("sim --duration 0.1 ") + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_THAT(r.output, ::testing::ContainsRegex("--|water|must"))
        << bad << "\n"
        << r.output;
  }
}

TEST(SimCliTest, PaperModelStillRuns) {
  const auto r = RunRipple("sim --duration 0.3 --fps 30 --waves paper");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("paper waves"));
}

}  // namespace
}  // namespace ripple
