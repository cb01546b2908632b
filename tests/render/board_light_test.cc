// The light on the board around the tank (render/board_light.h) against
// what optics says it must be: an index-matched tank changes nothing, the
// open board far away gets exactly its dry light, a path through one glass
// wall above the water keeps the slab's transmittance, the water column
// casts a full shadow where the light would have to leave its surface
// beyond the critical angle, and the walls take sky away from the board
// beside them.
#include "render/board_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace ripple::render::internal {
namespace {

struct Maps {
  TankGeometry tank;
  WaterOptics optics;
  BoardLightMap map;
};

Maps Compute(const WaterOptics& optics, const glm::dvec3& light,
             BoardLightOptions options = {}) {
  Maps m;
  m.optics = optics;
  m.map = BoardLightLayout(m.tank, optics, options);
  ComputeBoardSkyView(m.tank, optics, options, &m.map);
  ComputeBoardDirectLight(m.tank, optics, light, options, &m.map);
  return m;
}

// The texel whose centre is nearest to (x, y).
glm::ivec2 TexelAt(const BoardLightMap& m, double x, double y) {
  return {static_cast<int>(std::floor((x - m.origin.x) / m.texel)),
          static_cast<int>(std::floor((y - m.origin.y) / m.texel))};
}

// The index of the sky view's texel nearest to (x, y).
size_t ViewAt(const BoardLightMap& m, double x, double y) {
  const int i =
      static_cast<int>(std::floor((x - m.view.origin.x) / m.view.texel));
  const int j =
      static_cast<int>(std::floor((y - m.view.origin.y) / m.view.texel));
  return static_cast<size_t>(j) * m.view.nx + i;
}

TEST(BoardLightTest, AnIndexMatchedTankChangesNothing) {
  WaterOptics optics;
  optics.ior = 1.0f;
  optics.glass_ior = 1.0f;
  optics.absorption_per_m = glm::vec3(0.0f);
  const Maps m = Compute(optics, {0.35, 0.25, 1.0});
  for (int j = 0; j < m.map.ny; ++j) {
    for (int i = 0; i < m.map.nx; ++i) {
      const BoardTexel v = m.map.Texel(i, j, optics, 0.9f);
      ASSERT_NEAR(v.light.r, 1.0f, 1e-5) << i << " " << j;
      ASSERT_NEAR(v.light.b, 1.0f, 1e-5) << i << " " << j;
      ASSERT_NEAR(v.diffuse + 0.9f * v.floor, 0.0f, 1e-6) << i << " " << j;
    }
  }
}

TEST(BoardLightTest, TheOpenBoardKeepsItsLight) {
  const Maps m = Compute(WaterOptics{}, {0.35, 0.25, 1.0});
  // The map's corners lie 2.5 wall heights out: the sky is nearly all
  // there, the light exactly.
  for (const glm::ivec2 t :
       {glm::ivec2(0, 0), glm::ivec2(m.map.nx - 1, 0),
        glm::ivec2(0, m.map.ny - 1), glm::ivec2(m.map.nx - 1, m.map.ny - 1)}) {
    const size_t k = static_cast<size_t>(t.y) * m.map.nx + t.x;
    EXPECT_NEAR(m.map.direct[k].g, 1.0f, 1e-5);
    const double x = m.map.origin.x + (t.x + 0.5) * m.map.texel;
    const double y = m.map.origin.y + (t.y + 0.5) * m.map.texel;
    EXPECT_GT(m.map.view.sky[ViewAt(m.map, x, y)].g, 0.98f);
  }
}

TEST(BoardLightTest,
     LightThroughOneWallAboveTheWaterKeepsTheSlabsTransmittance) {
  // The light 45 degrees up over +x. A board point 32 mm beyond the -x
  // wall's foot sees it through that wall between 32 and 35 mm up (above
  // the 25 mm water, under the 40 mm top), then over the water and out of
  // the open top: only the two faces of one slab are in the way.
  const glm::dvec3 light(1.0, 0.0, 1.0);
  const Maps m = Compute(WaterOptics{}, light);
  const double cos_i = 1.0 / std::sqrt(2.0);
  const double r = FresnelReflectance(cos_i, 1.0, 1.5);
  const double slab = (1.0 - r) / (1.0 + r);  // every inner reflection
  const double x = -m.map.outer_x - 0.032;
  const glm::ivec2 t = TexelAt(m.map, x, 0.0);
  const size_t k = static_cast<size_t>(t.y) * m.map.nx + t.x;
  EXPECT_NEAR(m.map.direct[k].g, slab, 0.01);
  EXPECT_LT(slab, 0.92);  // the slab's loss is what is measured
}

TEST(BoardLightTest, TheWaterColumnCastsAFullShadow) {
  // Under 25 mm of water the same light would have to cross the surface
  // from below at cos = 1 / (sqrt(2) n) (58 degrees, beyond the critical
  // 48.6): nothing comes straight through, and the board 5-20 mm beyond
  // the wall gets the sky only.
  const Maps m = Compute(WaterOptics{}, {1.0, 0.0, 1.0});
  for (double d : {0.006, 0.012, 0.018}) {
    const glm::ivec2 t = TexelAt(m.map, -m.map.outer_x - d, 0.0);
    const size_t k = static_cast<size_t>(t.y) * m.map.nx + t.x;
    EXPECT_LT(m.map.direct[k].g, 0.02f) << d;
    // On the lit side the same distance is in full light, plus the light
    // that the wall facing it mirrors down: air-glass Fresnel at 45
    // degrees, and a little from the glass-water face behind it.
    const glm::ivec2 u = TexelAt(m.map, m.map.outer_x + d, 0.0);
    const double r = FresnelReflectance(1.0 / std::sqrt(2.0), 1.0, 1.5);
    const float lit = m.map.direct[static_cast<size_t>(u.y) * m.map.nx + u.x].g;
    EXPECT_GT(lit, 1.0 + r - 1e-4) << d;
    EXPECT_LT(lit, 1.0 + r + 0.01) << d;
  }
}

TEST(BoardLightTest, TheWallsTakeSkyFromTheBoardBesideThem) {
  // The sky seen beside a long wall of height H at distance d is at most
  // 1 - (1 - d / sqrt(d^2 + H^2)) / 2 of the open sky's (the view factor of
  // the wall); glass lets part of it through, and the tank shows its floor
  // and the mirrored board in its place.
  const Maps m = Compute(WaterOptics{}, {0.0, 0.0, 1.0});
  const double h = m.tank.wall_height;
  double last = 0;
  for (double d : {0.004, 0.01, 0.02, 0.04, 0.08}) {
    const size_t k = ViewAt(m.map, 0.0, m.map.outer_y + d);
    const double hidden = 0.5 * (1.0 - d / std::sqrt(d * d + h * h));
    const float sky = m.map.view.sky[k].g;
    EXPECT_GT(sky, 1.0 - hidden) << d;        // the glass passes some sky
    EXPECT_LT(sky, 1.0 - 0.3 * hidden) << d;  // but not most of it
    EXPECT_GT(sky, last) << d;                // more sky further out
    last = sky;
    EXPECT_GT(m.map.view.floor[k] + m.map.view.board[k], 0.0f) << d;
  }
}

// What the water's floor-return map takes from the board beside the tank
// (BoardLightMap::LightAt): with the light from +x, +y, the board just
// beyond the -y wall lies in the water column's shadow, the board just
// beyond the +y wall gets the light the glass facing it reflects at grazing
// incidence on top of its own, the open board far away keeps its light, and
// points off the map read 1.
TEST(BoardLightTest, LightAtReadsTheWetBoardBesideTheTank) {
  const glm::dvec3 light(0.35, 0.25, 1.0);
  const Maps m = Compute(WaterOptics{}, light);
  const double y_out = 0.5 * m.tank.size_y + m.optics.glass_thickness_m;
  const glm::vec3 shadow = m.map.LightAt(0.0, -y_out - 0.004, m.optics, 0.85f);
  const glm::vec3 lit = m.map.LightAt(0.0, y_out + 0.004, m.optics, 0.85f);
  const glm::vec3 far = m.map.LightAt(0.0, y_out + 0.07, m.optics, 0.85f);
  const glm::vec3 off = m.map.LightAt(1.0, 1.0, m.optics, 0.85f);
  std::printf(
      "board beside the tank: shadow side %.3f, lit side %.3f, "
      "7 cm out %.3f\n",
      shadow.g, lit.g, far.g);
  EXPECT_LT(shadow.g, 0.6f);
  EXPECT_GT(lit.g, far.g + 0.1f);
  EXPECT_NEAR(far.g, 1.0f, 0.03f);
  EXPECT_EQ(off, glm::vec3(1.0f));
}

}  // namespace
}  // namespace ripple::render::internal
