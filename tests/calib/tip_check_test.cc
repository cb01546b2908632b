#include "calib/tip_check.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "tests/shipped_data.h"

namespace ripple::calib {
namespace {

using test_data::DefaultRig;

TEST(TipCheckTest, CheckPointsAvoidTags) {
  const auto points = BoardCheckPoints(DefaultRig());
  ASSERT_EQ(points.size(), 5u);
  EXPECT_EQ(points[0].name, "P1");
  EXPECT_TRUE(points[0].point_in_tank.isZero());
  EXPECT_NEAR(points[2].point_in_tank.x(), 0.0425, 1e-9);
  EXPECT_NEAR(points[2].point_in_tank.y(), 0.0275, 1e-9);
}

TEST(TipCheckTest, MeasuresEachTouch) {
  const auto points = BoardCheckPoints(DefaultRig());
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0, 0.0003);
  std::vector<TipSample> samples;
  double t = 0;
  const Eigen::Vector3d offset(0.001, 0.0, 0.0005);  // the setup's error
  Eigen::Vector3d last(0, 0, 0.05);
  for (int p : {0, 1, 3}) {
    const Eigen::Vector3d target = points[p].point_in_tank + offset;
    for (int i = 0; i < 15; ++i, t += 1 / 30.0)  // moving there
      samples.push_back(
          {t, last + (target - last) * i / 15.0 +
                  Eigen::Vector3d(0, 0, 0.02 * std::sin(i / 5.0))});
    for (int i = 0; i < 30; ++i, t += 1 / 30.0)  // one second still
      samples.push_back(
          {t, target + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))});
    last = target;
  }
  TipCheckSummary summary;
  std::string error;
  ASSERT_TRUE(
      EvaluateTipCheck(TipCheckOptions(), points, samples, &summary, &error))
      << error;
  std::printf("%s", summary.BriefReport().c_str());
  ASSERT_EQ(summary.touches.size(), 3u);
  EXPECT_EQ(summary.touches[0].name, "P1");
  EXPECT_EQ(summary.touches[1].name, "P2");
  EXPECT_EQ(summary.touches[2].name, "P4");
  for (const auto& touch : summary.touches) {
    EXPECT_NEAR(touch.error_m, offset.norm(), 0.0002);
    EXPECT_NEAR(touch.error_z_m, 0.0005, 0.0002);
    EXPECT_GE(touch.samples, 28);
  }
}

TEST(TipCheckTest, NoTouchIsAnError) {
  const auto points = BoardCheckPoints(DefaultRig());
  std::vector<TipSample> samples;
  for (int i = 0; i < 100; ++i)  // always moving
    samples.push_back({i / 30.0, Eigen::Vector3d(0.002 * i, 0, 0.01)});
  TipCheckSummary summary;
  std::string error;
  EXPECT_FALSE(
      EvaluateTipCheck(TipCheckOptions(), points, samples, &summary, &error));
  EXPECT_NE(error.find("no touch"), std::string::npos);
}

TEST(TipCheckTest, WritesTheTouchesAsCsv) {
  TipCheckSummary summary;
  TouchResult touch;
  touch.name = "P2";
  touch.point_in_tank = Eigen::Vector3d(0.0425, 0.0275, 0);
  touch.measured_in_tank = Eigen::Vector3d(0.0435, 0.0275, 0.0005);
  touch.samples = 30;
  touch.start_s = 0.5;
  touch.end_s = 1.5;
  touch.error_m = 0.00112;
  touch.error_xy_m = 0.001;
  touch.error_z_m = 0.0005;
  summary.touches.push_back(touch);
  const std::string path = ::testing::TempDir() + "/tip_check_test.csv";
  std::string error;
  ASSERT_TRUE(WriteTipCheckCsv(summary, path, &error)) << error;
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(),
            "point,x_m,y_m,z_m,measured_x_m,measured_y_m,measured_z_m,"
            "samples,start_s,end_s,error_m,error_xy_m,error_z_m\n"
            "P2,0.04250,0.02750,0.00000,0.04350,0.02750,0.00050,30,0.500,"
            "1.500,0.00112,0.00100,0.00050\n");
  std::remove(path.c_str());
  EXPECT_FALSE(WriteTipCheckCsv(summary, "/nonexistent/dir/check.csv", &error));
  EXPECT_FALSE(error.empty());
}

}  // namespace
}  // namespace ripple::calib
