// The live-window path: Present() letterboxes the frame into a resizable
// GLFW window and blends the HUD overlay at its top-left corner (read back
// from the window's default framebuffer, under Xvfb in scripts/test.sh);
// RenderVideoOnly() shows the undistorted video without the tank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "render/gl.h"
#include "render/renderer.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::TestScene;
using testing::View;

constexpr int kW = 320, kH = 240;

// A visible window (Xvfb has no window manager, so it maps at once), or
// skip; fails under CI=true like RIPPLE_CONTEXT_OR_SKIP.
#define RIPPLE_WINDOW_OR_SKIP(var, w, h)                                   \
  std::string var##_error;                                                 \
  auto var = Context::TryCreate(Backend::kGlfw, w, h, &var##_error, true); \
  if (var == nullptr) {                                                    \
    if (testing::IsCi())                                                   \
      FAIL() << "no GLFW window under CI=true: " << var##_error;           \
    GTEST_SKIP() << "no GLFW window: " << var##_error;                     \
  }

// Two flat colours, top half and bottom half, BGR8: shows flips and scale.
std::vector<std::uint8_t> TwoToneVideo(int w, int h) {
  std::vector<std::uint8_t> v(static_cast<size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &v[(static_cast<size_t>(y) * w + x) * 3];
      const bool top = y < h / 2;
      p[0] = top ? 200 : 30;  // B
      p[1] = top ? 60 : 180;  // G
      p[2] = top ? 20 : 90;   // R
    }
  }
  return v;
}

// The window's default framebuffer after Present(), as BGR8 with the top
// row first, `w` x `h` framebuffer pixels. Present() has swapped already;
// Mesa's software (drisw) swap copies the back buffer into the window and
// leaves it intact, so the back buffer still holds the presented frame
// (its front buffer reads back black on Xvfb).
cv::Mat ReadWindow(int w, int h) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  cv::Mat rgba(h, w, CV_8UC4);
  glReadPixels(0, 0, w, h, GL_BGRA, GL_UNSIGNED_BYTE, rgba.data);
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_BGRA2BGR);
  cv::flip(bgr, bgr, 0);  // GL row 0 is the bottom
  return bgr;
}

::testing::AssertionResult Near(const cv::Vec3b& actual, int b, int g, int r,
                                int tol = 2) {
  if (std::abs(actual[0] - b) <= tol && std::abs(actual[1] - g) <= tol &&
      std::abs(actual[2] - r) <= tol) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "BGR (" << int(actual[0]) << ", " << int(actual[1]) << ", "
         << int(actual[2]) << ") != (" << b << ", " << g << ", " << r << ")";
}

// Waits (polling events) until the window framebuffer has the given size.
bool WaitForSize(Context* ctx, int w, int h) {
  for (int i = 0; i < 200; ++i) {
    ctx->PollEvents();
    int fw = 0, fh = 0;
    ctx->GetFramebufferSize(&fw, &fh);
    if (fw == w && fh == h) return true;
  }
  return false;
}

TEST(LetterboxRectTest, FitsAndCentres) {
  EXPECT_EQ(LetterboxRect(320, 240, 320, 240), glm::ivec4(0, 0, 320, 240));
  EXPECT_EQ(LetterboxRect(320, 240, 640, 240), glm::ivec4(160, 0, 320, 240));
  EXPECT_EQ(LetterboxRect(320, 240, 320, 480), glm::ivec4(0, 120, 320, 240));
  EXPECT_EQ(LetterboxRect(640, 480, 1280, 720), glm::ivec4(160, 0, 960, 720));
  EXPECT_EQ(LetterboxRect(640, 480, 0, 480), glm::ivec4(0, 0, 0, 0));
}

TEST(WindowTest, PresentBlendsOverlayTopLeft) {
  RIPPLE_WINDOW_OR_SKIP(ctx, kW, kH);
  ASSERT_TRUE(WaitForSize(ctx.get(), kW, kH));
  const Intrinsics k = testing::MakeIntrinsics(kW, kH);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  const std::vector<std::uint8_t> video = TwoToneVideo(kW, kH);
  ASSERT_TRUE(r->RenderVideoOnly({video.data(), kW, kH, kW * 3}));

  // 40 x 20 HUD in a wider buffer (stride 48 px): left half opaque red,
  // right half 50 % white, nothing in the padding.
  constexpr int kOw = 40, kOh = 20, kStride = 48 * 4;
  std::vector<std::uint8_t> hud(kStride * kOh, 77);
  for (int y = 0; y < kOh; ++y) {
    for (int x = 0; x < kOw; ++x) {
      std::uint8_t* p = &hud[y * kStride + x * 4];
      if (x < kOw / 2) {
        p[0] = 0, p[1] = 0, p[2] = 255, p[3] = 255;
      } else {
        p[0] = 255, p[1] = 255, p[2] = 255, p[3] = 128;
      }
    }
  }
  r->SetOverlay(hud.data(), kOw, kOh, kStride);
  hud.assign(hud.size(), 0);  // copied by SetOverlay
  r->Present();
  const cv::Mat win = ReadWindow(kW, kH);
  // Opaque part, 1:1 at the top-left.
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(0, 0), 0, 0, 255));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kOh - 1, kOw / 2 - 1), 0, 0, 255));
  // Half-transparent part: straight alpha over the video's top colour.
  const auto blend = [](int over, int under) {
    return (over * 128 + under * 127) / 255;
  };
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(5, kOw - 1), blend(255, 200),
                   blend(255, 60), blend(255, 20), 3));
  // Outside it (right of and under the overlay): the video, upright.
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(5, kOw), 200, 60, 20));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kOh, 5), 200, 60, 20));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kH - 1, kW - 1), 30, 180, 90));

  // Cleared: the video only.
  r->SetOverlay(nullptr, 0, 0, 0);
  r->Present();
  EXPECT_TRUE(Near(ReadWindow(kW, kH).at<cv::Vec3b>(0, 0), 200, 60, 20));
  EXPECT_TRUE(ctx->TakeTypedKeys().empty());  // nobody typed
  EXPECT_FALSE(ctx->ShouldClose());
}

