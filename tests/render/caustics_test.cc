// Nishita-Nakamae caustics: energy conservation, flat water gives a uniform
// map, and a ripple focuses light (bright and dark rings) without inventing
// any.
#include "render/caustics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "render/caustics_kernels.h"
#include "render/optics.h"

namespace ripple::render {
namespace {

struct Field {
  std::vector<float> h;
  HeightFieldView view;
};

// A 128 x 83 field over the default tank; `amplitude` of a cos * Gaussian
// ring at the centre.
Field MakeField(double amplitude, double x0 = 0.0, double sigma = 0.02) {
  Field f;
  const TankGeometry tank;
  const int nx = 128, ny = 83;
  const float d = tank.size_x / nx;
  f.h.resize(nx * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 - 0.5 * nx) * d - x0;
      const double y = (j + 0.5 - 0.5 * ny) * d;
      const double r = std::hypot(x, y);
      f.h[j * nx + i] =
          static_cast<float>(amplitude * std::cos(2 * M_PI * r / 0.012) *
                             std::exp(-r * r / (sigma * sigma)));
    }
  }
  f.view = {f.h.data(), nx, ny, d, 1};
  return f;
}

TEST(CausticsTest, FlatWaterUnderVerticalLightIsUniform) {
  Field f = MakeField(0.0);
  std::vector<float> map;
  CausticsSummary sum;
  ASSERT_TRUE(
      ComputeCaustics({}, f.view, TankGeometry{}, {0, 0, 1}, &map, &sum));
  ASSERT_EQ(map.size(), 256u * 256u);
  const auto [lo, hi] = std::minmax_element(map.begin(), map.end());
  EXPECT_NEAR(*lo, 1.0, 1e-3);
  EXPECT_NEAR(*hi, 1.0, 1e-3);
  // The 83-cell field is 0.2 mm wider than the tank in y: that strip's
  // light lands outside the map.
  EXPECT_NEAR(sum.flux_deposited + sum.flux_outside, sum.flux_in,
              1e-5 * sum.flux_in);
  EXPECT_LT(sum.flux_outside, 0.005 * sum.flux_in);
}

// Without a height field (null, or an empty size) the surface is flat by
// definition, so the map is the flat-water map: 1 wherever the refracted
// light lands, the same as a field of zeros gives, and the unlit strip along
// the walls facing an oblique light.
TEST(CausticsTest, MissingHeightFieldGivesTheFlatMap) {
  const std::vector<float> h(16, 0.0f);
  const HeightFieldView null_field;
  const HeightFieldView empty_field = {h.data(), 0, 0, 0.001f, 1};
  const HeightFieldView no_cell_size = {h.data(), 4, 4, 0.0f, 1};
  for (const HeightFieldView& view : {null_field, empty_field, no_cell_size}) {
    for (const glm::dvec3& light :
         {glm::dvec3(0, 0, 1), glm::dvec3(0.35, 0.25, 1.0)}) {
      CausticsOptions o;
      o.light_through_walls = false;
      o.glass_near_walls = false;
      std::vector<float> map, zeros;
      CausticsSummary sum;
      ASSERT_TRUE(ComputeCaustics(o, view, TankGeometry{}, light, &map, &sum));
      ASSERT_EQ(map.size(), 256u * 256u);
      Field f = MakeField(0.0);
      ASSERT_TRUE(
          ComputeCaustics(o, f.view, TankGeometry{}, light, &zeros, nullptr));
      // The zero field's mesh is 0.2 mm wider than the tank in y, which
      // moves the edge of the unlit strip along +y; away from it the two
      // agree.
      for (int b = 0; b < 230; ++b) {
        for (int a = 0; a < 256; ++a) {
          ASSERT_NEAR(map[b * 256 + a], zeros[b * 256 + a], 2e-3)
              << a << "," << b;
        }
      }
      const auto [lo, hi] = std::minmax_element(map.begin(), map.end());
      EXPECT_EQ(*hi, 1.0f);
      EXPECT_EQ(*lo, light.x == 0 ? 1.0f : 0.0f);
      EXPECT_NEAR(sum.flux_deposited + sum.flux_outside, sum.flux_in, 1e-9);
      EXPECT_EQ(sum.flux_walls, 0.0);
    }
  }
}

