// The effects passes on EGL (llvmpipe in CI): shadow on and off, the tank's
// shadow on the board around it, caustics from a single ripple, the pen dipped
// into the water (its phantom hides the water in front of it), the
// redraw-only-when-changed rules, and the GL state every pass returns to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <opencv2/core.hpp>
#include <vector>

#include "render/board_light.h"
#include "render/gl.h"
#include "render/pass_height.h"
#include "render/pass_water.h"
#include "render/renderer.h"
#include "render/water_regions.h"
#include "tests/render/golden.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

using testing::MakeScene;
using testing::MatchesGolden;
using testing::TestScene;
using testing::View;

constexpr int kW = 320, kH = 240;

// A floor map's mean over the floor, band c (optics.h, FloorReturnMap).
double MapMean(const std::vector<glm::vec3>& m, int c) {
  double sum = 0;
  for (const glm::vec3& t : m) sum += t[c];
  return sum / m.size();
}

// The tank floor's radiance as the air above flat water sees it (the water
// pass's FloorReturnLight::floor_seen), band `rgb`, for a video of one grey
// on the floor and another on the board around: the floor's mean light
// (the sky and the light through the surface, the surroundings through the
// walls from the board's grey), the surface's return, over n^2.
// The direct light's mean factor over the floor, as the renderer takes it:
// the caustics map's mean with caustics on (the walls add light: above 1),
// else 1.
double DirectMean(const RendererOptions& o, const SceneInputs& in) {
  if (!in.effects.caustics) return 1.0;
  const CausticsOptions co = CausticsOptionsFor(o);
  std::vector<float> map;
  if (!ComputeCaustics(co, in.water, in.tank, glm::normalize(in.light_in_tank),
                       &map, nullptr))
    return 1.0;
  double sum = 0;
  for (const float v : map) sum += v;
  return sum / map.size();
}

double FloorSeen(const RendererOptions& o, const SceneInputs& in,
                 std::uint8_t floor_grey, std::uint8_t board_grey, int rgb) {
  const TankGeometry& t = in.tank;
  const WaterShading sh =
      ComputeWaterShading(o.optics, t.water_level, in.light_in_tank);
  const FloorReturnMap ret = ComputeFloorReturn(
      o.optics, t.size_x, t.size_y, t.water_level, t.wall_height,
      internal::WaterPass::kReturnNx, internal::WaterPass::kReturnNy,
      internal::WaterPass::kReturnRays);
  const double board = SrgbToLinear(board_grey / 255.0);
  double light_mean = sh.floor_sky[rgb] +
                      sh.floor_sun[rgb] * DirectMean(o, in) +
                      MapMean(ret.sky, rgb);
  for (const std::vector<glm::vec3>& b : ret.board)
    light_mean += MapMean(b, rgb) * board;
  const double back = MapMean(ret.returned, rgb);
  const double rho = SrgbToLinear(floor_grey / 255.0);
  return rho / (1.0 - back * std::min(rho, 0.95)) * light_mean * sh.inv_n2;
}

// The frame state of a test scene with its height field uploaded to
// `heights` (its range and slopes in FrameState::height).
internal::FrameState FrameWithHeights(const TestScene& s,
                                      const WaterOptics& optics,
                                      internal::HeightTexturePass* heights) {
  heights->Create();
  EXPECT_TRUE(heights->Update(s.inputs));
  internal::FrameState f =
      internal::MakeFrameState(s.inputs, s.k, optics, Transfer::kSrgb);
  f.height = heights->info();
  return f;
}

// The height field's bilinear height (metres over the rest level) at tank
// point (x, y), clamped to the field.
double HeightAt(const HeightFieldView& w, double x, double y) {
  const double u =
      std::clamp(x / w.cell_size + 0.5 * w.nx - 0.5, 0.0, w.nx - 1.0);
  const double v =
      std::clamp(y / w.cell_size + 0.5 * w.ny - 0.5, 0.0, w.ny - 1.0);
  const int i = std::min(int(u), w.nx - 2), j = std::min(int(v), w.ny - 2);
  const double a = u - i, b = v - j;
  auto h = [&](int ii, int jj) { return w.heights[jj * w.nx + ii]; };
  return (1 - b) * ((1 - a) * h(i, j) + a * h(i + 1, j)) +
         b * ((1 - a) * h(i, j + 1) + a * h(i + 1, j + 1));
}

// The surface point on the ray from `eye` along `ray` (pointing down), by
// fixed-point steps.
glm::dvec3 SurfaceOnRay(const SceneInputs& in, const glm::dvec3& eye,
                        const glm::dvec3& ray) {
  double z = in.tank.water_level;
  glm::dvec3 p;
  for (int it = 0; it < 6; ++it) {
    p = eye + ray * ((z - eye.z) / ray.z);
    z = in.tank.water_level + HeightAt(in.water, p.x, p.y);
  }
  return p;
}

// Pixel (u, v)'s unit viewing ray (tank frame) and the surface point it
// meets; false when the ray does not point down or the point lies outside
// the tank's inner walls.
bool WaterAtPixel(const TestScene& s, const internal::FrameState& f, int u,
                  int v, glm::dvec3* ray, glm::dvec3* p) {
  *ray = glm::normalize(
      glm::dmat3(f.tank_from_cam) *
      glm::dvec3((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0));
  if (ray->z >= -1e-6) return false;
  *p = SurfaceOnRay(s.inputs, f.cam_in_tank, *ray);
  const TankGeometry& t = s.inputs.tank;
  return std::abs(p->x) <= 0.5 * t.size_x && std::abs(p->y) <= 0.5 * t.size_y;
}

// The surface's unit normal at p, by central differences over a cell.
glm::dvec3 SurfaceNormal(const HeightFieldView& w, const glm::dvec3& p) {
  const double e = 0.5 * w.cell_size;
  return glm::normalize(glm::dvec3(
      -(HeightAt(w, p.x + e, p.y) - HeightAt(w, p.x - e, p.y)) / (2 * e),
      -(HeightAt(w, p.x, p.y + e) - HeightAt(w, p.x, p.y - e)) / (2 * e), 1.0));
}

// Every effect but refraction off: the water's own shading of the floor it
// shows, without reflections, shadows, caustics or the walls.
void RefractionOnly(TestScene* s) {
  s->inputs.effects.reflection = false;
  s->inputs.effects.shadows = false;
  s->inputs.effects.caustics = false;
  s->inputs.effects.walls = false;
}

// The pixel (x, y) on which tank point p projects (the scene's pinhole).
cv::Point ImagePoint(const TestScene& s, const glm::dvec3& p) {
  const glm::dvec4 c = s.inputs.cam_from_tank * glm::dvec4(p, 1.0);
  return {static_cast<int>(std::lround(s.k.fx * c.x / c.z + s.k.cx)),
          static_cast<int>(std::lround(s.k.fy * c.y / c.z + s.k.cy))};
}

using testing::RenderScene;

// The front view over a uniform grey video with one box obstacle, the light
// from behind (the box's -y face out of it), no shadows or caustics.
TestScene ObstacleScene(std::uint8_t grey, const glm::vec3& size,
                        const glm::dvec3& base) {
  TestScene s = MakeScene(kW, kH, View::kFront, false);
  std::fill(s.video.begin(), s.video.end(), grey);
  s.inputs.effects.shadows = s.inputs.effects.caustics = false;
  s.inputs.light_in_tank = {0.0, 1.0, 1.0};
  Obstacle box;
  box.shape = Obstacle::Shape::kBox;
  box.size = size;
  box.tank_from_obstacle[3] = glm::dvec4(base, 1.0);
  s.inputs.obstacles = {box};
  return s;
}

double MeanDiff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

// A pen leaning over the tank, its tip `tip_depth` under the rest level.
glm::dmat4 PenPose(const TankGeometry& tank, double tip_depth) {
  const double tip_in_pen_z = -0.14;  // default rig: cube half + shaft
  glm::dmat4 m = glm::rotate(glm::dmat4(1.0), 0.35, glm::dvec3(1, 0.3, 0));
  const glm::dvec3 tip_in_tank(-0.03, 0.01, tank.water_level - tip_depth);
  const glm::dvec3 tip_offset = glm::dmat3(m) * glm::dvec3(0, 0, tip_in_pen_z);
  m[3] = glm::dvec4(tip_in_tank - tip_offset, 1.0);
  return m;
}

// The point of the pen's shaft `height_m` over the rest level, on its side
// facing the camera (0.8 of the radius out from the axis).
glm::dvec3 ShaftPointFacingTheCamera(const TestScene& s, double height_m) {
  const glm::dvec3 cam(glm::inverse(s.inputs.cam_from_tank)[3]);
  const glm::dmat4& pen = s.inputs.tank_from_pen;
  const double z_pen =
      (s.inputs.tank.water_level + height_m - pen[3].z) / pen[2].z;
  const glm::dvec3 axis_point(pen * glm::dvec4(0, 0, z_pen, 1));
  const glm::dvec3 to_cam = glm::normalize(cam - axis_point);
  return axis_point + to_cam * (0.8 * s.inputs.pen.shaft_radius);
}

TestScene SceneWithOccluders(View view) {
  TestScene s = MakeScene(kW, kH, view, false);
  s.inputs.pen_visible = true;
  s.inputs.tank_from_pen = PenPose(s.inputs.tank, 0.008);
  Obstacle pillar;
  pillar.tank_from_obstacle[3] = glm::dvec4(0.045, 0.015, 0.0, 1.0);
  s.inputs.obstacles.push_back(pillar);
  s.inputs.effects.caustics = false;
  return s;
}

// A hand-sized occluder over `window` of the image and a striped plate of
// the board (300 x 300 texels of 1 mm from (-0.15, -0.15) m), which the
// refraction reads behind it; the buffers are the caller's.
struct RealObjectBuffers {
  std::vector<std::uint8_t> mask, plate;
};
void AddOccluderAndPlate(const glm::ivec4& window, RealObjectBuffers* b,
                         SceneInputs* in) {
  b->mask.assign(kW * kH, 0);
  for (int y = window.y; y < window.y + window.w; ++y)
    for (int x = window.x; x < window.x + window.z; ++x)
      b->mask[y * kW + x] = 255;
  in->occluders = {b->mask.data(), kW, kH, kW, window};
  const int n = 300;
  b->plate.resize(4 * n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      std::uint8_t* t = &b->plate[4 * (j * n + i)];
      const bool stripe = (i / 6 + j / 6) % 2 == 0;
      t[0] = stripe ? 40 : 200;
      t[1] = 60;
      t[2] = stripe ? 220 : 30;
      t[3] = 255;
    }
  }
  in->plate = {b->plate.data(), n, n, 4 * n, {-0.15, -0.15}, 0.001, 1.0f, 1};
}

TEST(EffectsTest, ShadowOnAndOff) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  s.inputs.effects.pen_occludes = false;  // the video has no pen here
  RendererOptions o;
  o.pen_casts_shadow = true;  // nor its shadow
  auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat on = RenderScene(r.get(), s.inputs);
  EXPECT_TRUE(r->timings().shadow_redrawn);
  s.inputs.effects.shadows = false;
  const cv::Mat off = RenderScene(r.get(), s.inputs);
  EXPECT_FALSE(r->timings().shadow_redrawn);
  EXPECT_TRUE(MatchesGolden(on, "shadow_on"));
  EXPECT_TRUE(MatchesGolden(off, "shadow_off"));
  // The pen's and the pillar's shadows (the glass walls transmit).
  EXPECT_GT(MeanDiff(on, off), 0.3) << "the shadow should show";
}

TEST(EffectsTest, CausticsFromSingleRipple) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kTop, true);
  s.inputs.effects.shadows = false;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat on = RenderScene(r.get(), s.inputs);
  EXPECT_TRUE(r->timings().caustics_recomputed);
  s.inputs.effects.caustics = false;
  const cv::Mat off = RenderScene(r.get(), s.inputs);
  EXPECT_TRUE(MatchesGolden(on, "caustics_ripple"));
  EXPECT_GT(MeanDiff(on, off), 0.3) << "the caustics should show";
}

// The real pen (painted into the video) dips 8 mm into the water: where it
// is in front of the surface the output is the video itself.
TEST(EffectsTest, PenDippedIntoWater) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  s.inputs.obstacles.clear();
  testing::PaintPen(s.k, s.inputs.cam_from_tank, s.inputs.tank_from_pen,
                    s.inputs.pen, &s.video);
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat with_phantom = RenderScene(r.get(), s.inputs);
  EXPECT_TRUE(MatchesGolden(with_phantom, "pen_dipped"));

  // A shaft point 4 mm above the surface, on the camera's side, whose pixel
  // looks at the water behind the pen.
  const glm::dvec3 surface_point = ShaftPointFacingTheCamera(s, 0.004);
  const glm::dvec4 c = s.inputs.cam_from_tank * glm::dvec4(surface_point, 1);
  const int u = static_cast<int>(std::lround(s.k.fx * c.x / c.z + s.k.cx));
  const int v = static_cast<int>(std::lround(s.k.fy * c.y / c.z + s.k.cy));
  const cv::Mat video(kH, kW, CV_8UC3, s.video.data());
  EXPECT_EQ(with_phantom.at<cv::Vec3b>(v, u), video.at<cv::Vec3b>(v, u))
      << "the pen in front of the water shows the video";
  s.inputs.effects.pen_occludes = false;
  const cv::Mat without = RenderScene(r.get(), s.inputs);
  EXPECT_NE(without.at<cv::Vec3b>(v, u), video.at<cv::Vec3b>(v, u))
      << "without the phantom the water covers the pen";
}

