// The water's optics against their formulas: Fresnel's equations, pure
// water's absorption, the sRGB transfer, the highlight shoulder, and the
// diffuse interface relations the shading model relies on.
#include "render/optics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>

namespace ripple::render {
namespace {

constexpr double kWater = 1.333;

TEST(OpticsTest, FresnelAtNormalIncidenceBrewsterAndGrazing) {
  const double r0 = std::pow((kWater - 1) / (kWater + 1), 2);
  EXPECT_NEAR(FresnelReflectance(1.0, 1.0, kWater), r0, 1e-12);
  EXPECT_NEAR(FresnelReflectance(1.0, kWater, 1.0), r0, 1e-12);
  // At Brewster's angle p-polarised light is not reflected: R = rs^2 / 2.
  const double tb = std::atan(kWater);
  const double ci = std::cos(tb), ct = std::sin(tb);  // theta_t = 90 - theta_b
  const double rs = (ci - kWater * ct) / (ci + kWater * ct);
  EXPECT_NEAR(FresnelReflectance(ci, 1.0, kWater), 0.5 * rs * rs, 1e-12);
  EXPECT_NEAR(FresnelReflectance(1e-9, 1.0, kWater), 1.0, 1e-6);
  // Monotonic in the angle from the air side.
  double last = 0;
  for (double c = 1.0; c > 0.0; c -= 0.01) {
    const double r = FresnelReflectance(c, 1.0, kWater);
    EXPECT_GE(r, last - 1e-12);
    last = r;
  }
}

TEST(OpticsTest, FresnelIsReciprocalAndTotalInsideBeyondTheCriticalAngle) {
  for (double c_air = 0.05; c_air <= 1.0; c_air += 0.05) {
    const double sin_w = std::sqrt(1 - c_air * c_air) / kWater;
    const double c_water = std::sqrt(1 - sin_w * sin_w);
    EXPECT_NEAR(FresnelReflectance(c_air, 1.0, kWater),
                FresnelReflectance(c_water, kWater, 1.0), 1e-12);
  }
  const double c_crit = std::sqrt(1 - 1 / (kWater * kWater));
  EXPECT_EQ(FresnelReflectance(c_crit - 1e-6, kWater, 1.0), 1.0);
  EXPECT_LT(FresnelReflectance(c_crit + 1e-3, kWater, 1.0), 1.0);
}

TEST(OpticsTest, PopeAndFryTableAndBandMeans) {
  // Table values (Pope & Fry 1997, Table 3).
  EXPECT_DOUBLE_EQ(PureWaterAbsorptionAt(420), 0.00454);
  EXPECT_DOUBLE_EQ(PureWaterAbsorptionAt(550), 0.0565);
  EXPECT_DOUBLE_EQ(PureWaterAbsorptionAt(650), 0.34);
  EXPECT_NEAR(PureWaterAbsorptionAt(655), 0.5 * (0.34 + 0.41), 1e-12);
  // Band means by a fine independent quadrature of the interpolant.
  auto mean = [](double lo, double hi) {
    double s = 0;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
      s += PureWaterAbsorptionAt(lo + (i + 0.5) * (hi - lo) / n);
    }
    return s / n;
  };
  const glm::dvec3 rgb = PureWaterAbsorptionRgb();
  EXPECT_NEAR(rgb.r, mean(600, 700), 1e-6);
  EXPECT_NEAR(rgb.g, mean(500, 600), 1e-6);
  EXPECT_NEAR(rgb.b, mean(400, 500), 1e-6);
  // Red is absorbed ~5x more than green and ~40x more than blue.
  EXPECT_NEAR(rgb.r, 0.36, 0.02);
  EXPECT_NEAR(rgb.g, 0.070, 0.005);
  EXPECT_NEAR(rgb.b, 0.0086, 0.002);
}

TEST(OpticsTest, SrgbTransfer) {
  EXPECT_NEAR(LinearToSrgb(0.5), 0.735357, 1e-6);
  EXPECT_NEAR(SrgbToLinear(0.5), 0.214041, 1e-6);
  EXPECT_EQ(LinearToSrgb(0.0), 0.0);
  EXPECT_NEAR(LinearToSrgb(1.0), 1.0, 1e-12);
  for (double x = 0; x <= 1.0; x += 0.001) {
    EXPECT_NEAR(SrgbToLinear(LinearToSrgb(x)), x, 1e-9);
  }
  // Continuous at the breakpoint (to the standard's rounding of 12.92).
  EXPECT_NEAR(LinearToSrgb(0.0031308 - 1e-9), LinearToSrgb(0.0031308 + 1e-9),
              1e-6);
}

TEST(OpticsTest, HighlightShoulderKeepsTheShapeAboveTheKnee) {
  const double k = 0.8;
  EXPECT_EQ(HighlightShoulder(0.5, k), 0.5);
  EXPECT_EQ(HighlightShoulder(k, k), k);
  const double h = 1e-6;
  EXPECT_NEAR((HighlightShoulder(k + h, k) - HighlightShoulder(k, k)) / h, 1.0,
              1e-4);
  double last = 0;
  for (double x = 0; x < 50; x += 0.05) {
    const double y = HighlightShoulder(x, k);
    EXPECT_GT(y, last - 1e-15);
    EXPECT_LT(y, 1.0);
    last = y;
  }
  // Caustic irradiance of 1.5 and 3 stays apart by several 8-bit levels
  // after sRGB encoding (clipping made them equal).
  EXPECT_GE(255 * (LinearToSrgb(HighlightShoulder(3.0, k)) -
                   LinearToSrgb(HighlightShoulder(1.5, k))),
            3.0);
}

// Snell's window's shares of a plane's view under water, against direct
// quadrature over directions (zenith t, azimuth p): (1 / pi) times the
// integral of max(0, d . n) sin t over the window, for a plane facing up and
// a vertical one; the rest of the upper view is the total reflection; the
// window's reflectance makes up DiffuseInternalReflectance.
TEST(OpticsTest, SnellWindowSharesMatchQuadrature) {
  const SnellWindowShares w = ComputeSnellWindowShares(kWater);
  const double theta_c = std::asin(1.0 / kWater);
  const int nt = 2000, np = 2000;
  double up = 0, side = 0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * theta_c / nt;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * 2.0 * M_PI / np;
      const double dw = std::sin(t) * (theta_c / nt) * (2.0 * M_PI / np);
      up += std::cos(t) * dw;
      side += std::max(0.0, std::sin(t) * std::cos(p)) * dw;
    }
  }
  EXPECT_NEAR(w.facing_up, up / M_PI, 1e-5);
  EXPECT_NEAR(w.facing_side, side / M_PI, 1e-5);
  EXPECT_NEAR(w.facing_up, 1.0 / (kWater * kWater), 1e-12);
  EXPECT_NEAR(w.facing_side, 0.112, 0.001);
  EXPECT_NEAR(w.facing_up * w.reflectance + 1.0 - w.facing_up,
              DiffuseInternalReflectance(kWater), 1e-12);
  EXPECT_GT(w.reflectance, 0.02);  // normal incidence's 0.0204 and more
  EXPECT_LT(w.reflectance, 0.2);
}

