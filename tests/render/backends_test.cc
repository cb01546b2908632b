// Every compiled backend makes a 3.3 core context and renders the flat-water
// scene like the EGL golden image. GLFW needs a display (Xvfb in
// scripts/test.sh).
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "render/renderer.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::View;

constexpr int kW = 320, kH = 240;

class BackendTest : public ::testing::TestWithParam<Backend> {};

TEST_P(BackendTest, RendersFlatWaterGolden) {
  const Backend backend = GetParam();
  RIPPLE_CONTEXT_OR_SKIP(ctx, backend, kW, kH);
  RecordProperty("gl", ctx->Description());
  testing::TestScene s = MakeScene(kW, kH, View::kFront, false);
  s.inputs.effects.shadows = false;
  s.inputs.effects.caustics = false;
  std::string error;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, &error);
  ASSERT_NE(r, nullptr) << error;
  ASSERT_TRUE(r->Render(s.inputs));
  cv::Mat out(kH, kW, CV_8UC3);
  ASSERT_TRUE(r->ReadBgr(out.data, static_cast<int>(out.step)));
  r->Present();  // shows the frame on GLFW, no-op headless
  EXPECT_TRUE(testing::MatchesGolden(out, "flat"))
      << BackendName(backend) << ": " << ctx->Description();
}

// The rasteriser's threads go to llvmpipe through LP_NUM_THREADS, and a
// value the user set is kept.
TEST(SoftwareRasterThreadsTest, SetsTheVariableUnlessTheUserDid) {
  const char* was = std::getenv("LP_NUM_THREADS");
  const std::optional<std::string> saved =
      was ? std::optional<std::string>(was) : std::nullopt;
  unsetenv("LP_NUM_THREADS");
  EXPECT_FALSE(SetSoftwareRasterThreads(-1));
  EXPECT_EQ(std::getenv("LP_NUM_THREADS"), nullptr);
  EXPECT_TRUE(SetSoftwareRasterThreads(0));
  ASSERT_NE(std::getenv("LP_NUM_THREADS"), nullptr);
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "0");
  setenv("LP_NUM_THREADS", "3", 1);
  EXPECT_FALSE(SetSoftwareRasterThreads(0));
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "3");
  if (saved) {
    setenv("LP_NUM_THREADS", saved->c_str(), 1);
  } else {
    unsetenv("LP_NUM_THREADS");
  }
}

std::string Name(const ::testing::TestParamInfo<Backend>& info) {
  return BackendName(info.param);
}

INSTANTIATE_TEST_SUITE_P(Compiled, BackendTest,
                         ::testing::ValuesIn(CompiledBackends()), Name);

}  // namespace
}  // namespace ripple::render