// Light through a glass side wall below the waterline: under flat water the
// strip along the wall facing an oblique light, which the surface's light
// misses, gets the slab formula's irradiance, T_wall cos_i |t_z| / (T_surface
// cos_l |t_x|) relative to flat water, and the light through the wall
// reaches level |t_x / t_z| into the tank.
TEST(CausticsTest, LightThroughTheWallsFollowsTheSlabFormula) {
  const TankGeometry tank;
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.35, 0.0, 1.0));
  std::vector<float> map;
  CausticsSummary sum;
  CausticsOptions o;
  o.glass_near_walls = false;  // the light through the walls alone
  ASSERT_TRUE(ComputeCaustics(o, HeightFieldView{}, tank, l, &map, &sum));
  const double n = 1.333, ng = 1.5;
  const double cos_i = l.x;
  const double sin_w = std::sqrt(1 - cos_i * cos_i) / n;  // in the water
  const double tx = std::sqrt(1 - sin_w * sin_w), tz = sin_w;
  const double cos_g = std::sqrt(1 - (1 - cos_i * cos_i) / (ng * ng));
  const double t_wall = (1 - FresnelReflectance(cos_i, 1, ng)) *
                        (1 - FresnelReflectance(cos_g, ng, n));
  const double t_surface = 1 - FresnelReflectance(l.z, 1, n);
  const double ratio = t_wall * cos_i * tz / (t_surface * l.z * tx);
  const double texel = tank.size_x / 256;
  // Flat water's unlit strip along +x and the wall light's reach.
  const double sin_s = std::sqrt(1 - l.z * l.z) / n;
  const double strip = tank.water_level * sin_s / std::sqrt(1 - sin_s * sin_s);
  const double reach = tank.water_level * tx / tz;
  ASSERT_GT(reach, strip + 4 * texel);
  const int b = 128;
  for (int a = 0; a < 256; ++a) {
    const double x0 = -0.5 * tank.size_x + a * texel;
    const double from_wall = 0.5 * tank.size_x - (x0 + texel);
    const float v = map[b * 256 + a];
    if (0.5 * tank.size_x - x0 < strip - 1e-9) {
      EXPECT_NEAR(v, ratio, 1e-4) << a;  // through the wall only
    } else if (x0 > 0.5 * tank.size_x - reach + 1e-9 &&
               from_wall > strip + 1e-9) {
      EXPECT_NEAR(v, 1.0 + ratio, 1e-4) << a;  // both
    } else if (from_wall > reach + 1e-9) {
      EXPECT_NEAR(v, 1.0, 1e-6) << a;  // the surface only
    }
  }
  // The light through the +x wall's submerged area (all of it lands on the
  // floor for a light in the x-z plane), in the map's units.
  EXPECT_NEAR(sum.flux_walls, ratio * tank.size_y * reach * l.z,
              2e-3 * sum.flux_walls);
}

