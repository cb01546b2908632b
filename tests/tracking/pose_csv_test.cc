#include "tracking/pose_csv.h"

#include <gtest/gtest.h>

#include <fstream>

namespace ripple::tracking {
namespace {

TEST(PoseTest, ComposeInvertAndLookAt) {
  const Pose a = Pose::FromAxisAngle({0.3, -0.2, 0.9}, {0.1, 0.2, 0.3});
  const Pose b = Pose::FromAxisAngle({-1.1, 0.4, 0.2}, {-0.5, 0.0, 0.7});
  const Eigen::Vector3d p(0.3, -0.4, 0.5);
  EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
  EXPECT_LT((a.Inverse() * (a * p) - p).norm(), 1e-12);
  EXPECT_LT(RotationDistance(a * a.Inverse(), Pose()), 1e-12);
  EXPECT_LT((a.Matrix() * p.homogeneous() - (a * p).homogeneous()).norm(),
            1e-12);
  // LookAt: the target lies on the optical axis (+z), image y points down.
  const Pose world_from_cam = LookAt({0, 0, 1}, {0, 0, 0}, {0, 1, 0});
  const Eigen::Vector3d t_in_cam =
      world_from_cam.Inverse() * Eigen::Vector3d(0, 0, 0);
  EXPECT_LT((t_in_cam - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((world_from_cam.R().col(1) - Eigen::Vector3d(0, -1, 0)).norm(),
            1e-12);
}

TEST(PoseCsvTest, RoundTripAndCanonicalQuaternion) {
  const std::string path = ::testing::TempDir() + "poses.csv";
  PoseCsvWriter w;
  std::string error;
  ASSERT_TRUE(w.Open(path, &error)) << error;
  PoseRow tank;
  tank.frame = 3;
  tank.time_s = 0.1;
  tank.object = "tank";
  tank.status = TrackStatus::kTracked;
  // A quaternion with w < 0 must be written with qw >= 0.
  tank.cam_from_object =
      Pose(Eigen::Quaterniond(-0.5, 0.5, -0.5, 0.5), {0.01, -0.02, 0.5});
  tank.faces = {1, 2, 7};
  tank.reproj_rmse_px = 0.25;
  tank.ms = 1.5;
  PoseRow pen;
  pen.frame = 3;
  pen.time_s = 0.1;
  pen.object = "pen";
  pen.status = TrackStatus::kLost;
  ASSERT_TRUE(w.Write(tank));
  ASSERT_TRUE(w.Write(pen));
  ASSERT_TRUE(w.Close());
  std::ifstream in(path);
  std::string header, row1, row2;
  std::getline(in, header);
  std::getline(in, row1);
  std::getline(in, row2);
  EXPECT_EQ(header,
            "frame,time_s,object,status,tx,ty,tz,qw,qx,qy,qz,tip_x,tip_y,tip_z,"
            "faces,reproj_rmse_px,ms");
  EXPECT_NE(row1.find(",0.500000000,-0.500000000,0.500000000,-0.500000000,"),
            std::string::npos)
      << row1;
  EXPECT_EQ(row2, "3,0.100000,pen,lost,,,,,,,,,,,,0.0000,0.0000");
  const auto rows = ReadPoseCsv(path, &error);
  ASSERT_TRUE(rows) << error;
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0].faces, std::vector<int>({1, 2, 7}));
  ASSERT_TRUE((*rows)[0].cam_from_object);
  EXPECT_LT(
      RotationDistance(*(*rows)[0].cam_from_object, *tank.cam_from_object),
      1e-8);
  EXPECT_FALSE((*rows)[1].cam_from_object);
  EXPECT_EQ((*rows)[1].status, TrackStatus::kLost);
}

TEST(PoseCsvTest, BadFilesAreRejectedWithLineNumbers) {
  const std::string path = ::testing::TempDir() + "bad_poses.csv";
  std::ofstream(path) << kPoseCsvHeader
                      << "\n0,0.0,tank,flying,,,,,,,,,,,,0,0\n";
  std::string error;
  EXPECT_FALSE(ReadPoseCsv(path, &error));
  EXPECT_NE(error.find("line 2"), std::string::npos) << error;
  std::ofstream(path) << "frame,time\n";
  EXPECT_FALSE(ReadPoseCsv(path, &error));
  EXPECT_FALSE(ReadPoseCsv("/nonexistent.csv", &error));
}

}  // namespace
}  // namespace ripple::tracking