TEST(WindowTest, ResizedWindowLetterboxes) {
  RIPPLE_WINDOW_OR_SKIP(ctx, kW, kH);
  const Intrinsics k = testing::MakeIntrinsics(kW, kH);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  const std::vector<std::uint8_t> video = TwoToneVideo(kW, kH);
  ASSERT_TRUE(r->RenderVideoOnly({video.data(), kW, kH, kW * 3}));

  // Wider: black bars left and right, the frame at 1:1 in the middle.
  ctx->SetWindowSize(2 * kW, kH);
  ASSERT_TRUE(WaitForSize(ctx.get(), 2 * kW, kH))
      << "the window system ignored the resize";
  r->Present();
  r->Present();  // the driver may pick up the new size one frame late
  cv::Mat win = ReadWindow(2 * kW, kH);
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kH / 2, 10), 0, 0, 0));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kH / 2, 2 * kW - 10), 0, 0, 0));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(10, kW), 200, 60, 20));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(kH - 10, kW), 30, 180, 90));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(10, kW / 2 + 2), 200, 60, 20));

  // Larger and taller: scaled 2x to the width, bars top and bottom.
  ctx->SetWindowSize(2 * kW, 3 * kH);
  ASSERT_TRUE(WaitForSize(ctx.get(), 2 * kW, 3 * kH));
  r->Present();
  r->Present();
  win = ReadWindow(2 * kW, 3 * kH);
  const glm::ivec4 rect = LetterboxRect(kW, kH, 2 * kW, 3 * kH);
  ASSERT_EQ(rect, glm::ivec4(0, kH / 2, 2 * kW, 2 * kH));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y - 5, kW), 0, 0, 0));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y + 5, kW), 200, 60, 20));
  // The two-tone boundary scales with the frame: 2 * kH / 2 below the top.
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y + kH - 4, 5), 200, 60, 20));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y + kH + 4, 5), 30, 180, 90));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y + rect.w - 5, kW), 30, 180, 90));
  EXPECT_TRUE(Near(win.at<cv::Vec3b>(rect.y + rect.w + 5, kW), 0, 0, 0));
}

cv::Mat ReadFrame(Renderer* r) {
  cv::Mat out(r->intrinsics().height, r->intrinsics().width, CV_8UC3);
  EXPECT_TRUE(r->ReadBgr(out.data, static_cast<int>(out.step)));
  return out;
}

TEST(VideoOnlyTest, ReproducesVideoWithoutTank) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, true);
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  const cv::Mat video(kH, kW, CV_8UC3, s.video.data());
  // A full frame first, so that the FBO holds water and walls.
  ASSERT_TRUE(r->Render(s.inputs));
  cv::Mat diff;
  cv::absdiff(ReadFrame(r.get()), video, diff);
  ASSERT_GT(cv::norm(diff, cv::NORM_INF), 20) << "the tank should show";

  ASSERT_TRUE(r->RenderVideoOnly(s.inputs.video));
  cv::absdiff(ReadFrame(r.get()), video, diff);
  EXPECT_LE(cv::norm(diff, cv::NORM_INF), 1);
  EXPECT_FALSE(r->timings().caustics_recomputed);
  EXPECT_FALSE(r->timings().shadow_redrawn);
}

TEST(VideoOnlyTest, UndistortsLikeTheMainPass) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene ideal = MakeScene(kW, kH, View::kFront, false);
  Intrinsics k = ideal.k;
  k.dist = {-0.12, 0.03, 0, 0, 0, 0, 0, 0};
  // The ideal frame seen through the lens: each distorted pixel samples the
  // ideal frame where its undistorted position lands (nearest).
  const cv::Mat ideal_img(kH, kW, CV_8UC3, ideal.video.data());
  const cv::Matx33d kk(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  std::vector<cv::Point2d> src, dst;
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) src.emplace_back(u, v);
  const std::vector<double> dist(k.dist.begin(), k.dist.end());
  cv::undistortPoints(src, dst, kk, dist, cv::noArray(), kk);
  cv::Mat dist_img(kH, kW, CV_8UC3);
  for (int i = 0; i < kW * kH; ++i) {
    const int x =
        std::clamp(static_cast<int>(std::lround(dst[i].x)), 0, kW - 1);
    const int y =
        std::clamp(static_cast<int>(std::lround(dst[i].y)), 0, kH - 1);
    dist_img.at<cv::Vec3b>(i / kW, i % kW) = ideal_img.at<cv::Vec3b>(y, x);
  }
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  ASSERT_TRUE(r->RenderVideoOnly(
      {dist_img.data, kW, kH, static_cast<int>(dist_img.step)}));
  const cv::Mat out = ReadFrame(r.get());
  cv::Mat diff;
  cv::absdiff(out, ideal_img, diff);
  const cv::Scalar mean = cv::mean(diff);
  // Checker edges move by up to a pixel (nearest resampling twice); without
  // undistortion the mean is several times larger.
  EXPECT_LT((mean[0] + mean[1] + mean[2]) / 3.0, 6.0);
  cv::absdiff(dist_img, ideal_img, diff);
  const cv::Scalar raw = cv::mean(diff);
  EXPECT_GT((raw[0] + raw[1] + raw[2]) / 3.0,
            2.0 * (mean[0] + mean[1] + mean[2]) / 3.0);
}

}  // namespace
}  // namespace ripple::render