// The glass near the walls in the thin slab's limit, flat water, light in
// the x-z plane: the +x wall's glass above the water transmits the light
// reaching a band of surface as a slab in air, (1 - R) / (1 + R); the -x wall's
// glass above the water reflects 2R / (1 + R) onto a band of the same width;
// below the water the -x wall mirrors back, totally, the light the surface
// sends beyond it, so the strip along it reads 2. The two bands cancel in flux:
// what is added is the light that would land beyond the -x wall.
TEST(CausticsTest, GlassNearTheWallsFollowsTheSlabFormulas) {
  const TankGeometry tank;
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.35, 0.0, 1.0));
  CausticsOptions o;
  o.light_through_walls = false;
  o.glass_thickness_m = 1e-6;  // the thin slab's limit
  std::vector<float> map;
  CausticsSummary sum;
  ASSERT_TRUE(ComputeCaustics(o, HeightFieldView{}, tank, l, &map, &sum));
  const double n = 1.333;
  const double r = FresnelReflectance(l.x, 1.0, 1.5);
  const double r_slab = 2 * r / (1 + r);
  const double sin_t = std::sqrt(1 - l.z * l.z) / n;
  const double shift =
      tank.water_level * sin_t / std::sqrt(1 - sin_t * sin_t);  // towards -x
  const double band = (tank.wall_height - tank.water_level) * l.x / l.z;
  const double h = 0.5 * tank.size_x, texel = tank.size_x / 256;
  ASSERT_GT(band, 4 * texel);
  ASSERT_GT(shift, 4 * texel);
  int checked[4] = {};
  const int b = 128;
  for (int a = 0; a < 256; ++a) {
    const double x0 = -h + a * texel, x1 = x0 + texel;
    const float v = map[b * 256 + a];
    // A texel wholly inside, and a texel from each edge (the glass's maps
    // are splatted bilinearly).
    auto inside = [&](double lo, double hi) {
      return x0 > lo + texel && x1 < hi - texel;
    };
    if (inside(-h, -h + shift)) {
      EXPECT_NEAR(v, 2.0, 5e-3) << a;  // mirrored by total reflection
      ++checked[0];
    } else if (inside(-h + shift, -h + shift + band)) {
      EXPECT_NEAR(v, 1.0 + r_slab, 5e-3) << a;  // reflected from above
      ++checked[1];
    } else if (inside(h - shift - band, h - shift)) {
      EXPECT_NEAR(v, 1.0 - r_slab, 5e-3) << a;  // through the glass
      ++checked[2];
    } else if (inside(-h + shift + band, h - shift - band)) {
      EXPECT_NEAR(v, 1.0, 1e-6) << a;
      ++checked[3];
    }
  }
  for (int k = 0; k < 4; ++k) EXPECT_GT(checked[k], 2) << k;
  // Each of the three band edges is resolved to a quarter texel (4 x 4
  // samples): an error of at most texel / 8 of the band's flux per edge.
  EXPECT_NEAR(sum.flux_near_walls, shift * tank.size_y * l.z,
              3 * texel / 8 * tank.size_y * l.z);
  // Off, the map is the surface's light alone.
  o.glass_near_walls = false;
  std::vector<float> plain;
  ASSERT_TRUE(ComputeCaustics(o, HeightFieldView{}, tank, l, &plain, &sum));
  EXPECT_NEAR(plain[b * 256 + 2], 1.0, 1e-6);
  EXPECT_EQ(sum.flux_near_walls, 0.0);
}

