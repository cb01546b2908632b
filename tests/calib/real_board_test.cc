// Real data: recover the ViSP board's layout (../shared/data/real/
// visp_board_sequence, 99 hand-held frames) with `ripple calib rig` and
// compare it with board_layout.csv there (medians of ViSP's back-projected
// corners, about +-1 mm). Skips when the folder is absent, except under
// CI=true where it must be present.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tests/app/cli_test.h"
#include "tracking/rig.h"

namespace ripple::calib {
namespace {

namespace fs = std::filesystem;

std::map<int, std::array<Eigen::Vector3d, 4>> LoadLayout(
    const std::string& path) {
  std::map<int, std::array<Eigen::Vector3d, 4>> layout;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("id", 0) == 0) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    int id, seen;
    s >> id >> seen;
    std::array<Eigen::Vector3d, 4> c;
    for (auto& p : c) {
      p.z() = 0;
      s >> p.x() >> p.y();
    }
    layout[id] = c;
  }
  return layout;
}

// Corners of `rig` rigidly aligned (Umeyama, no scale) onto the layout's;
// returns the per-corner distances by tag.
std::map<int, std::array<double, 4>> AlignedErrors(
    const tracking::Rig& rig,
    const std::map<int, std::array<Eigen::Vector3d, 4>>& layout) {
  std::vector<int> ids;
  for (const auto& [id, c] : layout)
    if (rig.FindTankTag(id)) ids.push_back(id);
  Eigen::Matrix3Xd a(3, 4 * ids.size()), b(3, 4 * ids.size());
  for (size_t i = 0; i < ids.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      a.col(4 * i + k) = rig.FindTankTag(ids[i])->CornerInObject(k);
      b.col(4 * i + k) = layout.at(ids[i])[k];
    }
  const Eigen::Matrix4d t = Eigen::umeyama(a, b, false);
  std::map<int, std::array<double, 4>> errors;
  for (size_t i = 0; i < ids.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p =
          t.topLeftCorner<3, 3>() * a.col(4 * i + k) + t.topRightCorner<3, 1>();
      errors[ids[i]][k] = (p - b.col(4 * i + k)).norm();
    }
  return errors;
}

void Stats(const std::map<int, std::array<double, 4>>& errors, double* rms,
           double* max) {
  double sse = 0;
  int n = 0;
  *max = 0;
  for (const auto& [id, e] : errors)
    for (double d : e) sse += d * d, ++n, *max = std::max(*max, d);
  *rms = std::sqrt(sse / std::max(n, 1));
}

TEST(RealBoardTest, RecoversLayoutOfVispBoard) {
  const std::string dir =
      std::string(RIPPLE_REAL_DATA_DIR) + "/visp_board_sequence";
  if (!fs::exists(dir + "/frames")) {
    const char* ci = std::getenv("CI");
    if (ci && std::string(ci) == "true")
      FAIL() << "CI=true but the real data is missing: " << dir;
    GTEST_SKIP() << "real data not present: " << dir;
  }
  const std::string out = ::testing::TempDir() + "/visp_board_refined.yml";
  fs::remove(out);
  const std::string src = RIPPLE_SOURCE_DIR;
  const auto r =
      testing::RunRipple("calib rig --input " + dir + "/frames --camera " +
                         src + "/data/camera/visp_640x480.yml --rig " + src +
                         "/data/rig/visp_board.yml --object tank --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::cout << r.output;
  std::string error;
  const auto refined = tracking::LoadRig(out, &error);
  ASSERT_TRUE(refined) << error;
  const auto nominal =
      tracking::LoadRig(src + "/data/rig/visp_board.yml", &error);
  ASSERT_TRUE(nominal) << error;
  const auto layout = LoadLayout(dir + "/board_layout.csv");
  ASSERT_EQ(layout.size(), 10u);

  double rms_nominal, max_nominal, rms, max;
  Stats(AlignedErrors(*nominal, layout), &rms_nominal, &max_nominal);
  const auto errors = AlignedErrors(*refined, layout);
  Stats(errors, &rms, &max);
  for (const auto& [id, e] : errors)
    std::printf("tag %2d corner errors mm: %.2f %.2f %.2f %.2f\n", id,
                1e3 * e[0], 1e3 * e[1], 1e3 * e[2], 1e3 * e[3]);
  std::printf(
      "layout vs board_layout.csv (rigid alignment): nominal RMS %.2f mm max "
      "%.2f mm; calibrated RMS %.2f mm max %.2f mm\n",
      1e3 * rms_nominal, 1e3 * max_nominal, 1e3 * rms, 1e3 * max);
  EXPECT_LT(rms, 0.0015);
  EXPECT_LT(max, 0.004);

  // From a wrong start: every tag moved in the board plane by up to 5 mm
  // and 2 degrees (a badly measured layout); the video alone brings it back.
  tracking::Rig wrong = *nominal;
  for (auto& t : wrong.tank_tags) {
    const double a = 0.7 * t.id;
    t.object_from_tag =
        t.object_from_tag *
        tracking::Pose::FromAxisAngle(
            Eigen::Vector3d(0, 0, 2.0 * M_PI / 180 * std::sin(a)),
            Eigen::Vector3d(0.005 * std::cos(a), 0.005 * std::sin(2 * a), 0));
  }
  const std::string wrong_path = ::testing::TempDir() + "/visp_wrong.yml";
  ASSERT_TRUE(tracking::SaveRig(wrong, wrong_path, &error)) << error;
  const std::string out2 = ::testing::TempDir() + "/visp_from_wrong.yml";
  const auto r2 =
      testing::RunRipple("calib rig --input " + dir + "/frames --camera " +
                         src + "/data/camera/visp_640x480.yml --rig " +
                         wrong_path + " --object tank --out " + out2);
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  const auto from_wrong = tracking::LoadRig(out2, &error);
  ASSERT_TRUE(from_wrong) << error;
  double rms_wrong, max_wrong, rms2, max2;
  Stats(AlignedErrors(wrong, layout), &rms_wrong, &max_wrong);
  Stats(AlignedErrors(*from_wrong, layout), &rms2, &max2);
  std::printf(
      "from a perturbed start: start RMS %.2f mm max %.2f mm; calibrated "
      "RMS %.2f mm max %.2f mm\n",
      1e3 * rms_wrong, 1e3 * max_wrong, 1e3 * rms2, 1e3 * max2);
  EXPECT_LT(rms2, 0.0015);
  EXPECT_LT(max2, 0.004);
}

}  // namespace
}  // namespace ripple::calib
