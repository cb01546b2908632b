// The real-time caustics map near the glass walls (render/caustics.h) against
// the reference renderer's light tracer (render/reference): under flat water
// and an oblique light, the floor's direct light in strips along each wall,
// where 3 mm slabs mirror, transmit and shade the surface's light, and the
// strip the surface's light misses is lit through the wall.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "render/caustics.h"
#include "render/optics.h"
#include "render/reference/reference.h"

namespace ripple {
namespace {

// One 1 mm bin of a profile across a wall: the values that fell in it.
struct Bin {
  double sum = 0;
  int count = 0;
  double Mean() const { return count > 0 ? sum / count : 0.0; }
};

// The light-traced and the real-time relative irradiance, per wall (+x, -x,
// +y, -y) and per 1 mm bin from the wall's inner face out to `depth_m`.
struct Profiles {
  std::vector<Bin> reference[4], realtime[4];
};

// Adds the value at floor point (x, y) to the bin of each wall whose inner
// face it lies within `depth_m` of, if it lies within `across_share` of
// that wall's half length of the wall's middle.
void Accumulate(double x, double y, double value, const render::TankGeometry& t,
                double depth_m, double across_share, std::vector<Bin>* bins) {
  const double h[2] = {0.5 * t.size_x, 0.5 * t.size_y};
  const double p[2] = {x, y};
  for (int wall = 0; wall < 4; ++wall) {
    const int axis = wall / 2;
    const double side = wall % 2 == 0 ? 1.0 : -1.0;
    const double from = h[axis] - side * p[axis];
    if (from < 0 || from >= depth_m) continue;
    if (std::abs(p[1 - axis]) > across_share * h[1 - axis]) continue;
    Bin& b = bins[wall][static_cast<int>(from / 0.001)];
    b.sum += value;
    ++b.count;
  }
}

Profiles Measure(double glass_thickness_m, const glm::dvec3& light,
                 double depth_m) {
  reference::ReferenceScene rs;
  rs.camera = geometry::MakeIdealCamera(64, 48, 60);
  rs.scene.light_in_tank = light;
  rs.absorption_per_m = {0.0f, 0.0f, 0.0f};
  rs.glass_thickness_m = glass_thickness_m;
  reference::ReferenceOptions o;
  o.caustic_map_size = 340;  // 0.5 mm texels
  o.light_paths_per_texel = 64;
  o.threads = 2;
  reference::LightMaps maps;
  reference::LightTraceSummary sum;
  std::string error;
  EXPECT_TRUE(reference::ComputeLightMaps(o, rs, &maps, &sum, &error)) << error;
  const glm::dvec3 l = glm::normalize(light);
  const reference::LightRadiometry rad = reference::ComputeLightRadiometry(rs);
  const double open =
      rad.disc_irradiance * l.z *
      (1.0 - render::FresnelReflectance(l.z, 1.0, rs.water_ior));
  const render::TankGeometry& tank = rs.scene.tank;
  const int bins = static_cast<int>(std::ceil(depth_m / 0.001));
  Profiles pr;
  for (int w = 0; w < 4; ++w) {
    pr.reference[w].resize(bins);
    pr.realtime[w].resize(bins);
  }
  const cv::Mat& m = maps.floor_irradiance;
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) {
      const double x =
          maps.floor_rect_m.x + (c + 0.5) * maps.floor_rect_m.width / m.cols;
      const double y =
          maps.floor_rect_m.y + (r + 0.5) * maps.floor_rect_m.height / m.rows;
      Accumulate(x, y, m.at<cv::Vec3f>(r, c)[1] / open, tank, depth_m, 0.6,
                 pr.reference);
    }
  }
  render::CausticsOptions co;  // 256 x 256, the renderer's map
  co.glass_ior = rs.glass_ior;
  co.glass_thickness_m = glass_thickness_m;
  co.light_angular_radius_rad = rs.light_angular_radius_rad;
  std::vector<float> map;
  EXPECT_TRUE(render::ComputeCaustics(co, {}, tank, l, &map, nullptr));
  for (int b = 0; b < co.map_ny; ++b) {
    for (int a = 0; a < co.map_nx; ++a) {
      const double x = (a + 0.5) * tank.size_x / co.map_nx - 0.5 * tank.size_x;
      const double y = (b + 0.5) * tank.size_y / co.map_ny - 0.5 * tank.size_y;
      Accumulate(x, y, map[b * co.map_nx + a], tank, depth_m, 0.6, pr.realtime);
    }
  }
  return pr;
}