// Glass 3 mm thick, flat water, light in the x-z plane. Below the water the
// -x wall mirrors the surface's light by total reflection at its outer face,
// but the round trip through the slab moves it down by
// dz = 2 thickness |g_z / g_x| (g the direction in the glass), so only what
// meets the inner face above dz comes back into the water: the doubled strip
// narrows from level tan(theta_t) to (level - dz) tan(theta_t); beyond it
// only the water-glass face's own reflection R_wg is added. Above the water
// the +x wall's top face turns away the light it takes in (total reflection
// at the inner face guides it down the slab), and the light through the
// outer face drops by the slab's dz_a = thickness |g_z / g_x| on the way
// through: a band of the surface dz_a l_x / l_z wide, ending where the
// light grazes the wall's top, gets none, and the floor a dark line there,
// moved by the refraction's shift. Thin glass only dims that band as a slab
// in air.
TEST(CausticsTest, ThickGlassNarrowsTheMirrorAndShadesTheTopFace) {
  const TankGeometry tank;
  const glm::dvec3 l = glm::normalize(glm::dvec3(0.5, 0.0, 1.0));
  const double n = 1.333, ng = 1.5, g = 0.003;
  const double h = 0.5 * tank.size_x, texel = tank.size_x / 256;
  const double sin_t = std::sqrt(1 - l.z * l.z) / n;
  const double tan_t = sin_t / std::sqrt(1 - sin_t * sin_t);
  const double shift = tank.water_level * tan_t;
  // The mirror: in the glass, n g_z = n cos(theta_t) (tangential).
  const double gz = n * std::sqrt(1 - sin_t * sin_t) / ng;
  const double dz = 2 * g * gz / std::sqrt(1 - gz * gz);
  const double strip = (tank.water_level - dz) * tan_t;
  const double r_wg = FresnelReflectance(sin_t, n, ng);
  // The top face's shade on the surface and on the floor (from the +x wall).
  const double gz_air = l.z / ng;
  const double dz_air = g * gz_air / std::sqrt(1 - gz_air * gz_air);
  const double above = tank.wall_height - tank.water_level;
  const double shade_far = above * l.x / l.z + shift;
  const double shade_near = (above - dz_air) * l.x / l.z + shift;
  ASSERT_GT(strip, 4 * texel);
  ASSERT_GT(shift - strip, 4 * texel);
  std::vector<float> thick, thin;
  CausticsOptions o;
  o.light_through_walls = false;
  o.glass_thickness_m = g;
  ASSERT_TRUE(ComputeCaustics(o, HeightFieldView{}, tank, l, &thick, nullptr));
  o.glass_thickness_m = 1e-6;
  ASSERT_TRUE(ComputeCaustics(o, HeightFieldView{}, tank, l, &thin, nullptr));
  const int b = 128;
  double mirror = 0, beyond = 0, shade_thick = 2, shade_thin = 2;
  int n_mirror = 0, n_beyond = 0;
  for (int a = 0; a < 256; ++a) {
    const double x0 = -h + a * texel, x1 = x0 + texel;
    const float v = thick[b * 256 + a];
    if (x0 > -h + texel && x1 < -h + strip - texel) {
      mirror += v;
      ++n_mirror;
    } else if (x0 > -h + strip + texel && x1 < -h + shift - texel) {
      beyond += v;
      ++n_beyond;
    }
    if (x1 > h - shade_far && x0 < h - shade_near) {
      shade_thick = std::min<double>(shade_thick, v);
      shade_thin = std::min<double>(shade_thin, thin[b * 256 + a]);
    }
  }
  ASSERT_GT(n_mirror, 2);
  ASSERT_GE(n_beyond, 2);
  std::printf(
      "mirror strip %.2f mm: %.3f; beyond it %.3f (1 + R_wg %.3f); top face's "
      "shade %.2f-%.2f mm: %.3f (thin glass %.3f)\n",
      1e3 * strip, mirror / n_mirror, beyond / n_beyond, 1 + r_wg,
      1e3 * shade_near, 1e3 * shade_far, shade_thick, shade_thin);
  EXPECT_GT(mirror / n_mirror, 1.9);
  EXPECT_NEAR(beyond / n_beyond, 1 + r_wg, 0.02);
  // Thin glass mirrors the whole strip.
  EXPECT_NEAR(
      thin[b * 256 + static_cast<int>((strip + 0.5 * (shift - strip)) / texel)],
      2.0, 0.01);
  EXPECT_LT(shade_thick, 0.5);
  EXPECT_GT(shade_thin, 0.75);  // 1 - 2R / (1 + R), a slab in air
}

// Oblique light shifts the lit area by level * tan(refracted angle) away
// from the light; outside the unlit strip along the walls nearest the light
// the map stays uniform.
// The light's disc of angular radius alpha: straight down through flat
// water a direction tilted by b refracts to asin(sin b / n), so the disc
// lands on the floor as a uniform disc of radius
// rho = level tan(asin(sin alpha / n)), whose variance per axis is rho^2 / 4
// (plus 1/12 texel^2 for rounding each direction to its texel). Under an
// oblique light the footprint is no longer round but stays centred.
TEST(CausticsTest, PenumbraIsTheLightsDiscOnTheFloor) {
  const TankGeometry tank;
  const double n = 1.333, alpha = 2.0 * M_PI / 180.0;
  const double tx = tank.size_x / 1024.0, ty = tank.size_y / 1024.0;
  int r = -1;
  const std::vector<float> none =
      caustics_internal::PenumbraKernel(tank, {0, 0, 1}, n, 0.0, tx, ty, 8, &r);
  EXPECT_EQ(r, 0);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0], 1.0f);
  for (const glm::dvec3& light :
       {glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(0.35, 0.25, 1.0))}) {
    SCOPED_TRACE(light.x);
    const std::vector<float> k =
        caustics_internal::PenumbraKernel(tank, light, n, alpha, tx, ty, 8, &r);
    ASSERT_GT(r, 0);
    ASSERT_LT(r, 8);  // the whole disc fits
    const int side = 2 * r + 1;
    double sum = 0, mx = 0, my = 0, vx = 0, vy = 0;
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) {
        const double w = k[j * side + i], x = i - r, y = j - r;
        sum += w;
        mx += w * x;
        my += w * y;
        vx += w * x * x;
        vy += w * y * y;
      }
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    EXPECT_NEAR(mx, 0.0, 0.05);
    EXPECT_NEAR(my, 0.0, 0.05);
    if (light.x == 0) {
      const double rho =
          tank.water_level * std::tan(std::asin(std::sin(alpha) / n));
      EXPECT_NEAR(vx * tx * tx, rho * rho / 4 + tx * tx / 12, 0.05 * rho * rho);
      EXPECT_NEAR(vy * ty * ty, rho * rho / 4 + ty * ty / 12, 0.05 * rho * rho);
    }
  }
}

