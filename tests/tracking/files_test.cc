// Camera and rig files: good files load, bad ones fail with one message that
// names the file and the field.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tracking/camera.h"
#include "tracking/rig.h"

namespace ripple::tracking {
namespace {

using ::testing::HasSubstr;

const std::string kData = std::string(RIPPLE_SOURCE_DIR) + "/data";

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string Replace(std::string s, const std::string& from,
                    const std::string& to) {
  const size_t i = s.find(from);
  EXPECT_NE(i, std::string::npos) << "fixture text not found: " << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

TEST(CameraFileTest, DefaultCameraIsA60DegreeWebcam) {
  std::string error;
  const auto cam = LoadCamera(kData + "/camera/default_640x480.yml", &error);
  ASSERT_TRUE(cam) << error;
  EXPECT_EQ(cam->width, 640);
  EXPECT_EQ(cam->height, 480);
  EXPECT_NEAR(2 * std::atan(0.5 * cam->width / cam->fx) * 180 / M_PI, 60.0,
              0.01);
  EXPECT_FALSE(cam->HasDistortion());
}

TEST(CameraFileTest, RoundTripKeepsEveryValue) {
  Camera c = MakeIdealCamera(1280, 720, 70);
  c.dist = {-0.1, 0.02, 0.001, -0.002, 0.003, 0, 0, 0};
  std::string error;
  const std::string path = ::testing::TempDir() + "cam_rt.yml";
  ASSERT_TRUE(SaveCamera(c, path, &error)) << error;
  // OpenCV's own tools read the same keys.
  EXPECT_THAT(ReadAll(path), HasSubstr("camera_matrix: !!opencv-matrix"));
  const auto back = LoadCamera(path, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->width, 1280);
  EXPECT_DOUBLE_EQ(back->fx, c.fx);
  EXPECT_DOUBLE_EQ(back->cy, c.cy);
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(back->dist[i], c.dist[i]);
}

TEST(CameraFileTest, ScaledKeepsPixelCentreConvention) {
  const Camera c = MakeIdealCamera(640, 480, 60);
  const Camera s = c.Scaled(1280, 960);
  // The image centre stays the image centre: (w - 1) / 2.
  EXPECT_DOUBLE_EQ(s.cx, 639.5);
  EXPECT_DOUBLE_EQ(s.cy, 479.5);
  EXPECT_DOUBLE_EQ(s.fx, 2 * c.fx);
}

struct BadCase {
  std::string name, from, to, expect;
};

TEST(CameraFileTest, BadFilesNameFileAndField) {
  const std::string good = ReadAll(kData + "/camera/default_640x480.yml");
  const std::vector<BadCase> cases = {
      {"neg_width", "image_width: 640", "image_width: -640", "image_width"},
      {"no_height", "image_height: 480", "", "image_height"},
      {"not_int", "image_width: 640", "image_width: abc", "image_width"},
      {"inf_width", "image_width: 640", "image_width: .inf", "image_width"},
      {"huge_width", "image_width: 640", "image_width: 1e300", "image_width"},
      {"huge_size", "image_width: 640", "image_width: 100000",
       "exceeds 16384 pixels per side"},
      {"matrix_shape", "rows: 3\n   cols: 3", "rows: 1\n   cols: 9",
       "camera_matrix"},
      {"zero_focal", "data: [ 554.25625842204079, 0.", "data: [ 0.0, 0.",
       "focal"},
      {"no_dist", "distortion_coefficients", "other_coefficients",
       "distortion_coefficients"},
      {"truncated", "distortion_coefficients: !!opencv-matrix",
       "distortion_coefficients: !!opencv-matrix\n   rows: [", "camera file"},
  };
  for (const BadCase& c : cases) {
    const std::string path =
        WriteTemp("cam_" + c.name + ".yml", Replace(good, c.from, c.to));
    std::string error;
    EXPECT_FALSE(LoadCamera(path, &error)) << c.name;
    EXPECT_THAT(error, HasSubstr(path)) << c.name;
    EXPECT_THAT(error, HasSubstr(c.expect)) << c.name << ": " << error;
  }
  std::string error;
  EXPECT_FALSE(LoadCamera("/nonexistent/cam.yml", &error));
  EXPECT_THAT(error, HasSubstr("cannot open"));
  EXPECT_FALSE(LoadCamera(
      WriteTemp("cam_garbage.yml", "%YAML:1.0\n---\n: : [ {\n"), &error));
  EXPECT_FALSE(LoadCamera(WriteTemp("cam_empty.yml", ""), &error));
}

TEST(RigFileTest, DefaultRigMatchesTheDesign) {
  std::string error;
  const auto rig = LoadRig(kData + "/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  EXPECT_EQ(rig->family, "tag36h11");
  EXPECT_NEAR(rig->tank.size_x_m, 0.17, 0.02);
  EXPECT_NEAR(rig->tank.size_y_m, 0.11, 0.02);
  // The board fits A4 and Letter landscape with 8 mm margins: the printable
  // area common to both is 263.4 x 194 mm. Each tag's white margin (one cell)
  // must fit too.
  for (const TagPlacement& t : rig->tank_tags) {
    const double margin = t.edge_m / 8;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d c = t.CornerInObject(k);
      EXPECT_LE(std::abs(c.x()) + margin, 0.2634 / 2) << "tag " << t.id;
      EXPECT_LE(std::abs(c.y()) + margin, 0.194 / 2) << "tag " << t.id;
      EXPECT_NEAR(c.z(), 0, 1e-12);
      // Tags lie outside the tank so the water never hides them.
      EXPECT_TRUE(std::abs(c.x()) > rig->tank.size_x_m / 2 ||
                  std::abs(c.y()) > rig->tank.size_y_m / 2)
          << "tag " << t.id;
    }
    // Tag z points into the board (tank -z).
    EXPECT_NEAR(t.object_from_tag.R().col(2).z(), -1, 1e-6);
  }
  ASSERT_TRUE(rig->pen);
  EXPECT_EQ(rig->pen->faces.size(), 5u);
  EXPECT_NEAR(rig->pen->cube_edge_m, 0.03, 0.003);
  EXPECT_NEAR(rig->pen->tip_in_pen.norm(), 0.14, 0.01);
  for (const TagPlacement& f : rig->pen->faces) {
    EXPECT_NEAR(f.edge_m, 0.024, 0.002);
    // On a cube face, its z axis pointing into the cube, and upright: the
    // tag's y (down in its image) points toward the tip on the side faces.
    const Eigen::Vector3d z = f.object_from_tag.R().col(2);
    EXPECT_NEAR(f.object_from_tag.translation.norm(), rig->pen->cube_edge_m / 2,
                1e-6);
    EXPECT_NEAR(z.dot(-f.object_from_tag.translation.normalized()), 1.0, 1e-6)
        << f.id;
    if (std::abs(z.z()) < 0.5) {
      EXPECT_NEAR(f.object_from_tag.R().col(1).z(), -1.0, 1e-6) << f.id;
    }
  }
  // No face on the shaft side.
  for (const TagPlacement& f : rig->pen->faces)
    EXPECT_GT(f.object_from_tag.translation.z(), -1e-9);
}

TEST(RigFileTest, VispRigMatchesMeasuredBoardLayout) {
  std::string error;
  const auto rig = LoadRig(kData + "/rig/visp_board.yml", &error);
  ASSERT_TRUE(rig) << error;
  EXPECT_EQ(rig->tank_tags.size(), 12u);
  EXPECT_FALSE(rig->pen);
  const std::string csv = std::string(RIPPLE_REAL_DATA_DIR) +
                          "/visp_board_sequence/board_layout.csv";
  std::ifstream in(csv);
  if (!in) {
    if (std::getenv("CI") && std::string(std::getenv("CI")) == "true")
      FAIL() << "real data missing under CI: " << csv;
    GTEST_SKIP() << "real data absent: " << csv;
  }
  // Board frame of ViSP -> tank frame: tank = (by, -bx, bz) - centre.
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'i') continue;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    const TagPlacement* tag = rig->FindTankTag(int(v[0]));
    ASSERT_NE(tag, nullptr);
    Eigen::Vector3d centre_board(0, 0, 0);
    for (int k = 0; k < 4; ++k)
      centre_board += Eigen::Vector3d(v[2 + 2 * k], v[3 + 2 * k], 0) / 4;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d b(v[2 + 2 * k], v[3 + 2 * k], 0);
      const Eigen::Vector3d in_tank = tag->CornerInObject(k);
      const Eigen::Vector3d b_in_tank(b.y(), -b.x(), 0);
      const Eigen::Vector3d c_in_tank(centre_board.y(), -centre_board.x(), 0);
      // Compare corners relative to the tag centre (the board origin differs)
      // and the centres relative to tag 5's.
      EXPECT_NEAR(
          (in_tank - tag->object_from_tag.translation - (b_in_tank - c_in_tank))
              .norm(),
          0, 0.004)
          << "tag " << v[0] << " corner " << k;
    }
    ++checked;
  }
  EXPECT_GE(checked, 8);
}

