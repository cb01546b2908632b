#include "tracking/synth/synth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "tests/synth/one_tag_scene.h"
#include "tracking/synth/raster.h"
#include "tracking/tag_family.h"

namespace ripple::synth {
namespace {

using testing::BlackFraction;
using testing::OneTagRig;
using testing::TestCamera;

using Eigen::Vector2d;
using Eigen::Vector3d;
using tracking::Camera;
using tracking::Rig;

// Black cells of tag 0 as tag-frame rectangles.
std::vector<std::array<double, 4>> BlackCells(double edge) {
  const auto family = tracking::TagFamily::Create("tag36h11");
  const auto bitmap = tracking::MakeTagBitmap(*family, 0);
  const double cell = edge / bitmap->width_at_border;
  const double origin = -0.5 * bitmap->total_width * cell;
  std::vector<std::array<double, 4>> cells;
  for (int r = 0; r < bitmap->total_width; ++r)
    for (int c = 0; c < bitmap->total_width; ++c)
      if (bitmap->black(r, c))
        cells.push_back({origin + c * cell, origin + r * cell,
                         origin + (c + 1) * cell, origin + (r + 1) * cell});
  return cells;
}

TEST(SynthCoverageTest, FrontoParallelMatchesExactIntervalOverlap) {
  const double edge = 0.12, z = 0.25;
  const Camera cam = TestCamera();
  const Rig rig = OneTagRig(edge);
  SceneRenderer renderer(cam, rig);
  SceneState scene;
  scene.flat_lighting = true;
  // Camera straight above: image x = tank x = tag x, image y = -tank y = tag y.
  scene.cam_from_tank =
      tracking::LookAt({0, 0, z}, {0, 0, 0}, {0, 1, 0}).Inverse();
  const cv::Mat img = renderer.RenderLinear(scene);
  const auto cells = BlackCells(edge);
  double max_err = 0;
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      double expected = 0;
      for (const auto& c : cells) {
        const double u0 = cam.fx * c[0] / z + cam.cx,
                     u1 = cam.fx * c[2] / z + cam.cx;
        const double v0 = cam.fy * c[1] / z + cam.cy,
                     v1 = cam.fy * c[3] / z + cam.cy;
        const double ox =
            std::max(0.0, std::min(u + 0.5, u1) - std::max(u - 0.5, u0));
        const double oy =
            std::max(0.0, std::min(v + 0.5, v1) - std::max(v - 0.5, v0));
        expected += ox * oy;
      }
      max_err =
          std::max(max_err, std::abs(BlackFraction(img, u, v) - expected));
    }
  }
  EXPECT_LT(max_err, 2e-5);
}

TEST(SynthCoverageTest, PerspectiveMatchesImageSpaceClipping) {
  const double edge = 0.1;
  const Camera cam = TestCamera();
  const Rig rig = OneTagRig(edge);
  SceneRenderer renderer(cam, rig);
  SceneState scene;
  scene.flat_lighting = true;
  scene.cam_from_tank =
      tracking::LookAt({0.12, -0.2, 0.22}, {0.005, 0.01, 0}, {0, 0, 1})
          .Inverse();
  const cv::Mat img = renderer.RenderLinear(scene);
  // Reference: each black cell projected to an image quad (pinhole maps
  // lines to lines), clipped against each pixel square.
  cv::Mat expected(cam.height, cam.width, CV_64F, cv::Scalar(0));
  cv::Rect tag_box;  // pixels near the tag: the sheet covers them for sure
  const Pose cam_from_tag =
      scene.cam_from_tank * rig.tank_tags[0].object_from_tag;
  for (const auto& c : BlackCells(edge)) {
    std::vector<Vector2d> quad;
    for (const Vector2d& p : {Vector2d(c[0], c[1]), Vector2d(c[2], c[1]),
                              Vector2d(c[2], c[3]), Vector2d(c[0], c[3])})
      quad.push_back(
          cam.Project(Vector3d(cam_from_tag * Vector3d(p.x(), p.y(), 0))));
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const auto& q : quad) {
      x0 = std::min(x0, q.x()), x1 = std::max(x1, q.x());
      y0 = std::min(y0, q.y()), y1 = std::max(y1, q.y());
    }
    tag_box |=
        cv::Rect(int(x0) - 2, int(y0) - 2, int(x1 - x0) + 5, int(y1 - y0) + 5);
    for (int v = std::max(0, int(y0) - 1);
         v <= std::min(cam.height - 1, int(y1) + 1); ++v)
      for (int u = std::max(0, int(x0) - 1);
           u <= std::min(cam.width - 1, int(x1) + 1); ++u)
        expected.at<double>(v, u) += std::abs(
            PolygonArea(ClipToRect(quad, u - 0.5, v - 0.5, u + 0.5, v + 0.5)));
  }
  double max_err = 0, edge_pixels = 0;
  tag_box &= cv::Rect(0, 0, cam.width, cam.height);
  ASSERT_FALSE(tag_box.empty());
  for (int v = tag_box.y; v < tag_box.br().y; ++v)
    for (int u = tag_box.x; u < tag_box.br().x; ++u) {
      const double e = expected.at<double>(v, u);
      if (e > 0.01 && e < 0.99) ++edge_pixels;
      max_err = std::max(max_err, std::abs(BlackFraction(img, u, v) - e));
    }
  EXPECT_GT(edge_pixels, 500);  // the test really exercises partial pixels
  EXPECT_LT(max_err, 2e-5);
}