// Under flat water and an oblique light the disc softens the edge of the
// strip the surface's light misses, and moves no light: every row keeps its
// sum, and the interior stays exactly 1.
TEST(CausticsTest, PenumbraSoftensTheStripEdgeAndKeepsTheLight) {
  const TankGeometry tank;
  CausticsOptions o;
  o.map_nx = o.map_ny = 512;
  o.light_through_walls = false;
  o.glass_near_walls = false;
  std::vector<float> sharp, soft;
  const glm::dvec3 light(0.35, 0.25, 1.0);
  ASSERT_TRUE(ComputeCaustics(o, {}, tank, light, &sharp, nullptr));
  o.light_angular_radius_rad = 2.0 * M_PI / 180.0;
  ASSERT_TRUE(ComputeCaustics(o, {}, tank, light, &soft, nullptr));
  int soft_texels = 0, sharp_texels = 0;
  for (int b = 20; b < 400; ++b) {
    double s0 = 0, s1 = 0;
    for (int a = 0; a < 512; ++a) {
      const float v0 = sharp[b * 512 + a], v1 = soft[b * 512 + a];
      s0 += v0;
      s1 += v1;
      sharp_texels += v0 > 0.02f && v0 < 0.98f;
      soft_texels += v1 > 0.02f && v1 < 0.98f;
    }
    EXPECT_NEAR(s1, s0, 1e-3) << b;
    for (int a = 0; a < 400; ++a) EXPECT_NEAR(soft[b * 512 + a], 1.0, 1e-5);
  }
  EXPECT_GT(soft_texels, 2 * sharp_texels);  // a penumbra, not an edge
}

TEST(CausticsTest, FlatWaterUnderObliqueLightIsUniformInside) {
  Field f = MakeField(0.0);
  const TankGeometry tank;
  std::vector<float> map;
  CausticsOptions o;
  o.light_through_walls = false;
  o.glass_near_walls = false;
  ASSERT_TRUE(
      ComputeCaustics(o, f.view, tank, {0.35, 0.25, 1.0}, &map, nullptr));
  float lo = 1e9f, hi = -1e9f;
  for (int b = 0; b < 256 - 40; ++b) {
    for (int a = 0; a < 256 - 40; ++a) {
      lo = std::min(lo, map[b * 256 + a]);
      hi = std::max(hi, map[b * 256 + a]);
    }
  }
  EXPECT_NEAR(lo, 1.0, 1e-3);
  EXPECT_NEAR(hi, 1.0, 1e-3);
}

