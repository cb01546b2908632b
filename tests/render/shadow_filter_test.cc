// The shadow map's filters on EGL (llvmpipe in CI): a pillar's shadow on the
// floor seen through flat water, over a uniform grey board, rendered with
// each RendererOptions::shadow_filter. The filters differ only across the
// shadow's edge: the same fully shadowed core and fully lit surroundings,
// the hard filter's edge the narrowest, a wider Gaussian the widest, and the
// Gaussian's edge profile monotonic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::RenderScene;
using testing::TestScene;
using testing::View;

constexpr int kW = 320, kH = 240;

// The pillar alone, from above, over a board of one grey: the shadow is
// the only thing that changes a floor pixel.
TestScene PillarScene() {
  TestScene s = MakeScene(kW, kH, View::kTop, false);
  std::fill(s.video.begin(), s.video.end(), std::uint8_t{200});
  Obstacle pillar;
  pillar.tank_from_obstacle[3] = glm::dvec4(0.045, 0.015, 0.0, 1.0);
  s.inputs.obstacles.push_back(pillar);
  s.inputs.effects.caustics = false;
  s.inputs.effects.pen_occludes = false;
  return s;
}

cv::Mat Grey(const cv::Mat& bgr) {
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  g.convertTo(g, CV_32F);
  return g;
}

struct Renders {
  cv::Mat off;     // shadows off (grey, float)
  cv::Mat on;      // shadows on (grey, float)
  cv::Mat on_bgr;  // shadows on
};

// Writes the shadowed render next to the test binary as
// shadow_filter_<tag>.png for inspection.
Renders RenderWith(Context* ctx, const TestScene& scene, const char* tag,
                   ShadowFilter filter, float sigma_texels = 1.5f) {
  RendererOptions o;
  o.shadow_filter = filter;
  o.shadow_gauss_sigma_texels = sigma_texels;
  std::string error;
  auto r = Renderer::TryCreate(ctx, scene.k, o, &error);
  EXPECT_NE(r, nullptr) << error;
  if (r == nullptr) return {};
  SceneInputs in = scene.inputs;
  Renders out;
  out.on_bgr = RenderScene(r.get(), in);
  out.on = Grey(out.on_bgr);
  in.effects.shadows = false;
  out.off = Grey(RenderScene(r.get(), in));
  cv::imwrite(std::string("shadow_filter_") + tag + ".png", out.on_bgr);
  return out;
}

class ShadowFilterTest : public ::testing::Test {
 protected:
  // The floor's pixels: where the pillar (its shading changes with the
  // filter too, by self-shadowing) is not drawn, grown by a few pixels.
  static cv::Mat FloorMask(const cv::Mat& off, const cv::Mat& empty) {
    cv::Mat diff = cv::abs(off - empty) > 2.0f;
    cv::dilate(diff, diff, cv::Mat::ones(7, 7, CV_8U));
    return diff == 0;
  }
};

