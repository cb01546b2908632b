// The command line contract: help, exit codes, one clear message per bad
// input, and `ripple synth`'s outputs.
#include "tests/app/cli_test.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace ripple {
namespace {

using ::testing::HasSubstr;
using testing::RunRipple;

std::string Temp(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "ripple_cli_" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CliTest, HelpAndUsageErrors) {
  auto r = RunRipple("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("synth"));
  r = RunRipple("synth --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("--preset"));
  EXPECT_EQ(RunRipple("").exit_code, 2);
  EXPECT_EQ(RunRipple("no-such-command").exit_code, 2);
  EXPECT_EQ(RunRipple("synth").exit_code, 2);  // --out is required
  EXPECT_EQ(RunRipple("synth --out x --frames -3").exit_code, 2);
  EXPECT_EQ(RunRipple("synth --out x --preset nope").exit_code, 2);
}

TEST(CliTest, MalformedSizesAndPatternsAreUsageErrors) {
  for (const char* command :
       {"synth --out x --size 64by48", "live --size 0x480",
        "bench tracking --sizes 640x480,1280",
        "markers --out x --chessboard 1x6",
        "calib camera --input x --out x.yml --chessboard 9x"}) {
    const auto r = RunRipple(command);
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_THAT(r.output, ::testing::ContainsRegex("--(size|sizes|chessboard)"))
        << command;
  }
}

TEST(CliTest, BadFilesGiveOneLineAndExitCode2) {
  const std::string dir = Temp("bad");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/broken.yml")
      << "%YAML:1.0\n---\nrig_version: 1\ntank: [ {\n";
  auto r = RunRipple("synth --out " + dir + "/o --frames 1 --rig " + dir +
                     "/broken.yml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr(dir + "/broken.yml"));
  r = RunRipple("synth --out " + dir + "/o --frames 1 --camera " + dir +
                "/missing.yml");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("missing.yml"));
  EXPECT_THAT(r.output, HasSubstr("cannot open"));
  r = RunRipple("synth --out " + dir + "/o --frames 1 --size 64by48");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--size"));
  r = RunRipple("synth --out /proc/ripple_cannot_write --frames 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("/proc/ripple_cannot_write"));
  // Never a partial success line after a failure.
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("synth: 1 frames")));
}

TEST(CliTest, SynthWritesFramesFilesAndIsDeterministic) {
  const std::string a = Temp("a"), b = Temp("b");
  auto r =
      RunRipple("synth --out " + a + " --frames 3 --size 320x240 --seed 9");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunRipple("synth --out " + b + " --frames 3 --size 320x240 --seed 9");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"camera.yml", "rig.yml", "groundtruth.csv",
                        "frames/000000.png", "frames/000002.png"}) {
    EXPECT_TRUE(std::filesystem::exists(a + "/" + f)) << f;
    EXPECT_EQ(ReadAll(a + "/" + f), ReadAll(b + "/" + f)) << f;
  }
  // The written camera and rig are readable by the next command.
  r = RunRipple("synth --out " + b + "/again --frames 1 --camera " + a +
                "/camera.yml --rig " + a + "/rig.yml");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = ReadAll(a + "/groundtruth.csv");
  EXPECT_THAT(csv, HasSubstr("0,0.000000,tank,tracked,"));
  EXPECT_THAT(csv, HasSubstr("0,0.000000,pen,tracked,"));
}

}  // namespace
}  // namespace ripple