// The total deposited equals the light entering the surface, however much
// the ripple focuses it, for several lights and thread counts.
TEST(CausticsTest, ConservesEnergy) {
  Field f = MakeField(0.002);
  for (const glm::dvec3 light :
       {glm::dvec3(0, 0, 1), glm::dvec3(0.35, 0.25, 1.0),
        glm::dvec3(-0.2, 0.5, 1.0)}) {
    for (int threads : {1, 3}) {
      CausticsOptions o;
      o.threads = threads;
      o.light_through_walls = false;  // the surface's light only
      o.glass_near_walls = false;
      std::vector<float> map;
      CausticsSummary sum;
      ASSERT_TRUE(
          ComputeCaustics(o, f.view, TankGeometry{}, light, &map, &sum));
      EXPECT_EQ(sum.triangles, 2 * 128 * 83);
      EXPECT_GT(sum.flux_in, 0.0);
      EXPECT_NEAR(sum.flux_deposited + sum.flux_outside, sum.flux_in,
                  1e-5 * sum.flux_in);
      // The map itself integrates to the deposited flux.
      const double texel_area = (0.17 / 256) * (0.11 / 256);
      const double lz = glm::normalize(light).z;
      const double total =
          std::accumulate(map.begin(), map.end(), 0.0) * texel_area * lz;
      EXPECT_NEAR(total, sum.flux_deposited, 1e-5 * sum.flux_in);
      for (float v : map) ASSERT_GE(v, -1e-4f);
    }
  }
}

// A ripple focuses light into bright rings and leaves dark ones, and the
// map stays finite even where rays cross.
TEST(CausticsTest, RippleFocusesLight) {
  Field f = MakeField(0.003);
  std::vector<float> map;
  CausticsSummary sum;
  ASSERT_TRUE(
      ComputeCaustics({}, f.view, TankGeometry{}, {0, 0, 1}, &map, &sum));
  const auto [lo, hi] = std::minmax_element(map.begin(), map.end());
  EXPECT_GT(*hi, 1.5f);
  EXPECT_LT(*lo, 0.7f);
  EXPECT_TRUE(std::isfinite(*hi));
  // Away from the ripple, flat water.
  EXPECT_NEAR(map[10 * 256 + 10], 1.0, 1e-3);
}

// The AVX2 and baseline-ISA builds of the kernels agree (the CPU picks one
// at run time; `simd = false` forces the baseline).
TEST(CausticsTest, SimdAndBaselineAgree) {
  Field f = MakeField(0.003, 0.01);
  for (const glm::dvec3 light :
       {glm::dvec3(0, 0, 1), glm::dvec3(0.35, 0.25, 1.0)}) {
    CausticsOptions o;
    o.attenuation_per_m = 5.0;
    std::vector<float> a, b;
    CausticsSummary sa, sb;
    ASSERT_TRUE(ComputeCaustics(o, f.view, TankGeometry{}, light, &a, &sa));
    o.simd = false;
    ASSERT_TRUE(ComputeCaustics(o, f.view, TankGeometry{}, light, &b, &sb));
    ASSERT_EQ(a.size(), b.size());
    float worst = 0;
    for (size_t k = 0; k < a.size(); ++k) {
      worst = std::max(worst, std::abs(a[k] - b[k]));
    }
    EXPECT_LE(worst, 1e-4f);
    EXPECT_NEAR(sa.flux_deposited, sb.flux_deposited, 1e-6 * sa.flux_in);
  }
}

TEST(CausticsTest, AttenuationIsRelativeToFlatWater) {
  Field f = MakeField(0.0);
  CausticsOptions o;
  o.attenuation_per_m = 20.0;
  std::vector<float> map;
  ASSERT_TRUE(
      ComputeCaustics(o, f.view, TankGeometry{}, {0, 0, 1}, &map, nullptr));
  EXPECT_NEAR(map[128 * 256 + 128], 1.0, 1e-3);
}

TEST(CausticsTest, RejectsBadInput) {
  CausticsOptions o;
  o.ior = 0.5;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  for (const double thickness : {-0.001, 0.2}) {
    CausticsOptions g;
    g.glass_thickness_m = thickness;
    EXPECT_FALSE(g.IsValid(&error)) << thickness;
  }
  for (const int paths : {0, 17}) {
    CausticsOptions g;
    g.glass_paths_per_axis = paths;
    EXPECT_FALSE(g.IsValid(&error)) << paths;
    EXPECT_NE(error.find("paths per axis"), std::string::npos) << error;
  }
  std::vector<float> map;
  EXPECT_FALSE(ComputeCaustics({}, {}, TankGeometry{}, {0, 0, -1}, &map,
                               nullptr));  // light from below
}

}  // namespace
}  // namespace ripple::render