// Energy between the two sides of a flat interface: the diffuse light a
// medium of index n lets out is (1 - R_internal), and reciprocity makes it
// the external diffuse transmittance over n^2.
TEST(OpticsTest, DiffuseInterfaceRelations) {
  const double r_int = DiffuseInternalReflectance(kWater);
  const double t_ext = SkyTransmittance(kWater, 0.0, 0.0);
  EXPECT_NEAR((1 - r_int) * kWater * kWater, t_ext, 1e-4);
  EXPECT_GT(r_int, 1 - 1 / (kWater * kWater));  // TIR alone
  EXPECT_NEAR(r_int, 0.475, 0.01);
  EXPECT_NEAR(t_ext, 0.934, 0.005);
  // Absorption: the mean path to the floor is longer than the depth.
  const double sigma = 2.0, d = 0.05;
  EXPECT_LT(SkyTransmittance(kWater, sigma, d), t_ext * std::exp(-sigma * d));
  EXPECT_GT(SkyTransmittance(kWater, sigma, d),
            t_ext * std::exp(-sigma * d * kWater));
  EXPECT_NEAR(DirectTransmittance(1.0, kWater, sigma, d),
              (1 - FresnelReflectance(1.0, 1.0, kWater)) * std::exp(-sigma * d),
              1e-12);
}

