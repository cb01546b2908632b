// The printed floor: tiles where the options put them, exact area means,
// image floors read and oriented as printed, bad options and files refused,
// and the synthetic renderer's floor matching the board albedo image pixel
// for pixel from straight above.
#include "tracking/synth/floor_pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "tests/shipped_data.h"
#include "tracking/synth/synth.h"

namespace ripple::synth {
namespace {

using Box = Eigen::AlignedBox2d;
using Eigen::Vector2d;

constexpr double kMm = 1e-3;

FloorPattern Make(const FloorOptions& options, double sx = 0.17,
                  double sy = 0.11) {
  std::string error;
  auto floor = FloorPattern::Create(options, sx, sy, &error);
  EXPECT_TRUE(floor) << error;
  return floor.value_or(FloorPattern());
}

double Luminance(const cv::Vec3f& bgr) {
  return 0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2];
}

void ExpectNear(const cv::Vec3f& a, const cv::Vec3f& b, double tol) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tol) << "channel " << k;
}

TEST(FloorPatternTest, DefaultTilesAreLightIsoluminantAndCentred) {
  const FloorOptions o;
  EXPECT_EQ(o.kind, FloorKind::kTiles);
  EXPECT_DOUBLE_EQ(o.tile_m, 0.010);
  EXPECT_DOUBLE_EQ(o.grout_m, 0.0008);
  // The detector sees one grey for both tints; the pattern's contrast is far
  // below the tags'.
  EXPECT_NEAR(Luminance(o.tile_a_bgr), Luminance(o.tile_b_bgr), 1e-3);
  EXPECT_GT(Luminance(o.tile_a_bgr), 0.7);
  const double tag_contrast = Luminance(kPaperBgr) / Luminance(kInkBgr);
  EXPECT_LT(Luminance(o.tile_a_bgr) / Luminance(o.grout_bgr),
            0.2 * tag_contrast);
  const FloorPattern floor = Make(o);
  EXPECT_EQ(floor.kind(), FloorKind::kTiles);
  ExpectNear(floor.AlbedoAt({0, 0}), o.tile_a_bgr, 0);
  ExpectNear(floor.AlbedoAt({0.010, 0}), o.tile_b_bgr, 0);
  ExpectNear(floor.AlbedoAt({0.010, 0.010}), o.tile_a_bgr, 0);
  ExpectNear(floor.AlbedoAt({0.005, 0.002}), o.grout_bgr, 0);  // grout line
  ExpectNear(floor.AlbedoAt({0.0053, 0.002}), o.grout_bgr, 0);
  ExpectNear(floor.AlbedoAt({0.0055, 0.002}), o.tile_b_bgr, 0);
  ExpectNear(floor.AlbedoAt({0.0, 0.0552}), kPaperBgr, 0);  // outside
  // 17 x 11 whole tiles in the default tank, over one grout rectangle.
  const auto cells = floor.TileCells();
  ASSERT_EQ(cells.size(), 1u + 17 * 11);
  EXPECT_TRUE(cells[0].rect.isApprox(floor.rect()));
  for (size_t i = 1; i < cells.size(); ++i)
    EXPECT_NEAR(cells[i].rect.sizes().x(), 9.2 * kMm, 1e-12);
}

TEST(FloorPatternTest, AreaMeansAreExact) {
  const FloorOptions o;
  const FloorPattern floor = Make(o);
  // One pitch cell centred on a tile: 9.2 mm square of tile, grout around.
  const double tile = 9.2 * 9.2 / 100.0;
  const cv::Vec3f cell =
      floor.AverageOver(Box(Vector2d(-5, -5) * kMm, Vector2d(5, 5) * kMm));
  ExpectNear(cell, o.tile_a_bgr * tile + o.grout_bgr * (1 - tile), 1e-6);
  // A box straddling a grout line: 1 mm of tile A, 0.8 mm grout, 0.2 mm B.
  const cv::Vec3f straddle =
      floor.AverageOver(Box(Vector2d(3.6, 1) * kMm, Vector2d(5.6, 2) * kMm));
  ExpectNear(
      straddle,
      (o.tile_a_bgr * 1.0 + o.grout_bgr * 0.8 + o.tile_b_bgr * 0.2) / 2.0,
      1e-6);
  // Half on the floor, half on paper at the tank's edge.
  const cv::Vec3f edge =
      floor.AverageOver(Box(Vector2d(-1, 54) * kMm, Vector2d(1, 56) * kMm));
  ExpectNear(edge,  // tile (0, 5) is tint B
             (o.tile_b_bgr * 0.6 + o.grout_bgr * 0.4 + kPaperBgr * 1.0) / 2.0,
             1e-6);
}