// The water shades the real pen, the clean plate and the mirror only inside
// their screen regions (RendererOptions::water_regions): the image must be
// the one every pixel running every effect gives, on calm and steep water,
// from the front, tilted and from above, and each effect must show in it
// (else the comparison proves nothing).
TEST(EffectsTest, WaterRegionsLeaveTheImageUnchanged) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  RendererOptions split, every;
  every.water_regions = false;
  // The ripple centred in the tank, and at the pillar (whose mirror image
  // the steep slopes there displace most).
  struct Case {
    double amplitude, x0, y0;
  };
  const Case cases[] = {{0.0, 0.0, 0.0},
                        {0.0003, 0.02, 0.0},
                        {0.0015, 0.02, 0.0},
                        {0.0015, 0.045, 0.015}};
  for (const View view : {View::kFront, View::kTilted, View::kTop}) {
    for (const Case& c : cases) {
      const double amplitude = c.amplitude;
      TestScene s = SceneWithOccluders(view);
      for (float& h : s.heights) h *= 0.0;
      if (amplitude > 0) {
        TestScene rippled = MakeScene(kW, kH, view, true, false, c.x0, c.y0);
        s.heights = rippled.heights;
        for (float& h : s.heights) h *= amplitude / 0.0015;
        s.inputs.water.change_counter = 2;
      }
      s.inputs.water.heights = s.heights.data();
      testing::PaintPen(s.k, s.inputs.cam_from_tank, s.inputs.tank_from_pen,
                        s.inputs.pen, &s.video);
      // A hand-sized occluder over part of the tank, and a striped plate
      // of the board that the refraction reads behind it.
      RealObjectBuffers real;
      AddOccluderAndPlate(glm::ivec4(kW / 2, kH / 2, kW / 6, kH / 8), &real,
                          &s.inputs);
      auto a = Renderer::TryCreate(ctx.get(), s.k, split, nullptr);
      auto b = Renderer::TryCreate(ctx.get(), s.k, every, nullptr);
      ASSERT_NE(a, nullptr);
      ASSERT_NE(b, nullptr);
      const cv::Mat with_regions = RenderScene(a.get(), s.inputs);
      const cv::Mat everywhere = RenderScene(b.get(), s.inputs);
      cv::Mat diff;
      cv::absdiff(with_regions, everywhere, diff);
      EXPECT_EQ(cv::countNonZero(diff.reshape(1)), 0)
          << "view " << int(view) << ", amplitude " << amplitude << " at "
          << c.x0 << ", " << c.y0;
      // Each effect changes the image somewhere.
      SceneInputs no_real = s.inputs;
      no_real.effects.real_objects = false;
      EXPECT_GT(MeanDiff(RenderScene(b.get(), no_real), everywhere), 0.01)
          << "the pen and the plate show in the water";
      SceneInputs no_mirror = s.inputs;
      no_mirror.obstacles.clear();
      no_mirror.pen_visible = false;
      no_mirror.occluders = {};
      no_mirror.plate = {};
      SceneInputs only_pen = no_mirror;
      only_pen.pen_visible = true;
      only_pen.effects.real_objects = false;
      EXPECT_GT(MeanDiff(RenderScene(b.get(), only_pen),
                         RenderScene(b.get(), no_mirror)),
                0.01)
          << "the pen's mirror image shows in the water";
    }
  }
}

// The front glass shows the water up to wherever the surface stands: a
// surface raised 8 mm everywhere (above any fixed margin for waves) must look
// through the front wall as the same tank filled 8 mm higher at rest. The
// band compared lies 6.5-7.5 mm over the lower rest level; without the
// water there (the lower tank at rest) it shows dry glass, far from both.
TEST(EffectsTest, FrontGlassFollowsTheSurfaceAtAnyHeight) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene raised = MakeScene(kW, kH, View::kFront, false);
  raised.inputs.tank.wall_height = 0.05f;
  for (float& h : raised.heights) h = 0.008f;
  raised.inputs.water.change_counter = 2;
  TestScene filled = MakeScene(kW, kH, View::kFront, false);
  filled.inputs.tank.wall_height = 0.05f;
  filled.inputs.tank.water_level += 0.008f;
  TestScene dry = MakeScene(kW, kH, View::kFront, false);
  dry.inputs.tank.wall_height = 0.05f;
  for (TestScene* s : {&raised, &filled, &dry})
    s->inputs.effects.caustics = s->inputs.effects.shadows = false;
  auto r = Renderer::TryCreate(ctx.get(), raised.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat a = RenderScene(r.get(), raised.inputs);
  const cv::Mat b = RenderScene(r.get(), filled.inputs);
  const cv::Mat c = RenderScene(r.get(), dry.inputs);
  // Pixels of the front wall (y = -size_y / 2) in the band.
  const TankGeometry& t = dry.inputs.tank;
  const glm::dmat4 clip_from_tank = r->ClipFromTank(dry.inputs.cam_from_tank);
  double ab = 0, ac = 0;
  int n = 0;
  for (double z = t.water_level + 0.0065; z <= t.water_level + 0.0075;
       z += 0.0005) {
    for (double x = -0.06; x <= 0.06; x += 0.002) {
      const glm::dvec2 px = PixelFromWindow(WindowFromClip(
          clip_from_tank * glm::dvec4(x, -0.5 * t.size_y, z, 1), kW, kH));
      const int u = static_cast<int>(std::lround(px.x));
      const int v = static_cast<int>(std::lround(px.y));
      ASSERT_TRUE(u >= 0 && u < kW && v >= 0 && v < kH);
      for (int ch = 0; ch < 3; ++ch) {
        ab += std::abs(a.at<cv::Vec3b>(v, u)[ch] - b.at<cv::Vec3b>(v, u)[ch]);
        ac += std::abs(a.at<cv::Vec3b>(v, u)[ch] - c.at<cv::Vec3b>(v, u)[ch]);
      }
      n += 3;
    }
  }
  // The two water tanks differ only in what depends on the rest depth (the
  // floor-return map and the floor's light are computed for it).
  EXPECT_LT(ab / n, 2.0) << "raised surface against the filled tank";
  EXPECT_GT(ac / n, 10.0) << "the band over the dry tank is dry glass";
}

// The mirror's region holds every pixel whose lookup lands in the mirrored
// objects' window: each pixel's ray is cast against the field on the CPU
// (bilinear heights, slopes by differences), its lookup point moved by
// 2 kMirrorDepth_m times the normal's xy and projected. A steep ripple
// 3 cm from the pillar sends some lookups far; the tiles' slopes must cover
// them, and zero slopes must not in at least one view (else the check
// proves nothing).
TEST(EffectsTest, MirrorRegionHoldsEveryLookupIntoTheMirror) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  int beyond_calm = 0;
  for (const View view : {View::kFront, View::kTilted}) {
    TestScene s = MakeScene(kW, kH, view, true, false, 0.015, 0.0);
    for (float& h : s.heights) h *= 1.5f;
    Obstacle pillar;
    pillar.tank_from_obstacle[3] = glm::dvec4(0.045, 0.015, 0.0, 1.0);
    s.inputs.obstacles.push_back(pillar);
    internal::HeightTexturePass heights;
    const WaterOptics optics;
    const internal::FrameState f = FrameWithHeights(s, optics, &heights);
    ASSERT_NE(f.height.tile_slope, nullptr);
    const glm::ivec4 window = internal::MirroredObjectsRect(f);
    const glm::ivec4 region = internal::MirrorLookupRect(f, window);
    internal::FrameState calm = f;
    const std::vector<float> zeros(f.height.tiles_x * f.height.tiles_y, 0.0f);
    calm.height.tile_slope = zeros.data();
    calm.height.decode_scale = glm::vec3(0.0f);
    const glm::ivec4 calm_region = internal::MirrorLookupRect(calm, window);

    const HeightFieldView& w = s.inputs.water;
    auto inside = [](const glm::ivec4& r, double x, double y) {
      return x >= r.x && x < r.x + r.z && y >= r.y && y < r.y + r.w;
    };
    const TankGeometry& t = s.inputs.tank;
    int lookups = 0, outside = 0;
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        const glm::dvec3 ray =
            glm::dmat3(f.tank_from_cam) *
            glm::dvec3((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0);
        if (ray.z >= -1e-6) continue;
        const glm::dvec3 p = SurfaceOnRay(s.inputs, f.cam_in_tank, ray);
        if (std::abs(p.x) > 0.5 * t.size_x || std::abs(p.y) > 0.5 * t.size_y)
          continue;
        const glm::dvec3 n = SurfaceNormal(w, p);
        const glm::dvec3 look =
            p + glm::dvec3(2.0 * internal::kMirrorDepth_m * n.x,
                           2.0 * internal::kMirrorDepth_m * n.y, 0.0);
        const glm::dvec2 win =
            WindowFromClip(f.clip_from_tank * glm::dvec4(look, 1.0), kW, kH);
        if (!inside(window, win.x, win.y)) continue;
        ++lookups;
        if (!inside(region, u + 0.5, v + 0.5)) ++outside;
        if (!inside(calm_region, u + 0.5, v + 0.5)) ++beyond_calm;
      }
    }
    EXPECT_GT(lookups, 100) << "view " << int(view);
    EXPECT_EQ(outside, 0) << "view " << int(view);
  }
  EXPECT_GT(beyond_calm, 0) << "the slopes must matter";
}

// Inside the wall-free rectangle no pixel's rays meet a wall: for the
// test scene's ripple seen from the front, at an angle and from above,
// every pixel there sees a surface point whose view ray passes over the
// camera-side walls' glass (not through it, under their tops) and whose
// refracted ray meets the floor inside the tank; and the rectangle holds a
// good share of the water (what it is for).
TEST(EffectsTest, WallFreeRectangleHoldsNoRayThatMeetsAWall) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (const View view : {View::kFront, View::kTilted, View::kTop}) {
    TestScene s = MakeScene(kW, kH, view, true, false, 0.015, 0.0);
    internal::HeightTexturePass heights;
    const WaterOptics optics;
    const internal::FrameState f = FrameWithHeights(s, optics, &heights);
    const glm::ivec4 r = internal::WallFreeRect(f);
    const TankGeometry& t = s.inputs.tank;
    const glm::dvec3& eye = f.cam_in_tank;
    int water = 0, inside = 0, through_glass = 0, to_wall = 0;
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        glm::dvec3 ray, p;
        if (!WaterAtPixel(s, f, u, v, &ray, &p)) continue;
        ++water;
        // Window x = u + 0.5; the FBO's rows are the image's (top first).
        if (!(u >= r.x && u < r.x + r.z && v >= r.y && v < r.y + r.w)) continue;
        ++inside;
        // The view ray at each wall's outer face on the camera's side.
        for (int a = 0; a < 2; ++a) {
          const double half = 0.5 * (a == 0 ? t.size_x : t.size_y);
          const double outer = half + optics.glass_thickness_m;
          for (const double side : {-1.0, 1.0}) {
            if (!(side * eye[a] > outer)) continue;
            const double s_out = (side * outer - p[a]) / (eye[a] - p[a]);
            if (p.z + s_out * (eye.z - p.z) < t.wall_height) ++through_glass;
          }
        }
        const glm::dvec3 tr = glm::refract(
            ray, SurfaceNormal(s.inputs.water, p), 1.0 / double(optics.ior));
        const glm::dvec3 floor = p + tr * (-p.z / tr.z);
        if (std::abs(floor.x) > 0.5 * t.size_x ||
            std::abs(floor.y) > 0.5 * t.size_y)
          ++to_wall;
      }
    }
    // Seen across a corner from low down (kTilted: 27 deg over the
    // table) the camera-side walls hide much of the surface behind their
    // glass and the refracted rays run far: little is wall-free there.
    // From the front 27% of the water is wall-free, from above 54%.
    if (view != View::kTilted) {
      EXPECT_GT(inside, water / 5) << "view " << int(view) << ": " << inside
                                   << " of " << water << " water pixels";
    }
    EXPECT_GT(inside, 0) << "view " << int(view);
    EXPECT_EQ(through_glass, 0) << "view " << int(view);
    EXPECT_EQ(to_wall, 0) << "view " << int(view);
  }
}

// The shadow map is redrawn only when an occluder moved by more than the
// threshold or the light changed; caustics only when the surface changed.
// An idle scene skips both.
TEST(EffectsTest, RedrawsOnlyWhenInputsChange) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  s.inputs.effects.caustics = true;
  RendererOptions o;
  o.pen_casts_shadow = true;
  auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
  ASSERT_NE(r, nullptr);
  SceneInputs& in = s.inputs;
  ASSERT_TRUE(r->Render(in));
  EXPECT_TRUE(r->timings().shadow_redrawn);
  EXPECT_TRUE(r->timings().caustics_recomputed);

  ASSERT_TRUE(r->Render(in));  // idle
  EXPECT_FALSE(r->timings().shadow_redrawn);
  EXPECT_FALSE(r->timings().caustics_recomputed);
  EXPECT_EQ(r->timings().shadow_ms, 0.0);
  EXPECT_EQ(r->timings().caustics_ms, 0.0);

  // Jitter: 0.4 mm and 0.2 degrees, twice (not accumulating past 1 mm).
  const glm::dmat4 rest = in.tank_from_pen;
  in.tank_from_pen = glm::rotate(rest, 0.0035, glm::dvec3(0, 1, 0));
  in.tank_from_pen[3].x += 0.0004;
  ASSERT_TRUE(r->Render(in));
  EXPECT_FALSE(r->timings().shadow_redrawn);
  in.tank_from_pen = rest;
  in.tank_from_pen[3].y -= 0.0004;
  ASSERT_TRUE(r->Render(in));
  EXPECT_FALSE(r->timings().shadow_redrawn);

  in.tank_from_pen[3].y -= 0.002;  // a real move
  ASSERT_TRUE(r->Render(in));
  EXPECT_TRUE(r->timings().shadow_redrawn);
  EXPECT_FALSE(r->timings().caustics_recomputed);

  in.obstacles[0].tank_from_obstacle[3].x += 0.005;
  ASSERT_TRUE(r->Render(in));
  EXPECT_TRUE(r->timings().shadow_redrawn);

  in.light_in_tank = {0.1, 0.3, 1.0};  // light: both
  ASSERT_TRUE(r->Render(in));
  EXPECT_TRUE(r->timings().shadow_redrawn);
  EXPECT_TRUE(r->timings().caustics_recomputed);

  in.water.change_counter++;  // surface: caustics only
  ASSERT_TRUE(r->Render(in));
  EXPECT_FALSE(r->timings().shadow_redrawn);
  EXPECT_TRUE(r->timings().caustics_recomputed);

  in.pen_visible = false;  // pen leaves the view
  ASSERT_TRUE(r->Render(in));
  EXPECT_TRUE(r->timings().shadow_redrawn);

  // By default the pen does not cast (its real shadow is in the video), so
  // its moves do not redraw the map.
  auto d = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(d, nullptr);
  in.pen_visible = true;
  ASSERT_TRUE(d->Render(in));
  EXPECT_TRUE(d->timings().shadow_redrawn);
  in.tank_from_pen[3].y += 0.01;
  ASSERT_TRUE(d->Render(in));
  EXPECT_FALSE(d->timings().shadow_redrawn);
  in.pen_visible = false;
  ASSERT_TRUE(d->Render(in));
  EXPECT_FALSE(d->timings().shadow_redrawn);
}