// A face above the water sees the surface's reflectance over its lower
// view: facing down, the diffuse external reflectance, 1 - that is the sky
// transmittance (reciprocity: n^2 (1 - R_internal)); facing sideways, the
// directions near the horizon weigh in, where the surface mirrors. The
// vertical face's figure against a Monte Carlo estimate (cosine-weighted
// directions about the face's normal, 400,000, fixed seed).
TEST(OpticsTest, LowerViewReflectanceOfTheWater) {
  const LowerViewReflectance r = ComputeLowerViewReflectance(kWater);
  EXPECT_NEAR(1.0 - r.facing_down, SkyTransmittance(kWater, 0.0, 0.0), 1e-4);
  EXPECT_NEAR(1.0 - r.facing_down,
              kWater * kWater * (1.0 - DiffuseInternalReflectance(kWater)),
              1e-4);
  std::uint64_t state = 12345;
  auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return ((state >> 11) + 0.5) * 0x1.0p-53;
  };
  double sum = 0;
  int n = 0;
  for (int k = 0; k < 400000; ++k) {
    // Cosine-weighted about +x: (sqrt(1 - u), sqrt(u) cos phi, sqrt(u) sin
    // phi); the lower half of them.
    const double u = uniform(), phi = 2.0 * M_PI * uniform();
    const double dz = std::sqrt(u) * std::sin(phi);
    if (dz >= 0) continue;
    sum += FresnelReflectance(-dz, 1.0, kWater);
    ++n;
  }
  EXPECT_NEAR(r.facing_side, sum / n, 0.002);
  EXPECT_GT(r.facing_side, 2.0 * r.facing_down);
  EXPECT_NEAR(r.facing_side, 0.21, 0.01);
}

TEST(OpticsTest, WaterShadingConstants) {
  WaterOptics o = WaterOptics::ForLook(WaterLook::kClear);
  const glm::dvec3 light(0.0, 0.6, 0.8);
  const WaterShading s = ComputeWaterShading(o, 0.025, light);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(
        s.floor_sky[c],
        o.ambient_share * SkyTransmittance(o.ior, o.absorption_per_m[c], 0.025),
        1e-6);
    EXPECT_NEAR(
        s.floor_sun[c],
        (1 - o.ambient_share) *
            DirectTransmittance(0.8, o.ior, o.absorption_per_m[c], 0.025),
        1e-6);
  }
  // Clear water at 25 mm keeps ~95% of the light for every band.
  EXPECT_GT(s.floor_sky.r + s.floor_sun.r, 0.9);
  const double alpha = o.light_angular_radius_rad;
  EXPECT_NEAR(s.glint_peak, (1 - o.ambient_share) / (0.8 * alpha * alpha),
              1e-3);
  EXPECT_NEAR(s.inv_n2, 1 / (o.ior * o.ior), 1e-6);
}

// The board under a glass wall, seen through the wall from inside the
// water: the sky's share keeps its light (the n_g^2 of the glass's filled
// hemisphere cancels on the way out), the collimated direct light loses
// n_g^2; both cross the glass-water interface. Under a vertical light only
// the top face lets the light in. Normal-incidence Fresnel written out:
// ((n1 - n2) / (n1 + n2))^2.
TEST(OpticsTest, BoardUnderGlassKeepsTheSkyAndLosesNSquaredOfTheDirectLight) {
  WaterOptics o = WaterOptics::ForLook(WaterLook::kClear);
  const double inner = 1.0 - std::pow((1.5 - 1.333) / (1.5 + 1.333), 2.0);
  const double top = 1.0 - std::pow(0.5 / 2.5, 2.0);
  o.ambient_share = 1.0f;
  WaterShading s = ComputeWaterShading(o, 0.025, glm::dvec3(0.3, 0.2, 1.0));
  for (int w = 0; w < 4; ++w)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.under_glass[w][c], inner, 1e-6);
  o.ambient_share = 0.0f;
  s = ComputeWaterShading(o, 0.025, glm::dvec3(0.0, 0.0, 1.0));
  for (int w = 0; w < 4; ++w)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(s.under_glass[w][c], top * inner / 2.25, 1e-6);
  // Daylight tints weigh the two shares per band.
  o.ambient_share = 0.3f;
  o.sky_tint = glm::vec3(1.4f, 1.0f, 0.6f);
  o.sun_tint = (glm::vec3(1.0f) - 0.3f * o.sky_tint) / 0.7f;
  s = ComputeWaterShading(o, 0.025, glm::dvec3(0.0, 0.0, 1.0));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(
        s.under_glass[0][c],
        (0.3 * o.sky_tint[c] + 0.7 * o.sun_tint[c] * top / 2.25) * inner, 1e-6);
  }
}