TEST(RigFileTest, RoundTripKeepsEverything) {
  std::string error;
  auto rig = LoadRig(kData + "/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  ObstacleSpec box;
  box.shape = ObstacleSpec::Shape::kBox;
  box.attached_tag = 3;
  box.box_size_m = {0.02, 0.03, 0.04};
  box.parent_from_obstacle =
      Pose::FromAxisAngle({0.1, 0.2, 0.3}, {0.01, 0.02, 0.03});
  rig->obstacles.push_back(box);
  const std::string path = ::testing::TempDir() + "rig_rt.yml";
  ASSERT_TRUE(SaveRig(*rig, path, &error)) << error;
  const auto back = LoadRig(path, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->tank_tags.size(), rig->tank_tags.size());
  for (size_t i = 0; i < rig->tank_tags.size(); ++i) {
    EXPECT_EQ(back->tank_tags[i].id, rig->tank_tags[i].id);
    EXPECT_LT(RotationDistance(back->tank_tags[i].object_from_tag,
                               rig->tank_tags[i].object_from_tag),
              1e-9);
  }
  ASSERT_TRUE(back->pen);
  EXPECT_LT((back->pen->tip_in_pen - rig->pen->tip_in_pen).norm(), 1e-12);
  ASSERT_EQ(back->obstacles.size(), 2u);
  EXPECT_EQ(back->obstacles[1].attached_tag, 3);
  EXPECT_LT((back->obstacles[1].box_size_m - box.box_size_m).norm(), 1e-12);
  EXPECT_LT(TranslationDistance(back->obstacles[1].parent_from_obstacle,
                                box.parent_from_obstacle),
            1e-12);
  EXPECT_EQ(back->obstacles[0].shape, ObstacleSpec::Shape::kCylinder);
}

TEST(RigFileTest, BadFilesNameFileAndField) {
  const std::string good = ReadAll(kData + "/rig/default.yml");
  const std::vector<BadCase> cases = {
      {"family", "tag_family: tag36h11", "tag_family: tag99h99", "tag_family"},
      {"version", "rig_version: 1", "rig_version: 7", "rig_version"},
      {"no_version", "rig_version: 1", "", "rig_version"},
      {"neg_size", "inner_size: [ 0.17, 0.11 ]", "inner_size: [ -0.17, 0.11 ]",
       "tank.inner_size"},
      {"short_size", "inner_size: [ 0.17, 0.11 ]", "inner_size: [ 0.17 ]",
       "tank.inner_size"},
      {"no_level", "water_level: 0.025", "", "tank.water_level"},
      {"level_high", "water_level: 0.025", "water_level: 0.5",
       "tank.water_level"},
      {"dup_tank", "{ id: 1, edge", "{ id: 0, edge", "duplicate tag id 0"},
      {"dup_pen", "{ id: 10, edge", "{ id: 3, edge", "duplicate tag id 3"},
      {"zero_edge", "{ id: 2, edge: 0.03", "{ id: 2, edge: 0",
       "tank.tags[2].edge"},
      {"bad_quat",
       "{ id: 4, edge: 0.03, position: [ -0.105000, -0.076000, 0.000000 ], "
       "quaternion: [ 0.0000000, 1.0000000",
       "{ id: 4, edge: 0.03, position: [ -0.105000, -0.076000, 0.000000 ], "
       "quaternion: [ 0.0000000, 2.0000000",
       "tank.tags[4].quaternion"},
      {"no_tip", "tip: [ 0., 0., -0.14 ]", "", "pen.tip"},
      {"shape", "shape: cylinder", "shape: sphere", "obstacles[0].shape"},
      {"frame", "frame: tank", "frame: tag:99", "tag:99"},
      {"truncated", "pen:", "pen: [ {", "rig file"},
      // Ids the family cannot draw or decode (tag36h11 has 587).
      {"tank_id_beyond", "{ id: 5, edge", "{ id: 100000, edge",
       "tag id 100000 is beyond tag36h11 (ids 0 to 586)"},
      {"pen_id_beyond", "{ id: 12, edge", "{ id: 587, edge",
       "pen.faces: tag id 587 is beyond"},
  };
  for (const BadCase& c : cases) {
    const std::string path =
        WriteTemp("rig_" + c.name + ".yml", Replace(good, c.from, c.to));
    std::string error;
    EXPECT_FALSE(LoadRig(path, &error)) << c.name;
    EXPECT_THAT(error, HasSubstr(path)) << c.name;
    EXPECT_THAT(error, HasSubstr(c.expect)) << c.name << ": " << error;
  }
  // Cut in the middle of a line.
  const std::string cut =
      WriteTemp("rig_cut.yml", good.substr(0, good.size() / 2));
  std::string error;
  EXPECT_FALSE(LoadRig(cut, &error));
  EXPECT_THAT(error, HasSubstr(cut));
  EXPECT_FALSE(LoadRig("/nonexistent/rig.yml", &error));
  EXPECT_THAT(error, HasSubstr("cannot open"));
}

}  // namespace
}  // namespace ripple::tracking