// Caustics traced before Render (UpdateCaustics, which a caller overlaps
// with its own work) are the ones Render draws: Render finds them up to
// date, and the frame is the one Render alone makes.
TEST(EffectsTest, CausticsTracedAheadAreTheOnesRenderDraws) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  s.inputs.effects.caustics = true;
  auto alone = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  auto ahead = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(alone, nullptr);
  ASSERT_NE(ahead, nullptr);
  SceneInputs& in = s.inputs;
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    in.water.change_counter++;
    double ms = -1;
    EXPECT_TRUE(ahead->UpdateCaustics(in, &ms));
    EXPECT_GE(ms, 0.0);
    EXPECT_FALSE(ahead->UpdateCaustics(in, &ms));  // already up to date
    EXPECT_EQ(ms, 0.0);
    const cv::Mat a = RenderScene(ahead.get(), in);
    EXPECT_FALSE(ahead->timings().caustics_recomputed);
    const cv::Mat b = RenderScene(alone.get(), in);
    EXPECT_TRUE(alone->timings().caustics_recomputed);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  }
  // Without the effect there is nothing to trace.
  in.effects.caustics = false;
  in.water.change_counter++;
  double ms = -1;
  EXPECT_FALSE(ahead->UpdateCaustics(in, &ms));
  EXPECT_EQ(ms, 0.0);
}

// Render says when it has copied what the scene's buffers hold, once and
// before it draws: what a caller writes into the heights, the occluder mask
// and the plate from then on (a worker preparing the next frame) leaves
// the frame as it would have been; the next frame does read them.
TEST(EffectsTest, BuffersWrittenOnceInputsAreCopiedLeaveTheFrameAlone) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, true);
  s.inputs.effects.caustics = true;
  RealObjectBuffers real;
  AddOccluderAndPlate(glm::ivec4(kW / 3, kH / 2, kW / 4, kH / 6), &real,
                      &s.inputs);
  std::vector<std::uint8_t>& mask = real.mask;
  std::vector<std::uint8_t>& plate = real.plate;
  auto plain = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  auto told = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(plain, nullptr);
  ASSERT_NE(told, nullptr);
  const cv::Mat expected = RenderScene(plain.get(), s.inputs);
  int calls = 0;
  auto scribble = [&] {
    ++calls;
    for (float& h : s.heights) h = 0.004f - h;
    std::fill(mask.begin(), mask.end(), 0);
    for (size_t i = 0; i < plate.size(); ++i)
      plate[i] = i % 4 == 3 ? 255 : static_cast<std::uint8_t>(255 - plate[i]);
  };
  ASSERT_TRUE(told->Render(s.inputs, scribble));
  cv::Mat out(kH, kW, CV_8UC3);
  ASSERT_TRUE(told->ReadBgr(out.data, static_cast<int>(out.step)));
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(cv::norm(out, expected, cv::NORM_INF), 0.0);
  // The scribbles are what the next frame shows.
  s.inputs.water.change_counter++;
  s.inputs.plate.change_counter++;
  EXPECT_GT(MeanDiff(RenderScene(told.get(), s.inputs), expected), 0.5);
}

// Without a height field the water is flat, and under a vertical light flat
// water's caustics map is uniform 1 (no strip along the walls, no light
// through them): turning caustics on must not change the floor.
TEST(EffectsTest, FlatWaterCausticsLeaveTheFloorLit) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, false);
  s.inputs.water = HeightFieldView{};
  s.inputs.light_in_tank = {0.0, 0.0, 1.0};
  s.inputs.effects.shadows = false;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  s.inputs.effects.caustics = true;
  const cv::Mat on = RenderScene(r.get(), s.inputs);
  EXPECT_TRUE(r->timings().caustics_recomputed);
  s.inputs.effects.caustics = false;
  const cv::Mat off = RenderScene(r.get(), s.inputs);
  cv::Mat d;
  cv::absdiff(on, off, d);
  double max_diff = 0;
  cv::minMaxLoc(d.reshape(1), nullptr, &max_diff);
  EXPECT_LE(max_diff, 1.0);
}

// Every pass returns the capabilities and write masks it changed to GL's
// defaults (gl_state.h), so no pass depends on what another left behind.
TEST(EffectsTest, PassesLeaveTheGlStateAtRest) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  s.inputs.effects.caustics = true;
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  ASSERT_TRUE(r->Render(s.inputs));
  ASSERT_TRUE(r->timings().shadow_redrawn);
  for (GLenum cap : {GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_BLEND,
                     GL_POLYGON_OFFSET_FILL}) {
    GLint on = -1;
    glGetIntegerv(cap, &on);
    EXPECT_EQ(on, 0) << "capability 0x" << std::hex << cap;
  }
  GLint depth_write = 0, stencil_write = 0, color_write[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_DEPTH_WRITEMASK, &depth_write);
  glGetIntegerv(GL_STENCIL_WRITEMASK, &stencil_write);
  glGetIntegerv(GL_COLOR_WRITEMASK, color_write);
  EXPECT_EQ(depth_write, GL_TRUE);
  EXPECT_EQ(stencil_write & 0xff, 0xff);
  for (GLint c : color_write) EXPECT_EQ(c, GL_TRUE);
}

// Linear-light compositing, checked against the optics model: a uniform
// grey table under flat clear water, seen from above with every effect but
// refraction off, must read what render/optics.h predicts (the video
// decoded, the floor's sky and direct light through the surface, the
// surroundings through the walls with the board as the video shows it, the
// floor<->surface inter-reflection, 1/n^2, Beer-Lambert, Fresnel), encoded
// back with the video's transfer. Both transfers.
TEST(EffectsTest, FlatClearWaterReadsWhatTheOpticsModelPredicts) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (const Transfer transfer : {Transfer::kSrgb, Transfer::kLinear}) {
    TestScene s = MakeScene(kW, kH, View::kTop, false);
    const std::uint8_t grey[3] = {150, 180, 210};  // B, G, R
    for (size_t i = 0; i < s.video.size(); ++i) s.video[i] = grey[i % 3];
    RefractionOnly(&s);
    RendererOptions o;
    o.video_transfer = transfer;
    auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
    ASSERT_NE(r, nullptr);
    const cv::Mat out = RenderScene(r.get(), s.inputs);
    // The pixel at the principal point looks at the floor's centre.
    const int u = kW / 2, v = kH / 2;
    const glm::dvec3 eye = glm::inverse(s.inputs.cam_from_tank)[3];
    const glm::dvec3 ray = glm::normalize(glm::dvec3(
        glm::inverse(s.inputs.cam_from_tank) *
        glm::dvec4((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0, 0.0)));
    const double cos_v = -ray.z;
    const double sin_t = std::sqrt(1 - cos_v * cos_v) / o.optics.ior;
    const double path =
        s.inputs.tank.water_level / std::sqrt(1 - sin_t * sin_t);
    const WaterShading w = ComputeWaterShading(
        o.optics, s.inputs.tank.water_level, s.inputs.light_in_tank);
    const double fresnel = FresnelReflectance(cos_v, 1.0, o.optics.ior);
    // The floor-return map, bilinear at the floor point (tank centre).
    const FloorReturnMap ret = ComputeFloorReturn(
        o.optics, s.inputs.tank.size_x, s.inputs.tank.size_y,
        s.inputs.tank.water_level, s.inputs.tank.wall_height,
        internal::WaterPass::kReturnNx, internal::WaterPass::kReturnNy,
        internal::WaterPass::kReturnRays);
    const glm::dvec3 floor_point =
        eye + ray * ((eye.z - s.inputs.tank.water_level) / -ray.z) +
        glm::dvec3(0.0);
    auto bilinear = [&](const std::vector<glm::vec3>& m, int c) {
      const double fx =
          (floor_point.x / s.inputs.tank.size_x + 0.5) * ret.nx - 0.5;
      const double fy =
          (floor_point.y / s.inputs.tank.size_y + 0.5) * ret.ny - 0.5;
      const int x0 = static_cast<int>(std::floor(fx)),
                y0 = static_cast<int>(std::floor(fy));
      const double ax = fx - x0, ay = fy - y0;
      auto at = [&](int x, int y) {
        x = std::clamp(x, 0, ret.nx - 1);
        y = std::clamp(y, 0, ret.ny - 1);
        return double(m[y * ret.nx + x][c]);
      };
      return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
             ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
    };
    auto returned = [&](int c) { return bilinear(ret.returned, c); };
    // The map's means over the floor: the floor around the point, which the
    // surface's return comes from, is lit as the mean (frame_state.h).
    for (int c = 0; c < 3; ++c) {  // B, G, R
      const int rgb = 2 - c;
      const double e = grey[c] / 255.0;
      const double video = transfer == Transfer::kSrgb ? SrgbToLinear(e) : e;
      // The board beyond every wall is the video's grey.
      double surround = bilinear(ret.sky, rgb);
      double mean_surround = MapMean(ret.sky, rgb);
      for (const std::vector<glm::vec3>& board : ret.board) {
        surround += bilinear(board, rgb) * video;
        mean_surround += MapMean(board, rgb) * video;
      }
      const double light = w.floor_sky[rgb] + w.floor_sun[rgb];
      const double around =
          (light + mean_surround) / (1 - MapMean(ret.returned, rgb) * video);
      double x = video * (light + surround + returned(rgb) * video * around) *
                 w.inv_n2;
      x *= std::exp(-o.optics.absorption_per_m[rgb] * path) * (1 - fresnel);
      x = HighlightShoulder(x, o.optics.highlight_knee);
      const double expected =
          255.0 * (transfer == Transfer::kSrgb ? LinearToSrgb(x) : x);
      EXPECT_NEAR(out.at<cv::Vec3b>(v, u)[c], expected, 1.0)
          << "channel " << c << " transfer " << TransferName(transfer);
    }
  }
}

// Seen through the water, a floor point lands between the frame's pixels,
// so the refraction's lookup interpolates the frame. A vertical grating of
// 4 pixels' period in the video (linear transfer, so the output is linear
// in it): where the lookups' fractional offsets t are spread evenly, a
// lookup's RMS response to the grating is sqrt(mean over t of |H(t)|^2):
// bilinear 0.816 (|H|^2 = 1 - 2 t (1 - t) (1 - cos(2 pi / 4))), the
// Catmull-Rom lookup 0.951 (five taps, renormalised: the same sum over the
// vertical offset too). Measured per pixel as the grating minus its
// inverse over twice its amplitude against the uniform video's pixel (the
// water's gain there), in the middle of the top view's floor, where the
// flat water magnifies the floor by about 2% and t drifts through two
// whole pixels across the window.
TEST(EffectsTest, TheRefractedFloorKeepsAFineGratingsContrast) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kTop, false);
  RefractionOnly(&s);
  const double mean = 128, amplitude = 60, period = 4;
  auto grating = [&](double sign) {
    std::vector<std::uint8_t> v(s.video.size());
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const double g =
            mean + sign * amplitude * std::sin(2 * M_PI * (x + 0.3) / period);
        for (int c = 0; c < 3; ++c)
          v[(static_cast<size_t>(y) * kW + x) * 3 + c] =
              static_cast<std::uint8_t>(std::lround(g));
      }
    }
    return v;
  };
  const std::vector<std::uint8_t> up = grating(1), down = grating(-1),
                                  flat(s.video.size(), mean);
  auto response = [&](RefractionFilter filter) {
    RendererOptions o;
    o.video_transfer = Transfer::kLinear;
    o.refraction_filter = filter;
    auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
    EXPECT_NE(r, nullptr);
    if (r == nullptr) return 0.0;
    cv::Mat out[3];
    const std::vector<std::uint8_t>* videos[3] = {&up, &down, &flat};
    for (int i = 0; i < 3; ++i) {
      s.inputs.video.bgr = videos[i]->data();
      out[i] = RenderScene(r.get(), s.inputs);
    }
    double sum2 = 0;
    int n = 0;
    for (int y = kH / 2 - 16; y < kH / 2 + 16; ++y) {
      for (int x = kW / 2 - 48; x < kW / 2 + 48; ++x) {
        const double gain = out[2].at<cv::Vec3b>(y, x)[1] / mean;
        const double swing = double(out[0].at<cv::Vec3b>(y, x)[1]) -
                             out[1].at<cv::Vec3b>(y, x)[1];
        const double ratio = swing / (2 * amplitude * gain);
        sum2 += ratio * ratio;
        ++n;
      }
    }
    return std::sqrt(2 * sum2 / n);
  };
  const double linear = response(RefractionFilter::kLinear);
  const double cubic = response(RefractionFilter::kCubic);
  EXPECT_NEAR(linear, 0.816, 0.02);
  EXPECT_NEAR(cubic, 0.951, 0.02);
}