// The direct light under a wall, against parallel rays marched through the
// slab (a cross-section normal to the wall): rays entering the inner face
// from the water at evenly spaced heights, or the outer face from outside,
// each counted when it reaches the board inside the glass, on its way in
// or after the outer face's reflection.
TEST(OpticsTest, UnderGlassDirectLightMatchesRaysMarchedThroughTheSlab) {
  const WaterOptics o = WaterOptics::ForLook(WaterLook::kClear);
  const double nw = o.ior, ng = o.glass_ior, g = o.glass_thickness_m;
  const double depth = 0.025;
  const glm::dvec3 light = glm::normalize(glm::dvec3(0.6, 0.1, 0.8));
  const double top = 1.0 - FresnelReflectance(light.z, 1.0, ng);
  // Marches a ray entering a face at height z0 with direction `t` in the
  // glass (its component across the slab is |t.x|): the share of it that
  // reaches z = 0 inside the slab.
  auto reaches = [&](double z0, glm::dvec3 t, double weight, bool reflect) {
    const double drop = g * std::abs(t.z) / std::abs(t.x);
    if (z0 <= drop) return weight;
    if (!reflect) return 0.0;
    const double cos_g = std::abs(t.x);
    const double sin_g = std::sqrt(1.0 - cos_g * cos_g);
    const double r =
        ng * sin_g >= 1.0 ? 1.0 : FresnelReflectance(cos_g, ng, 1.0);
    return z0 <= 2.0 * drop ? weight * r : 0.0;
  };
  const int n = 20000;
  // The -x wall, met by the refracted beam in the water.
  const glm::dvec3 dw = glm::refract(-light, glm::dvec3(0, 0, 1), 1.0 / nw);
  const glm::dvec3 into_glass(1.0, 0.0, 0.0);  // the inner face's normal
  const glm::dvec3 tg = glm::refract(dw, into_glass, nw / ng);
  ASSERT_GT(glm::length(tg), 0.5);
  const double c_in = -dw.x;
  const double t_in = 1.0 - FresnelReflectance(c_in, nw, ng);
  double flux = 0;  // per unit of the wall's irradiance, per metre of wall
  for (int i = 0; i < n; ++i) {
    const double z0 = (i + 0.5) / n * depth;
    flux += reaches(z0, tg, t_in, true) * depth / n;
  }
  const double per_wall =
      (1.0 - FresnelReflectance(light.z, 1.0, nw)) * c_in / -dw.z;
  EXPECT_NEAR(UnderGlassDirectLight(o, light, {-1, 0, 0}, depth),
              top + per_wall * flux / g, 2e-3);
  // The +x wall, met from outside (its outer face looks at the light).
  const glm::dvec3 to = glm::refract(-light, glm::dvec3(1, 0, 0), 1.0 / ng);
  const double c_out = light.x;
  const double t_out = 1.0 - FresnelReflectance(c_out, 1.0, ng);
  flux = 0;
  const double wall = 0.04;
  for (int i = 0; i < n; ++i) {
    const double z0 = (i + 0.5) / n * wall;
    flux += reaches(z0, to, t_out, false) * wall / n;
  }
  EXPECT_NEAR(UnderGlassDirectLight(o, light, {1, 0, 0}, depth),
              top + c_out / light.z * flux / g, 2e-3);
  // The walls along x see neither beam: the top face alone (the light's y
  // is small but not zero: the -y wall's inner face and the +y wall's
  // outer face take a little).
  EXPECT_GT(UnderGlassDirectLight(o, light, {0, -1, 0}, depth), top);
  EXPECT_GT(UnderGlassDirectLight(o, light, {0, 1, 0}, depth), top);
  EXPECT_LT(UnderGlassDirectLight(o, light, {0, -1, 0}, depth),
            UnderGlassDirectLight(o, light, {-1, 0, 0}, depth));
  // A shallower tank lets in less through the inner face.
  EXPECT_LT(UnderGlassDirectLight(o, light, {-1, 0, 0}, 0.004),
            UnderGlassDirectLight(o, light, {-1, 0, 0}, depth));
}

