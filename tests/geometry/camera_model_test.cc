#include "geometry/camera_model.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>
#include <vector>

namespace ripple::geometry {
namespace {

// A webcam-like lens with every distortion term of OpenCV's rational model.
CameraModel DistortedCamera() {
  CameraModel c = MakeIdealCamera(640, 480, 60.0);
  c.fy = 1.01 * c.fx;
  c.cx += 3.2;
  c.cy -= 2.1;
  c.dist = {-0.21, 0.09, 0.0012, -0.0007, -0.015, 0.02, -0.01, 0.004};
  return c;
}

std::vector<Eigen::Vector3d> PointsInView(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> xy(-0.25, 0.25), z(0.3, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) {
    const double depth = z(rng);
    points.emplace_back(xy(rng) * depth, xy(rng) * depth, depth);
  }
  return points;
}

TEST(CameraModelTest, ProjectMatchesOpenCvProjectPoints) {
  for (const CameraModel& camera :
       {MakeIdealCamera(640, 480, 60.0), DistortedCamera()}) {
    const std::vector<Eigen::Vector3d> points = PointsInView(200, 1);
    std::vector<cv::Point3d> cv_points;
    for (const Eigen::Vector3d& p : points)
      cv_points.emplace_back(p.x(), p.y(), p.z());
    const cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0,
                       camera.fy, camera.cy, 0, 0, 1);
    const cv::Mat d(1, 8, CV_64F, const_cast<double*>(camera.dist.data()));
    std::vector<cv::Point2d> expected;
    cv::projectPoints(cv_points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d,
                      expected);
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d uv = camera.Project(points[i]);
      EXPECT_NEAR(uv.x(), expected[i].x, 1e-9) << i;
      EXPECT_NEAR(uv.y(), expected[i].y, 1e-9) << i;
    }
  }
}

TEST(CameraModelTest, JacobianMatchesFiniteDifferences) {
  const CameraModel camera = DistortedCamera();
  for (const Eigen::Vector3d& p : PointsInView(50, 2)) {
    Eigen::Matrix<double, 2, 3> j;
    const Eigen::Vector2d uv = camera.ProjectWithJacobian(p, &j);
    // Same pixel as Project() up to rounding (1/z is taken once here).
    EXPECT_LT((uv - camera.Project(p)).norm(), 1e-9);
    const double h = 1e-7;  // metres
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[c] = h;
      const Eigen::Vector2d numeric =
          (camera.Project(Eigen::Vector3d(p + dp)) -
           camera.Project(Eigen::Vector3d(p - dp))) /
          (2 * h);
      // Pixels per metre of order 1e3; central differences are good to ~1e-6
      // relative.
      EXPECT_NEAR(j(0, c), numeric.x(), 1e-5 * (1 + std::abs(numeric.x())));
      EXPECT_NEAR(j(1, c), numeric.y(), 1e-5 * (1 + std::abs(numeric.y())));
    }
  }
}

TEST(CameraModelTest, UndistortInvertsProjection) {
  for (const CameraModel& camera :
       {MakeIdealCamera(640, 480, 60.0), DistortedCamera()}) {
    for (const Eigen::Vector3d& p : PointsInView(100, 3)) {
      const Eigen::Vector2d n = camera.UndistortToNormalized(camera.Project(p));
      EXPECT_NEAR(n.x(), p.x() / p.z(), 1e-9);
      EXPECT_NEAR(n.y(), p.y() / p.z(), 1e-9);
    }
  }
}

TEST(CameraModelTest, ScaledKeepsTheImageEdges) {
  const CameraModel camera = DistortedCamera();
  const CameraModel half = camera.Scaled(320, 240);
  EXPECT_EQ(half.width, 320);
  EXPECT_DOUBLE_EQ(half.fx, 0.5 * camera.fx);
  // The continuous image edge (-0.5 px) stays the edge.
  EXPECT_DOUBLE_EQ((half.cx + 0.5) * 2, camera.cx + 0.5);
  EXPECT_EQ(half.dist, camera.dist);
}

TEST(CameraModelTest, Validates) {
  std::string error;
  EXPECT_FALSE(CameraModel{}.IsValid(&error));
  EXPECT_NE(error.find("image_width"), std::string::npos);
  CameraModel camera = MakeIdealCamera(640, 480, 60.0);
  EXPECT_TRUE(camera.IsValid(&error)) << error;
  EXPECT_FALSE(camera.HasDistortion());
  camera.dist[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(camera.HasDistortion());
  EXPECT_FALSE(camera.IsValid(&error));
  EXPECT_NE(error.find("distortion"), std::string::npos);
  EXPECT_EQ(DistortedCamera(), DistortedCamera());
  EXPECT_NE(DistortedCamera(), MakeIdealCamera(640, 480, 60.0));
}

}  // namespace
}  // namespace ripple::geometry
