// The board under the glass walls (render/under_glass.h) against what
// radiometry says it must see, and WaterShading::under_glass's use of it:
// inside a world of one radiance over n^2 everywhere the point under the
// glass reads that radiance (its hemisphere's shares add up to one), the
// walls' mirror images see alike, and the shading weighs each share by the
// light of where it ends.
#include "render/under_glass.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace ripple::render::internal {
namespace {

WaterOptics ClearWithoutAbsorption() {
  WaterOptics o = WaterOptics::ForLook(WaterLook::kClear);
  o.absorption_per_m = glm::vec3(0.0f);
  return o;
}

// An isothermal enclosure: where the sky, the board, the floor and the
// board under the glass all have the same radiance over n^2, the point
// under the glass sees it whatever the glass does, so the shares of its
// hemisphere must add up to one (less the branches the tracer drops under
// 1e-3 of weight or beyond 24 interfaces).
TEST(UnderGlassTest, AWorldOfOneRadianceLooksUniformFromUnderTheGlass) {
  const TankGeometry tank;
  const UnderGlassView v = TraceUnderGlassView(tank, ClearWithoutAbsorption());
  ASSERT_TRUE(v.traced);
  for (int w = 0; w < 4; ++w) {
    const double sum = v.sky[w].y + v.board[w] + v.floor[w] + v.under[w];
    std::printf(
        "wall %d: sky %.4f board %.4f floor %.4f under the glass %.4f, sum "
        "%.4f\n",
        w, v.sky[w].y, v.board[w], v.floor[w], v.under[w], sum);
    EXPECT_GT(sum, 0.99) << w;
    EXPECT_LE(sum, 1.0 + 1e-9) << w;
    // Each way out is open: the top and outer faces to the sky and the
    // board, the inner face to the floor, total reflection back down.
    EXPECT_GT(v.sky[w].y, 0.3f) << w;
    EXPECT_GT(v.board[w], 0.01f) << w;
    EXPECT_GT(v.floor[w], 0.01f) << w;
    EXPECT_GT(v.under[w], 0.01f) << w;
  }
  // The -x and -y walls are the mirror images of +x and +y.
  EXPECT_EQ(v.sky[0], v.sky[1]);
  EXPECT_EQ(v.floor[2], v.floor[3]);
  // Without water the inner face borders air like the outer one, whose
  // critical angle is smaller: both faces reflect totally over more
  // directions, and more of the hemisphere comes back to the board under
  // the glass (0.159 against 0.083 on the +x wall).
  TankGeometry empty = tank;
  empty.water_level = 0.0f;
  const UnderGlassView e = TraceUnderGlassView(empty, ClearWithoutAbsorption());
  // (There rays running along the slab are guided past the tracer's 24
  // interfaces: the shares add up to 0.85 only. With water the inner face
  // lets them out.)
  EXPECT_GT(e.under[0], 1.5f * v.under[0]);
}

// Water absorbs on the way to the floor: red, absorbed most, sees less of
// it than blue does, and the sky through the top face keeps its colour.
TEST(UnderGlassTest, TheWaterTintsOnlyWhatIsSeenThroughIt) {
  const UnderGlassView v = TraceUnderGlassView(
      TankGeometry{}, WaterOptics::ForLook(WaterLook::kClear));
  EXPECT_LT(v.sky[2].x, v.sky[2].z);
  EXPECT_GT(v.sky[2].x, 0.95f * v.sky[2].z);
}

// The shading's sum, written out: the sky's share at the sky's light, the
// board's at the dry board's, the floor's at the floor's mean under water
// over n_w^2, the direct light as before, all over 1 - under x albedo. A
// view whose sky fills the hemisphere gives the untraced shading.
TEST(UnderGlassTest, ShadingWeighsEachShareByItsLight) {
  WaterOptics o = WaterOptics::ForLook(WaterLook::kClear);
  o.ambient_share = 0.3f;
  const glm::dvec3 light(0.3, 0.2, 1.0);
  UnderGlassView full;
  full.traced = true;
  for (int w = 0; w < 4; ++w) full.sky[w] = glm::vec3(1.0f);
  const WaterShading plain = ComputeWaterShading(o, 0.025, light);
  const WaterShading same = ComputeWaterShading(o, 0.025, light, full);
  for (int w = 0; w < 4; ++w)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(same.under_glass[w][c], plain.under_glass[w][c], 1e-6);

  UnderGlassView v;
  v.traced = true;
  v.albedo = 0.8f;
  for (int w = 0; w < 4; ++w) {
    v.sky[w] = glm::vec3(0.6f);
    v.board[w] = 0.1f;
    v.floor[w] = 0.15f;
    v.under[w] = 0.12f;
  }
  const WaterShading s = ComputeWaterShading(o, 0.025, light, v);
  const double nw2 = double(o.ior) * o.ior;
  const double inner = 1.0 - std::pow((1.5 - 1.333) / (1.5 + 1.333), 2.0);
  for (int w = 0; w < 4; ++w) {
    for (int c = 0; c < 3; ++c) {
      // The untraced shading's direct part, taken out of it.
      const double direct =
          plain.under_glass[w][c] / inner - 0.3 * o.sky_tint[c];
      const double floor_light = s.floor_sky[c] + s.floor_sun[c];
      const double expected = (0.3 * o.sky_tint[c] * 0.6 + 0.1 * 0.8 +
                               0.15 * 0.8 * floor_light / nw2 + direct) /
                              (1.0 - 0.12 * 0.8) * inner;
      EXPECT_NEAR(s.under_glass[w][c], expected, 1e-5) << w << " " << c;
    }
  }
}

}  // namespace
}  // namespace ripple::render::internal
