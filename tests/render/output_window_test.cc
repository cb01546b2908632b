// The output window (RendererOptions::full_frame_output): drawing only the
// tank's and the obstacles' part of the frame through GL and copying the
// rest of the video gives the very same image as drawing every pixel, and
// the window is as small as the scene allows.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "render/pixel_convert.h"
#include "render/renderer.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::RenderScene;
using testing::TestScene;
using testing::View;

// 640x480 with a wider field of view than the golden tests: the tank takes
// a small part of the frame, as on a webcam looking at a desk.
constexpr int kW = 640, kH = 480;

TestScene DeskScene() {
  TestScene s = MakeScene(kW, kH, View::kFront, true);
  s.k = testing::MakeIntrinsics(kW, kH, 90.0);
  testing::SynthesizeTable(s.k, s.inputs.cam_from_tank, &s.video, false);
  s.inputs.video = {s.video.data(), kW, kH, kW * 3};
  s.inputs.pen_visible = true;
  s.inputs.tank_from_pen[3] = glm::dvec4(0.03, 0.0, 0.16, 1.0);
  Obstacle pillar;
  pillar.tank_from_obstacle[3] = glm::dvec4(0.045, 0.015, 0.0, 1.0);
  s.inputs.obstacles.push_back(pillar);
  return s;
}

int Area(const glm::ivec4& r) { return r.z * r.w; }

cv::Mat Video(const TestScene& s) {
  return cv::Mat(kH, kW, CV_8UC3, const_cast<std::uint8_t*>(s.video.data()))
      .clone();
}

// A renderer with the output window (the default) and one that draws every
// pixel through GL (RendererOptions::full_frame_output), for the same
// camera.
struct WindowedAndWhole {
  std::unique_ptr<Renderer> windowed, whole;
};
WindowedAndWhole MakeRenderers(Context* ctx, const Intrinsics& k) {
  RendererOptions whole_options;
  whole_options.full_frame_output = true;
  std::string error;
  WindowedAndWhole r;
  r.windowed = Renderer::TryCreate(ctx, k, {}, &error);
  EXPECT_NE(r.windowed, nullptr) << error;
  r.whole = Renderer::TryCreate(ctx, k, whole_options, &error);
  EXPECT_NE(r.whole, nullptr) << error;
  return r;
}

TEST(OutputWindowTest, SameImageAsDrawingEveryPixel) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = DeskScene();
  const auto [windowed, whole] = MakeRenderers(ctx.get(), s.k);
  ASSERT_TRUE(windowed && whole);
  // Two frames each: the second one's shadow and caustics are reused.
  for (int frame = 0; frame < 2; ++frame) {
    const cv::Mat a = RenderScene(windowed.get(), s.inputs);
    const glm::ivec4 window = windowed->timings().window;
    const cv::Mat b = RenderScene(whole.get(), s.inputs);
    EXPECT_EQ(whole->timings().window, glm::ivec4(0, 0, kW, kH));
    // The saving is real: the tank is a small part of this frame...
    EXPECT_GT(Area(window), 0);
    EXPECT_LT(Area(window), kW * kH / 3)
        << "window " << window.z << "x" << window.w;
    // ...the images are identical...
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << "frame " << frame;
    // ...and differ from the video inside the window only.
    cv::Mat diff = a != Video(s);
    cv::Mat inside = cv::Mat::zeros(kH, kW, CV_8UC3);
    inside(cv::Rect(window.x, window.y, window.z, window.w)).setTo(255);
    const cv::Mat outside = diff & ~inside;
    EXPECT_EQ(cv::countNonZero(outside.reshape(1)), 0);
    EXPECT_GT(cv::countNonZero(diff.reshape(1)), 1000);
    s.inputs.water.change_counter++;
  }
}

TEST(OutputWindowTest, WindowHoldsTallObstacles) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = DeskScene();
  // A pillar four times the walls' height rises above the tank's box.
  s.inputs.obstacles[0].size.z = 0.16f;
  const auto [r, whole] = MakeRenderers(ctx.get(), s.k);
  ASSERT_TRUE(r && whole);
  std::string error;
  const cv::Mat a = RenderScene(r.get(), s.inputs);
  const glm::ivec4 tall = r->timings().window;
  // Grown upwards (top row first) beyond the tank's box.
  SceneInputs tank_only = s.inputs;
  tank_only.obstacles.clear();
  auto low_renderer = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(low_renderer, nullptr) << error;
  RenderScene(low_renderer.get(), tank_only);
  EXPECT_LT(tall.y, low_renderer->timings().window.y - 20);
  EXPECT_EQ(cv::norm(a, RenderScene(whole.get(), s.inputs), cv::NORM_INF), 0.0);
}