TEST(FloorPatternTest, AlbedoImageIsTheExactMeanInTankLayout) {
  const FloorOptions o;
  const FloorPattern floor = Make(o);
  const double px_per_m = 2000;  // 0.5 mm pixels
  const cv::Mat img = RenderFloorAlbedo(floor, floor.rect(), px_per_m);
  ASSERT_EQ(img.type(), CV_32FC3);
  EXPECT_EQ(img.cols, 340);
  EXPECT_EQ(img.rows, 220);
  // The mean over the floor: 187 tiles of 9.2 mm, 93 of them tint A.
  const double tile_area = 9.2e-3 * 9.2e-3, floor_area = 0.17 * 0.11;
  const cv::Vec3d expected =
      (cv::Vec3d(o.tile_a_bgr) * 93 + cv::Vec3d(o.tile_b_bgr) * 94) *
          (tile_area / floor_area) +
      cv::Vec3d(o.grout_bgr) * (1 - 187 * tile_area / floor_area);
  const cv::Scalar mean = cv::mean(img);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], expected[k], 1e-5);
  // Rows grow with tank y: the tile at (10 mm, 20 mm) is pixel (190, 150).
  ExpectNear(img.at<cv::Vec3f>(150, 190), floor.AlbedoAt({0.01, 0.02}), 1e-6);
  ExpectNear(img.at<cv::Vec3f>(150, 190), o.tile_b_bgr, 1e-6);
}

class FloorImageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/ripple_floor_test";
    std::filesystem::create_directories(dir_);
  }
  std::string dir_;
};

TEST_F(FloorImageTest, ImageIsStretchedOverTheFloorAsPrinted) {
  // 4 x 2 texels: row 0 is the top of the printed page (+y).
  cv::Mat img(2, 4, CV_8UC3);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 4; ++c)
      img.at<cv::Vec3b>(r, c) = cv::Vec3b(40 * c, 200 - 100 * r, 255);
  const std::string path = dir_ + "/floor.png";
  ASSERT_TRUE(cv::imwrite(path, img));
  FloorOptions o;
  o.kind = FloorKind::kImage;
  o.image_path = path;
  const FloorPattern floor = Make(o);
  EXPECT_EQ(floor.image_bgr8().size(), img.size());
  auto linear = [](int v, int k) {
    const double c = v / 255.0;
    return kPaperBgr[k] *
           (c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  };
  // Top-left texel at the floor's (-x, +y) corner; white is paper.
  const cv::Vec3f tl = floor.AlbedoAt({-0.084, 0.054});
  EXPECT_NEAR(tl[0], linear(0, 0), 1e-6);
  EXPECT_NEAR(tl[1], linear(200, 1), 1e-6);
  EXPECT_NEAR(tl[2], kPaperBgr[2], 1e-6);
  const cv::Vec3f br = floor.AlbedoAt({0.084, -0.054});
  EXPECT_NEAR(br[0], linear(120, 0), 1e-6);
  EXPECT_NEAR(br[1], linear(100, 1), 1e-6);
  // The mean over the whole floor is the texels' mean.
  const cv::Vec3f mean = floor.AverageOver(floor.rect());
  double b = 0;
  for (int c = 0; c < 4; ++c) b += linear(40 * c, 0) / 4;
  EXPECT_NEAR(mean[0], b, 1e-6);
  EXPECT_NEAR(mean[1], 0.5 * (linear(200, 1) + linear(100, 1)), 1e-6);
  // A box over exactly one texel (42.5 x 55 mm) is that texel.
  const cv::Vec3f one =
      floor.AverageOver(Box(Vector2d(-0.0425, 0.0), Vector2d(0.0, 0.055)));
  EXPECT_NEAR(one[0], linear(40, 0), 1e-6);
  EXPECT_NEAR(one[1], linear(200, 1), 1e-6);
}

