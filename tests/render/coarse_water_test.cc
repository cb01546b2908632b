// The water shaded on a coarse grid (RendererOptions::water_shading_columns,
// render/coarse_grid.h): the grid's geometry on the CPU, and on EGL that the
// upsampled water leaves every pixel outside the tank as it was, has no
// holes, and stays close to the water shaded at every output pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "render/camera.h"
#include "render/coarse_grid.h"
#include "render/frame_state.h"
#include "render/gl.h"
#include "render/renderer.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using internal::CoarseGrid;
using internal::CoarseGridFor;
using internal::ConvexHull;
using internal::GrownBoxHull;
using testing::MakeScene;
using testing::RenderScene;
using testing::TestScene;
using testing::View;

double Cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Inside or on a counter-clockwise convex polygon, to `tol`.
bool Inside(const std::vector<glm::dvec2>& poly, const glm::dvec2& p,
            double tol) {
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2& a = poly[i];
    const glm::dvec2& b = poly[(i + 1) % poly.size()];
    if (Cross(a, b, p) < -tol * glm::length(b - a)) return false;
  }
  return true;
}

TEST(CoarseGridTest, KeepsTheAspectAndIsOffUpToItsColumns) {
  EXPECT_FALSE(CoarseGridFor(640, 480, 640).active());
  EXPECT_FALSE(CoarseGridFor(320, 240, 640).active());
  EXPECT_FALSE(CoarseGridFor(1920, 1080, 0).active());
  const CoarseGrid hd = CoarseGridFor(1280, 720, 640);
  ASSERT_TRUE(hd.active());
  EXPECT_EQ(hd.width, 640);
  EXPECT_EQ(hd.height, 360);
  EXPECT_DOUBLE_EQ(hd.scale.x, 0.5);
  EXPECT_DOUBLE_EQ(hd.scale.y, 0.5);
  const CoarseGrid fhd = CoarseGridFor(1920, 1080, 640);
  EXPECT_EQ(fhd.width, 640);
  EXPECT_EQ(fhd.height, 360);
  // Automatic: the output's pixels up to 640 columns, 640 columns above.
  EXPECT_FALSE(CoarseGridFor(640, 480, kWaterColumnsAuto).active());
  EXPECT_FALSE(CoarseGridFor(320, 240, kWaterColumnsAuto).active());
  const CoarseGrid svga = CoarseGridFor(800, 600, kWaterColumnsAuto);
  EXPECT_EQ(svga.width, 640);
  EXPECT_EQ(svga.height, 480);
  EXPECT_EQ(CoarseGridFor(1280, 720, kWaterColumnsAuto).width, 640);
  EXPECT_EQ(CoarseGridFor(1920, 1080, kWaterColumnsAuto).height, 360);
  // An odd size: the aspect to the nearest row, each axis its own scale.
  const CoarseGrid odd = CoarseGridFor(1000, 563, 640);
  EXPECT_EQ(odd.height, 360);
  EXPECT_DOUBLE_EQ(odd.scale.y, 360.0 / 563);
}

// Every coarse texel whose centre lies within `pad` texels of an output
// rectangle is in the scaled rectangle.
TEST(CoarseGridTest, RectOutHoldsEveryTexelNearTheRect) {
  const CoarseGrid g = CoarseGridFor(1920, 1080, 640);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> x(0, 1919), y(0, 1079), s(1, 400);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::ivec4 r(x(rng), y(rng), s(rng), s(rng));
    const glm::ivec4 c = g.RectOut(r, 1);
    // The rectangle's extent in texel units, grown by one texel.
    const double x0 = r.x * g.scale.x - 1, x1 = (r.x + r.z) * g.scale.x + 1;
    const double y0 = r.y * g.scale.y - 1, y1 = (r.y + r.w) * g.scale.y + 1;
    for (int i = 0; i < g.width; ++i) {
      const double cx = i + 0.5;
      if (cx < x0 || cx > x1) continue;
      ASSERT_TRUE(i >= c.x && i < c.x + c.z) << "trial " << trial;
    }
    for (int j = 0; j < g.height; ++j) {
      const double cy = j + 0.5;
      if (cy < y0 || cy > y1) continue;
      ASSERT_TRUE(j >= c.y && j < c.y + c.w) << "trial " << trial;
    }
    EXPECT_GE(c.x, 0);
    EXPECT_LE(c.x + c.z, g.width);
  }
  EXPECT_EQ(g.RectOut({5, 5, 0, 10}, 1), glm::ivec4(0));
}

