#include "app/app_render_scenes.h"

#include <cmath>

#include "app/app_obstacles.h"
#include "app/app_water.h"
#include "geometry/check.h"
#include "sim/water_factory.h"
#include "tracking/pose.h"
#include "tracking/synth/synth.h"

namespace ripple::app {
namespace {

using Eigen::Vector3d;

// cam_from_tank of a camera at `eye` looking at `target` (tank frame), the
// image's x axis horizontal.
glm::dmat4 LookAt(const Vector3d& eye, const Vector3d& target) {
  return ToGlm(tracking::LookAt(eye, target, Vector3d::UnitZ()).Inverse());
}

// tank_from_pen with the tip at `tip_in_tank` and the shaft pointing from
// the tip towards `up` (the pen's +z runs from the tip to the cube).
glm::dmat4 PenAt(const tracking::PenSpec& pen, const Vector3d& tip_in_tank,
                 const Vector3d& up) {
  const Vector3d z = up.normalized();
  const Vector3d x = Vector3d::UnitY().cross(z).normalized();
  const Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r << x, y, z;
  const Vector3d origin = tip_in_tank - r * pen.tip_in_pen;
  return ToGlm(tracking::Pose::FromMatrix(r, origin));
}

// A ring wave of `amplitude` and `wavelength` under a Gaussian envelope of
// radius `sigma`, centred at (x0, y0), on a grid of `cell` metres.
std::shared_ptr<std::vector<float>> Ring(const render::TankGeometry& tank,
                                         double cell, double amplitude,
                                         double wavelength, double sigma,
                                         double x0, double y0,
                                         render::HeightFieldView* view) {
  const int nx = static_cast<int>(std::lround(tank.size_x / cell));
  const int ny = static_cast<int>(std::lround(tank.size_y / cell));
  const double d = tank.size_x / nx;
  auto h = std::make_shared<std::vector<float>>(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 - 0.5 * nx) * d - x0;
      const double y = (j + 0.5 - 0.5 * ny) * d - y0;
      const double r = std::hypot(x, y);
      (*h)[static_cast<size_t>(j) * nx + i] =
          static_cast<float>(amplitude * std::cos(2 * M_PI * r / wavelength) *
                             std::exp(-r * r / (2 * sigma * sigma)));
    }
  }
  *view = {h->data(), nx, ny, static_cast<float>(d), 1};
  return h;
}

struct DemoSnapshot {
  std::shared_ptr<std::vector<float>> heights;
  render::HeightFieldView view;
  std::optional<tracking::Pose> tank_from_pen;
};

// The demo's script (tracking/synth/sequence.cc, preset "demo") driving the
// default water model with the rig's obstacles; the surface and pen at
// `at_frames`.
bool RunDemoWater(const tracking::Camera& camera, const tracking::Rig& rig,
                  const std::vector<int>& at_frames,
                  std::vector<DemoSnapshot>* out, std::string* error) {
  synth::SequenceOptions seq;
  seq.preset = "demo";
  seq.frames = 240;
  std::vector<synth::FrameSpec> frames;
  if (!synth::MakeSequence(camera, rig, seq, &frames, error)) return false;
  sim::WaterModelOptions options;
  sim::GridSpec grid;
  if (!WaterForRig(rig, DefaultWaterCells(options.waves), false, &options,
                   &grid, error))
    return false;
  auto water = sim::CreateWater(grid, options, error);
  if (!water) return false;
  std::vector<sim::Obstacle> obstacles;
  if (!SimObstaclesFromRig(rig, &obstacles, error)) return false;
  for (const sim::Obstacle& o : obstacles)
    if (water->AddObstacle(o, error) < 0) return false;
  for (const synth::FrameSpec& f : frames) {
    if (f.scene.tank_from_pen) {
      const Vector3d tip = *f.scene.tank_from_pen * rig.pen->tip_in_pen;
      water->SetPenTip({tip.x(), tip.y(), tip.z()});
    } else {
      water->ClearPen();
    }
    water->Advance(1.0 / seq.fps);
    for (int at : at_frames) {
      if (f.index != at) continue;
      const sim::HeightFieldView v = water->View();
      DemoSnapshot s;
      s.heights = std::make_shared<std::vector<float>>(
          v.heights, v.heights + static_cast<size_t>(v.nx) * v.ny);
      s.view = {s.heights->data(), v.nx, v.ny, static_cast<float>(v.cell_m), 1};
      s.tank_from_pen = f.scene.tank_from_pen;
      out->push_back(s);
    }
  }
  if (out->size() != at_frames.size()) {
    *error = "the demo script is shorter than its snapshots";
    return false;
  }
  return true;
}

}  // namespace

