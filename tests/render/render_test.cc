// Golden-image tests of the main pass on EGL (llvmpipe in CI), and the
// tank's edges on a rendered synthetic frame. 320x240 keeps the stored PNGs
// small.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <vector>

#include "render/renderer.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::MatchesGolden;
using testing::TestScene;
using testing::View;

constexpr int kW = 320, kH = 240;

using testing::RenderScene;

// The core golden images: the main pass alone, shadow and caustics off.
SceneInputs CoreOnly(SceneInputs in) {
  in.effects.shadows = false;
  in.effects.caustics = false;
  return in;
}

class RenderTest : public ::testing::Test {};

TEST_F(RenderTest, FlatWater) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, false);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  EXPECT_TRUE(MatchesGolden(RenderScene(r.get(), CoreOnly(s.inputs)), "flat"));
}

TEST_F(RenderTest, SingleRipple) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, true);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  EXPECT_TRUE(
      MatchesGolden(RenderScene(r.get(), CoreOnly(s.inputs)), "ripple"));
}

TEST_F(RenderTest, TiltedView) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kTilted, true);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  EXPECT_TRUE(
      MatchesGolden(RenderScene(r.get(), CoreOnly(s.inputs)), "tilted"));
}

// An unchanged height field (same change counter) is not uploaded again.
TEST_F(RenderTest, IdleFrameSkipsUploads) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, true);
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  ASSERT_TRUE(r->Render(s.inputs));
  EXPECT_TRUE(r->timings().surface_uploaded);
  ASSERT_TRUE(r->Render(s.inputs));
  EXPECT_FALSE(r->timings().surface_uploaded);
  s.inputs.water.change_counter++;
  ASSERT_TRUE(r->Render(s.inputs));
  EXPECT_TRUE(r->timings().surface_uploaded);
}

// Signed offset (pixels, positive outwards) of the rendered water's edge
// from the line p0 -> p1, measured over the middle 60% of the edge by area:
// covered pixels in a band minus the pixels inside the true line, divided by
// the length. Binary coverage averages to sub-pixel accuracy along a slanted
// edge.
double EdgeOffset(const cv::Mat& covered, cv::Point2d p0, cv::Point2d p1,
                  cv::Point2d inside_point) {
  const cv::Point2d dir = (p1 - p0) / cv::norm(p1 - p0);
  cv::Point2d n(-dir.y, dir.x);                // unit normal
  if ((inside_point - p0).dot(n) < 0) n = -n;  // n points inwards
  const double len = cv::norm(p1 - p0);
  const double band = 3.0;
  double counted = 0, expected = 0;
  for (int v = 0; v < covered.rows; ++v) {
    for (int u = 0; u < covered.cols; ++u) {
      const cv::Point2d q(u, v);
      const double along = (q - p0).dot(dir), across = (q - p0).dot(n);
      if (along < 0.2 * len || along > 0.8 * len || std::abs(across) > band)
        continue;
      counted += covered.at<std::uint8_t>(v, u) ? 1 : 0;
      expected += across > 0 ? 1 : 0;
    }
  }
  return (counted - expected) / (0.6 * len);
}