// The floor's light that comes back to it: in a wide layer without
// absorption it is the diffuse internal reflectance; absorption takes more
// red than blue; the walls let part of it out, more near them, and let the
// surroundings' light in.
TEST(OpticsTest, FloorReturnInTheTanksBox) {
  WaterOptics clear;
  WaterOptics no_absorption = clear;
  no_absorption.absorption_per_m = glm::vec3(0.0f);
  const FloorReturnMap wide =
      ComputeFloorReturn(no_absorption, 50.0, 50.0, 0.025, 0.04, 1, 1, 4096);
  EXPECT_NEAR(wide.returned[0].g, DiffuseInternalReflectance(1.333), 0.005);
  const FloorReturnMap tank =
      ComputeFloorReturn(clear, 0.17, 0.11, 0.025, 0.04, 17, 11, 4096);
  const glm::vec3 centre = tank.returned[5 * 17 + 8];
  const glm::vec3 edge = tank.returned[5 * 17 + 0];
  EXPECT_LT(centre.r, centre.b);
  EXPECT_LT(centre.b, wide.returned[0].b);
  EXPECT_GT(centre.b, 0.15);
  EXPECT_LT(edge.b, wide.returned[0].b);
  // Symmetric about the tank's centre (to the sampling's noise: each texel's
  // directions are shifted by its own offset).
  EXPECT_NEAR(tank.returned[2 * 17 + 3].g, tank.returned[8 * 17 + 13].g, 4e-3);
  // What leaves through the walls is replaced by the surroundings' light: a
  // board as bright as the floor nearly makes up for it; the wide layer has
  // no walls to let light in.
  EXPECT_NEAR(wide.surround[0].g, 0.0, 1e-3);
  EXPECT_GT(tank.surround[5 * 17 + 8].g, 0.1);
}

// Clausius' law: inside a lossless dielectric of index n in an enclosure of
// uniform radiance L, the radiance is n^2 L in every direction. A white
// floor under clear water in the tank, the sky and the board around it of
// radiance 1: the floor's light (sky through the surface, the surroundings
// through the walls, its own light returned) must be n^2 at `texels`
// (17 x 11 over the default tank), within `tolerance`.
void ExpectUniformWorldFloorLight(const WaterOptics& glass,
                                  std::initializer_list<int> texels,
                                  double tolerance) {
  WaterOptics o = glass;
  o.absorption_per_m = glm::vec3(0.0f);
  o.ambient_share = 1.0f;
  const WaterShading shading =
      ComputeWaterShading(o, 0.025, glm::dvec3(0.3, 0.2, 1.0));
  const FloorReturnMap map =
      ComputeFloorReturn(o, 0.17, 0.11, 0.025, 0.04, 17, 11, 4096, 1.0);
  const double n2 = double(o.ior) * o.ior;
  for (const int at : texels) {
    const double light = shading.floor_sky.g + map.surround[at].g;
    const double floor = light / (1.0 - map.returned[at].g);
    EXPECT_NEAR(floor / n2, 1.0, tolerance) << "texel " << at;
  }
}

// Glass of the water's index: the walls are a water-air interface, so the
// surface's and the walls' bookkeeping is checked alone, at the centre, by a
// wall and in a corner.
TEST(OpticsTest, FloorLightInAUniformWorldIsNSquared) {
  WaterOptics o;
  o.glass_ior = o.ior;
  ExpectUniformWorldFloorLight(o, {5 * 17 + 8, 5 * 17 + 0, 0}, 0.002);
}

// The same law with real glass walls, 3 mm thick and 15 mm taller than the
// water: light the slabs trap (totally reflected at their outer faces and
// guided up to their top faces, or down onto the board under them) is
// followed to where it leaves, so the floor's light stays n^2 everywhere.
// Within 1%: the directions are shifted per texel, so each texel carries
// its own sampling noise.
TEST(OpticsTest, FloorLightInAUniformWorldIsNSquaredWithThickGlass) {
  const WaterOptics o;
  ASSERT_GT(o.glass_ior, o.ior);
  ASSERT_GT(o.glass_thickness_m, 0.0f);
  ExpectUniformWorldFloorLight(o, {5 * 17 + 8, 5 * 17 + 0, 0, 10 * 17 + 8},
                               0.01);
}