TEST(CoarseGridTest, HullDropsInteriorAndCollinearPoints) {
  std::vector<glm::dvec2> p = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {2, 0},
                               {4, 2}, {1, 1}, {3, 2}, {2, 2}, {0, 0}};
  const std::vector<glm::dvec2> hull = ConvexHull(p);
  ASSERT_EQ(hull.size(), 4u);
  for (size_t i = 0; i < hull.size(); ++i) {
    EXPECT_GT(Cross(hull[i], hull[(i + 1) % 4], hull[(i + 2) % 4]), 0.0);
  }
  for (const glm::dvec2& q : p) EXPECT_TRUE(Inside(hull, q, 1e-12));
}

// The tank's box seen from many places: the polygon is convex and holds
// every corner's projection moved by up to `grow` in x and y; a corner
// behind the camera gives no polygon.
TEST(CoarseGridTest, GrownHullHoldsTheBoxOnScreen) {
  const int w = 640, h = 360;
  const Intrinsics k = testing::MakeIntrinsics(w, h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double sx = 0.17, sy = 0.11, z0 = 0.015, z1 = 0.035, grow = 1.5;
  for (int trial = 0; trial < 100; ++trial) {
    const glm::dvec3 eye(0.2 * u(rng), -0.25 + 0.1 * u(rng),
                         0.2 + 0.1 * u(rng));
    const glm::dmat4 cam_from_tank =
        testing::LookAt(eye, glm::dvec3(0.02 * u(rng), 0.02 * u(rng), 0));
    const glm::dmat4 clip = ClipFromCam(k) * cam_from_tank;
    const std::vector<glm::dvec2> hull =
        GrownBoxHull(clip, sx, sy, z0, z1, w, h, grow);
    ASSERT_GE(hull.size(), 4u);
    for (size_t i = 0; i < hull.size(); ++i) {
      ASSERT_GT(Cross(hull[i], hull[(i + 1) % hull.size()],
                      hull[(i + 2) % hull.size()]),
                0.0);
    }
    for (int c = 0; c < 8; ++c) {
      const glm::dvec4 p =
          clip * glm::dvec4((c & 1 ? 0.5 : -0.5) * sx,
                            (c & 2 ? 0.5 : -0.5) * sy, c & 4 ? z1 : z0, 1.0);
      const glm::dvec2 win = WindowFromClip(p, w, h);
      for (int s = 0; s < 4; ++s) {
        const glm::dvec2 q =
            win + glm::dvec2(s & 1 ? grow : -grow, s & 2 ? grow : -grow);
        EXPECT_TRUE(Inside(hull, q, 1e-6)) << "trial " << trial;
      }
    }
  }
  // The camera inside the box's height range, looking along it: corners
  // behind it.
  const glm::dmat4 inside =
      ClipFromCam(k) *
      testing::LookAt(glm::dvec3(0, 0, 0.02), glm::dvec3(0, 1, 0.02));
  EXPECT_TRUE(GrownBoxHull(inside, sx, sy, z0, z1, w, h, grow).empty());
}

// 1280x960 (twice 640x480 in each axis, the same field of view): the water
// on 640 columns against the water at every pixel.
constexpr int kW = 1280, kH = 960;

struct Pair {
  cv::Mat coarse, full;
};

Pair RenderBoth(Context* ctx, const TestScene& s) {
  RendererOptions coarse_options, full_options;
  coarse_options.water_shading_columns = 640;
  full_options.water_shading_columns = 0;
  std::string error;
  auto coarse = Renderer::TryCreate(ctx, s.k, coarse_options, &error);
  EXPECT_NE(coarse, nullptr) << error;
  auto full = Renderer::TryCreate(ctx, s.k, full_options, &error);
  EXPECT_NE(full, nullptr) << error;
  if (!coarse || !full) return {};
  return {RenderScene(coarse.get(), s.inputs),
          RenderScene(full.get(), s.inputs)};
}

TEST(CoarseWaterTest, UpsampledWaterChangesOnlyTheWaterAndLeavesNoHoles) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (View view : {View::kFront, View::kTilted}) {
    TestScene s = MakeScene(kW, kH, view, /*ripple=*/true);
    const Pair p = RenderBoth(ctx.get(), s);
    ASSERT_FALSE(p.coarse.empty());
    // Outside the water's screen rectangle (the tank's interior within 1 cm
    // of the rest level, as the water pass bounds it) nothing changes: the
    // walls, the board and the video are drawn at the output's pixels.
    const TankGeometry& t = s.inputs.tank;
    const glm::ivec4 r = internal::BoxRect(
        ClipFromCam(s.k) * s.inputs.cam_from_tank, t.size_x, t.size_y,
        t.water_level - 0.01, t.water_level + 0.01, 1, kW, kH);
    ASSERT_GT(r.z * r.w, 100000);
    cv::Mat diff;
    cv::absdiff(p.coarse, p.full, diff);
    cv::Mat outside = diff.clone();
    outside(cv::Rect(r.x, r.y, r.z, r.w)).setTo(0);
    EXPECT_EQ(cv::norm(outside, cv::NORM_INF), 0.0);
    // Inside it the water is interpolated, not lost. No holes: a pixel the
    // coarse shading missed reads black (its coverage is 0), where the full
    // image and its neighbours are lit.
    const cv::Rect roi(r.x, r.y, r.z, r.w);
    cv::Mat lo, hi, coarse_max, lo_min;
    const cv::Mat box = cv::Mat::ones(5, 5, CV_8U);
    cv::erode(p.full, lo, box);
    cv::dilate(p.full, hi, box);
    const cv::Mat coarse_dark = p.coarse(roi) == 0, full_lit = lo(roi) > 40;
    cv::Mat hole = coarse_dark & full_lit;
    EXPECT_EQ(cv::countNonZero(hole.reshape(1)), 0) << "view " << int(view);
    // Each coarse texel is the shading at a point between output pixels,
    // and each output pixel interpolates the texels around it, within two
    // pixels: its value lies in the range of the full image's 5x5
    // neighbourhood (an edge moves by up to a pixel). Two exceptions, on
    // under 1% of the pixels: where refraction shrinks the floor's image
    // several-fold a point between pixels can see a check edge its
    // neighbours do not, and along the water's edge the texels beyond it
    // hold the shading of the edge's point (the shader clamps to the
    // walls).
    cv::Mat below, above;
    cv::subtract(lo(roi), p.coarse(roi), below);  // saturates at 0
    cv::subtract(p.coarse(roi), hi(roi), above);
    const cv::Mat far_below = below > 3, far_above = above > 3;
    const cv::Mat far = far_below | far_above;
    cv::Mat far_any;
    cv::reduce(far.reshape(1, r.z * r.w), far_any, 1, cv::REDUCE_MAX);
    EXPECT_LT(cv::countNonZero(far_any), r.z * r.w / 100)
        << "view " << int(view);
    // On average it is closer to the full image than the full image is to
    // itself moved by one pixel: less than a pixel's misregistration.
    const cv::Mat in = diff(roi).reshape(1);
    cv::Mat moved;
    cv::absdiff(p.full(roi), p.full(roi + cv::Point(1, 0)), moved);
    const double mean = cv::mean(in)[0];
    const double one_pixel = cv::mean(moved.reshape(1))[0];
    EXPECT_LT(mean, one_pixel) << "view " << int(view);
    std::printf("view %d: mean |coarse - full| %.2f, full moved 1 px %.2f\n",
                int(view), mean, one_pixel);
    EXPECT_GT(cv::countNonZero(in), 1000) << "the coarse path did not run";
  }
}