TEST(SynthProjectionTest, CameraProjectMatchesOpenCv) {
  Camera cam = TestCamera();
  cam.dist = {-0.21, 0.06, 0.0012, -0.0007, 0.01, 0.002, -0.001, 0.0005};
  const std::vector<double> dist(cam.dist.begin(), cam.dist.end());
  cv::Mat k =
      (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  std::vector<cv::Point3d> pts;
  for (int i = 0; i < 200; ++i)
    pts.emplace_back(0.3 * std::sin(i * 1.3), 0.2 * std::cos(i * 0.7),
                     0.4 + 0.1 * std::sin(i));
  std::vector<cv::Point2d> ref;
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist, ref);
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vector2d p = cam.Project(Vector3d(pts[i].x, pts[i].y, pts[i].z));
    EXPECT_NEAR(p.x(), ref[i].x, 1e-6);
    EXPECT_NEAR(p.y(), ref[i].y, 1e-6);
    // And the inverse used for pixel rays.
    const Vector2d n = cam.UndistortToNormalized(p);
    EXPECT_NEAR(n.x(), pts[i].x / pts[i].z, 1e-9);
    EXPECT_NEAR(n.y(), pts[i].y / pts[i].z, 1e-9);
  }
}

// The rendered image of a tag's outer edge, under lens distortion, sits where
// cv::projectPoints puts it: the black area in a row window across the edge
// gives its sub-pixel position.
TEST(SynthProjectionTest, RenderedEdgeMatchesProjectPointsUnderDistortion) {
  const double edge = 0.1;
  Camera cam = TestCamera();
  cam.dist = {-0.25, 0.08, 0.001, -0.0008, 0, 0, 0, 0};
  const Rig rig = OneTagRig(edge);
  SceneRenderer renderer(cam, rig);
  SceneState scene;
  scene.flat_lighting = true;
  scene.cam_from_tank =
      tracking::LookAt({0.06, -0.05, 0.2}, {0.02, 0.0, 0}, {0, 1, 0}).Inverse();
  const cv::Mat img = renderer.RenderLinear(scene);
  const Pose cam_from_tag =
      scene.cam_from_tank * rig.tank_tags[0].object_from_tag;
  cv::Mat k =
      (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  const std::vector<double> dist(cam.dist.begin(), cam.dist.begin() + 5);
  cv::Mat rvec, tvec;
  cv::Mat r_cv(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r_cv.at<double>(i, j) = cam_from_tag.R()(i, j);
  cv::Rodrigues(r_cv, rvec);
  tvec = (cv::Mat_<double>(3, 1) << cam_from_tag.translation.x(),
          cam_from_tag.translation.y(), cam_from_tag.translation.z());
  // Dense samples of the left outer edge (tag x = -edge/2).
  std::vector<cv::Point3d> edge_pts;
  for (int i = 0; i <= 2000; ++i)
    edge_pts.emplace_back(-edge / 2, -edge / 2 + edge * i / 2000.0, 0);
  std::vector<cv::Point2d> edge_px;
  cv::projectPoints(edge_pts, rvec, tvec, k, dist, edge_px);
  const double cell_px = std::abs(edge_px[2000].y - edge_px[0].y) / 8;
  int rows = 0;
  double max_err = 0;
  for (int v = int(edge_px[700].y); v < int(edge_px[1300].y); v += 3) {
    // Edge crossing of row v by interpolation of the dense samples.
    double u_edge = 0;
    for (int i = 0; i < 2000; ++i)
      if ((edge_px[i].y - v) * (edge_px[i + 1].y - v) <= 0) {
        const double t = (v - edge_px[i].y) / (edge_px[i + 1].y - edge_px[i].y);
        u_edge = edge_px[i].x + t * (edge_px[i + 1].x - edge_px[i].x);
      }
    const int u0 = int(std::floor(u_edge)) - 4,
              u1 = int(std::floor(u_edge + 0.4 * cell_px));
    double black = 0;
    for (int u = u0; u <= u1; ++u) black += BlackFraction(img, u, v);
    max_err = std::max(max_err, std::abs((u1 + 0.5 - black) - u_edge));
    ++rows;
  }
  EXPECT_GT(rows, 5);
  EXPECT_LT(max_err, 0.01);
}

TEST(SynthRenderTest, DeterministicPerSeedAndNoisy) {
  const Camera cam = TestCamera();
  const Rig rig = OneTagRig(0.08);
  SceneRenderer renderer(cam, rig);
  SceneState scene;
  scene.cam_from_tank =
      tracking::LookAt({0, -0.1, 0.3}, {0, 0, 0}, {0, 0, 1}).Inverse();
  ImagingOptions imaging;
  imaging.defocus_sigma_px = 0.8;
  imaging.motion_blur_px = 2;
  imaging.read_noise_dn = 3;
  imaging.shot_noise_gain = 0.1;
  imaging.jpeg_quality = 80;
  const RenderedFrame a = renderer.Render(scene, imaging, 42);
  const RenderedFrame b = renderer.Render(scene, imaging, 42);
  const RenderedFrame c = renderer.Render(scene, imaging, 43);
  EXPECT_EQ(cv::norm(a.image, b.image, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.image, c.image, cv::NORM_L1), 0.0);
  ASSERT_EQ(a.tank_tags.size(), 1u);
  EXPECT_EQ(a.tank_tags[0], 0);
}

TEST(SynthRenderTest, OccluderHidesTagFromGroundTruthList) {
  const Camera cam = TestCamera();
  const Rig rig = OneTagRig(0.08);
  SceneRenderer renderer(cam, rig);
  SceneState scene;
  scene.cam_from_tank =
      tracking::LookAt({0, 0, 0.3}, {0, 0, 0}, {0, 1, 0}).Inverse();
  std::vector<int> tank, pen;
  renderer.VisibleTags(scene, &tank, &pen);
  ASSERT_EQ(tank.size(), 1u);
  Occluder hand;
  hand.cam_from_occluder =
      Pose(Eigen::Quaterniond::Identity(), Vector3d(0.01, 0.0, 0.15));
  hand.outline_m = {{-0.02, -0.02}, {0.02, -0.02}, {0.02, 0.02}, {-0.02, 0.02}};
  scene.occluders.push_back(hand);
  renderer.VisibleTags(scene, &tank, &pen);
  EXPECT_TRUE(tank.empty());
  // And the occluder's colour is in the image where it projects.
  const cv::Mat img = renderer.RenderLinear(scene);
  const Vector2d c = cam.Project(Vector3d(0.01, 0.0, 0.15));
  const cv::Vec3f px = img.at<cv::Vec3f>(int(c.y()), int(c.x()));
  EXPECT_NEAR(px[2], hand.bgr[2], 1e-5);
}

TEST(SynthSequenceTest, SegmentsAreSmoothWithCutsAndThePenDips) {
  const Camera cam = tracking::MakeIdealCamera(640, 480, 60);
  std::string error;
  auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  SequenceOptions opt;
  opt.frames = 150;
  opt.segment_frames = 50;
  std::vector<FrameSpec> frames;
  ASSERT_TRUE(MakeSequence(cam, *rig, opt, &frames, &error)) << error;
  ASSERT_EQ(frames.size(), 150u);
  int below = 0, above = 0;
  for (size_t i = 1; i < frames.size(); ++i) {
    const double jump = tracking::TranslationDistance(
        frames[i].scene.cam_from_tank, frames[i - 1].scene.cam_from_tank);
    if (i % 50 == 0) {
      EXPECT_GT(jump, 0.01) << "cut expected at frame " << i;
    } else {
      EXPECT_LT(jump, 0.01) << "smooth motion expected at frame " << i;
    }
    const Vector3d tip = *frames[i].scene.tank_from_pen * rig->pen->tip_in_pen;
    (tip.z() < rig->tank.water_level_m ? below : above)++;
  }
  EXPECT_GT(below, 10);
  EXPECT_GT(above, 10);
  opt.preset = "nope";
  EXPECT_FALSE(MakeSequence(cam, *rig, opt, &frames, &error));
}

// The pen standing upright with its tip `tip_height_m` above the tank centre.
Pose UprightPen(const Rig& rig, double tip_height_m) {
  return Pose(Eigen::Quaterniond::Identity(),
              Vector3d(0, 0, tip_height_m) - rig.pen->tip_in_pen);
}

Vector3d LightAt(double azimuth_deg, double elevation_deg) {
  const double a = azimuth_deg * M_PI / 180, e = elevation_deg * M_PI / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

TEST(SynthShadowTest, PenShadowDarkensTheBoardToTheAmbientShare) {
  const Camera cam = tracking::MakeIdealCamera(640, 480, 60);
  std::string error;
  auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  ASSERT_TRUE(rig->pen);
  SceneRenderer renderer(cam, *rig);
  SceneState scene;
  const Pose cam_from_tank =
      tracking::LookAt({0.0, -0.15, 0.35}, {-0.03, -0.02, 0}, {0, 0, 1})
          .Inverse();
  scene.cam_from_tank = cam_from_tank;
  scene.tank_from_pen = UprightPen(*rig, 0.02);
  const cv::Mat unlit = renderer.RenderLinear(scene);
  scene.light_in_tank = LightAt(30, 50);
  scene.ambient_share = 0.4;
  const cv::Mat lit = renderer.RenderLinear(scene);
  cv::Mat hands, pen;
  renderer.OccluderCoverage(scene, &hands, &pen);
  // Brightness with the light over brightness without it at a board point.
  auto ratio_at = [&](const Vector2d& p_in_tank) {
    const Vector2d px = cam.Project(
        Vector3d(cam_from_tank * Vector3d(p_in_tank.x(), p_in_tank.y(), 0)));
    const int u = int(std::lround(px.x())), v = int(std::lround(px.y()));
    EXPECT_TRUE(u >= 0 && v >= 0 && u < cam.width && v < cam.height);
    EXPECT_LT(pen.at<float>(v, u), 1e-6f) << "the pen hides the board there";
    return lit.at<cv::Vec3f>(v, u)[1] / unlit.at<cv::Vec3f>(v, u)[1];
  };
  // The upright shaft's axis casts the line from the tip's shadow away from
  // the light; its half-way point (80 mm up) lands 80 mm cot(50 deg) away.
  const Vector2d away = -LightAt(30, 50).head<2>().normalized();
  const double cot = 1 / std::tan(50 * M_PI / 180);
  const Vector2d mid = away * 0.08 * cot;
  EXPECT_NEAR(ratio_at(mid), 0.4, 1e-3);
  // The cube's shadow, from its centre 160 mm up.
  EXPECT_NEAR(ratio_at(away * 0.16 * cot), 0.4, 1e-3);
  // Far from the shadow, and on the light's side of the tip: untouched.
  EXPECT_EQ(ratio_at(Vector2d(0.06, -0.035)), 1.0f);
  EXPECT_EQ(ratio_at(-away * 0.03), 1.0f);
  // Across the shaft's shadow: full light, a soft edge near the radius
  // (partial values, not a step), the umbra, and back.
  const Vector2d side(-away.y(), away.x());
  const double r = rig->pen->shaft_radius_m;
  EXPECT_NEAR(ratio_at(mid + side * (r + 0.004)), 1.0, 1e-6);
  EXPECT_NEAR(ratio_at(mid - side * (r + 0.004)), 1.0, 1e-6);
  EXPECT_NEAR(ratio_at(mid + side * (r - 0.003)), 0.4, 1e-3);
  int partial = 0;
  for (double o = r - 0.002; o <= r + 0.002; o += 0.0002) {
    const double q = ratio_at(mid + side * o);
    partial += q > 0.42 && q < 0.98;
  }
  EXPECT_GE(partial, 4) << "the shadow's edge is a step";
  EXPECT_NEAR(ratio_at(mid + side * r), 0.7, 0.15);
  // No shadow when all the light is ambient, nor under flat lighting.
  scene.ambient_share = 1.0;
  const cv::Mat all_ambient = renderer.RenderLinear(scene);
  const Vector2d px =
      cam.Project(Vector3d(cam_from_tank * Vector3d(mid.x(), mid.y(), 0)));
  EXPECT_EQ(
      all_ambient.at<cv::Vec3f>(int(std::lround(px.y())),
                                int(std::lround(px.x()))),
      unlit.at<cv::Vec3f>(int(std::lround(px.y())), int(std::lround(px.x()))));
  scene.ambient_share = 0.4;
  scene.flat_lighting = true;
  SceneState flat = scene;
  flat.light_in_tank.reset();
  EXPECT_EQ(cv::norm(renderer.RenderLinear(scene), renderer.RenderLinear(flat),
                     cv::NORM_INF),
            0.0);
}

TEST(SynthSequenceTest, DirectionalLightIsDrawnPerSegmentApart) {
  const Camera cam = tracking::MakeIdealCamera(640, 480, 60);
  std::string error;
  auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  ASSERT_TRUE(rig) << error;
  SequenceOptions opt;
  opt.preset = "hands";
  opt.frames = 120;
  opt.segment_frames = 30;
  std::vector<FrameSpec> plain, lit;
  ASSERT_TRUE(MakeSequence(cam, *rig, opt, &plain, &error)) << error;
  opt.directional_light = true;
  ASSERT_TRUE(MakeSequence(cam, *rig, opt, &lit, &error)) << error;
  ASSERT_EQ(plain.size(), lit.size());
  for (size_t i = 0; i < lit.size(); ++i) {
    EXPECT_FALSE(plain[i].scene.light_in_tank);
    ASSERT_TRUE(lit[i].scene.light_in_tank);
    // The rest of the sequence is drawn as without the light.
    EXPECT_EQ(tracking::TranslationDistance(plain[i].scene.cam_from_tank,
                                            lit[i].scene.cam_from_tank),
              0.0);
    EXPECT_EQ(plain[i].noise_seed, lit[i].noise_seed);
    const Vector3d& l = *lit[i].scene.light_in_tank;
    EXPECT_NEAR(l.norm(), 1.0, 1e-12);
    const double elev = std::asin(l.z()) * 180 / M_PI;
    EXPECT_GE(elev, 30 - 1e-9);
    EXPECT_LE(elev, 75 + 1e-9);
    EXPECT_GE(lit[i].scene.ambient_share, 0.25);
    EXPECT_LE(lit[i].scene.ambient_share, 0.5);
    if (i % 30 != 0) {
      EXPECT_EQ(l, *lit[i - 1].scene.light_in_tank) << "fixed in a segment";
    }
  }
  EXPECT_GT((*lit[0].scene.light_in_tank - *lit[30].scene.light_in_tank).norm(),
            1e-3);
}

}  // namespace
}  // namespace ripple::synth