// The surface's return comes from the floor around a point, so on a floor
// of two albedos a dark square and the bright square beside it get the same
// light back: under flat clear water their pixels keep the ratio of their
// albedos (L = V (E + R V_mean E_mean / (1 - R_mean V_mean))). Were the
// return the point's own light, the dark square would read about 15% too
// dark against the bright one.
TEST(EffectsTest, TheSurfacesReturnCarriesTheFloorsMeanAlbedo) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kTop, false);
  constexpr std::uint8_t kDark = 60, kBright = 220;  // linear video
  constexpr int kSquare = 32;                        // video pixels
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool bright = ((x / kSquare) + (y / kSquare)) % 2 == 0;
      for (int c = 0; c < 3; ++c)
        s.video[(static_cast<size_t>(y) * kW + x) * 3 + c] =
            bright ? kBright : kDark;
    }
  }
  RefractionOnly(&s);
  RendererOptions o;
  o.video_transfer = Transfer::kLinear;
  auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat out = RenderScene(r.get(), s.inputs);
  // Around the image's centre (the floor's middle): the squares' plateaus,
  // as the median of the pixels below and above the middle grey (the
  // pixels along the edges between squares, interpolated and, with the
  // cubic refraction lookup, overshooting a little, are a minority of
  // either side).
  const cv::Rect window(kW / 2 - 40, kH / 2 - 30, 80, 60);
  std::vector<double> dark, bright;
  double lo = 255, hi = 0;
  for (int y = window.y; y < window.y + window.height; ++y)
    for (int x = window.x; x < window.x + window.width; ++x) {
      lo = std::min(lo, double(out.at<cv::Vec3b>(y, x)[1]));
      hi = std::max(hi, double(out.at<cv::Vec3b>(y, x)[1]));
    }
  const double middle = 0.5 * (lo + hi);
  for (int y = window.y; y < window.y + window.height; ++y)
    for (int x = window.x; x < window.x + window.width; ++x) {
      const double g = out.at<cv::Vec3b>(y, x)[1];
      (g < middle ? dark : bright).push_back(g);
    }
  ASSERT_GT(dark.size(), 1000u);
  ASSERT_GT(bright.size(), 1000u);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double dark_level = median(dark), bright_level = median(bright);
  // Under the highlight shoulder's knee: the output is linear here.
  ASSERT_LT(bright_level, 255.0 * o.optics.highlight_knee);
  ASSERT_GT(bright_level - dark_level, 50.0);
  const double ratio = dark_level / bright_level;
  EXPECT_NEAR(ratio / (double(kDark) / kBright), 1.0, 0.03)
      << "dark " << dark_level << " bright " << bright_level;
}

// A virtual obstacle's face sees the sky above and the ground below by its
// view factors: a box on the board, out of the light's reach on its
// camera side, over a uniform grey board, reads albedo x (a (1 + n.z) / 2
// + G (1 - n.z) / 2) on its vertical face (n.z = 0; G the board's radiance
// from the video) and albedo on its lit top; and its face reads brighter
// over a brighter board.
TEST(EffectsTest, ObstacleFacesSeeTheSkyAndTheBoard) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const RendererOptions o;
  auto r = Renderer::TryCreate(ctx.get(), testing::MakeIntrinsics(kW, kH), o,
                               nullptr);
  ASSERT_NE(r, nullptr);
  auto face = [&](std::uint8_t grey, cv::Vec3b* top) {
    const TestScene s =
        ObstacleScene(grey, {0.03f, 0.02f, 0.02f}, {0.0, -0.085, 0.0});
    const cv::Mat out = RenderScene(r.get(), s.inputs);
    auto pixel = [&](const glm::dvec3& p) {
      return out.at<cv::Vec3b>(ImagePoint(s, p));
    };
    *top = pixel({0.0, -0.085, 0.02});
    return pixel({0.0, -0.095, 0.01});  // the -y face's centre
  };
  cv::Vec3b top_dark, top_bright;
  const cv::Vec3b dark = face(60, &top_dark);
  const cv::Vec3b bright = face(200, &top_bright);
  const double a = o.optics.ambient_share;
  for (int c = 0; c < 3; ++c) {  // B, G, R
    const double albedo = o.obstacle_albedo[2 - c];
    for (const auto& [px, grey] : {std::pair{dark, 60}, {bright, 200}}) {
      const double g = SrgbToLinear(grey / 255.0);
      const double want =
          255.0 * LinearToSrgb(HighlightShoulder(albedo * (0.5 * a + 0.5 * g),
                                                 o.optics.highlight_knee));
      EXPECT_NEAR(px[c], want, 1.5) << "band " << c << " grey " << grey;
    }
    const double lit = 255.0 * LinearToSrgb(HighlightShoulder(
                                   albedo, o.optics.highlight_knee));
    EXPECT_NEAR(top_dark[c], lit, 1.5) << c;
    EXPECT_NEAR(top_bright[c], lit, 1.5) << c;
    EXPECT_GT(bright[c], dark[c] + 20) << c;
  }
}

// An obstacle standing in the tank sees, below, the water out to the walls
// and the board beyond them: its vertical face (out of the light) reads
// albedo x (a / 2 + ((1 - b) ((1 - R) W / n^2 + R a) + b G) / 2), with
// W / n^2 the wet floor as the air above the water sees it (the video's
// grey G lit as the water lights the floor at its mean: the sky and the
// light through the surface, the surroundings through the walls and the
// surface's return; FloorSeen), R the surface's mean reflectance over a
// vertical face's lower view (0.21: it sees the water mostly near the
// horizon, where the surface mirrors the sky of radiance a), and b = sin of
// the depression to the wall's foot at the water line, h / sqrt(h^2 + D^2)
// for a point h over the water and D from the wall along the face's
// normal. At three heights over the front wall's top.
TEST(EffectsTest, ObstacleInTheTankSeesTheBoardBeyondTheWalls) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const RendererOptions o;
  auto r = Renderer::TryCreate(ctx.get(), testing::MakeIntrinsics(kW, kH), o,
                               nullptr);
  ASSERT_NE(r, nullptr);
  const std::uint8_t grey = 200;
  const glm::vec3 size(0.03f, 0.02f, 0.07f);
  const TestScene s = ObstacleScene(grey, size, glm::dvec3(0.0));
  const cv::Mat out = RenderScene(r.get(), s.inputs);
  const TankGeometry& t = s.inputs.tank;
  const WaterShading sh =
      ComputeWaterShading(o.optics, t.water_level, s.inputs.light_in_tank);
  const double a = o.optics.ambient_share;
  const double g = SrgbToLinear(grey / 255.0);
  const double reach = 0.5 * t.size_y - 0.5 * size.y;
  for (const double z : {0.045, 0.055, 0.065}) {
    ASSERT_GT(z, t.wall_height);
    const cv::Vec3b px =
        out.at<cv::Vec3b>(ImagePoint(s, {0.0, -0.5 * size.y, z}));
    const double h = z - t.water_level;
    const double b = h / std::sqrt(h * h + reach * reach);
    for (int ch = 0; ch < 3; ++ch) {  // B, G, R
      const int rgb = 2 - ch;
      const double seen = FloorSeen(o, s.inputs, grey, grey, rgb);
      // The floor lit by the sky and the light alone reads darker by more
      // than the tolerance: the return and the surroundings matter here.
      ASSERT_GT(seen,
                1.15 * g * (sh.floor_sky[rgb] + sh.floor_sun[rgb]) * sh.inv_n2);
      const double mirror =
          ComputeLowerViewReflectance(o.optics.ior).facing_side;
      const double water = (1.0 - mirror) * seen + mirror * a;
      const double below = (1.0 - b) * water + b * g;
      const double want =
          255.0 * LinearToSrgb(HighlightShoulder(
                      o.obstacle_albedo[rgb] * (0.5 * a + 0.5 * below),
                      o.optics.highlight_knee));
      EXPECT_NEAR(px[ch], want, 1.5) << "band " << ch << " z " << z;
    }
  }
}

// Distance along o + s d (0 < s < s_max) to a vertical cylinder standing on
// the floor (base centre `base`, radius r, height h); s_max when it misses.
double CylinderHit(const glm::dvec3& o, const glm::dvec3& d, double s_max,
                   const glm::dvec2& base, double r, double h) {
  const glm::dvec2 m = glm::dvec2(o) - base, dd(d);
  const double a = glm::dot(dd, dd), b = glm::dot(m, dd);
  const double disc = b * b - a * (glm::dot(m, m) - r * r);
  if (a < 1e-15 || disc <= 0.0) return s_max;
  const double root = std::sqrt(disc);
  for (const double s : {(-b - root) / a, (-b + root) / a}) {
    const double z = o.z + s * d.z;
    if (s > 0.0 && s < s_max && z >= 0.0 && z <= h) return s;
  }
  // Through the top face (a ray entering from above).
  if (std::abs(d.z) > 1e-12) {
    const double s = (h - o.z) / d.z;
    if (s > 0.0 && s < s_max &&
        glm::length(glm::dvec2(o + s * d) - base) <= r) {
      return s;
    }
  }
  return s_max;
}

// Where a pillar stands out of the water it hides floor points from the
// camera that rays refracted at the surface behind it still reach: the
// scene copy (the camera's view, obstacles drawn) shows the pillar there.
// Flat water, refraction only: every water pixel's ray is traced on the
// CPU. Pixels whose refracted ray passes the pillar but whose floor point
// the pillar hides from the camera read the floor, as without the pillar;
// pixels whose refracted ray meets the pillar show it.
TEST(EffectsTest, ARayPastAnObstacleSeesTheFloorItHidesFromTheCamera) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = MakeScene(kW, kH, View::kFront, false);
  RefractionOnly(&s);
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat without = RenderScene(r.get(), s.inputs);
  const TankGeometry& t = s.inputs.tank;
  const double n = RendererOptions{}.optics.ior;
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  auto inside = [&](const glm::dvec3& q, double margin) {
    return std::abs(q.x) < 0.5 * t.size_x - margin &&
           std::abs(q.y) < 0.5 * t.size_y - margin;
  };
  // A pillar half out of the water, in turn: near the front wall, the
  // surface behind it showing above its top (rays past it); behind the
  // middle, seen over the front wall through the water in front of it
  // (rays meeting it).
  const double radius = 0.012, height = 0.05;
  int past = 0, meets = 0;
  double past_max = 0.0, past_sum = 0.0, meets_sum = 0.0;
  for (const glm::dvec2 base :
       {glm::dvec2(-0.04, -0.03), glm::dvec2(0.04, 0.02)}) {
    Obstacle pillar;
    pillar.size = glm::vec3(radius, radius, height);
    pillar.tank_from_obstacle[3] = glm::dvec4(base, 0.0, 1.0);
    s.inputs.obstacles = {pillar};
    const cv::Mat with = RenderScene(r.get(), s.inputs);
    auto pillar_hit = [&](const glm::dvec3& o, const glm::dvec3& d,
                          double s_max) {
      return CylinderHit(o, d, s_max, base, radius, height);
    };
    // 0: not tested; 1: the ray passes the pillar, which hides its floor
    // point from the camera; 2: the ray meets the pillar under the water.
    cv::Mat kind(kH, kW, CV_8U, cv::Scalar(0));
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        const glm::dvec3 d = glm::normalize(
            glm::dmat3(tank_from_cam) *
            glm::dvec3((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0));
        if (d.z > -1e-6) continue;
        // In over the walls' tops, onto the open surface.
        const glm::dvec3 top = eye + d * ((t.wall_height - eye.z) / d.z);
        const double to_surface = (t.water_level - eye.z) / d.z;
        const glm::dvec3 p = eye + d * to_surface;
        if (!inside(top, 0.0) || !inside(p, 0.008) ||
            pillar_hit(eye, d, to_surface) < to_surface) {
          continue;
        }
        const glm::dvec3 tr = glm::refract(d, glm::dvec3(0, 0, 1), 1.0 / n);
        const double to_floor = -p.z / tr.z;
        const glm::dvec3 f = p + tr * to_floor;
        if (!inside(f, 0.003)) continue;
        if (pillar_hit(p, tr, to_floor) < to_floor) {
          kind.at<uchar>(v, u) = 2;
        } else {
          const double to_f = glm::length(f - eye);
          if (pillar_hit(eye, (f - eye) / to_f, to_f) < to_f)
            kind.at<uchar>(v, u) = 1;
        }
      }
    }
    // Away from the classes' edges (filtering mixes neighbours).
    for (int v = 1; v + 1 < kH; ++v) {
      for (int u = 1; u + 1 < kW; ++u) {
        const uchar k = kind.at<uchar>(v, u);
        bool uniform = k != 0;
        for (int dv = -1; dv <= 1 && uniform; ++dv)
          for (int du = -1; du <= 1 && uniform; ++du)
            uniform = kind.at<uchar>(v + dv, u + du) == k;
        if (!uniform) continue;
        const cv::Vec3b a = with.at<cv::Vec3b>(v, u);
        const cv::Vec3b b = without.at<cv::Vec3b>(v, u);
        double diff = 0.0;
        for (int c = 0; c < 3; ++c)
          diff = std::max(diff, std::abs(a[c] - b[c]) + 0.0);
        if (k == 1) {
          ++past;
          past_max = std::max(past_max, diff);
          past_sum += diff;
        } else {
          ++meets;
          meets_sum += diff;
        }
      }
    }
  }
  std::printf(
      "rays past the pillar: %d px, mean diff %.1f, max %.0f; rays "
      "meeting it: %d px, mean diff %.1f\n",
      past, past > 0 ? past_sum / past : 0.0, past_max, meets,
      meets > 0 ? meets_sum / meets : 0.0);
  ASSERT_GT(past, 40) << "the scene should have floor the pillar hides";
  ASSERT_GT(meets, 40);
  // The camera's frame is read by one bilinear fetch where the copy's is
  // cubic: apart on the checkers' edges (the pillar is 60-140 levels off).
  EXPECT_LE(past_sum / past, 5.0) << "a ray past the pillar reads the floor";
  EXPECT_LE(past_max, 24.0);
  EXPECT_GT(meets_sum / meets, 20.0) << "a ray meeting the pillar shows it";
}

