// Registration by the renderer's own matrices: tank corners land where
// cv::projectPoints puts them, to 0.01 px (catches the half-pixel error).
#include "render/camera.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <vector>

#include "render/renderer.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::LookAt;
using testing::MakeIntrinsics;

std::vector<cv::Point2d> CvProject(const Intrinsics& k, const glm::dmat4& m,
                                   const std::vector<glm::dvec3>& pts,
                                   bool with_distortion) {
  cv::Mat r(3, 3, CV_64F), t(3, 1, CV_64F), rvec;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r.at<double>(i, j) = m[j][i];
    t.at<double>(i) = m[3][i];
  }
  cv::Rodrigues(r, rvec);
  const cv::Matx33d kk(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  std::vector<double> dist(k.dist.begin(), k.dist.end());
  if (!with_distortion) dist.assign(8, 0.0);
  std::vector<cv::Point3d> obj;
  for (const auto& p : pts) obj.emplace_back(p.x, p.y, p.z);
  std::vector<cv::Point2d> img;
  cv::projectPoints(obj, rvec, t, kk, dist, img);
  return img;
}

std::vector<glm::dvec3> TankCorners(const TankGeometry& t) {
  std::vector<glm::dvec3> c;
  for (double z : {0.0, double(t.water_level), double(t.wall_height)}) {
    for (double sx : {-0.5, 0.5}) {
      for (double sy : {-0.5, 0.5})
        c.emplace_back(sx * t.size_x, sy * t.size_y, z);
    }
  }
  return c;
}

TEST(CameraTest, TankCornersMatchProjectPoints) {
  const TankGeometry tank;
  struct Case {
    Intrinsics k;
    glm::dvec3 eye;
  };
  Intrinsics odd = MakeIntrinsics(640, 480);
  odd.fx = 610.3;
  odd.fy = 604.9;
  odd.cx = 331.7;
  odd.cy = 228.2;
  const Case cases[] = {
      {MakeIntrinsics(640, 480), {0.0, -0.24, 0.22}},
      {MakeIntrinsics(320, 240, 75), {0.17, -0.17, 0.12}},
      {odd, {-0.1, 0.2, 0.3}},
      {MakeIntrinsics(1280, 720, 70), {0.02, -0.05, 0.35}},
  };
  for (const Case& c : cases) {
    const glm::dmat4 cam_from_tank = LookAt(c.eye, glm::dvec3(0.01, 0, 0.02));
    const glm::dmat4 clip_from_tank = ClipFromCam(c.k) * cam_from_tank;
    const auto corners = TankCorners(tank);
    const auto expected = CvProject(c.k, cam_from_tank, corners, false);
    for (size_t i = 0; i < corners.size(); ++i) {
      const glm::dvec2 window = WindowFromClip(
          clip_from_tank * glm::dvec4(corners[i], 1.0), c.k.width, c.k.height);
      const glm::dvec2 px = PixelFromWindow(window);
      EXPECT_NEAR(px.x, expected[i].x, 0.01) << "corner " << i;
      EXPECT_NEAR(px.y, expected[i].y, 0.01) << "corner " << i;
    }
  }
}

TEST(CameraTest, DepthRangeMapsNearAndFar) {
  const Intrinsics k = MakeIntrinsics(640, 480);
  const glm::dmat4 m = ClipFromCam(k, 0.01, 20.0);
  const glm::dvec4 n = m * glm::dvec4(0, 0, 0.01, 1),
                   f = m * glm::dvec4(0, 0, 20.0, 1);
  EXPECT_NEAR(n.z / n.w, -1.0, 1e-12);
  EXPECT_NEAR(f.z / f.w, 1.0, 1e-12);
}

// The undistortion map evaluates OpenCV's distortion model forwards.
TEST(CameraTest, DistortedPixelMatchesProjectPoints) {
  Intrinsics k = MakeIntrinsics(640, 480);
  k.dist = {-0.21, 0.08, 0.0012, -0.0007, -0.01, 0.002, 0.001, -0.003};
  const glm::dmat4 cam_from_tank = LookAt({0.05, -0.22, 0.2}, {0, 0, 0});
  const auto corners = TankCorners(TankGeometry{});
  const auto expected = CvProject(k, cam_from_tank, corners, true);
  for (size_t i = 0; i < corners.size(); ++i) {
    const glm::dvec3 c = glm::dvec3(cam_from_tank * glm::dvec4(corners[i], 1));
    const glm::dvec2 px = DistortedPixel(k, c.x / c.z, c.y / c.z);
    EXPECT_NEAR(px.x, expected[i].x, 1e-6);
    EXPECT_NEAR(px.y, expected[i].y, 1e-6);
  }
}

TEST(CameraTest, IntrinsicsValidation) {
  std::string error;
  EXPECT_FALSE(Intrinsics{}.IsValid(&error));
  EXPECT_FALSE(error.empty());
  EXPECT_TRUE(MakeIntrinsics(640, 480).IsValid(&error));
  EXPECT_FALSE(MakeIntrinsics(640, 480).HasDistortion());
  EXPECT_TRUE(ParseBackend("egl").has_value());
  EXPECT_FALSE(ParseBackend("vulkan").has_value());
}

}  // namespace
}  // namespace ripple::render
