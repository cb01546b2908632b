// The command line contract: help, exit codes, one clear message per bad
// input, and `ripple synth`'s outputs.
#include "tests/app/cli_test.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace ripple {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
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

TEST(CliTest, BadSmoothingOptionsExitCode2) {
  EXPECT_EQ(RunRipple("track --input x --out y --smoothing maybe").exit_code,
            2);
  for (const std::string option :
       {"--smooth-pen-hz -1", "--smooth-pen-rot-hz 0", "--smooth-tank-hz -2",
        "--smooth-max-lag 0", "--smooth-pen-beta -1",
        "--smooth-bridge-loss -0.1"}) {
    const auto r = RunRipple("track --input x --out y " + option);
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_THAT(r.output, HasSubstr(option.substr(0, option.find(' '))))
        << option;
  }
  const auto r =
      RunRipple("bench tracking --sweep smoothing --smoothing-grid 1/2/3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.output, HasSubstr("--smoothing-grid"));
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

// Every command that draws the board takes the same --floor: bad names and
// unreadable images are one line and exit code 2, before any work starts.
TEST(CliTest, FloorOptionIsCheckedTheSameEverywhere) {
  const std::string dir = Temp("floor");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/text.png") << "not an image";
  for (const std::string& command :
       {"markers --out " + dir + "/m", "synth --frames 1 --out " + dir + "/s",
        "demo --frames 10 --idle-frames 1 --out " + dir + "/d",
        "bench tracking --frames 1 --sizes 64x48 --out " + dir + "/b"}) {
    auto r = RunRipple(command + " --floor tile");
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr("--floor")) << command;
    EXPECT_THAT(r.output, HasSubstr("expected plain, tiles or an image file"))
        << command;
    for (const std::string& bad : {dir + "/missing.png", dir + "/text.png"}) {
      r = RunRipple(command + " --floor " + bad);
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
      EXPECT_THAT(r.output, HasSubstr("ripple: --floor: floor image '" + bad))
          << command;
      EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
          << r.output;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/s/groundtruth.csv"));
}

TEST(CliTest, SynthDrawsTheChosenFloor) {
  const std::string dir = Temp("synth_floor");
  for (const char* floor : {"plain", "tiles"}) {
    const auto r = RunRipple("synth --out " + dir + "/" + floor +
                             " --frames 1 --size 320x240 --preset clean "
                             "--floor " +
                             floor);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr(std::string(floor) + " floor"));
  }
  // The default is tiles.
  const auto r = RunRipple("synth --out " + dir +
                           "/default --frames 1 --size "
                           "320x240 --preset clean");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string frame = "/frames/000000.png";
  EXPECT_EQ(ReadAll(dir + "/default" + frame), ReadAll(dir + "/tiles" + frame));
  EXPECT_NE(ReadAll(dir + "/plain" + frame), ReadAll(dir + "/tiles" + frame));
}

}  // namespace
// The water's optics options: bad names and out-of-range values are one
// line and exit code 2, before any work starts.
TEST(CliTest, LightOptionIsChecked) {
  const std::string dir = Temp("light");
  for (const std::string& bad :
       {std::string("--light 30"), std::string("--light 30,0"),
        std::string("--light 30,95"), std::string("--light 400,45"),
        std::string("--light a,45"), std::string("--light 30,45,1"),
        std::string("--light 30,nan")}) {
    const auto r =
        RunRipple("demo --frames 10 --idle-frames 1 --out " + dir + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
    EXPECT_THAT(r.output, HasSubstr("--light")) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/demo.mp4"));
  // A fixed light is used as given.
  const auto r = RunRipple("demo --frames 10 --idle-frames 1 --out " + dir +
                           " --light 140,55");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("light: azimuth 140.0, elevation 55.0 deg"));
}

TEST(CliTest, OpticsOptionsAreChecked) {
  const std::string dir = Temp("optics");
  for (const std::string& bad :
       {std::string("--water-look murky"), std::string("--ambient 1.5"),
        std::string("--ambient -0.1"), std::string("--light-size 0"),
        std::string("--light-size 90"), std::string("--shadows blur"),
        std::string("--shadow-sigma 9"),
        std::string("--refraction-filter sharp"),
        std::string("--tank-shadow maybe")}) {
    const auto r =
        RunRipple("demo --frames 10 --idle-frames 1 --out " + dir + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
  }
  // Not a number: CLI11's usage error.
  EXPECT_EQ(RunRipple("demo --out " + dir + " --ambient x").exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/demo.mp4"));
  // A camera file states its transfer: srgb or linear, nothing else.
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/camera.yml")
      << "%YAML:1.0\nimage_width: 64\nimage_height: 48\ncamera_matrix: "
         "!!opencv-matrix\n"
         "  rows: 3\n  cols: 3\n  dt: d\n  data: [60, 0, 32, 0, 60, 24, 0, 0, "
         "1]\n"
         "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 5\n"
         "  dt: d\n  data: [0, 0, 0, 0, 0]\ntransfer: gamma\n";
  const auto r = RunRipple("synth --frames 1 --out " + dir + "/s --camera " +
                           dir + "/camera.yml");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("field 'transfer' must be srgb or linear"));
}

// --sun sets the light from the solar position; a bad place or time, --sun
// with --light, a bearing or turbidity out of range is one line and exit 2;
// a sun below the horizon runs with the direct light off.
TEST(CliTest, SunOptionIsChecked) {
  const std::string dir = Temp("sun_option");
  for (const std::string& bad :
       {std::string("--sun 48.14,11.58"),
        std::string("--sun 48.14,11.58,2026-06-21T12:00Z --turbidity 12"),
        std::string("--reflection mirror"),
        std::string("--sun 48.14,11.58,2026-06-21T12:00"),
        std::string("--sun 95,11.58,2026-06-21T12:00Z"),
        std::string("--sun 48.14,11.58,2026-06-21T12:00Z --light 30,60"),
        std::string("--sun 48.14,11.58,2026-06-21T12:00Z --north 400")}) {
    const auto r =
        RunRipple("demo --frames 10 --idle-frames 1 --out " + dir + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
  }
  const auto r = RunRipple("demo --frames 10 --idle-frames 1 --out " + dir +
                           " --sun 48.14,11.58,2026-06-21T23:30+02:00");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("below the horizon (direct light off)"));
  EXPECT_THAT(r.output, HasSubstr("sky share 1.00"));
}

// `ripple bench render` end to end on small frames: one row per scene in
// the CSV with FLIP values in [0, 1], the panels and, with --export, the
// renderer-neutral scene files; bad scene names are one line, exit 2.
TEST(CliTest, BenchRenderComparesAgainstTheReference) {
  const std::string dir = Temp("bench_render");
  auto r = RunRipple(
      "bench render --size 96x72 --spp 1 --timing-frames 1 "
      "--scenes flat ring --out " +
      dir + "/out --export " + dir + "/scenes");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(dir + "/out/bench_render.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_THAT(header, HasSubstr("scene,water_pixels,flip,flip_open_water,"
                                "flip_no_reflection"));
  int rows = 0;
  double ring_flip = -1;
  while (std::getline(csv, line)) {
    ++rows;
    std::stringstream ss(line);
    std::string name, pixels, flip;
    std::getline(ss, name, ',');
    std::getline(ss, pixels, ',');
    std::getline(ss, flip, ',');
    EXPECT_GT(std::stoi(pixels), 100) << line;
    EXPECT_GT(std::stod(flip), 0.0) << line;
    EXPECT_LT(std::stod(flip), 1.0) << line;
    if (name == "ring") ring_flip = std::stod(flip);
  }
  EXPECT_EQ(rows, 2);
  for (const char* f :
       {"/out/flat.png", "/out/ring.png", "/scenes/ring/heights.npy",
        "/scenes/ring/scene.yml", "/scenes/ring/camera.yml",
        "/scenes/ring/video.png", "/scenes/ring/reference.png",
        "/scenes/ring/realtime.png", "/scenes/flat/floor_albedo.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + f)) << f;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/scenes/flat/heights.npy"));

  // `ripple bench flip` scores the exported real-time render as the
  // benchmark did; a reference against itself scores 0.
  const std::string ring = dir + "/scenes/ring/";
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                ring + "realtime.png --mask " + ring + "water_mask.png --map " +
                dir + "/ring_flip.png");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const size_t at = r.output.find("mean ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_NEAR(std::stod(r.output.substr(at + 5)), ring_flip, 1e-4) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/ring_flip.png"));
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                ring + "reference.png");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("mean 0.0000, median 0.0000, p95 0.0000"));
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                dir + "/out/ring.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(", the reference 96x72"));
  r = RunRipple("bench flip --reference " + ring + "scene.yml --test " + ring +
                "realtime.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("not a readable PNG or JPEG"));
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                ring + "realtime.png --mask " + dir + "/missing.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("cannot be opened"));
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                ring + "realtime.png --map " + dir + "/no/such/map.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("its folder does not exist"));
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                ring + "realtime.png --map " + dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("is a folder"));
  // A truncated PNG: our one line, not libpng's.
  {
    std::ifstream in(ring + "realtime.png", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir + "/truncated.png", std::ios::binary)
        << bytes.substr(0, 100);
  }
  r = RunRipple("bench flip --reference " + ring + "reference.png --test " +
                dir + "/truncated.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("not a readable PNG or JPEG"));
  EXPECT_THAT(r.output, Not(HasSubstr("libpng")));
  r = RunRipple("bench render --scenes puddle --out " + dir + "/bad");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("unknown scene 'puddle'"));
  r = RunRipple("bench render --water-look murky --out " + dir + "/bad2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--water-look 'murky'"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad2"));
  r = RunRipple("bench render --shadows blur --out " + dir + "/bad3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--shadows 'blur'"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad3"));
  r = RunRipple("bench render --refraction-filter sharp --out " + dir +
                "/bad4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--refraction-filter 'sharp'"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad4"));
  r = RunRipple("bench render --tank-shadow maybe --out " + dir + "/bad5");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--tank-shadow 'maybe'"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad5"));
}