TEST_F(ShadowFilterTest, FiltersDifferOnlyAcrossTheEdge) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const TestScene scene = PillarScene();
  TestScene empty_scene = scene;
  empty_scene.inputs.obstacles.clear();
  const Renders hard =
      RenderWith(ctx.get(), scene, "hard", ShadowFilter::kHard);
  const Renders pcf = RenderWith(ctx.get(), scene, "pcf", ShadowFilter::kPcf);
  const Renders gauss =
      RenderWith(ctx.get(), scene, "gauss", ShadowFilter::kGauss);
  const Renders wide =
      RenderWith(ctx.get(), scene, "gauss_sigma4", ShadowFilter::kGauss, 4.f);
  const Renders empty =
      RenderWith(ctx.get(), empty_scene, "empty", ShadowFilter::kPcf);
  ASSERT_FALSE(hard.on.empty() || pcf.on.empty() || gauss.on.empty() ||
               wide.on.empty() || empty.on.empty());
  const cv::Mat floor = FloorMask(hard.off, empty.off);

  // The shadow's full depth: the darkening in the hard shadow's core.
  const cv::Mat hard_dark = hard.off - hard.on;
  double full = 0;
  cv::minMaxLoc(hard_dark, nullptr, &full, nullptr, nullptr, floor);
  ASSERT_GT(full, 30) << "the pillar's shadow should show";

  // Core and lit regions from the hard shadow, shrunk well past the
  // widest edge (a few pixels at this view's ~1.1 mm per pixel).
  const cv::Mat k = cv::Mat::ones(11, 11, CV_8U);
  cv::Mat core = hard_dark > 0.5 * full, lit = hard_dark <= 0.5 * full;
  cv::erode(core, core, k);
  cv::erode(lit, lit, k);
  core &= floor;
  lit &= floor;
  ASSERT_GT(cv::countNonZero(core), 20);
  ASSERT_GT(cv::countNonZero(lit), 1000);
  for (const Renders* other : {&pcf, &gauss, &wide}) {
    const cv::Mat diff = cv::abs(other->on - hard.on);
    double core_max = 0, lit_max = 0;
    cv::minMaxLoc(diff, nullptr, &core_max, nullptr, nullptr, core);
    cv::minMaxLoc(diff, nullptr, &lit_max, nullptr, nullptr, lit);
    EXPECT_LE(core_max, 2.0) << "fully shadowed floor";
    EXPECT_LE(lit_max, 2.0) << "fully lit floor";
  }

  // Partial shadow: darkened by 10-90 % of the full depth.
  auto partial = [&](const Renders& r) {
    const cv::Mat dark = r.off - r.on;
    const cv::Mat p = (dark > 0.1 * full) & (dark < 0.9 * full) & floor;
    return cv::countNonZero(p);
  };
  const int n_hard = partial(hard), n_pcf = partial(pcf),
            n_gauss = partial(gauss), n_wide = partial(wide);
  RecordProperty("partial_hard", n_hard);
  RecordProperty("partial_pcf", n_pcf);
  RecordProperty("partial_gauss", n_gauss);
  RecordProperty("partial_gauss_sigma4", n_wide);
  std::printf("partial-shadow pixels: hard %d, gauss %d, pcf %d, gauss(4) %d\n",
              n_hard, n_gauss, n_pcf, n_wide);
  EXPECT_LT(n_hard, n_gauss);
  EXPECT_LT(n_hard, n_pcf);
  EXPECT_LT(n_gauss, n_wide);
}

TEST_F(ShadowFilterTest, GaussianEdgeIsMonotonic) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const TestScene scene = PillarScene();
  TestScene empty_scene = scene;
  empty_scene.inputs.obstacles.clear();
  const Renders gauss =
      RenderWith(ctx.get(), scene, "gauss", ShadowFilter::kGauss);
  const Renders empty =
      RenderWith(ctx.get(), empty_scene, "empty", ShadowFilter::kPcf);
  ASSERT_FALSE(gauss.on.empty() || empty.on.empty());
  const cv::Mat floor = FloorMask(gauss.off, empty.off);
  const cv::Mat dark = gauss.off - gauss.on;
  double full = 0;
  cv::Point deepest;
  cv::minMaxLoc(dark, nullptr, &full, nullptr, &deepest, floor);
  ASSERT_GT(full, 30);
  // From the deepest floor pixel outwards along its row and column, away
  // from the pillar (in both directions until the floor mask ends): the
  // darkening never rises by more than a level of rounding until it is lit.
  int profiles = 0;
  for (const cv::Point step :
       {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
    std::vector<float> profile;
    for (cv::Point p = deepest;
         p.x >= 0 && p.y >= 0 && p.x < kW && p.y < kH && floor.at<uchar>(p);
         p += step) {
      profile.push_back(dark.at<float>(p));
      if (profile.back() < 1.0f) break;
    }
    if (profile.empty() || profile.back() >= 1.0f) continue;  // hit the pillar
    ++profiles;
    for (size_t i = 1; i < profile.size(); ++i) {
      EXPECT_LE(profile[i], profile[i - 1] + 1.0f)
          << "step (" << step.x << ", " << step.y << ") at " << i;
    }
  }
  EXPECT_GE(profiles, 2);
}

}  // namespace
}  // namespace ripple::render