TEST_F(FloorImageTest, UnreadableFilesAreRefusedByName) {
  FloorOptions o;
  o.kind = FloorKind::kImage;
  std::string error;
  o.image_path = dir_ + "/missing.png";
  EXPECT_FALSE(FloorPattern::Create(o, 0.17, 0.11, &error));
  EXPECT_NE(error.find("missing.png"), std::string::npos) << error;
  const std::string text = dir_ + "/not_an_image.png";
  std::ofstream(text) << "hello";
  o.image_path = text;
  error.clear();
  EXPECT_FALSE(FloorPattern::Create(o, 0.17, 0.11, &error));
  EXPECT_NE(error.find("not_an_image.png"), std::string::npos) << error;
  o.image_path.clear();
  EXPECT_FALSE(FloorPattern::Create(o, 0.17, 0.11, &error));
}

TEST(FloorPatternTest, BadOptionsAreRefused) {
  std::string error;
  FloorOptions o;
  o.grout_m = o.tile_m;
  EXPECT_FALSE(o.IsValid(&error));
  o = FloorOptions();
  o.tile_m = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = FloorOptions();
  o.tile_a_bgr = cv::Vec3f(0.5f, 0.5f, 0.95f);  // whiter than the paper
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_FALSE(FloorPattern::Create(FloorOptions(), 0, 0.1, &error));
  EXPECT_TRUE(FloorOptions().IsValid(&error));
}

tracking::Camera TopCamera() {
  tracking::Camera c;
  c.width = 320;
  c.height = 240;
  c.fx = c.fy = 300;
  c.cx = 161.3;
  c.cy = 117.8;
  return c;
}

// From straight above (image x = tank x, image y = -tank y) the renderer's
// pixels are squares of the board: with flat lighting each must be the
// board albedo image's pixel over the same square, tags, sheet edge and
// floor alike.
TEST(FloorPatternTest, RendererMatchesTheBoardAlbedoFromAbove) {
  const tracking::Rig rig = test_data::DefaultRig();
  const tracking::Camera cam = TopCamera();
  const double z = 0.5, px_per_m = cam.fx / z;
  SceneState scene;
  scene.flat_lighting = true;
  scene.cam_from_tank =
      tracking::LookAt({0, 0, z}, {0, 0, 0}, {0, 1, 0}).Inverse();
  // An image floor of texels larger than the pixels: both sides integrate
  // the same texels exactly.
  const std::string image = ::testing::TempDir() + "/ripple_floor_above.png";
  cv::Mat texels(5, 8, CV_8UC3);
  cv::randu(texels, 0, 256);
  ASSERT_TRUE(cv::imwrite(image, texels));
  for (const FloorKind kind :
       {FloorKind::kPlain, FloorKind::kTiles, FloorKind::kImage}) {
    FloorOptions o;
    o.kind = kind;
    o.image_path = image;
    const FloorPattern floor = Make(o, rig.tank.size_x_m, rig.tank.size_y_m);
    const cv::Mat img = SceneRenderer(cam, rig, floor).RenderLinear(scene);
    // Pixel u spans tank x in [(u - 0.5 - cx), (u + 0.5 - cx)] / px_per_m;
    // row v spans y down from (cy + 0.5 - v) / px_per_m.
    const Box rect(
        Vector2d(-0.5 - cam.cx, 0.5 + cam.cy - cam.height) / px_per_m,
        Vector2d(cam.width - 0.5 - cam.cx, 0.5 + cam.cy) / px_per_m);
    cv::Mat board = RenderBoardAlbedo(rig, floor, rect, px_per_m);
    ASSERT_EQ(board.size(), img.size());
    cv::flip(board, board, 0);
    double max_err = 0;
    for (int v = 0; v < img.rows; ++v)
      for (int u = 0; u < img.cols; ++u)
        max_err = std::max(max_err, cv::norm(img.at<cv::Vec3f>(v, u) -
                                                 board.at<cv::Vec3f>(v, u),
                                             cv::NORM_INF));
    EXPECT_LT(max_err, 2e-5) << ToString(kind);
  }
}

