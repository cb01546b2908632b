// Nishita-Nakamae caustics: energy conservation, flat water gives a uniform
// map, and a ripple focuses light (bright and dark rings) without inventing
// any.
#include "render/caustics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

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
// definition, so the map is the flat-water map: uniform 1, not 0, whatever
// the light.
TEST(CausticsTest, MissingHeightFieldGivesTheFlatMap) {
  const std::vector<float> h(16, 0.0f);
  const HeightFieldView null_field;
  const HeightFieldView empty_field = {h.data(), 0, 0, 0.001f, 1};
  const HeightFieldView no_cell_size = {h.data(), 4, 4, 0.0f, 1};
  for (const HeightFieldView& view : {null_field, empty_field, no_cell_size}) {
    for (const glm::dvec3& light :
         {glm::dvec3(0, 0, 1), glm::dvec3(0.35, 0.25, 1.0)}) {
      std::vector<float> map;
      CausticsSummary sum;
      ASSERT_TRUE(ComputeCaustics({}, view, TankGeometry{}, light, &map, &sum));
      ASSERT_EQ(map.size(), 256u * 256u);
      const auto [lo, hi] = std::minmax_element(map.begin(), map.end());
      EXPECT_EQ(*lo, 1.0f);
      EXPECT_EQ(*hi, 1.0f);
      EXPECT_NEAR(sum.flux_deposited, sum.flux_in, 1e-12);
      EXPECT_EQ(sum.flux_outside, 0.0);
    }
  }
}

// Oblique light shifts the lit area by level * tan(refracted angle) away
// from the light; outside the unlit strip along the walls nearest the light
// the map stays uniform.
TEST(CausticsTest, FlatWaterUnderObliqueLightIsUniformInside) {
  Field f = MakeField(0.0);
  const TankGeometry tank;
  std::vector<float> map;
  ASSERT_TRUE(
      ComputeCaustics({}, f.view, tank, {0.35, 0.25, 1.0}, &map, nullptr));
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
  std::vector<float> map;
  EXPECT_FALSE(ComputeCaustics({}, {}, TankGeometry{}, {0, 0, -1}, &map,
                               nullptr));  // light from below
}

}  // namespace
}  // namespace ripple::render