const std::vector<std::string>& RenderSceneNames() {
  static const std::vector<std::string> names = {
      "flat", "ring", "demo_a",  "demo_b", "demo_c", "tiles",
      "pen",  "hand", "grazing", "lens",   "room"};
  return names;
}

bool MakeRenderScenes(const RenderScenesOptions& options,
                      const tracking::Camera& camera, const tracking::Rig& rig,
                      std::vector<RenderBenchScene>* scenes,
                      std::string* error) {
  if (!rig.pen || !(rig.tank.size_x_m > 0)) {
    *error = "the render benchmark needs a rig with a tank and a pen";
    return false;
  }
  tracking::Camera cam = camera.Scaled(options.width, options.height);
  cam.dist = {};
  cam.transfer = geometry::Transfer::kSrgb;  // a webcam's frames

  render::SceneInputs base;
  base.tank.size_x = static_cast<float>(rig.tank.size_x_m);
  base.tank.size_y = static_cast<float>(rig.tank.size_y_m);
  base.tank.wall_height = static_cast<float>(rig.tank.wall_height_m);
  base.tank.water_level = static_cast<float>(rig.tank.water_level_m);
  base.pen.cube_edge = static_cast<float>(rig.pen->cube_edge_m);
  base.pen.shaft_radius = static_cast<float>(rig.pen->shaft_radius_m);
  base.pen.shaft_length = static_cast<float>(rig.pen->shaft_length_m);
  base.light_in_tank = {0.35, 0.25, 1.0};
  const double level = rig.tank.water_level_m;
  const glm::dmat4 front = LookAt({0.0, -0.30, 0.36}, {0.0, 0.005, 0.0});
  const glm::dmat4 grazing = LookAt({0.0, -0.40, 0.10}, {0.0, 0.0, 0.015});
  base.cam_from_tank = front;

  std::vector<render::Obstacle> obstacles;
  for (const auto& o : RenderObstaclesFromRig(rig))
    if (o) obstacles.push_back(*o);

  // Board albedo images: plain paper and the printed tiles.
  Eigen::AlignedBox2d rect = synth::BoardSheetRect(rig);
  rect.min() -= Eigen::Vector2d(0.05, 0.05);
  rect.max() += Eigen::Vector2d(0.05, 0.05);
  synth::FloorOptions tiles_options;  // tiles by default
  const auto tiles =
      synth::FloorPattern::Create(tiles_options, rig.tank, error);
  if (!tiles) return false;
  const cv::Mat board_plain = synth::RenderBoardAlbedo(
      rig, synth::FloorPattern(), rect, options.board_px_per_m);
  const cv::Mat board_tiles =
      synth::RenderBoardAlbedo(rig, *tiles, rect, options.board_px_per_m);

  auto make = [&](const std::string& name, const std::string& description,
                  bool tiled) {
    RenderBenchScene s;
    s.name = name;
    s.description = description;
    s.scene.scene = base;
    s.scene.camera = cam;
    s.scene.floor_albedo = tiled ? board_tiles : board_plain;
    if (tiled) s.floor = *tiles;
    s.scene.floor_rect_m = cv::Rect2d(rect.min().x(), rect.min().y(),
                                      rect.sizes().x(), rect.sizes().y());
    s.scene.table_albedo = synth::kTableBgr;
    return s;
  };
  const double cell = 0.17 / 270;  // the default capillary grid's cell
  const double ring_x = 0.02, ring_y = 0.0;

  scenes->clear();
  scenes->push_back(make("flat", "flat water, plain floor", false));
  {
    RenderBenchScene s =
        make("ring", "ring wave 0.4 mm / 8 mm, plain floor", false);
    s.heights = Ring(s.scene.scene.tank, cell, 0.0004, 0.008, 0.02, ring_x,
                     ring_y, &s.scene.scene.water);
    scenes->push_back(s);
  }
  std::vector<DemoSnapshot> demo;
  if (!RunDemoWater(camera, rig, {60, 120, 158}, &demo, error)) return false;
  const char* demo_names[] = {"demo_a", "demo_b", "demo_c"};
  // The demo's water and pen at a snapshot, and the rig's obstacles.
  auto with_demo = [&](const DemoSnapshot& d, RenderBenchScene* s) {
    s->heights = d.heights;
    s->scene.scene.water = d.view;
    s->scene.scene.obstacles = obstacles;
    if (d.tank_from_pen) {
      s->scene.scene.pen_visible = true;
      s->scene.scene.tank_from_pen = ToGlm(*d.tank_from_pen);
    }
  };
  for (size_t i = 0; i < demo.size(); ++i) {
    RenderBenchScene s = make(demo_names[i],
                              "the demo's water and pen, frame " +
                                  std::to_string(i == 0   ? 60
                                                 : i == 1 ? 120
                                                          : 158) +
                                  ", tiles, obstacles",
                              true);
    with_demo(demo[i], &s);
    scenes->push_back(s);
  }
  {
    RenderBenchScene s = make("tiles", "ring wave over the tiled floor", true);
    s.heights = Ring(s.scene.scene.tank, cell, 0.0004, 0.008, 0.02, ring_x,
                     ring_y, &s.scene.scene.water);
    scenes->push_back(s);
  }
  {
    RenderBenchScene s =
        make("pen", "pen dipped 10 mm, its shadow, a pillar, tiles", true);
    s.scene.scene.pen_visible = true;
    s.scene.scene.tank_from_pen =
        PenAt(*rig.pen, {0.015, -0.005, level - 0.010}, {0.15, -0.30, 1.0});
    s.scene.scene.obstacles = obstacles;
    scenes->push_back(s);
  }
  {
    // A hand (a flat mitten outline, skin-coloured) held 60 mm over the
    // tank's left half, facing the camera, over the demo's water and pen.
    RenderBenchScene s = make(
        "hand", "a hand over the tank, the demo's water, pen and pillar", true);
    with_demo(demo[1], &s);
    const glm::dvec3 eye(glm::inverse(front)[3]);
    const glm::dvec3 centre(-0.045, 0.005, 0.06);
    const glm::dvec3 view = glm::normalize(centre - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(view, {0.0, 0.0, 1.0}));
    const glm::dvec3 up = glm::cross(right, view);
    // Palm 70 x 60 mm with four fingers (and a thumb) pointing up-right.
    const double outline[][2] = {
        {-0.035, -0.045}, {0.030, -0.045}, {0.036, 0.000},  {0.040, 0.050},
        {0.030, 0.052},   {0.024, 0.012},  {0.020, 0.062},  {0.010, 0.064},
        {0.006, 0.016},   {0.000, 0.066},  {-0.010, 0.064}, {-0.008, 0.014},
        {-0.018, 0.058},  {-0.028, 0.056}, {-0.026, 0.004}, {-0.052, 0.018},
        {-0.058, 0.008},  {-0.036, -0.020}};
    reference::ReferenceScene::Occluder hand;
    for (const auto& p : outline)
      hand.polygon_in_tank.push_back(centre + p[0] * right + p[1] * up);
    hand.radiance_bgr = {0.38f, 0.47f, 0.68f};
    s.scene.occluders.push_back(hand);
    scenes->push_back(s);
  }
  {
    RenderBenchScene s = make("grazing", "ring wave seen at 14 degrees", true);
    s.scene.scene.cam_from_tank = grazing;
    s.heights = Ring(s.scene.scene.tank, cell, 0.0004, 0.008, 0.02, ring_x,
                     ring_y, &s.scene.scene.water);
    scenes->push_back(s);
  }
  {
    RenderBenchScene s =
        make("lens", "ring wave through a distorting lens (k1 -0.28)", true);
    s.scene.camera.dist = {-0.28, 0.09, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    s.heights = Ring(s.scene.scene.tank, cell, 0.0004, 0.008, 0.02, ring_x,
                     ring_y, &s.scene.scene.water);
    scenes->push_back(s);
  }
  {
    // The demo's water, pen and pillar in a room whose walls (striped,
    // a colour each) the camera sees beyond the board's far edge and the
    // water and the glass reflect: the surroundings the reflection maps
    // fold from the video are really there.
    RenderBenchScene s = make(
        "room", "the demo's water, pen and pillar in a striped room", true);
    with_demo(demo[1], &s);
    s.scene.room.on = true;
    s.scene.room.half_x = 0.30;
    s.scene.room.half_y = 0.34;
    s.scene.room.height = 0.5;
    scenes->push_back(s);
  }
  RIPPLE_CHECK(scenes->size() == RenderSceneNames().size(),
               "RenderSceneNames() lists every scene");
  for (size_t i = 0; i < scenes->size(); ++i) {
    RIPPLE_CHECK((*scenes)[i].name == RenderSceneNames()[i],
                 "RenderSceneNames() in build order");
  }
  return true;
}

void WaterMasks(const reference::ReferenceScene& scene, cv::Mat* water,
                cv::Mat* open_water) {
  const geometry::CameraModel& cam = scene.camera;
  const render::TankGeometry& t = scene.scene.tank;
  const glm::dmat4 tank_from_cam = glm::inverse(scene.scene.cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  water->create(cam.height, cam.width, CV_8U);
  open_water->create(cam.height, cam.width, CV_8U);
  water->setTo(0);
  open_water->setTo(0);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const glm::dvec3 d(tank_from_cam * glm::dvec4((u - cam.cx) / cam.fx,
                                                    (v - cam.cy) / cam.fy, 1.0,
                                                    0.0));
      if (d.z >= -1e-9) continue;
      const double s = (t.water_level - eye.z) / d.z;
      const glm::dvec3 p = eye + s * d;
      if (!(s > 0 && std::abs(p.x) < 0.5 * t.size_x &&
            std::abs(p.y) < 0.5 * t.size_y))
        continue;
      water->at<std::uint8_t>(v, u) = 255;
      // Where the ray from the eye crosses a wall's plane (x = +-X/2 or
      // y = +-Y/2) below the wall's top, it passed through the glass.
      bool through_glass = false;
      for (int axis = 0; axis < 2 && !through_glass; ++axis) {
        const double half = 0.5 * (axis == 0 ? t.size_x : t.size_y);
        const double e = axis == 0 ? eye.x : eye.y;
        const double dd = axis == 0 ? d.x : d.y;
        for (const double wall : {-half, half}) {
          if (std::abs(dd) < 1e-12) continue;
          const double sw = (wall - e) / dd;
          if (sw <= 0 || sw >= s) continue;
          const glm::dvec3 q = eye + sw * d;
          const double across = axis == 0 ? q.y : q.x;
          const double half_across = 0.5 * (axis == 0 ? t.size_y : t.size_x);
          if (q.z < t.wall_height && std::abs(across) <= half_across)
            through_glass = true;
        }
      }
      if (!through_glass) open_water->at<std::uint8_t>(v, u) = 255;
    }
  }
}

}  // namespace ripple::app