// The perspective renderer against an independent reference: each pixel's
// pre-image in the board plane is a quadrilateral (pinhole), supersampled
// 16 x 16 here through the floor's point albedo.
TEST(FloorPatternTest, RendererCoverageMatchesSupersampledTilesInPerspective) {
  tracking::Rig rig = test_data::DefaultRig();
  rig.tank_tags.clear();
  const tracking::Camera cam = TopCamera();
  const FloorPattern floor = Make(FloorOptions(), 0.17, 0.11);
  SceneState scene;
  scene.flat_lighting = true;
  scene.cam_from_tank =
      tracking::LookAt({0.1, -0.25, 0.2}, {0.0, 0.0, 0}, {0, 0, 1}).Inverse();
  const cv::Mat img = SceneRenderer(cam, rig, floor).RenderLinear(scene);
  const tracking::Pose tank_from_cam = scene.cam_from_tank.Inverse();
  auto on_board = [&](double u, double v) {
    const Eigen::Vector3d ray((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1);
    const Eigen::Vector3d o = tank_from_cam.translation;
    const Eigen::Vector3d d = tank_from_cam.R() * ray;
    return Vector2d((o + d * (-o.z() / d.z())).head<2>());
  };
  double max_err = 0, sum_err = 0;
  int n = 0, partial = 0;
  for (int v = 60; v < 200; v += 2) {
    for (int u = 40; u < 280; u += 2) {
      const Vector2d c = on_board(u, v);
      if (std::abs(c.x()) > 0.083 || std::abs(c.y()) > 0.053) continue;
      cv::Vec3d ref(0, 0, 0);
      const int s = 16;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i)
          ref += cv::Vec3d(floor.AlbedoAt(
              on_board(u - 0.5 + (i + 0.5) / s, v - 0.5 + (j + 0.5) / s)));
      ref *= 1.0 / (s * s);
      const double e =
          cv::norm(cv::Vec3d(img.at<cv::Vec3f>(v, u)) - ref, cv::NORM_INF);
      const cv::Vec3f centre = floor.AlbedoAt(on_board(u, v));
      partial += cv::norm(cv::Vec3d(centre) - ref, cv::NORM_INF) > 0.02;
      max_err = std::max(max_err, e);
      sum_err += e;
      ++n;
    }
  }
  EXPECT_GT(partial, 100);  // grout edges really are inside the samples
  // 16 x 16 samples resolve an edge's coverage to about 1/16 of the
  // tile-grout step (0.34-0.40) in the worst case, far better on average.
  std::printf("%d pixels (%d on edges): max error %.4f, mean %.5f\n", n,
              partial, max_err, sum_err / n);
  EXPECT_GT(n, 1000);
  EXPECT_LT(max_err, 0.015);
  EXPECT_LT(sum_err / n, 1e-3);
}

TEST(FloorPatternTest, PlainFloorRendersExactlyAsNoFloor) {
  const tracking::Rig rig = test_data::DefaultRig();
  const tracking::Camera cam = TopCamera();
  SceneState scene;
  scene.cam_from_tank =
      tracking::LookAt({0.1, -0.3, 0.35}, {0.0, 0.0, 0}, {0, 0, 1}).Inverse();
  FloorOptions plain;
  plain.kind = FloorKind::kPlain;
  const cv::Mat a = SceneRenderer(cam, rig).RenderLinear(scene);
  const cv::Mat b = SceneRenderer(cam, rig, Make(plain)).RenderLinear(scene);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  const cv::Mat c =
      SceneRenderer(cam, rig, Make(FloorOptions())).RenderLinear(scene);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.1);  // the tiles do show
}

}  // namespace
}  // namespace ripple::synth