// The obstacles' region holds every ray that lands where the copy shows
// the obstacle: for the test scene's ripple (1.5 times steeper) seen from
// the front and at an angle, every pixel whose refracted ray meets the
// floor at a point the pillar hides from the camera lies inside
// ObstacleLookupRect, and from the front the region leaves part of the
// water out (what it is for).
TEST(EffectsTest, ObstacleRegionHoldsEveryLookupThePillarHides) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  for (const View view : {View::kFront, View::kTilted}) {
    TestScene s = MakeScene(kW, kH, view, true, false, 0.015, 0.0);
    for (float& h : s.heights) h *= 1.5f;
    Obstacle pillar;
    const glm::dvec2 base(0.045, 0.015);
    pillar.tank_from_obstacle[3] = glm::dvec4(base, 0.0, 1.0);
    s.inputs.obstacles.push_back(pillar);
    internal::HeightTexturePass heights;
    const WaterOptics optics;
    const internal::FrameState f = FrameWithHeights(s, optics, &heights);
    const glm::ivec4 region = internal::ObstacleLookupRect(f);
    auto inside = [](const glm::ivec4& r, double x, double y) {
      return x >= r.x && x < r.x + r.z && y >= r.y && y < r.y + r.w;
    };
    const HeightFieldView& w = s.inputs.water;
    const TankGeometry& t = s.inputs.tank;
    int hidden = 0, outside = 0, water = 0, water_outside = 0;
    for (int v = 0; v < kH; ++v) {
      for (int u = 0; u < kW; ++u) {
        glm::dvec3 ray, p;
        if (!WaterAtPixel(s, f, u, v, &ray, &p)) continue;
        // The pillar itself, in front of the surface: not water.
        const double to_p = glm::length(p - f.cam_in_tank);
        if (CylinderHit(f.cam_in_tank, ray, to_p, base, pillar.size.x,
                        pillar.size.z) < to_p) {
          continue;
        }
        ++water;
        if (!inside(region, u + 0.5, v + 0.5)) ++water_outside;
        const glm::dvec3 tr =
            glm::refract(ray, SurfaceNormal(w, p), 1.0 / optics.ior);
        if (tr.z > -1e-6) continue;
        const glm::dvec3 fl = p + tr * (-p.z / tr.z);
        if (std::abs(fl.x) > 0.5 * t.size_x || std::abs(fl.y) > 0.5 * t.size_y)
          continue;
        const double to_floor = glm::length(fl - f.cam_in_tank);
        const glm::dvec3 to = (fl - f.cam_in_tank) / to_floor;
        if (CylinderHit(f.cam_in_tank, to, to_floor, base, pillar.size.x,
                        pillar.size.z) >= to_floor) {
          continue;
        }
        ++hidden;
        if (!inside(region, u + 0.5, v + 0.5)) ++outside;
      }
    }
    EXPECT_GT(hidden, 100) << "view " << int(view);
    EXPECT_EQ(outside, 0) << "view " << int(view);
    std::printf(
        "view %d: %d hidden lookups, %d of %d water pixels outside "
        "the region\n",
        int(view), hidden, water_outside, water);
    // From the tilted view's camera, 12 cm up, the pillar hides the board
    // out past the tank: there the region is all the water.
    if (view == View::kFront) {
      EXPECT_GT(water_outside, water / 10);
    }
  }
}

// The real pen hides a virtual obstacle behind it, as it hides the water:
// where the pen's shaft stands in front of a pillar the output is the
// video (which shows the pen); without the pen's phantom the pillar covers
// it.
TEST(EffectsTest, PenInFrontOfAnObstacleHidesIt) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  TestScene s = SceneWithOccluders(View::kFront);
  testing::PaintPen(s.k, s.inputs.cam_from_tank, s.inputs.tank_from_pen,
                    s.inputs.pen, &s.video);
  // A shaft point 10 mm over the surface, on the camera's side; a pillar
  // of 14 mm radius stands where the camera's ray through it comes down to
  // 15 mm.
  const glm::dvec3 cam(glm::inverse(s.inputs.cam_from_tank)[3]);
  const glm::dvec3 shaft_point = ShaftPointFacingTheCamera(s, 0.010);
  const glm::dvec3 ray = glm::normalize(shaft_point - cam);
  const glm::dvec3 behind = cam + ray * ((0.015 - cam.z) / ray.z);
  s.inputs.obstacles[0].tank_from_obstacle[3] =
      glm::dvec4(behind.x, behind.y + 0.006, 0.0, 1.0);
  s.inputs.obstacles[0].size = {0.014f, 0.0f, 0.045f};
  const cv::Point px = ImagePoint(s, shaft_point);
  const cv::Mat video(kH, kW, CV_8UC3, s.video.data());
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat with_phantom = RenderScene(r.get(), s.inputs);
  EXPECT_EQ(with_phantom.at<cv::Vec3b>(px), video.at<cv::Vec3b>(px))
      << "the pen in front of the pillar shows the video";
  s.inputs.effects.pen_occludes = false;
  const cv::Mat without = RenderScene(r.get(), s.inputs);
  EXPECT_NE(without.at<cv::Vec3b>(px), video.at<cv::Vec3b>(px))
      << "without the phantom the pillar covers the pen";
  // The pillar, wider than the shaft, is drawn beside it.
  const double dx = 0.011, radius = s.inputs.obstacles[0].size.x;
  const cv::Point beside = ImagePoint(
      s, glm::dvec3(behind.x + dx,
                    behind.y + 0.006 - std::sqrt(radius * radius - dx * dx),
                    0.035));
  EXPECT_NE(with_phantom.at<cv::Vec3b>(beside), video.at<cv::Vec3b>(beside));
  EXPECT_EQ(with_phantom.at<cv::Vec3b>(beside), without.at<cv::Vec3b>(beside));
}

// A glass wall facing the camera is a vertical mirror: its faces reflect
// the board in front of it (2 x Fresnel at the ray's incidence), which the
// video shows. On a grey board, a band of it painted red, then green,
// changes the front glass over the water by that share of the difference
// in linear light; a band out of the mirror's reach leaves it unchanged.
TEST(EffectsTest, FrontGlassMirrorsTheBoardInFrontOfIt) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  auto r = Renderer::TryCreate(ctx.get(), testing::MakeIntrinsics(kW, kH),
                               RendererOptions{}, nullptr);
  ASSERT_NE(r, nullptr);
  // The front glass's point over the water, seen from the front view.
  TestScene base = MakeScene(kW, kH, View::kFront, false);
  const TankGeometry& t = base.inputs.tank;
  const glm::dvec3 p(0.0, -0.5 * t.size_y,
                     0.5 * (t.water_level + t.wall_height));
  const glm::dvec3 eye = glm::inverse(base.inputs.cam_from_tank)[3];
  const glm::dvec3 v = glm::normalize(p - eye);
  const glm::dvec3 mirrored(v.x, -v.y, v.z);
  const glm::dvec3 board = p + mirrored * (p.z / -mirrored.z);
  ASSERT_LT(board.y, -0.5 * t.size_y - 0.01);  // on the board in front
  const cv::Point at = ImagePoint(base, p);
  // Renders with the board's band y in [y0, y1] painted `bgr`.
  auto render = [&](double y0, double y1, cv::Vec3b bgr) {
    TestScene s = MakeScene(kW, kH, View::kFront, false);
    s.inputs.effects.caustics = s.inputs.effects.shadows = false;
    std::fill(s.video.begin(), s.video.end(), std::uint8_t{180});
    const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const glm::dvec3 ray = glm::dvec3(
            tank_from_cam *
            glm::dvec4((x - s.k.cx) / s.k.fx, (y - s.k.cy) / s.k.fy, 1.0, 0.0));
        if (ray.z >= 0) continue;
        const double by = eye.y + ray.y * (eye.z / -ray.z);
        if (by < y0 || by > y1) continue;
        for (int c = 0; c < 3; ++c) s.video[3 * (y * kW + x) + c] = bgr[c];
      }
    }
    return RenderScene(r.get(), s.inputs).at<cv::Vec3b>(at);
  };
  const double lo = board.y - 0.01, hi = board.y + 0.005;
  const cv::Vec3b red = render(lo, hi, {0, 0, 255});
  const cv::Vec3b green = render(lo, hi, {0, 255, 0});
  // Over the water the glass adds its reflection in linear light: a band
  // of 0 in R (G) leaves the water behind, seen through the glass; 1 adds
  // the reflectance to it (walls.frag).
  const double cos_i = std::abs(v.y);
  const double reflectance = 2.0 * FresnelReflectance(cos_i, 1.0, 1.5);
  auto step = [&](std::uint8_t without) {
    return 255.0 * LinearToSrgb(SrgbToLinear(without / 255.0) + reflectance) -
           without;
  };
  const double want_r = step(green[2]), want_g = step(red[1]);
  EXPECT_NEAR(red[2] - green[2], want_r, 0.1 * want_r + 1.0);
  EXPECT_NEAR(green[1] - red[1], want_g, 0.1 * want_g + 1.0);
  // Beyond the mirror's reach the paint does not show in the glass.
  const cv::Vec3b far_red = render(-0.4, -0.3, {0, 0, 255});
  const cv::Vec3b far_green = render(-0.4, -0.3, {0, 255, 0});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(far_red[c], far_green[c], 1) << c;
}

// `s` (flat water) over a video of one grey `level`, caustics and shadows
// off; empty if no renderer.
cv::Mat RenderOnUniformBoard(Context* ctx, std::uint8_t level, TestScene* s) {
  auto r = Renderer::TryCreate(ctx, s->k, RendererOptions{}, nullptr);
  if (r == nullptr) return {};
  s->inputs.effects.caustics = s->inputs.effects.shadows = false;
  std::fill(s->video.begin(), s->video.end(), level);
  s->inputs.video.bgr = s->video.data();
  return RenderScene(r.get(), s->inputs);
}

// Seen through a wall facing the camera, above the water, the surface and
// the floor behind it are shifted as a glass slab shifts them: the ray
// leaves the slab parallel to itself, displaced. A dark line painted on the
// floor near the front wall (flat water, 640x480) shows at the row that a
// ray traced through the slab, the surface (Snell) and down to the floor
// predicts, with the glass 3 mm thick and with it thin, within 0.25 px.
// Where the surface meets the front glass the image changes only as what
// the rays meet changes: no line of its own (the reference renderer's flat
// surface meets the glass without a meniscus). On a uniform grey video the
// rows around the waterline are no brighter than the rows a few pixels
// above and below it; the hand-drawn meniscus line read 21 levels brighter.
TEST(EffectsTest, NoLineWhereTheSurfaceMeetsTheGlass) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  const cv::Mat out = RenderOnUniformBoard(ctx.get(), 200, &s);
  ASSERT_FALSE(out.empty());
  const TankGeometry& t = s.inputs.tank;
  const WaterOptics optics;
  const int u = static_cast<int>(std::lround(s.k.cx));
  // The waterline on the glass's outer and inner faces: the line seen
  // through the slab lies between the two rows.
  auto row_at = [&](double y) {
    const glm::dvec4 c =
        s.inputs.cam_from_tank * glm::dvec4(0.0, y, t.water_level, 1.0);
    return static_cast<int>(std::lround(s.k.fy * c.y / c.z + s.k.cy));
  };
  const int outer = row_at(-0.5 * t.size_y - optics.glass_thickness_m);
  const int inner = row_at(-0.5 * t.size_y);
  const int lo = std::min(inner, outer) - 1, hi = std::max(inner, outer) + 1;
  ASSERT_GT(lo, 10);
  ASSERT_LT(hi, kH6 - 10);
  auto level = [&](int y) { return int{out.at<cv::Vec3b>(y, u)[1]}; };
  int around = 0, at = 0;
  for (int d = 4; d <= 8; ++d)
    around = std::max({around, level(lo - d), level(hi + d)});
  for (int y = lo; y <= hi; ++y) at = std::max(at, level(y));
  std::printf("waterline rows %d-%d: brightest there %d, 4-8 rows beyond %d\n",
              lo, hi, at, around);
  EXPECT_LE(at, around + 3);
}

// The walls' top faces are windows into the glass. The camera's ray
// refracted into the front wall's top face meets the slab's vertical faces
// beyond the glass-air critical angle; below the water it stays in the slab
// only while n_g sin(a) > n_w (a its angle from their normal). From a camera
// 24 degrees off the vertical it does, and runs down to the board under the
// glass: with that board painted red in the video and the rest grey, the
// front top face's pixels read red (a white rim at the wall's top edge read
// grey-white there). From the front view, 38 degrees off, it leaves the
// slab into the water and the face shows the grey floor near the wall.
TEST(EffectsTest, TopFaceShowsTheBoardUnderTheGlass) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  for (const bool steep : {true, false}) {
    TestScene s = MakeScene(kW6, kH6, View::kFront, false);
    if (steep) {
      // OpenCV's camera frame from GL's look-at (y and z flipped).
      s.inputs.cam_from_tank =
          glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, -1.0, -1.0)) *
          glm::lookAt(glm::dvec3(0.0, -0.2, 0.45), glm::dvec3(0.0),
                      glm::dvec3(0.0, 1.0, 0.0));
    }
    auto r = Renderer::TryCreate(ctx.get(), s.k, RendererOptions{}, nullptr);
    ASSERT_NE(r, nullptr);
    s.inputs.effects.caustics = s.inputs.effects.shadows = false;
    const TankGeometry& t = s.inputs.tank;
    const WaterOptics optics;
    const double y_in = -0.5 * t.size_y;
    const double y_out = y_in - optics.glass_thickness_m;
    const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
    const glm::dvec3 eye(tank_from_cam[3]);
    auto ray = [&](double u, double v) {
      return glm::normalize(glm::dvec3(
          tank_from_cam *
          glm::dvec4((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0, 0.0)));
    };
    // The board under the front glass red, the rest grey.
    for (int v = 0; v < kH6; ++v) {
      for (int u = 0; u < kW6; ++u) {
        const glm::dvec3 d = ray(u, v);
        const double y = d.z < 0 ? eye.y + d.y * (-eye.z / d.z) : 1.0;
        const bool under = y > y_out && y < y_in;
        std::uint8_t* px = &s.video[3 * (static_cast<size_t>(v) * kW6 + u)];
        px[0] = under ? 40 : 150;
        px[1] = under ? 40 : 150;
        px[2] = under ? 230 : 150;
      }
    }
    s.inputs.video.bgr = s.video.data();
    const cv::Mat out = RenderScene(r.get(), s.inputs);
    const glm::dvec3 top(0.0, 0.5 * (y_in + y_out), t.wall_height);
    const glm::dvec3 v = glm::normalize(top - eye);
    const glm::dvec3 g =
        glm::refract(v, glm::dvec3(0.0, 0.0, 1.0), 1.0 / optics.glass_ior);
    const bool trapped =
        optics.glass_ior * std::sqrt(1.0 - g.y * g.y) > optics.ior;
    ASSERT_EQ(trapped, steep);
    auto row_at = [&](double y) {
      const glm::dvec4 c =
          s.inputs.cam_from_tank * glm::dvec4(0.0, y, t.wall_height, 1.0);
      return s.k.fy * c.y / c.z + s.k.cy;
    };
    const double r_in = row_at(y_in), r_out = row_at(y_out);
    const int u = static_cast<int>(std::lround(s.k.cx));
    const int first = static_cast<int>(std::ceil(std::min(r_in, r_out) + 0.5));
    const int last = static_cast<int>(std::floor(std::max(r_in, r_out) - 0.5));
    ASSERT_LE(first, last);
    for (int row = first; row <= last; ++row) {
      const cv::Vec3b c = out.at<cv::Vec3b>(row, u);
      std::printf("%s view, top face row %d: BGR %d %d %d\n",
                  steep ? "steep" : "front", row, c[0], c[1], c[2]);
      if (steep) {
        EXPECT_GT(int{c[2]}, int{c[1]} + 60) << row;
      } else {
        EXPECT_LT(int{c[2]}, int{c[1]} + 20) << row;
      }
    }
  }
}