// The glass's thickness moves light from the floor's return to the board
// under the walls: a ray that the outer face reflects totally comes back
// lower, and one that meets the wall low reaches the board inside the glass.
TEST(OpticsTest, TheWallsThicknessMovesTheReturnUnderTheGlass) {
  WaterOptics thin, thick;
  thin.glass_thickness_m = 1e-6f;
  const FloorReturnMap a =
      ComputeFloorReturn(thin, 0.17, 0.11, 0.025, 0.04, 17, 11, 4096);
  const FloorReturnMap b =
      ComputeFloorReturn(thick, 0.17, 0.11, 0.025, 0.04, 17, 11, 4096);
  const size_t centre = 5 * 17 + 8;
  EXPECT_LT(b.returned[centre].g, a.returned[centre].g - 0.003);
  double board_a = 0, board_b = 0;
  for (int w = 0; w < 4; ++w) {
    board_a += a.board[w][centre].g;
    board_b += b.board[w][centre].g;
  }
  EXPECT_GT(board_b, board_a);
}

// The surroundings split by source add up to the constant-board map, and
// each wall's landing points lie on the board beyond that wall (within the
// distance a ray leaving the water's depth can travel at the steepest
// down-going exit the points sample).
TEST(OpticsTest, SurroundingsSplitByWallAndLandOnTheBoard) {
  const WaterOptics o;
  const double sx = 0.17, sy = 0.11, depth = 0.025, radiance = 0.6;
  const FloorReturnMap map =
      ComputeFloorReturn(o, sx, sy, depth, 0.04, 17, 11, 4096, radiance);
  for (size_t i = 0; i < map.surround.size(); ++i) {
    glm::vec3 sum = map.sky[i];
    for (const std::vector<glm::vec3>& b : map.board)
      sum += float(radiance) * b[i];
    EXPECT_NEAR(sum.g, map.surround[i].g, 1e-5) << "texel " << i;
    EXPECT_GT(map.board[0][i].g + map.board[1][i].g + map.board[2][i].g +
                  map.board[3][i].g,
              0.0f);
  }
  for (int w = 0; w < 4; ++w) {
    ASSERT_EQ(map.board_points[w].size(), size_t(FloorReturnMap::kBoardPoints))
        << "wall " << w;
    for (const glm::dvec2& p : map.board_points[w]) {
      const double beyond = w == 0   ? p.x - 0.5 * sx
                            : w == 1 ? -0.5 * sx - p.x
                            : w == 2 ? p.y - 0.5 * sy
                                     : -0.5 * sy - p.y;
      EXPECT_GE(beyond, 0.0) << "wall " << w;
      EXPECT_LT(beyond, 1.0) << "wall " << w;
    }
  }
  // The walls facing the centre symmetrically see symmetric shares (to the
  // sampling noise).
  const size_t centre = 5 * 17 + 8;
  EXPECT_NEAR(map.board[0][centre].g, map.board[1][centre].g, 3e-3);
  EXPECT_NEAR(map.board[2][centre].g, map.board[3][centre].g, 3e-3);
}

TEST(OpticsTest, OptionsAndNames) {
  std::string error;
  EXPECT_TRUE(WaterOptics::ForLook(WaterLook::kPool).IsValid(&error));
  WaterOptics o;
  o.ambient_share = 1.5f;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("ambient"), std::string::npos);
  o = WaterOptics();
  o.light_angular_radius_rad = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = WaterOptics();
  o.absorption_per_m.r = std::nanf("");
  EXPECT_FALSE(o.IsValid(&error));
  o = WaterOptics();
  o.glass_thickness_m = -0.001f;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("glass thickness"), std::string::npos);
  WaterLook look;
  EXPECT_TRUE(ParseWaterLook("pool", &look));
  EXPECT_EQ(look, WaterLook::kPool);
  EXPECT_FALSE(ParseWaterLook("Pool", &look));
  Transfer t;
  EXPECT_TRUE(geometry::ParseTransfer("linear", &t));
  EXPECT_EQ(t, Transfer::kLinear);
  EXPECT_FALSE(geometry::ParseTransfer("gamma", &t));
}

}  // namespace
}  // namespace ripple::render