// The tank's shadow on the board around it: the window grows to the board
// the tank lights, and the image is the one that drawing every pixel gives;
// with an occluder mask, the mask's pixels and the board beyond its window
// keep the video exactly.
TEST(OutputWindowTest, TheTanksShadowIsInTheWindow) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = DeskScene();
  const auto [windowed, whole] = MakeRenderers(ctx.get(), s.k);
  ASSERT_TRUE(windowed && whole);
  // The same frames through both: the mirror takes the pen's colour from
  // the last frame's scene copy.
  RenderScene(windowed.get(), s.inputs);
  RenderScene(whole.get(), s.inputs);
  const glm::ivec4 without = windowed->timings().window;
  s.inputs.effects.tank_shadow = true;
  // An occluder mask: a hand's block over the board in front of the tank,
  // looked for in a window that leaves out the tank's left end.
  std::vector<std::uint8_t> mask(static_cast<size_t>(kW) * kH, 0);
  const cv::Rect hand(250, 282, 80, 16);
  for (int y = hand.y; y < hand.y + hand.height; ++y)
    for (int x = hand.x; x < hand.x + hand.width; ++x) mask[y * kW + x] = 255;
  const glm::ivec4 looked(220, 120, kW - 220, kH - 120);
  const cv::Mat video = Video(s);
  cv::Mat changed_unmasked;
  for (const bool masked : {false, true}) {
    s.inputs.occluders = {};
    if (masked) s.inputs.occluders = {mask.data(), kW, kH, 0, looked};
    const cv::Mat a = RenderScene(windowed.get(), s.inputs);
    const glm::ivec4 window = windowed->timings().window;
    const cv::Mat b = RenderScene(whole.get(), s.inputs);
    EXPECT_GT(Area(window), Area(without)) << "masked " << masked;
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << "masked " << masked;
    // The board beyond the tank's box changes (the shadow and the light
    // the glass sends down reach past it)...
    const cv::Mat differs = a != video;
    cv::Mat changed;
    cv::reduce(differs.reshape(1, kH * kW), changed, 1, cv::REDUCE_MAX);
    changed = changed.reshape(1, kH);
    changed(cv::Rect(without.x, without.y, without.z, without.w)).setTo(0);
    EXPECT_GT(cv::countNonZero(changed), 1000) << "masked " << masked;
    if (!masked) {
      changed_unmasked = changed;
      continue;
    }
    // ...but not under the hand, nor where the mask was not looked for,
    // which both hold board that changes without a mask.
    const cv::Rect left(0, 0, looked.x, kH);
    EXPECT_GT(cv::countNonZero(changed_unmasked(hand)), 300);
    EXPECT_GT(cv::countNonZero(changed_unmasked(left)), 30);
    EXPECT_EQ(cv::norm(a(hand), video(hand), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::countNonZero(changed(left)), 0);
  }
}

TEST(OutputWindowTest, VideoOnlyFrameIsTheVideo) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = DeskScene();
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  RenderScene(r.get(), s.inputs);  // something drawn before
  ASSERT_TRUE(r->RenderVideoOnly(s.inputs.video));
  EXPECT_EQ(Area(r->timings().window), 0);
  cv::Mat out(kH, kW, CV_8UC3);
  ASSERT_TRUE(r->ReadBgr(out.data, static_cast<int>(out.step)));
  EXPECT_EQ(cv::norm(out, Video(s), cv::NORM_INF), 0.0);
}

TEST(OutputWindowTest, LensDistortionTakesTheWholeFrame) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = DeskScene();
  s.k.dist = {-0.12, 0.08, 0.0005, -0.0003, -0.02};
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  RenderScene(r.get(), s.inputs);
  EXPECT_EQ(r->timings().window, glm::ivec4(0, 0, kW, kH));
}

// The quarter-size reflection map straight from BGR equals the one made
// from the converted RGBA frame, byte for byte.
TEST(PixelConvertTest, QuarterFromBgrMatchesQuarterOfRgba) {
  const int w = 64, h = 36, stride = 3 * w + 5;
  std::vector<std::uint8_t> bgr(static_cast<size_t>(stride) * h);
  std::mt19937 rng(7);
  for (auto& v : bgr) v = static_cast<std::uint8_t>(rng());
  std::vector<std::uint32_t> rgba(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    internal::BgrToRgbaRow(bgr.data() + static_cast<size_t>(y) * stride, w,
                           rgba.data() + static_cast<size_t>(y) * w);
  std::vector<std::uint32_t> a((w / 4) * (h / 4)), b(a.size());
  internal::QuarterRgba(rgba.data(), w, h, a.data());
  internal::QuarterRgbaFromBgr(bgr.data(), stride, w, h, b.data());
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace ripple::render
