// The real-time renderer's floor-return map (render/optics.h) against the
// reference renderer's own geometry: from a floor point, cosine-weighted
// directions are followed through the reference's scene model (its glass
// walls 3 mm thick standing on the board, 40 mm tall), each interface split
// by Fresnel, and sorted by where they end: the sky, the floor (the water's
// return), the board beyond the walls or under the glass. Two independent
// tracers of the same box must agree on where a floor point's view goes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "render/optics.h"
#include "render/reference/reference.h"
#include "render/reference/scene_model.h"

namespace ripple {
namespace {

using reference::internal::Event;
using reference::internal::Medium;
using reference::internal::SceneModel;

// Where a floor point's cosine-weighted view ends, as the map counts it: the
// share of directions (weighted by the interfaces' transmittances and, for
// light from outside the water, n^2 over the index where it ends).
struct View {
  double sky = 0, floor = 0, board = 0;
};

void Follow(const SceneModel& model, const glm::dvec3& o, const glm::dvec3& d,
            Medium m, double weight, int depth, View* view) {
  if (weight < 1e-6 || depth > 24) return;
  const Event e = model.Next(o, d, m);
  const double n_here = model.Ior(m);
  const double n_water = model.Ior(Medium::kWater);
  const double scale = (n_water / n_here) * (n_water / n_here);
  if (e.kind == Event::Kind::kEscape) {
    if (m == Medium::kAir && d.z > 0) view->sky += weight * scale;
    return;
  }
  if (e.kind == Event::Kind::kDiffuse) {
    if (e.solid != -1) return;
    if (m == Medium::kWater) {
      view->floor += weight;
    } else if (m == Medium::kAir) {
      view->board += weight * scale;
    } else {
      // The board under the glass: its light in the glass is n_g^2 times
      // the surroundings' (a uniform world), which the map counts as the
      // board's at n^2.
      view->board += weight * n_water * n_water;
    }
    return;
  }
  const double n1 = n_here, n2 = model.Ior(e.next);
  const double r = render::FresnelReflectance(-glm::dot(d, e.n), n1, n2);
  Follow(model, e.p, glm::reflect(d, e.n), m, weight * r, depth + 1, view);
  if (r < 1.0) {
    Follow(model, e.p, glm::refract(d, e.n, n1 / n2), e.next,
           weight * (1.0 - r), depth + 1, view);
  }
}

View ReferenceView(const SceneModel& model, double x, double y, int rays) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  View v;
  for (int k = 0; k < rays; ++k) {
    const double u = u01(rng), phi = 2.0 * M_PI * u01(rng);
    const double r = std::sqrt(u);
    Follow(model, glm::dvec3(x, y, 1e-9),
           glm::dvec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u)),
           Medium::kWater, 1.0, 0, &v);
  }
  v.sky /= rays;
  v.floor /= rays;
  v.board /= rays;
  return v;
}

TEST(FloorReturnReferenceTest, TheMapSeesWhatTheReferenceGeometrySees) {
  reference::ReferenceScene scene;
  scene.absorption_per_m = {0, 0, 0};
  // A camera the scene checks want; the view traced here does not use it.
  scene.camera.width = 64;
  scene.camera.height = 48;
  scene.camera.fx = scene.camera.fy = 60;
  scene.camera.cx = 31.5;
  scene.camera.cy = 23.5;
  glm::dmat4 cam_from_tank(1.0);
  cam_from_tank[1][1] = -1;
  cam_from_tank[2][2] = -1;
  cam_from_tank[3] = glm::dvec4(0.0, 0.0, 0.4, 1.0);
  scene.scene.cam_from_tank = cam_from_tank;
  std::string error;
  ASSERT_TRUE(reference::IsValidScene(scene, &error)) << error;
  SceneModel model;
  model.Init(scene, /*dry=*/false, 0.001);

  render::WaterOptics optics;
  optics.absorption_per_m = glm::vec3(0.0f);
  optics.ambient_share = 1.0f;
  optics.ior = static_cast<float>(scene.water_ior);
  optics.glass_ior = static_cast<float>(scene.glass_ior);
  optics.glass_thickness_m = static_cast<float>(scene.glass_thickness_m);
  const render::TankGeometry& tank = scene.scene.tank;
  // 10 mm texels: centres at the tank's centre and 5 mm from the walls.
  const int nx = 17, ny = 11;
  ASSERT_NEAR(tank.size_x, 0.17, 1e-6);
  ASSERT_NEAR(tank.size_y, 0.11, 1e-6);
  const render::FloorReturnMap map = render::ComputeFloorReturn(
      optics, tank.size_x, tank.size_y, tank.water_level, tank.wall_height, nx,
      ny, 8192, 1.0);
  const double floor_sky =
      render::SkyTransmittance(optics.ior, 0.0, tank.water_level);
  struct Point {
    int i, j;
  };
  for (const Point p :
       {Point{8, 5}, Point{8, 10}, Point{16, 5}, Point{12, 7}}) {
    const double x = -0.5 * tank.size_x + (p.i + 0.5) * tank.size_x / nx;
    const double y = -0.5 * tank.size_y + (p.j + 0.5) * tank.size_y / ny;
    const View ref = ReferenceView(model, x, y, 60000);
    const size_t at = static_cast<size_t>(p.j) * nx + p.i;
    double board = 0;
    for (int w = 0; w < 4; ++w) board += map.board[w][at].g;
    const double sky = floor_sky + map.sky[at].g;
    SCOPED_TRACE(testing::Message()
                 << "floor point (" << x << ", " << y << "): return "
                 << map.returned[at].g << " / " << ref.floor << ", sky " << sky
                 << " / " << ref.sky << ", board " << board << " / "
                 << ref.board << " (map / reference)");
    EXPECT_NEAR(map.returned[at].g, ref.floor, 0.012);
    EXPECT_NEAR(sky, ref.sky, 0.02);
    EXPECT_NEAR(board, ref.board, 0.02);
    // Together they are the floor's whole view (n^2 for a uniform world).
    EXPECT_NEAR(sky + board + map.returned[at].g * optics.ior * optics.ior,
                ref.sky + ref.board + ref.floor * optics.ior * optics.ior,
                0.03);
  }
}

}  // namespace
}  // namespace ripple