// `ripple sun`: NREL SPA's worked example (azimuth 194.340, true elevation
// 39.872 deg; render/sun_test has the reference) and a polar night; every
// bad input is one `ripple:` line and exit code 2.
TEST(CliTest, SunPrintsThePositionAndTheSky) {
  auto r = RunRipple("sun 39.742476 -105.1786 2003-10-17T12:30:30-07:00");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::ContainsRegex(
                            "azimuth: +194\\.34[0-9] deg \\(clockwise from "
                            "true north\\)"));
  EXPECT_THAT(r.output,
              ::testing::ContainsRegex("elevation, true: +39\\.87[0-9] deg"));
  EXPECT_THAT(r.output,
              ::testing::ContainsRegex("elevation, apparent: +39\\.89[0-9] deg "
                                       "\\(refraction included"));
  EXPECT_THAT(r.output, ::testing::ContainsRegex("below horizon: +no"));
  EXPECT_THAT(r.output, HasSubstr("zenith colour:"));
  EXPECT_THAT(r.output, HasSubstr("ambient colour:"));
  EXPECT_THAT(r.output, HasSubstr("turbidity 3.00"));
  r = RunRipple(
      "sun 78.2232 15.6267 2024-12-21T12:00:00+01:00 --turbidity 2.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::ContainsRegex("elevation, true: +-11\\.6"));
  EXPECT_THAT(r.output, ::testing::ContainsRegex("below horizon: +yes"));
  EXPECT_THAT(r.output, ::testing::ContainsRegex("sky: +none"));
  r = RunRipple("sun --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("LAT LON DATETIME"));
  EXPECT_THAT(RunRipple("--help").output, HasSubstr("sun"));

  const struct {
    const char* args;
    const char* message;
  } kBad[] = {
      {"91 0 2026-06-21T12:00Z", "LAT '91' must be a number"},
      {"-90.5 0 2026-06-21T12:00Z", "LAT '-90.5'"},
      {"north 0 2026-06-21T12:00Z", "LAT 'north'"},
      {"0 180.5 2026-06-21T12:00Z", "LON '180.5' must be a number"},
      {"0 -181 2026-06-21T12:00Z", "LON '-181'"},
      {"0 12e 2026-06-21T12:00Z", "LON '12e'"},
      {"0 0 2026-06-21T12:00", "no time zone"},
      {"0 0 2026-13-21T12:00Z", "month 13"},
      {"0 0 2026-04-31T12:00Z", "day 31 does not exist in 2026-04"},
      {"0 0 2026-06-21T12:00+14:30", "beyond +-14:00"},
      {"0 0 21.06.2026", "bad date-time '21.06.2026'"},
      {"0 0 2026-06-21T12:00Z --turbidity 12", "--turbidity '12'"},
      {"0 0 2026-06-21T12:00Z --turbidity 1.2", "[1.7, 10]"},
      {"0 0 2026-06-21T12:00Z --turbidity haze", "--turbidity 'haze'"},
  };
  for (const auto& bad : kBad) {
    r = RunRipple(std::string("sun ") + bad.args);
    EXPECT_EQ(r.exit_code, 2) << bad.args << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(bad.message)) << bad.args;
    EXPECT_EQ(r.output.rfind("ripple: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
  }
  EXPECT_EQ(RunRipple("sun 0 0").exit_code, 2);  // DATETIME is required
}

}  // namespace ripple