// The walls' top faces look up the board under the glass, past the tank's
// corners too (the ray drifts along the wall), and the water looks up the
// board beyond the walls: both read the refraction copy, which must hold
// them. On an evenly grey board, from the front, every pixel of the front
// top face's corner squares reads the board, not an uncopied texel (black
// before the copy reached past the inner box).
TEST(EffectsTest, TopFacesReadTheBoardAtTheCorners) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  const cv::Mat out = RenderOnUniformBoard(ctx.get(), 150, &s);
  ASSERT_FALSE(out.empty());
  const TankGeometry& t = s.inputs.tank;
  const double g = WaterOptics{}.glass_thickness_m;
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  int seen = 0, dark = 0;
  for (int v = 0; v < kH6; ++v) {
    for (int u = 0; u < kW6; ++u) {
      const glm::dvec3 d(tank_from_cam * glm::dvec4((u - s.k.cx) / s.k.fx,
                                                    (v - s.k.cy) / s.k.fy, 1.0,
                                                    0.0));
      if (d.z >= 0) continue;
      const glm::dvec3 p = eye + d * ((t.wall_height - eye.z) / d.z);
      // The corner squares of the front wall's top face, less a tenth of a
      // millimetre at their edges.
      const double ax = std::abs(p.x) - 0.5 * t.size_x;
      const double y = -p.y - 0.5 * t.size_y;
      if (ax < 1e-4 || ax > g - 1e-4 || y < 1e-4 || y > g - 1e-4) continue;
      ++seen;
      const cv::Vec3b c = out.at<cv::Vec3b>(v, u);
      if (c[0] < 60 || c[1] < 60 || c[2] < 60) ++dark;
    }
  }
  EXPECT_GT(seen, 4) << "the corner squares are in view";
  EXPECT_EQ(dark, 0) << "of " << seen << " corner pixels";
}

// Above the water the front glass adds its Fresnel reflection to what lies
// behind it in linear light: out = behind T + R L, with R twice the exact
// reflectance at the pixel's angle (two faces), T = 1 - R and L the board it
// mirrors, on a uniform grey board. Through each pixel of the front wall
// between the waterline and the top (2 mm clear of both at the glass's
// inner and outer faces, and 5 mm of the ends), the image with the walls
// must equal that blend of the image without them to within half a level
// on average (measured 0.16). The former blend, the linear step scaled by
// the sRGB slope at mid-grey, was 2.5 levels off here (the water behind the
// glass, 0.33, is darker than mid-grey, where the slope is steeper).
TEST(EffectsTest, FrontGlassOverTheWaterBlendsInLinearLight) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  const cv::Mat with = RenderOnUniformBoard(ctx.get(), 180, &s);
  ASSERT_FALSE(with.empty());
  s.inputs.effects.walls = false;
  auto r = Renderer::TryCreate(ctx.get(), s.k, RendererOptions{}, nullptr);
  ASSERT_NE(r, nullptr);
  const cv::Mat without = RenderScene(r.get(), s.inputs);
  const TankGeometry& t = s.inputs.tank;
  const WaterOptics optics;
  const double board = SrgbToLinear(180.0 / 255.0);
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  const double y_in = -0.5 * t.size_y;
  const double y_out = y_in - optics.glass_thickness_m;
  double sum = 0;
  int n = 0;
  for (int v = 0; v < kH6; ++v) {
    for (int u = 0; u < kW6; ++u) {
      const glm::dvec3 d = glm::normalize(glm::dvec3(
          tank_from_cam *
          glm::dvec4((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0, 0.0)));
      if (d.y <= 0) continue;
      // Through the outer face below the top, and the inner face over the
      // water (where the ray goes on to the surface, with or without the
      // glass).
      const glm::dvec3 p = eye + d * ((y_out - eye.y) / d.y);
      const glm::dvec3 q = eye + d * ((y_in - eye.y) / d.y);
      if (q.z < t.water_level + 0.002 || p.z > t.wall_height - 0.002 ||
          std::abs(p.x) > 0.5 * t.size_x - 0.005) {
        continue;
      }
      const double refl = 2.0 * FresnelReflectance(d.y, 1.0, optics.glass_ior);
      for (int c = 0; c < 3; ++c) {
        const double behind =
            SrgbToLinear(without.at<cv::Vec3b>(v, u)[c] / 255.0);
        const double expected =
            255.0 * LinearToSrgb(behind * (1.0 - refl) + board * refl);
        sum += std::abs(with.at<cv::Vec3b>(v, u)[c] - expected);
        ++n;
      }
    }
  }
  ASSERT_GT(n, 300) << "the band is in view";
  std::printf(
      "front glass over the water: mean |out - blend| %.2f levels "
      "over %d values\n",
      sum / n, n);
  EXPECT_LT(sum / n, 0.5);
}