// Along each wall the glass changes the floor's light within about 12 mm
// (the light's run over the wall above the water and through the water's
// depth): the mirrored strip along the walls facing away, the shade of the
// top face's line and the light through the walls facing the light; and in
// a band about one depth from the walls facing away, the light that crossed
// such a wall above the water, was reflected by its outer face and came
// back in below the water line (refracted as if straight from the air
// through the wall's plane, steeply: 6 mm wide and 5% over the open water's
// light for this light and 3 mm glass). The real-time map follows the light
// tracer's profile to 30 mm, bin by bin (1 mm): the mean difference per
// wall within 0.03 and no bin off by more than 0.25 (the two blur edges
// differently: the tracer's 0.5 mm texels, the map's 0.66 x 0.43 mm and the
// light's disc), and from 15 to 30 mm, where only that band lies, the mean
// within 0.005 (without the band it is 0.02 low on the walls facing away).
TEST(CausticsReferenceTest, FloorNearTheWallsFollowsTheLightTracer) {
  const glm::dvec3 light(0.35, 0.25, 1.0);
  const double depth = 0.030;
  const Profiles pr = Measure(0.003, light, depth);
  const char* names[4] = {"+x", "-x", "+y", "-y"};
  for (int w = 0; w < 4; ++w) {
    double sum = 0, worst = 0, far = 0;
    int n = 0, n_far = 0;
    for (size_t k = 0; k < pr.reference[w].size(); ++k) {
      const double ref = pr.reference[w][k].Mean();
      const double rt = pr.realtime[w][k].Mean();
      std::printf("wall %s %2zu mm: reference %.3f real-time %.3f\n", names[w],
                  k, ref, rt);
      sum += std::abs(rt - ref);
      worst = std::max(worst, std::abs(rt - ref));
      ++n;
      if (k >= 15) {
        far += rt - ref;
        ++n_far;
      }
    }
    std::printf(
        "wall %s: mean |difference| %.4f, largest %.3f, 15-30 mm mean "
        "difference %.4f\n",
        names[w], sum / n, worst, far / n_far);
    EXPECT_LT(sum / n, 0.03) << names[w];
    EXPECT_LT(worst, 0.25) << names[w];
    EXPECT_LT(std::abs(far / n_far), 0.005) << names[w];
  }
}

// The floor's mean direct light: the surface moves the light it lets in,
// the walls add theirs (through the walls facing the light, mirrored and
// sent back in by the walls facing away), so under flat water and an
// oblique light the map's mean over the floor is above 1, and the renderer
// lights the floor's return with it (frame_state.h, FloorMeanLight). It is
// the light tracer's: the mean of its floor irradiance over flat open
// water's, to 0.5%.
TEST(CausticsReferenceTest, TheMapsMeanIsTheLightTracersFloorMean) {
  for (const glm::dvec3& light :
       {glm::dvec3(0.35, 0.25, 1.0), glm::dvec3(-0.6, 0.1, 1.0)}) {
    reference::ReferenceScene rs;
    rs.camera = geometry::MakeIdealCamera(64, 48, 60);
    rs.scene.light_in_tank = light;
    rs.absorption_per_m = {0.0f, 0.0f, 0.0f};
    reference::ReferenceOptions o;
    o.caustic_map_size = 170;
    o.light_paths_per_texel = 256;
    o.threads = 2;
    reference::LightMaps maps;
    std::string error;
    ASSERT_TRUE(reference::ComputeLightMaps(o, rs, &maps, nullptr, &error))
        << error;
    const glm::dvec3 l = glm::normalize(light);
    const reference::LightRadiometry rad =
        reference::ComputeLightRadiometry(rs);
    const double open =
        rad.disc_irradiance * l.z *
        (1.0 - render::FresnelReflectance(l.z, 1.0, rs.water_ior));
    const double reference_mean = cv::mean(maps.floor_irradiance)[1] / open;

    render::CausticsOptions co;
    co.glass_ior = rs.glass_ior;
    co.glass_thickness_m = rs.glass_thickness_m;
    co.light_angular_radius_rad = rs.light_angular_radius_rad;
    std::vector<float> map;
    ASSERT_TRUE(
        render::ComputeCaustics(co, {}, rs.scene.tank, l, &map, nullptr));
    double sum = 0;
    for (const float v : map) sum += v;
    const double mean = sum / map.size();
    std::printf("light (%.2f, %.2f, 1): map mean %.4f, light tracer %.4f\n",
                light.x, light.y, mean, reference_mean);
    EXPECT_GT(mean, 1.01);
    EXPECT_NEAR(mean / reference_mean, 1.0, 0.005);
  }
}

}  // namespace
}  // namespace ripple