// Up to the grid's columns the output is the full-resolution path's, bit for
// bit.
TEST(CoarseWaterTest, AtOrUnderItsColumnsTheImageIsUnchanged) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, 640, 480);
  TestScene s = MakeScene(640, 480, View::kFront, /*ripple=*/true);
  const Pair p = RenderBoth(ctx.get(), s);
  ASSERT_FALSE(p.coarse.empty());
  EXPECT_EQ(cv::norm(p.coarse, p.full, cv::NORM_INF), 0.0);
}

// The coarse path switches targets and viewports: the next pass finds the
// output bound with its own viewport and GL's resting state.
TEST(CoarseWaterTest, LeavesTheOutputBoundAndTheStateAtRest) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, /*ripple=*/true);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  ASSERT_TRUE(r->Render(s.inputs));
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  EXPECT_EQ(viewport[2], kW);
  EXPECT_EQ(viewport[3], kH);
  for (GLenum cap : {GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_BLEND,
                     GL_POLYGON_OFFSET_FILL}) {
    GLint on = -1;
    glGetIntegerv(cap, &on);
    EXPECT_EQ(on, 0) << "capability 0x" << std::hex << cap;
  }
  GLint stencil_write = 0;
  glGetIntegerv(GL_STENCIL_WRITEMASK, &stencil_write);
  EXPECT_EQ(stencil_write & 0xff, 0xff);
  EXPECT_TRUE(CheckGlError("after Render"));
}

}  // namespace
}  // namespace ripple::render