// Paints the scene's video grey by the board y (tank frame, z = 0) that
// each pixel's camera ray meets (y = 1 m for rays at or above the horizon).
template <typename F>
void PaintVideoByBoardY(TestScene* s, F&& grey) {
  const glm::dmat4 tank_from_cam = glm::inverse(s->inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  for (int y = 0; y < s->k.height; ++y) {
    for (int x = 0; x < s->k.width; ++x) {
      const glm::dvec3 ray(tank_from_cam * glm::dvec4((x - s->k.cx) / s->k.fx,
                                                      (y - s->k.cy) / s->k.fy,
                                                      1.0, 0.0));
      const double by = ray.z < 0 ? eye.y + ray.y * (eye.z / -ray.z) : 1.0;
      const auto g = static_cast<std::uint8_t>(grey(by));
      for (int c = 0; c < 3; ++c)
        s->video[3 * (static_cast<size_t>(y) * s->k.width + x) + c] = g;
    }
  }
}

// A renderer whose glass walls are `d` metres thick.
std::unique_ptr<Renderer> RendererWithGlass(Context* ctx, const Intrinsics& k,
                                            float d) {
  RendererOptions options;
  options.optics.glass_thickness_m = d;
  auto r = Renderer::TryCreate(ctx, k, options, nullptr);
  EXPECT_NE(r, nullptr);
  return r;
}

TEST(EffectsTest, FrontGlassShiftsWhatLiesBehindItAsASlab) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene base = MakeScene(kW6, kH6, View::kFront, false);
  const TankGeometry& t = base.inputs.tank;
  const WaterOptics optics;
  const glm::dmat4 tank_from_cam = glm::inverse(base.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  const int u = static_cast<int>(std::lround(base.k.cx));
  auto ray_at = [&](double row) {
    return glm::normalize(glm::dvec3(
        tank_from_cam * glm::dvec4((u - base.k.cx) / base.k.fx,
                                   (row - base.k.cy) / base.k.fy, 1.0, 0.0)));
  };
  const double y_in = -0.5 * t.size_y;  // the front wall's inner face
  // The floor's y that the pixel row's ray reaches through a slab of
  // thickness d; NaN where the ray does not cross the slab above the water.
  auto floor_y = [&](double row, double d) {
    const glm::dvec3 v = ray_at(row);
    const double t_out = (y_in - d - eye.y) / v.y, t_in = (y_in - eye.y) / v.y;
    if (eye.z + t_out * v.z > t.wall_height ||
        eye.z + t_in * v.z < t.water_level)
      return std::nan("");
    const glm::dvec3 n(0.0, -1.0, 0.0);
    const glm::dvec3 g = glm::refract(v, n, 1.0 / optics.glass_ior);
    const glm::dvec3 shift = g * (d / g.y) - v * (d / v.y);
    const glm::dvec3 o = eye + shift;
    const glm::dvec3 s = o + v * ((t.water_level - o.z) / v.z);
    const glm::dvec3 w =
        glm::refract(v, glm::dvec3(0.0, 0.0, 1.0), 1.0 / optics.ior);
    return s.y + w.y * (s.z / -w.z);
  };
  // The rows whose rays cross the 3 mm slab above the water.
  std::vector<int> band;
  for (int row = 0; row < kH6; ++row)
    if (!std::isnan(floor_y(row, optics.glass_thickness_m)))
      band.push_back(row);
  ASSERT_GE(band.size(), 8u);
  const double row_mid = 0.5 * (band.front() + band.back());
  const double y_line = floor_y(row_mid, optics.glass_thickness_m);
  // The row at which slab thickness d shows the line (bisection: lower rows
  // see the floor nearer the camera, at smaller y).
  auto predicted_row = [&](double d) {
    double lo = band.front() - 3, hi = band.back() + 3;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      const double y = floor_y(mid, d);
      const bool below = std::isnan(y) ? mid < row_mid : y > y_line;
      (below ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  auto measured_row = [&](float d) {
    auto r = RendererWithGlass(ctx.get(), base.k, d);
    if (r == nullptr) return std::nan("");
    TestScene s = MakeScene(kW6, kH6, View::kFront, false);
    s.inputs.effects.caustics = s.inputs.effects.shadows = false;
    PaintVideoByBoardY(&s, [&](double by) {
      return std::abs(by - y_line) < 0.001 ? 40 : 225;
    });
    const cv::Mat out = RenderScene(r.get(), s.inputs);
    // The paper's level: the band's median (the painted line is darker).
    std::vector<int> levels;
    for (int row : band) levels.push_back(out.at<cv::Vec3b>(row, u)[1]);
    std::nth_element(levels.begin(), levels.begin() + levels.size() / 2,
                     levels.end());
    const double paper = levels[levels.size() / 2];
    double sum = 0, weight = 0;
    for (int row : band) {
      for (int du = -2; du <= 2; ++du) {
        const double w =
            std::max(0.0, paper - out.at<cv::Vec3b>(row, u + du)[1]);
        sum += w * row;
        weight += w;
      }
    }
    return weight > 0 ? sum / weight : std::nan("");
  };
  const double want_thick = predicted_row(optics.glass_thickness_m);
  const double want_thin = predicted_row(0.0);
  ASSERT_GT(std::abs(want_thick - want_thin), 0.5);  // the slab's shift
  EXPECT_NEAR(measured_row(optics.glass_thickness_m), want_thick, 0.25);
  EXPECT_NEAR(measured_row(0.0f), want_thin, 0.25);
}

// A refracted ray that leaves the water through the back wall meets the
// board beyond it where a parallel slab puts it: the slab keeps the ray's
// direction but moves the point where it leaves (out and down by the path
// in the glass). A camera 7.5 cm over the board looks over the front wall
// at the water by the back wall; a line painted on the board 8 mm behind
// the back wall's inner face shows in the water at the row the exact trace
// (Snell at the surface, water to glass to air at the wall) predicts, with
// the 3 mm glass and with none. Without the slab's shift the thick glass
// would show the line where the thin one does, 2 rows off.
TEST(EffectsTest, BackGlassShiftsWhatTheWaterSeesBeyondItAsASlab) {
  constexpr int kW7 = 640, kH7 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW7, kH7);
  TestScene base = MakeScene(kW7, kH7, View::kFront, false);
  base.inputs.cam_from_tank = testing::LookAt(glm::dvec3(0.0, -0.2, 0.075),
                                              glm::dvec3(0.0, 0.02, 0.01));
  const TankGeometry& t = base.inputs.tank;
  const WaterOptics optics;
  const glm::dmat4 tank_from_cam = glm::inverse(base.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  const int u = static_cast<int>(std::lround(base.k.cx));
  const double half_y = 0.5 * t.size_y;
  // The board's y beyond the back wall that the pixel row's refracted ray
  // reaches through a slab of thickness d; NaN where the ray crosses the
  // front wall's glass, misses the water, meets the floor or leaves the
  // slab under the board, or where the slab mirrors it.
  auto board_y = [&](double row, double d) {
    const glm::dvec3 v = glm::normalize(glm::dvec3(
        tank_from_cam * glm::dvec4((u - base.k.cx) / base.k.fx,
                                   (row - base.k.cy) / base.k.fy, 1.0, 0.0)));
    const double nan = std::nan("");
    if (v.z >= 0 ||
        eye.z + v.z * ((-half_y - d - eye.y) / v.y) < t.wall_height) {
      return nan;
    }
    const glm::dvec3 s = eye + v * ((t.water_level - eye.z) / v.z);
    if (std::abs(s.y) > half_y) return nan;
    const glm::dvec3 w =
        glm::refract(v, glm::dvec3(0.0, 0.0, 1.0), 1.0 / optics.ior);
    const glm::dvec3 at_wall = s + w * ((half_y - s.y) / w.y);
    if (at_wall.z <= 0) return nan;
    const glm::dvec3 n(0.0, -1.0, 0.0);
    const glm::dvec3 g =
        glm::refract(w, n, double(optics.ior / optics.glass_ior));
    const glm::dvec3 out = glm::refract(w, n, double(optics.ior));
    if (glm::dot(out, out) < 0.5) return nan;
    const glm::dvec3 exit = at_wall + g * (d / g.y);
    if (exit.z <= 0) return nan;
    return exit.y + out.y * (exit.z / -out.z);
  };
  std::vector<int> band;
  for (int row = 0; row < kH7; ++row) {
    if (!std::isnan(board_y(row, optics.glass_thickness_m)) &&
        !std::isnan(board_y(row, 0.0))) {
      band.push_back(row);
    }
  }
  ASSERT_GE(band.size(), 8u);
  const double row_mid = 0.5 * (band.front() + band.back());
  const double y_line = board_y(row_mid, optics.glass_thickness_m);
  ASSERT_GT(y_line, half_y + optics.glass_thickness_m);
  // The row at which slab thickness d shows the line (bisection: lower rows
  // meet the wall lower and see the board nearer it).
  auto row_of = [&](double d, double y) {
    double lo = band.front(), hi = band.back();
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (board_y(mid, d) > y ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  auto predicted_row = [&](double d) { return row_of(d, y_line); };
  // The rendered line's row: the centroid of what the line takes from the
  // paper (the same render without the line subtracted), the line painted
  // in the video as a Gaussian across y (1.5 mm) so that its centre is not
  // rounded to the video's rows.
  auto measured_row = [&](float d) {
    auto r = RendererWithGlass(ctx.get(), base.k, d);
    if (r == nullptr) return std::nan("");
    TestScene s = base;
    s.inputs.video.bgr = s.video.data();
    s.inputs.water.heights = s.heights.data();
    s.inputs.effects.caustics = s.inputs.effects.shadows = false;
    s.inputs.effects.reflection = false;
    cv::Mat out[2];
    for (int with_line = 0; with_line < 2; ++with_line) {
      PaintVideoByBoardY(&s, [&](double by) {
        const double e = (by - y_line) / 0.0015;
        return static_cast<int>(
            std::lround(225.0 - with_line * 185.0 * std::exp(-e * e)));
      });
      out[with_line] = RenderScene(r.get(), s.inputs);
    }
    double sum = 0, weight = 0;
    for (int row : band) {
      for (int du = -2; du <= 2; ++du) {
        const double w = std::max(0, out[0].at<cv::Vec3b>(row, u + du)[1] -
                                         out[1].at<cv::Vec3b>(row, u + du)[1]);
        sum += w * row;
        weight += w;
      }
    }
    return weight > 0 ? sum / weight : std::nan("");
  };
  const double want_thick = predicted_row(optics.glass_thickness_m);
  const double want_thin = predicted_row(0.0);
  std::printf(
      "line beyond the back glass: rows %d-%d, predicted %.2f (3 mm) "
      "and %.2f (no glass)\n",
      band.front(), band.back(), want_thick, want_thin);
  ASSERT_GT(std::abs(want_thick - want_thin), 1.0);  // the slab's shift
  const double thick = measured_row(optics.glass_thickness_m);
  const double thin = measured_row(0.0f);
  std::printf("measured %.2f and %.2f\n", thick, thin);
  EXPECT_NEAR(thick, want_thick, 0.2);
  EXPECT_NEAR(thin, want_thin, 0.2);
}

// The tank's shadow on the board around it (pass_board_light.h): over a
// uniform grey video, board points in front of the tank read the grey times
// the factor that the board-light model gives there (its light through the
// highlight shoulder, encoded, over the board's), bilinear between texels:
// in the water column's shadow (at least 20 levels darker), beyond it, at
// the corner the light's glass lights, and far out; the video unchanged
// without the effect and beyond the map.
TEST(EffectsTest, TheTanksShadowOnTheBoardIsTheBoardLightModels) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const RendererOptions o;
  auto r = Renderer::TryCreate(ctx.get(), testing::MakeIntrinsics(kW, kH), o,
                               nullptr);
  ASSERT_NE(r, nullptr);
  const std::uint8_t grey = 200;
  TestScene s = MakeScene(kW, kH, View::kFront, false);
  std::fill(s.video.begin(), s.video.end(), grey);
  s.inputs.effects.tank_shadow = true;
  const cv::Mat on = RenderScene(r.get(), s.inputs);
  s.inputs.effects.tank_shadow = false;
  const cv::Mat off = RenderScene(r.get(), s.inputs);

  // The model for this tank and light, on a board of the video's grey.
  const TankGeometry& t = s.inputs.tank;
  const glm::dvec3 light = glm::normalize(s.inputs.light_in_tank);
  internal::BoardLightMap map =
      internal::BoardLightLayout(t, o.optics, internal::BoardLightOptions{});
  internal::ComputeBoardSkyView(t, o.optics, internal::BoardLightOptions{},
                                &map);
  internal::ComputeBoardDirectLight(t, o.optics, light,
                                    internal::BoardLightOptions{}, &map);
  const WaterShading sh = ComputeWaterShading(o.optics, t.water_level, light);
  float under_glass = 0;
  for (const glm::vec3& u : sh.under_glass) under_glass += 0.25f * u.g;
  const double g = SrgbToLinear(grey / 255.0);
  const double knee = o.optics.highlight_knee;
  // In front of the front wall (seen directly): in the water column's
  // shadow, beyond it, at the lit front-right corner; and far out.
  const double fy = map.outer_y;
  struct Probe {
    glm::dvec2 at;
    double min_change;  // levels the tank must move it by, at least
  } probes[] = {{{0.0, -fy - 0.003}, 20.0},
                {{0.0, -fy - 0.014}, 0.5},
                {{map.outer_x + 0.008, -fy - 0.004}, 0.5},
                {{-map.outer_x - 0.03, -fy - 0.02}, 0.0}};
  // The floor's radiance over the board's, as the water pass saw it.
  const float floor_radiance =
      static_cast<float>(FloorSeen(o, s.inputs, grey, grey, 1) / g);
  // What the pass multiplies the encoded board by at a texel: the board's
  // light through the shoulder, encoded, over the board's encoding.
  auto factor = [&](int i, int j) {
    const double f = map.Texel(i, j, o.optics, under_glass)
                         .Factor(1, static_cast<float>(g), floor_radiance);
    const double shown =
        g + HighlightShoulder(g * f, knee) - HighlightShoulder(g, knee);
    return std::clamp(
        LinearToSrgb(std::clamp(shown, 0.0, 1.0)) / LinearToSrgb(g), 0.5, 1.5);
  };
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  for (const Probe& p : probes) {
    const cv::Point px = ImagePoint(s, glm::dvec3(p.at, 0.0));
    ASSERT_TRUE(cv::Rect(0, 0, kW, kH).contains(px));
    // The board point the pixel's centre sees, and the map there
    // (bilinear between texel centres, as the shader's lookup).
    const glm::dvec3 ray(tank_from_cam * glm::dvec4((px.x - s.k.cx) / s.k.fx,
                                                    (px.y - s.k.cy) / s.k.fy,
                                                    1.0, 0.0));
    const glm::dvec3 b = eye + ray * (eye.z / -ray.z);
    const double u = (b.x - map.origin.x) / map.texel - 0.5;
    const double v = (b.y - map.origin.y) / map.texel - 0.5;
    const int i = static_cast<int>(std::floor(u));
    const int j = static_cast<int>(std::floor(v));
    const double a = u - i, c = v - j;
    const double f =
        (1 - c) * ((1 - a) * factor(i, j) + a * factor(i + 1, j)) +
        c * ((1 - a) * factor(i, j + 1) + a * factor(i + 1, j + 1));
    const double expected = grey * f;
    const double seen = on.at<cv::Vec3b>(px)[1];
    EXPECT_NEAR(seen, expected, 1.0) << b.x << " " << b.y << " f " << f;
    EXPECT_GE(std::abs(seen - grey), p.min_change) << b.x << " " << b.y;
    EXPECT_EQ(off.at<cv::Vec3b>(px)[1], grey) << b.x << " " << b.y;
  }
  // Beyond the map the video is untouched.
  EXPECT_EQ(on.at<cv::Vec3b>(2, 2), cv::Vec3b(grey, grey, grey));
}

// A glass wall seen from inside the tank (the back wall from the front) is a
// vertical mirror whose image goes down into the tank: above the water it
// shows the water near the walls, the floor under it lit as the floor's
// mean with its return, over n^2 (FloorReturnLight::floor_seen), by
// 2 x Fresnel of the glass times the surface's transmittance. Painting the
// tank floor (and only it) dark, then light, changes the back glass by that
// share of the difference (a glass that mirrored the sky there would not
// change at all).
TEST(EffectsTest, BackGlassMirrorsTheWaterBelowIt) {
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW, kH);
  const RendererOptions o;
  auto r = Renderer::TryCreate(ctx.get(), testing::MakeIntrinsics(kW, kH), o,
                               nullptr);
  ASSERT_NE(r, nullptr);
  TestScene base = MakeScene(kW, kH, View::kFront, false);
  const TankGeometry& t = base.inputs.tank;
  const double hx = 0.5 * t.size_x, hy = 0.5 * t.size_y;
  // A point of the back wall's inner face over the water, below the rim.
  const glm::dvec3 p(0.0, hy, t.wall_height - 0.003);
  const glm::dvec3 eye = glm::inverse(base.inputs.cam_from_tank)[3];
  const glm::dvec3 v = glm::normalize(p - eye);
  // The ray passes over the front wall and the water.
  ASSERT_GT(eye.z + v.z * ((-hy - eye.y) / v.y), t.wall_height);
  const cv::Point at = ImagePoint(base, p);
  const std::uint8_t board_grey = 200;
  // Renders with the tank's floor painted `grey` (the board around stays).
  auto render = [&](std::uint8_t grey) {
    TestScene s = MakeScene(kW, kH, View::kFront, false);
    s.inputs.effects.caustics = s.inputs.effects.shadows = false;
    s.inputs.effects.reflection = false;
    const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const glm::dvec3 ray = glm::dvec3(
            tank_from_cam *
            glm::dvec4((x - s.k.cx) / s.k.fx, (y - s.k.cy) / s.k.fy, 1.0, 0.0));
        const glm::dvec3 b = eye + ray * (eye.z / -ray.z);
        const bool floor =
            ray.z < 0 && std::abs(b.x) < hx && std::abs(b.y) < hy;
        for (int c = 0; c < 3; ++c)
          s.video[3 * (y * kW + x) + c] = floor ? grey : board_grey;
      }
    }
    return RenderScene(r.get(), s.inputs).at<cv::Vec3b>(at);
  };
  const cv::Vec3b dark = render(60), light = render(200);
  const double r_glass = 2.0 * FresnelReflectance(std::abs(v.y), 1.0, 1.5);
  const double t_surface = 1.0 - FresnelReflectance(-v.z, 1.0, o.optics.ior);
  // Over the water the glass adds to the board beyond it, seen through the
  // glass, its reflection in linear light: the mirrored surface's view of
  // the floor and of the sky (the ambient share's radiance).
  const double board = SrgbToLinear(board_grey / 255.0);
  for (int c = 0; c < 3; ++c) {  // B, G, R
    const int rgb = 2 - c;
    auto out = [&](std::uint8_t grey) {
      const double seen = FloorSeen(o, base.inputs, grey, board_grey, rgb);
      const double mirrored =
          t_surface * seen + (1.0 - t_surface) * o.optics.ambient_share;
      return 255.0 * LinearToSrgb(board * (1.0 - r_glass) + r_glass * mirrored);
    };
    const double want = out(200) - out(60);
    ASSERT_GT(want, 3.0);
    EXPECT_NEAR(light[c] - dark[c], want, 0.1 * want + 1.0) << c;
  }
}

// Seen through the water, the board under the back glass is a band a few
// pixels tall between the floor at the wall's foot and the floor in the
// wall's mirror (the ray's height where it meets the wall's plane between
// 0 and the descent of its way out and back through the slab). Its edge
// pixels hold band and floor by the share of the pixel each covers, as the
// reference's pixel-area samples do: summed down a column, each pixel's
// share of the band (in linear light, between the floor beside it and the
// band's inside) is the band's height in pixels that the geometry gives,
// fractions included. Drawing each pixel as its centre falls would sum to a
// whole number of pixels.
TEST(EffectsTest, TheBoardUnderTheGlassCoversItsEdgePixelsByShare) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  s.inputs.effects.reflection = false;
  RendererOptions o;
  // The disc's light alone, from behind the tank: the board under the back
  // glass, lit through the wall's top face and its outer face, reads far
  // brighter than the floor under the water (no sky lighting both alike).
  o.optics.ambient_share = 0.0f;
  auto r = Renderer::TryCreate(ctx.get(), s.k, o, nullptr);
  ASSERT_NE(r, nullptr);
  s.inputs.effects.caustics = s.inputs.effects.shadows = false;
  // Behind the tank: the back wall's outer face takes the light too.
  s.inputs.light_in_tank = {0.0, 0.6, 1.0};
  std::fill(s.video.begin(), s.video.end(), std::uint8_t{200});
  s.inputs.video.bgr = s.video.data();
  const cv::Mat out = RenderScene(r.get(), s.inputs);
  ASSERT_FALSE(out.empty());

  // The geometry, traced as the shader traces it: from pixel (u, v) to the
  // flat surface, refracted, to the back wall's plane (the +y inner face).
  const TankGeometry& t = s.inputs.tank;
  const double n = o.optics.ior, ng = o.optics.glass_ior;
  const double g = o.optics.glass_thickness_m;
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  // Height of the ray where it meets the wall's plane, less the band's top
  // when `top` (the band is where the first is positive and the second
  // negative).
  auto edge = [&](double u, double v, bool top) {
    const glm::dvec3 ray = glm::normalize(glm::dvec3(
        tank_from_cam *
        glm::dvec4((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0, 0.0)));
    const glm::dvec3 p = eye + ray * ((t.water_level - eye.z) / ray.z);
    const glm::dvec3 tw = glm::refract(ray, glm::dvec3(0, 0, 1), 1.0 / n);
    const double z_wall = p.z + tw.z * ((0.5 * t.size_y - p.y) / tw.y);
    const glm::dvec3 tg = glm::refract(tw, glm::dvec3(0, -1, 0), n / ng);
    return top ? z_wall - 2.0 * g * -tg.z / tg.y : z_wall;
  };
  // The row (continuous, pixel centres at integers) where `f` changes sign
  // between rows a and b.
  auto crossing = [&](double u, double a, double b, bool top) {
    for (int i = 0; i < 60; ++i) {
      const double m = 0.5 * (a + b);
      ((edge(u, a, top) > 0) == (edge(u, m, top) > 0) ? a : b) = m;
    }
    return 0.5 * (a + b);
  };
  auto linear = [&](int x, int y) {
    return SrgbToLinear(out.at<cv::Vec3b>(y, x)[1] / 255.0);
  };
  double sum_error = 0;
  int columns = 0;
  for (int x = 280; x <= 360; x += 4) {
    // Find the band: the rows of the wall's foot seen through the water.
    int v0 = -1;
    for (int v = 20; v < kH6 - 20 && v0 < 0; ++v)
      if (edge(x, v, false) > 0 && edge(x, v, true) < 0) v0 = v;
    ASSERT_GE(v0, 0) << "column " << x;
    const double bottom = crossing(x, v0, v0 + 20, false);
    const double top = crossing(x, v0 - 20, v0, true);
    const double height = bottom - top;
    ASSERT_GT(height, 2.0);
    ASSERT_LT(height, 8.0);
    const int first = static_cast<int>(std::floor(top)) - 1;
    const int last = static_cast<int>(std::ceil(bottom)) + 1;
    // The pixel at the band's middle lies wholly inside it (the band is
    // over 2 px tall); the floor either side two rows beyond its edge
    // pixels.
    const double middle = 0.5 * (top + bottom);
    const double inside = linear(x, static_cast<int>(std::lround(middle)));
    const double above = linear(x, first - 2), below = linear(x, last + 2);
    ASSERT_GT(std::min(std::abs(inside - above), std::abs(inside - below)),
              0.1 * inside)
        << "column " << x;
    double shares = 0;
    for (int v = first; v <= last; ++v) {
      const double floor = v < middle ? above : below;
      shares += (linear(x, v) - floor) / (inside - floor);
    }
    sum_error += std::abs(shares - height);
    ++columns;
  }
  const double mean_error = sum_error / columns;
  std::printf(
      "the band's height in pixels against its summed shares: mean "
      "difference %.3f px over %d columns\n",
      mean_error, columns);
  EXPECT_LT(mean_error, 0.12);
}

// A wall's top face, 3 mm of glass, covers the pixels its edges cross by
// the share of each that it covers, as the reference's pixel-area samples
// do: seen from above over a uniform board, the face shows the board under
// the glass, lit through the glass (apart from the open board beyond it
// and the wet floor inside), and the shares summed down a column across
// its outer edge (between the board beyond and the face's inside, in linear
// light) are the width of face they span in pixels, fractions included.
TEST(EffectsTest, TopFacesCoverTheirEdgePixelsByShare) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  const TankGeometry& t = s.inputs.tank;
  const double g = WaterOptics{}.glass_thickness_m;
  const double hy = 0.5 * t.size_y;
  auto r = Renderer::TryCreate(ctx.get(), s.k, RendererOptions{}, nullptr);
  ASSERT_NE(r, nullptr);
  s.inputs.effects.caustics = s.inputs.effects.shadows = false;
  s.inputs.effects.reflection = false;
  // Nearly straight down on the -y wall's top face, moved a third of a
  // pixel at a time.
  for (const double shift : {0.0, 0.00016, 0.00032}) {
    const double x_eye = 0.0;
    const glm::dvec3 eye(x_eye, -hy - 0.5 * g + 0.0003 + shift, 0.30);
    s.inputs.cam_from_tank =
        testing::LookAt(eye, glm::dvec3(x_eye, -hy - 0.5 * g + shift, 0.0));
    std::fill(s.video.begin(), s.video.end(), std::uint8_t{200});
    s.inputs.video.bgr = s.video.data();
    const cv::Mat out = RenderScene(r.get(), s.inputs);
    ASSERT_FALSE(out.empty());
    // The face's outer edge (tank y = -hy - g at the wall's height) along
    // the image column through the camera; the board beyond it is the
    // video as it is. (Beyond the inner edge the wall's inner face meets
    // the water, which the walls pass draws too.)
    auto row_of = [&](double y) {
      const glm::dvec4 c =
          s.inputs.cam_from_tank * glm::dvec4(x_eye, y, t.wall_height, 1.0);
      return s.k.fy * c.y / c.z + s.k.cy;
    };
    const double outer = row_of(-hy - g), inner = row_of(-hy);
    ASSERT_LT(outer, inner - 4.0);  // the outer edge on top, 4+ px wide
    const int u = static_cast<int>(std::lround(s.k.cx));
    auto level = [&](int v) {
      return SrgbToLinear(out.at<cv::Vec3b>(v, u)[1] / 255.0);
    };
    const int first = static_cast<int>(std::floor(outer)) - 1;
    const int last = static_cast<int>(std::lround(outer)) + 2;
    const double board = level(first - 2), inside = level(last + 1);
    ASSERT_GT(std::abs(board - inside), 0.05);
    double shares = 0;
    for (int v = first; v <= last; ++v)
      shares += (board - level(v)) / (board - inside);
    const double covered = last + 0.5 - outer;
    std::printf(
        "top face's outer edge at row %.3f: %.3f px of the face "
        "down to row %d, shares sum to %.3f\n",
        outer, covered, last, shares);
    EXPECT_NEAR(shares, covered, 0.1);
  }
}