// Registration on a rendered synthetic frame: over a black video with the
// walls off, the flat water (drawn in one flat colour) is exactly the
// tank's inner rectangle at the rest level. Its edges must lie within 0.25 px
// of cv::projectPoints' corners (the requirement is 0.5 px; a half-pixel
// convention error shows up as ~0.5 px on steep edges).
TEST_F(RenderTest, RenderedTankEdgesMatchProjection) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (View view : {View::kFront, View::kTilted}) {
    TestScene s = MakeScene(kW, kH, view, false, /*black_video=*/true);
    s.inputs.effects.walls = false;
    s.inputs.effects.flat_water = true;
    auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
    ASSERT_NE(r, nullptr);
    const cv::Mat img = RenderScene(r.get(), CoreOnly(s.inputs));
    cv::Mat covered(img.rows, img.cols, CV_8U);
    for (int v = 0; v < img.rows; ++v) {
      for (int u = 0; u < img.cols; ++u) {
        const cv::Vec3b p = img.at<cv::Vec3b>(v, u);
        covered.at<std::uint8_t>(v, u) = (p[0] + p[1] + p[2]) > 3;
      }
    }
    const TankGeometry& t = s.inputs.tank;
    const double hx = 0.5 * t.size_x, hy = 0.5 * t.size_y, z = t.water_level;
    std::vector<cv::Point3d> obj = {
        {-hx, -hy, z}, {hx, -hy, z}, {hx, hy, z}, {-hx, hy, z}, {0, 0, z}};
    cv::Mat rmat(3, 3, CV_64F), tvec(3, 1, CV_64F), rvec;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        rmat.at<double>(i, j) = s.inputs.cam_from_tank[j][i];
      tvec.at<double>(i) = s.inputs.cam_from_tank[3][i];
    }
    cv::Rodrigues(rmat, rvec);
    const cv::Matx33d kk(s.k.fx, 0, s.k.cx, 0, s.k.fy, s.k.cy, 0, 0, 1);
    std::vector<cv::Point2d> img_pts;
    cv::projectPoints(obj, rvec, tvec, kk, cv::noArray(), img_pts);
    for (int e = 0; e < 4; ++e) {
      const double off =
          EdgeOffset(covered, img_pts[e], img_pts[(e + 1) % 4], img_pts[4]);
      EXPECT_LT(std::abs(off), 0.25) << "view " << int(view) << " edge " << e;
      RecordProperty("edge_offset_px_" + std::to_string(int(view)) + "_" +
                         std::to_string(e),
                     std::to_string(off));
    }
  }
}

// With lens distortion the video is undistorted on the GPU: a frame
// synthesized through the distortion renders like the ideal-camera frame.
TEST_F(RenderTest, UndistortionMatchesIdealCamera) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene ideal = MakeScene(kW, kH, View::kFront, false);
  TestScene distorted = ideal;
  distorted.k.dist = {-0.12, 0.03, 0, 0, 0, 0, 0, 0};
  // Distorted frame: for each distorted pixel, sample the ideal frame where
  // the inverse map lands (nearest; fine for a checkerboard comparison).
  cv::Mat ideal_img(kH, kW, CV_8UC3, ideal.video.data());
  cv::Mat dist_img(kH, kW, CV_8UC3);
  const cv::Matx33d kk(ideal.k.fx, 0, ideal.k.cx, 0, ideal.k.fy, ideal.k.cy, 0,
                       0, 1);
  std::vector<cv::Point2d> src, dst;
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) src.emplace_back(u, v);
  std::vector<double> dist(distorted.k.dist.begin(), distorted.k.dist.end());
  cv::undistortPoints(src, dst, kk, dist, cv::noArray(), kk);
  cv::Mat map_x(kH, kW, CV_32F), map_y(kH, kW, CV_32F);
  for (int i = 0; i < kW * kH; ++i) {
    const cv::Point2d d = dst[i];
    const int x = std::clamp(static_cast<int>(std::lround(d.x)), 0, kW - 1);
    const int y = std::clamp(static_cast<int>(std::lround(d.y)), 0, kH - 1);
    dist_img.at<cv::Vec3b>(i / kW, i % kW) = ideal_img.at<cv::Vec3b>(y, x);
  }
  std::vector<std::uint8_t> buffer(dist_img.data, dist_img.data + kW * kH * 3);
  distorted.inputs.video.bgr = buffer.data();

  auto r_ideal = Renderer::TryCreate(ctx.get(), ideal.k, {}, nullptr);
  auto r_dist = Renderer::TryCreate(ctx.get(), distorted.k, {}, nullptr);
  ASSERT_NE(r_ideal, nullptr);
  ASSERT_NE(r_dist, nullptr);
  const cv::Mat a = RenderScene(r_ideal.get(), CoreOnly(ideal.inputs));
  const cv::Mat b = RenderScene(r_dist.get(), CoreOnly(distorted.inputs));
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  const cv::Scalar mean = cv::mean(diff);
  // Checker edges move by up to a pixel (nearest resampling twice).
  EXPECT_LT((mean[0] + mean[1] + mean[2]) / 3.0, 6.0);
}

}  // namespace
}  // namespace ripple::render