// The real pen's dry shaft in front of the water: along its outline each
// pixel holds the pen and the water behind it by the share of the pixel the
// pen covers. The video (640x480, front view, flat water) is a uniform
// board with a uniform pen painted by exact area cover (8 x 8 samples a
// pixel, mixed in linear light); the truth at each pixel is c P + (1 - c) W,
// W the scene rendered without the pen (and its video without it). The tip
// is held 10 mm over the water (a submerged shaft would show by refraction
// beside the dry one). Scored on the pixels over the water within 2.5 px of
// the shaft's outline, from 3 mm above the tip to 10 mm below the cube
// (nearer, the cube's own margin). Then the tracked pose is
// moved 0.5 mm across the shaft (half the margin), the video kept: the pixels
// the pen covers whole must still show the video, the board beside it the
// water.
TEST(EffectsTest, PenOutlineHoldsThePenAndTheWaterByShare) {
  constexpr int kW6 = 640, kH6 = 480;
  RIPPLE_CONTEXT_OR_SKIP(ctx, Backend::kEgl, kW6, kH6);
  TestScene s = MakeScene(kW6, kH6, View::kFront, false);
  s.inputs.effects.caustics = s.inputs.effects.shadows = false;
  s.inputs.pen_visible = true;
  // The tip 10 mm over the water: no submerged shaft to see by refraction.
  s.inputs.tank_from_pen = PenPose(s.inputs.tank, -0.01);
  const PenGeometry& g = s.inputs.pen;
  const TankGeometry& t = s.inputs.tank;
  const double level = s.inputs.tank.water_level;
  const glm::dmat4 tank_from_cam = glm::inverse(s.inputs.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  const glm::dmat4& pen = s.inputs.tank_from_pen;
  const glm::dvec3 tip(
      pen * glm::dvec4(0, 0, -0.5 * g.cube_edge - g.shaft_length, 1));
  const glm::dvec3 axis = glm::normalize(glm::dvec3(pen[2]));
  // Per pixel: the share of 8 x 8 sample rays that meet the shaft before
  // the rest level, and whether the pixel is scored.
  const int n = 8;
  std::vector<float> cover(kW6 * kH6, 0.0f);
  std::vector<std::uint8_t> scored(kW6 * kH6, 0);
  auto ray = [&](double u, double v) {
    return glm::normalize(
        glm::dmat3(tank_from_cam) *
        glm::dvec3((u - s.k.cx) / s.k.fx, (v - s.k.cy) / s.k.fy, 1.0));
  };
  // Along the ray from the eye: the axis coordinate and distance of the
  // ray's point nearest the axis, and whether the shaft is met before z =
  // level.
  auto nearest = [&](const glm::dvec3& d, double* u_axis, double* dist) {
    const glm::dvec3 w0 = eye - tip;
    const double b = glm::dot(d, axis), dd = glm::dot(d, w0),
                 e = glm::dot(axis, w0);
    const double sr = (b * e - dd) / (1 - b * b);
    const double ua = (e - b * dd) / (1 - b * b);
    const glm::dvec3 x = eye + sr * d, a = tip + ua * axis;
    *u_axis = ua;
    *dist = glm::length(x - a);
    return x.z > level;
  };
  for (int y = 0; y < kH6; ++y) {
    for (int x = 0; x < kW6; ++x) {
      int hits = 0;
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          double ua, dist;
          const bool dry =
              nearest(ray(x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n),
                      &ua, &dist);
          hits += dry && dist < g.shaft_radius && ua > 0 && ua < g.shaft_length;
        }
      }
      cover[y * kW6 + x] = float(hits) / (n * n);
      // Over the water: the pixel's ray meets the rest level inside the
      // tank.
      const glm::dvec3 d = ray(x, y);
      const glm::dvec3 q = eye + d * ((level - eye.z) / d.z);
      const bool over_water = std::abs(q.x) < 0.5 * t.size_x - 0.002 &&
                              std::abs(q.y) < 0.5 * t.size_y - 0.002;
      double ua, dist;
      nearest(d, &ua, &dist);
      scored[y * kW6 + x] = over_water && ua > 0.003 &&
                            ua < g.shaft_length - 0.01 &&
                            std::abs(dist - g.shaft_radius) <
                                2.5 * glm::length(eye - tip) / s.k.fx;
    }
  }
  // The board, and the pen over it by its cover, mixed in linear light.
  const double board = SrgbToLinear(180 / 255.0);
  const glm::dvec3 pen_bgr(SrgbToLinear(150 / 255.0), SrgbToLinear(60 / 255.0),
                           SrgbToLinear(40 / 255.0));
  std::fill(s.video.begin(), s.video.end(), std::uint8_t{180});
  std::vector<std::uint8_t> with_pen = s.video;
  for (int p = 0; p < kW6 * kH6; ++p) {
    for (int c = 0; c < 3; ++c) {
      const double lin = cover[p] * pen_bgr[c] + (1 - cover[p]) * board;
      with_pen[3 * p + c] =
          static_cast<std::uint8_t>(std::lround(255 * LinearToSrgb(lin)));
    }
  }
  auto r = Renderer::TryCreate(ctx.get(), s.k, {}, nullptr);
  ASSERT_NE(r, nullptr);
  s.inputs.pen_visible = false;
  s.inputs.video.bgr = s.video.data();
  const cv::Mat water = RenderScene(r.get(), s.inputs);
  s.inputs.pen_visible = true;
  s.inputs.video.bgr = with_pen.data();
  const cv::Mat out = RenderScene(r.get(), s.inputs);
  ASSERT_FALSE(water.empty() || out.empty());
  double err = 0, err_video = 0;
  int count = 0, edge = 0;
  for (int y = 0; y < kH6; ++y) {
    for (int x = 0; x < kW6; ++x) {
      const int p = y * kW6 + x;
      if (!scored[p]) continue;
      const cv::Vec3b w = water.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double truth =
            255 * LinearToSrgb(cover[p] * pen_bgr[c] +
                               (1 - cover[p]) * SrgbToLinear(w[c] / 255.0));
        err += std::abs(out.at<cv::Vec3b>(y, x)[c] - truth);
        err_video += std::abs(with_pen[3 * p + c] - truth);
      }
      ++count;
      edge += cover[p] > 0 && cover[p] < 1;
    }
  }
  ASSERT_GT(count, 150) << "the outline must cross the water";
  ASSERT_GT(edge, 30);
  err /= 3 * count;
  err_video /= 3 * count;
  std::printf(
      "pen outline, %d px (%d partly covered): mean |out - truth| %.2f "
      "levels (the video there: %.2f)\n",
      count, edge, err, err_video);
  EXPECT_LT(err, 3.0);

  // The tracked pose 0.5 mm off across the shaft, towards the camera's
  // right: the video's pen still shows where it covers its pixels whole
  // (on the scored band), and the water where the pen is not.
  const glm::dvec3 across =
      glm::normalize(glm::cross(axis, glm::normalize(tip - eye)));
  s.inputs.tank_from_pen =
      glm::translate(glm::dmat4(1.0), 0.0005 * across) * pen;
  const cv::Mat off = RenderScene(r.get(), s.inputs);
  int whole = 0, whole_kept = 0, bare = 0, bare_water = 0;
  for (int y = 0; y < kH6; ++y) {
    for (int x = 0; x < kW6; ++x) {
      const int p = y * kW6 + x;
      if (!scored[p] || (cover[p] > 0 && cover[p] < 1)) continue;
      const cv::Vec3b o = off.at<cv::Vec3b>(y, x);
      const cv::Vec3b ref =
          cover[p] == 1 ? cv::Vec3b(with_pen[3 * p], with_pen[3 * p + 1],
                                    with_pen[3 * p + 2])
                        : water.at<cv::Vec3b>(y, x);
      const bool same =
          std::max({std::abs(o[0] - ref[0]), std::abs(o[1] - ref[1]),
                    std::abs(o[2] - ref[2])}) <= 4;
      (cover[p] == 1 ? whole : bare) += 1;
      (cover[p] == 1 ? whole_kept : bare_water) += same;
    }
  }
  std::printf(
      "pose 0.5 mm off: pen pixels kept %d of %d, board pixels left to the "
      "water %d of %d\n",
      whole_kept, whole, bare_water, bare);
  ASSERT_GT(whole, 50);
  ASSERT_GT(bare, 50);
  EXPECT_GE(whole_kept, whole * 95 / 100);
  EXPECT_GE(bare_water, bare * 95 / 100);
}

}  // namespace
}  // namespace ripple::render
