// `ripple bench render`: the canonical scenes (app/app_render_scenes.h)
// through the real-time renderer and the physically based reference
// (render/reference), compared by LDR-FLIP (bench/flip.h) inside the water,
// with each effect turned off in turn (what each effect buys), and the
// real-time passes' times. Prints the table, writes bench_render.csv and one
// PNG per scene (reference | real-time | FLIP map); --export writes every
// scene's inputs in renderer-neutral files (docs/render.md, "Render
// benchmark").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "app/app_bench.h"
#include "app/app_common.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_render_scenes.h"
#include "app/app_wxh.h"
#include "bench/flip.h"
#include "bench/flip_budget.h"
#include "bench/stats.h"
#include "render/context.h"
#include "render/renderer.h"
#include "tracking/clean_plate.h"

namespace ripple::app {
namespace {

struct RenderBenchArgs {
  std::string out = "bench_render";
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string size = "640x480";
  std::string gl = "egl";
  std::vector<std::string> scenes;  // empty: all
  std::string export_dir;
  std::string water_look = "clear";
  std::string shadows = "pcf";  // the real-time renderer's shadow filter
  std::string refraction_filter = "cubic";  // and its refraction lookup
  // The real-time renderer's reflection map: fold, cubemap, or both (the
  // table with the fold, and the cube map against the same reference).
  std::string reflection = "fold";
  int samples_per_pixel = 64;
  int light_paths_per_texel = 64;
  int sky_rays = 4;
  // The reference's diffuse round trips (ReferenceOptions::
  // max_diffuse_bounces): 8 converges; fewer split its light by order.
  int diffuse_bounces = 8;
  int timing_frames = 15;
  // The sky's share of the board's light, for both renderers (the light's
  // disc has the rest): 1 lights by the sky alone, 0 by the disc alone.
  double ambient = 0.3;
  // --water-columns auto | full | N (RendererOptions::water_shading_columns)
  std::string water_columns = "auto";
  // --tank-shadow auto | on | off: the real-time renderer's, as the pipeline
  // resolves it (auto: by the frame's width).
  std::string tank_shadow = "auto";
};

// The effects whose contribution is measured, as `Effects` members.
struct EffectSwitch {
  const char* name;
  bool render::Effects::*flag;
};
constexpr EffectSwitch kEffects[] = {
    {"reflection", &render::Effects::reflection},
    {"refraction", &render::Effects::refraction},
    {"shadows", &render::Effects::shadows},
    {"caustics", &render::Effects::caustics},
    {"walls", &render::Effects::walls},
    {"tank_shadow", &render::Effects::tank_shadow},
};
constexpr int kNumEffects = sizeof(kEffects) / sizeof(kEffects[0]);

// The display's encoding of the reference's linear radiance: the same
// highlight shoulder as the real-time output, then sRGB.
cv::Mat EncodeLikeTheDisplay(const cv::Mat& linear, double knee) {
  cv::Mat out(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y) {
    for (int x = 0; x < linear.cols; ++x) {
      const cv::Vec3f& l = linear.at<cv::Vec3f>(y, x);
      cv::Vec3b& o = out.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        const double s = render::LinearToSrgb(
            render::HighlightShoulder(std::max(0.0f, l[c]), knee));
        o[c] = cv::saturate_cast<std::uint8_t>(std::lround(255.0 * s));
      }
    }
  }
  return out;
}

// The pixels where two renders differ by more than `levels` in any channel
// (the sum of the channels' differences), grown by a disc `grow` pixels
// across (0: not grown).
cv::Mat ChangedPixels(const cv::Mat& a, const cv::Mat& b, int levels,
                      int grow) {
  cv::Mat diff, changed;
  cv::absdiff(a, b, diff);
  cv::transform(diff, changed, cv::Matx13f(1, 1, 1));
  changed = changed > levels;
  if (grow > 0) {
    cv::dilate(changed, changed,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, {grow, grow}));
  }
  return changed;
}

struct SceneResult {
  double flip = 0;
  double flip_open = 0;  // over the open water (no glass on the way)
  double flip_off[kNumEffects] = {};
  double main_ms = 0, caustics_ms = 0, shadow_ms = 0;
  double reference_s = 0;
  // FLIP of the reference against itself rendered with other random
  // numbers: the part of `flip` that is the reference's own noise.
  double noise_floor = 0;
  int water_pixels = 0;
  // FLIP in windows: around the pen (its silhouette grown by 12 px, inside
  // the water) and over the hands (their pixels over the tank); -1: none.
  double flip_pen = -1, flip_hand = -1;
  // The same windows without the real objects (Effects::real_objects off,
  // no occluder mask: the water over everything, the floor read from the
  // video wherever it is, the submerged shaft not drawn).
  double flip_pen_plain = -1, flip_hand_plain = -1;
  // FLIP around the virtual shadows: the pixels that shadows on or off
  // changes by more than 3 levels, grown by 6 px, inside the water; -1:
  // none. Compares the shadow filters (--shadows) at their edges.
  double flip_shadow = -1;
  // FLIP where the reflection matters: the pixels that reflection on or off
  // changes by more than 3 levels, inside the water; -1: none. Compares the
  // reflection maps (--reflection).
  double flip_reflection = -1;
  // FLIP on the board around the tank, outside the water: the pixels that
  // the tank's shadow on or off changes by more than a level, grown by 4
  // px; with it and without it. -1: none.
  double flip_board = -1, flip_board_off = -1;
  double envmap_ms = 0;  // the cube map's rebuild (0 for the fold)
  // What `flip` is made of (bench/flip_budget.h): the uniform gain on the
  // water's light that brings the real-time image closest to the
  // reference, and FLIP at it; and FLIP of the reference read at 1/n of its
  // resolution (what refracting the camera's own frame cannot avoid).
  double best_gain = 1, flip_at_best_gain = 0, flip_resolution_loss = 0;
};

// The real objects as the pipeline sees them: a clean plate that knows the
// printed board (the rig's tags and the scene's floor), learned from the dry
// frames without the hands (`clean`: the pen excluded), then the occluder
// mask of the frame with them (`video`). Fills the plate and mask views of
// `in` (their storage in `plate`).
void RealObjects(const tracking::Rig& rig, const RenderBenchScene& s,
                 const cv::Mat& clean, const cv::Mat& video,
                 cv::Mat* pen_silhouette, cv::Mat* real_mask,
                 std::unique_ptr<tracking::CleanPlate>* plate,
                 render::SceneInputs* in) {
  const reference::ReferenceScene& rs = s.scene;
  const render::TankGeometry& t = rs.scene.tank;
  const double top = std::max(t.wall_height, t.water_level + 0.01f);
  // Its search widened as the pipeline widens it with the tank's shadow:
  // hands over the board around the tank too (always: the run with the
  // effect toggled uses the same mask).
  tracking::CleanPlateOptions po;
  po.surround_m = render::TankShadowReach(t, render::WaterOptics());
  po.margin_m = std::max(po.margin_m, po.surround_m);
  *plate = std::make_unique<tracking::CleanPlate>(rs.camera, t.size_x, t.size_y,
                                                  top, po);
  cv::Mat levels, valid;
  const cv::Point2d o = (*plate)->plate_origin_m();
  synth::BoardDesignLevels(
      rig, s.floor, {o.x, o.y}, (*plate)->texel_m(), (*plate)->plate_size(),
      rs.camera.transfer == geometry::Transfer::kSrgb, &levels, &valid);
  (*plate)->SetBoardPrior(levels, valid);
  auto pose = [](const glm::dmat4& m) {
    const Eigen::Matrix4d e = Eigen::Map<const Eigen::Matrix4d>(&m[0][0]);
    return tracking::Pose::FromMatrix(
        Eigen::Matrix3d(e.topLeftCorner<3, 3>()),
        Eigen::Vector3d(e.topRightCorner<3, 1>()));
  };
  const tracking::Pose cam_from_tank = pose(rs.scene.cam_from_tank);
  pen_silhouette->release();
  cv::Mat shaft;
  if (rs.scene.pen_visible) {
    const render::PenGeometry& g = rs.scene.pen;
    const glm::dmat4 m = rs.scene.cam_from_tank * rs.scene.tank_from_pen;
    tracking::DrawPenPlateMasks(
        rs.camera, pose(m), g.cube_edge, g.shaft_radius,
        Eigen::Vector3d(0, 0, -0.5 * g.cube_edge - g.shaft_length),
        rs.scene.pen_margin_m, pen_silhouette, &shaft);
  }
  for (int i = 0; i < 4; ++i)
    (*plate)->Process(clean, cam_from_tank, *pen_silhouette, shaft);
  (*plate)->Process(video, cam_from_tank, *pen_silhouette, shaft);
  CombineRealMask((*plate)->foreground(), (*plate)->foreground_window(),
                  *pen_silhouette, real_mask);
  SetRealObjectViews(**plate, *real_mask, in);
}

cv::Mat RenderRealTime(render::Renderer* r, const render::SceneInputs& in) {
  cv::Mat out(r->intrinsics().height, r->intrinsics().width, CV_8UC3);
  if (!r->Render(in) || !r->ReadBgr(out.data, static_cast<int>(out.step)))
    return {};
  return out;
}

bool WriteSceneFiles(const std::string& dir, const RenderBenchScene& s,
                     const render::RendererOptions& ro, const cv::Mat& video,
                     const cv::Mat& reference, const cv::Mat& realtime,
                     const cv::Mat& flip_map, const cv::Mat& water_mask,
                     const cv::Mat& open_water_mask, std::string* error) {
  if (!MakeDirectories(dir, error)) return false;
  const reference::ReferenceScene& r = s.scene;
  const render::SceneInputs& in = r.scene;
  tracking::Camera cam = r.camera;
  if (!tracking::SaveCamera(cam, dir + "/camera.yml", error)) return false;
  const render::HeightFieldView& w = in.water;
  if (w.heights != nullptr &&
      !WriteNpy(dir + "/heights.npy", w.heights, w.ny, w.nx)) {
    *error = "cannot write '" + dir + "/heights.npy'";
    return false;
  }
  cv::Mat albedo8;
  r.floor_albedo.convertTo(albedo8, CV_16UC3, 65535.0);
  cv::Mat flip16;
  flip_map.convertTo(flip16, CV_16U, 65535.0);
  bool ok = cv::imwrite(dir + "/video.png", video) &&
            cv::imwrite(dir + "/flip.png", flip16) &&
            cv::imwrite(dir + "/water_mask.png", water_mask) &&
            cv::imwrite(dir + "/open_water_mask.png", open_water_mask) &&
            cv::imwrite(dir + "/floor_albedo.png", albedo8) &&
            cv::imwrite(dir + "/reference.png", reference) &&
            cv::imwrite(dir + "/realtime.png", realtime);
  std::ofstream y(dir + "/scene.yml");
  auto mat = [&](const char* key, const glm::dmat4& m) {
    y << key << ": [";
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col)
        y << m[col][row] << (row == 3 && col == 3 ? "]\n" : ", ");
  };
  y << "# Ripple render-benchmark scene: " << s.description << "\n"
    << "# Frames: tank (origin at the tank centre, z up, floor z = 0) and\n"
    << "# OpenCV's camera frame; metres, 4x4 matrices row-major.\n"
    << "name: " << s.name << "\n";
  mat("cam_from_tank", in.cam_from_tank);
  y << "tank: {size_x: " << in.tank.size_x << ", size_y: " << in.tank.size_y
    << ", wall_height: " << in.tank.wall_height
    << ", water_level: " << in.tank.water_level
    << ", glass_thickness: " << r.glass_thickness_m << "}\n"
    << "heights: "
    << (w.heights ? "{file: heights.npy, nx: " + std::to_string(w.nx) +
                        ", ny: " + std::to_string(w.ny) +
                        ", cell_size: " + std::to_string(w.cell_size) + "}"
                  : std::string("flat"))
    << "  # metres above the rest level, cell (i, j) centred at\n"
    << "  # ((i + 0.5 - nx/2) d, (j + 0.5 - ny/2) d)\n"
    << "light: {towards: [" << in.light_in_tank.x << ", " << in.light_in_tank.y
    << ", " << in.light_in_tank.z
    << "], angular_radius_rad: " << r.light_angular_radius_rad
    << ", ambient_share: " << r.ambient_share << "}\n"
    << "optics: {water_ior: " << r.water_ior << ", glass_ior: " << r.glass_ior
    << ", absorption_per_m_bgr: [" << r.absorption_per_m[0] << ", "
    << r.absorption_per_m[1] << ", " << r.absorption_per_m[2] << "]}\n"
    << "floor: {file: floor_albedo.png, linear_bgr_16bit: true, rect: ["
    << r.floor_rect_m.x << ", " << r.floor_rect_m.y << ", "
    << r.floor_rect_m.width << ", " << r.floor_rect_m.height
    << "], row0: min_y, table_albedo_bgr: [" << r.table_albedo[0] << ", "
    << r.table_albedo[1] << ", " << r.table_albedo[2] << "]}\n"
    << "video: {file: video.png, transfer: srgb, note: the dry scene through "
       "the lens}\n"
    << "pen: {visible: " << (in.pen_visible ? "true" : "false")
    << ", cube_edge: " << in.pen.cube_edge
    << ", shaft_radius: " << in.pen.shaft_radius
    << ", shaft_length: " << in.pen.shaft_length << "}\n";
  mat("tank_from_pen", in.tank_from_pen);
  y << "obstacles:\n";
  for (const render::Obstacle& o : in.obstacles) {
    y << "  - {shape: "
      << (o.shape == render::Obstacle::Shape::kBox ? "box" : "cylinder")
      << ", size: [" << o.size.x << ", " << o.size.y << ", " << o.size.z
      << "]}\n";
    y << "    ";
    mat("tank_from_obstacle", o.tank_from_obstacle);
  }
  y << "renders: {reference: reference.png, realtime: realtime.png, "
       "flip: flip.png (16-bit, FLIP x 65535)}\n"
    << "flip_regions: {water: water_mask.png, open_water: "
       "open_water_mask.png}  # 255: averaged\n"
    << "realtime_look: " << render::WaterLookName(ro.optics.look) << "\n";
  y.close();
  if (!ok || !y) {
    *error = "cannot write the scene files in '" + dir + "'";
    return false;
  }
  return true;
}

int RunBenchRender(const RenderBenchArgs& args) {
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  WxH size;
  ParseWxH(args.size, &size);  // checked by the option's validator
  const auto backend = render::ParseBackend(args.gl);
  if (!backend || *backend == render::Backend::kGlfw)
    return Fail(kExitBadInput, "--gl '" + args.gl + "': use egl or osmesa");
  for (const std::string& n : args.scenes) {
    const auto& known = RenderSceneNames();
    if (std::find(known.begin(), known.end(), n) == known.end())
      return Fail(kExitBadInput, "--scenes: unknown scene '" + n + "'");
  }
  render::WaterLook look;
  if (!render::ParseWaterLook(args.water_look, &look))
    return Fail(kExitBadInput,
                "--water-look '" + args.water_look + "': use clear or pool");
  render::ShadowFilter shadow_filter;
  if (!render::ParseShadowFilter(args.shadows, &shadow_filter))
    return Fail(kExitBadInput,
                "--shadows '" + args.shadows + "': use pcf, gauss or hard");
  render::RefractionFilter refraction_filter;
  if (!render::ParseRefractionFilter(args.refraction_filter,
                                     &refraction_filter))
    return Fail(kExitBadInput, "--refraction-filter '" +
                                   args.refraction_filter +
                                   "': use cubic or linear");
  bool tank_shadow_by_size = true, tank_shadow = false;
  if (!ParseTankShadow(args.tank_shadow, &tank_shadow_by_size, &tank_shadow))
    return Fail(kExitBadInput, "--tank-shadow '" + args.tank_shadow +
                                   "': use auto, on or off");
  if (tank_shadow_by_size)
    tank_shadow = render::TankShadowByDefault(size.width);
  // The effects as this run draws them; each is toggled against these.
  render::Effects defaults;
  defaults.tank_shadow = tank_shadow;
  render::ReflectionMap reflection_map = render::ReflectionMap::kFold;
  const bool both_maps = args.reflection == "both";
  if (!both_maps &&
      !render::ParseReflectionMap(args.reflection, &reflection_map))
    return Fail(kExitBadInput, "--reflection '" + args.reflection +
                                   "': use fold, cubemap or both");
  // --reflection both: per scene, the cube map against the same reference.
  struct MapRow {
    std::string scene;
    double flip[2], open[2], refl[2], main_ms[2], envmap_ms;
  };
  std::vector<MapRow> map_rows;
  std::string error;
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);

  RenderScenesOptions so;
  so.width = size.width;
  so.height = size.height;
  std::vector<RenderBenchScene> scenes;
  if (!MakeRenderScenes(so, *camera, *rig, &scenes, &error))
    return Fail(kExitBadInput, error);
  if (!args.scenes.empty()) {
    scenes.erase(std::remove_if(scenes.begin(), scenes.end(),
                                [&](const RenderBenchScene& s) {
                                  return std::find(args.scenes.begin(),
                                                   args.scenes.end(),
                                                   s.name) == args.scenes.end();
                                }),
                 scenes.end());
  }

  auto ctx =
      render::Context::TryCreate(*backend, size.width, size.height, &error);
  if (!ctx) return Fail(kExitRuntime, error);
  render::RendererOptions ro;
  ro.timing = render::RendererOptions::Timing::kCpuFinish;
  ro.optics = render::WaterOptics::ForLook(look);
  ro.optics.ambient_share = static_cast<float>(args.ambient);
  ro.shadow_filter = shadow_filter;
  ro.refraction_filter = refraction_filter;
  ro.reflection_map = reflection_map;
  if (!ParseWaterColumns(args.water_columns, &ro.water_shading_columns))
    return Fail(kExitBadInput, "--water-columns '" + args.water_columns + "'");
  const render::WaterOptics& optics = ro.optics;

  reference::ReferenceOptions refo;
  refo.samples_per_pixel = args.samples_per_pixel;
  refo.light_paths_per_texel = args.light_paths_per_texel;
  refo.ambient_samples = args.sky_rays;
  // The floor's light that the surface returns, by default to 8 round trips:
  // for a white floor the series' remainder is then below 0.1%
  // (docs/reference.md).
  refo.max_diffuse_bounces = args.diffuse_bounces;
  if (!refo.IsValid(&error)) return Fail(kExitBadInput, error);

  const std::string csv_path = args.out + "/bench_render.csv";
  std::ofstream csv(csv_path);
  if (!csv) return Fail(kExitBadInput, "cannot write '" + csv_path + "'");
  csv << "scene,water_pixels,flip,flip_open_water";
  for (const EffectSwitch& e : kEffects) {
    csv << (defaults.*(e.flag) ? ",flip_no_" : ",flip_with_") << e.name;
  }
  csv << ",reference_noise,flip_pen,flip_hand,flip_pen_without_plate,"
         "flip_hand_without_mask,flip_shadow,flip_reflection,flip_board,"
         "flip_board_without_tank_shadow,main_ms,"
         "caustics_ms,shadow_ms,envmap_ms,reference_s,best_gain,"
         "flip_at_best_gain,flip_resolution_loss\n";
  std::printf(
      "mean LDR-FLIP inside the water, real-time (reflection %s) against "
      "the reference (%dx%d, %d spp, %d light paths per texel)\n",
      args.reflection.c_str(), size.width, size.height, refo.samples_per_pixel,
      refo.light_paths_per_texel);
  std::printf("%-8s %7s %6s %6s |", "scene", "pixels", "FLIP", "open");
  for (const EffectSwitch& e : kEffects) std::printf(" %6.6s", e.name);
  std::printf(
      " | %6s | %6s %6s %6s %6s %6s %6s | %6s %6s | %6s %6s %6s %6s | %6s | "
      "%6s %6s %6s\n",
      "noise", "pen", "hand", "pen", "hand", "shadow", "refl", "board", "board",
      "main", "caust", "shadow", "envmap", "ref_s", "gain", "FLIP", "res.");
  std::printf("%-8s %7s %6s %6s |", "", "", "", "water");
  for (int i = 0; i < kNumEffects; ++i)
    std::printf(" %6s", defaults.*(kEffects[i].flag) ? "off" : "on");
  std::printf(
      " | %6s | %6s %6s %6s %6s %6s %6s | %6s %6s | %6s %6s %6s %6s | %6s | "
      "%6s %6s %6s\n",
      "floor", "FLIP", "FLIP", "plain", "plain", "FLIP", "FLIP", "FLIP", "off",
      "ms", "ms", "ms", "ms", "", "best", "gain", "loss");

  for (RenderBenchScene& s : scenes) {
    reference::ReferenceScene& rs = s.scene;
    // One set of physical parameters for both renderers; the reference's
    // water is pure water whatever the real-time look.
    const glm::vec3 pure = render::WaterOptics().absorption_per_m;
    rs.absorption_per_m = {pure.b, pure.g, pure.r};
    rs.ambient_share = optics.ambient_share;
    rs.light_angular_radius_rad = optics.light_angular_radius_rad;
    rs.water_ior = optics.ior;
    rs.glass_ior = optics.glass_ior;
    rs.glass_thickness_m = optics.glass_thickness_m;
    rs.obstacle_albedo = {ro.obstacle_albedo.b, ro.obstacle_albedo.g,
                          ro.obstacle_albedo.r};
    SceneResult res;
    // The camera's frame: the dry scene through the lens, sRGB.
    reference::ReferenceOptions dry = refo;
    dry.dry = true;
    dry.distort = true;
    cv::Mat dry_linear, wet_linear;
    reference::ReferenceSummary sum_dry, sum_wet;
    if (!reference::RenderReference(dry, rs, &dry_linear, &sum_dry, &error) ||
        !reference::RenderReference(refo, rs, &wet_linear, &sum_wet, &error))
      return Fail(kExitRuntime, "scene '" + s.name + "': " + error);
    res.reference_s = sum_dry.total_seconds + sum_wet.total_seconds;
    const cv::Mat video = reference::LinearToSrgb8(dry_linear);
    const cv::Mat reference =
        EncodeLikeTheDisplay(wet_linear, optics.highlight_knee);
    reference::ReferenceOptions reseeded = refo;
    reseeded.seed = refo.seed + 1000;
    cv::Mat wet_again;
    if (!reference::RenderReference(reseeded, rs, &wet_again, nullptr, &error))
      return Fail(kExitRuntime, "scene '" + s.name + "': " + error);
    const cv::Mat reference_again =
        EncodeLikeTheDisplay(wet_again, optics.highlight_knee);

    render::Intrinsics k = rs.camera;
    auto renderer = render::Renderer::TryCreate(ctx.get(), k, ro, &error);
    if (!renderer) return Fail(kExitRuntime, error);
    render::SceneInputs in = rs.scene;
    in.effects.tank_shadow = defaults.tank_shadow;
    in.video = {video.data, video.cols, video.rows,
                static_cast<int>(video.step)};
    // With a pen or hands: the clean plate and occluder mask, as the
    // pipeline makes them (learned from hand-free frames).
    std::unique_ptr<tracking::CleanPlate> plate;
    cv::Mat pen_silhouette, real_mask;
    if (rs.scene.pen_visible || !rs.occluders.empty()) {
      cv::Mat clean = video;
      if (!rs.occluders.empty()) {
        reference::ReferenceScene without = rs;
        without.occluders.clear();
        cv::Mat clean_linear;
        if (!reference::RenderReference(dry, without, &clean_linear, nullptr,
                                        &error))
          return Fail(kExitRuntime, "scene '" + s.name + "': " + error);
        clean = reference::LinearToSrgb8(clean_linear);
      }
      RealObjects(*rig, s, clean, video, &pen_silhouette, &real_mask, &plate,
                  &in);
    }
    const cv::Mat realtime = RenderRealTime(renderer.get(), in);
    if (realtime.empty())
      return Fail(kExitRuntime, "scene '" + s.name + "': render failed");
    cv::Mat mask, open_mask;
    WaterMasks(rs, &mask, &open_mask);
    res.water_pixels = cv::countNonZero(mask);
    cv::Mat flip_map;
    bench::FlipOptions fo;
    if (!bench::ComputeFlip(fo, reference, realtime, &flip_map, &error))
      return Fail(kExitRuntime, error);
    res.flip = bench::MeanFlip(flip_map, mask);
    res.flip_open = cv::countNonZero(open_mask) > 0
                        ? bench::MeanFlip(flip_map, open_mask)
                        : 0.0;
    bench::UniformGainFit gain_fit;
    if (!bench::FitUniformGain(fo, reference, realtime, mask, 0.1, 0.002,
                               &gain_fit, &error) ||
        !bench::ResolutionLossFlip(fo, reference, mask, optics.ior,
                                   &res.flip_resolution_loss, &error))
      return Fail(kExitRuntime, "scene '" + s.name + "': " + error);
    res.best_gain = gain_fit.gain;
    res.flip_at_best_gain = gain_fit.flip;
    cv::Mat noise_map;
    if (!bench::ComputeFlip(fo, reference, reference_again, &noise_map, &error))
      return Fail(kExitRuntime, error);
    res.noise_floor = bench::MeanFlip(noise_map, mask);
    cv::Mat plain_map;
    if (plate) {
      render::SceneInputs plain = in;
      plain.occluders = {};
      plain.plate = {};
      plain.effects.real_objects = false;
      const cv::Mat img = RenderRealTime(renderer.get(), plain);
      if (img.empty() ||
          !bench::ComputeFlip(fo, reference, img, &plain_map, &error))
        return Fail(kExitRuntime, "scene '" + s.name + "': plain run failed");
    }
    if (!pen_silhouette.empty()) {
      cv::Mat around;
      cv::dilate(pen_silhouette, around,
                 cv::getStructuringElement(cv::MORPH_ELLIPSE, {25, 25}));
      around &= mask;
      if (cv::countNonZero(around) > 0) {
        res.flip_pen = bench::MeanFlip(flip_map, around);
        res.flip_pen_plain = bench::MeanFlip(plain_map, around);
      }
    }
    if (!rs.occluders.empty()) {
      // The hands' pixels over the water (their polygons projected).
      cv::Mat hands(mask.size(), CV_8U, cv::Scalar(0));
      for (const auto& o : rs.occluders) {
        std::vector<cv::Point> px;
        for (const glm::dvec3& p : o.polygon_in_tank) {
          const glm::dvec4 c = rs.scene.cam_from_tank * glm::dvec4(p, 1.0);
          px.emplace_back(cvRound(k.fx * c.x / c.z + k.cx),
                          cvRound(k.fy * c.y / c.z + k.cy));
        }
        cv::fillPoly(hands, std::vector<std::vector<cv::Point>>{px},
                     cv::Scalar(255));
      }
      hands &= mask;
      if (cv::countNonZero(hands) > 0) {
        res.flip_hand = bench::MeanFlip(flip_map, hands);
        res.flip_hand_plain = bench::MeanFlip(plain_map, hands);
      }
    }
    cv::Mat refl_window;
    for (int e = 0; e < kNumEffects; ++e) {
      // Each effect toggled: off, or on for one that is off by default.
      render::SceneInputs off = in;
      off.effects.*(kEffects[e].flag) = !(in.effects.*(kEffects[e].flag));
      const cv::Mat img = RenderRealTime(renderer.get(), off);
      cv::Mat m;
      if (img.empty() || !bench::ComputeFlip(fo, reference, img, &m, &error))
        return Fail(kExitRuntime, "scene '" + s.name + "': effect run failed");
      res.flip_off[e] = bench::MeanFlip(m, mask);
      if (kEffects[e].flag == &render::Effects::shadows) {
        cv::Mat window = ChangedPixels(realtime, img, 3, 13) & mask;
        if (cv::countNonZero(window) > 0)
          res.flip_shadow = bench::MeanFlip(flip_map, window);
      }
      if (kEffects[e].flag == &render::Effects::tank_shadow) {
        const cv::Mat window = ChangedPixels(realtime, img, 1, 9) & ~mask;
        if (cv::countNonZero(window) > 0) {
          const bool on = in.effects.tank_shadow;
          res.flip_board = bench::MeanFlip(on ? flip_map : m, window);
          res.flip_board_off = bench::MeanFlip(on ? m : flip_map, window);
        }
      }
      if (kEffects[e].flag == &render::Effects::reflection) {
        const cv::Mat window = ChangedPixels(realtime, img, 3, 0) & mask;
        refl_window = window;
        if (cv::countNonZero(window) > 0)
          res.flip_reflection = bench::MeanFlip(flip_map, window);
      }
    }
    cv::Mat cube_image, cube_map;
    MapRow row{s.name,
               {res.flip, 0},
               {res.flip_open, 0},
               {res.flip_reflection, -1},
               {0, 0},
               0};
    if (both_maps) {
      // The cube map on the same inputs; FLIP over the same masks and the
      // fold's reflection window (where reflections matter at all).
      render::RendererOptions cube_options = ro;
      cube_options.reflection_map = render::ReflectionMap::kCubeMap;
      auto cube =
          render::Renderer::TryCreate(ctx.get(), k, cube_options, &error);
      if (!cube) return Fail(kExitRuntime, error);
      cube_image = RenderRealTime(cube.get(), in);
      if (cube_image.empty() ||
          !bench::ComputeFlip(fo, reference, cube_image, &cube_map, &error))
        return Fail(kExitRuntime, "scene '" + s.name + "': cube map failed");
      row.envmap_ms = cube->timings().envmap_ms;
      row.flip[1] = bench::MeanFlip(cube_map, mask);
      row.open[1] = cv::countNonZero(open_mask) > 0
                        ? bench::MeanFlip(cube_map, open_mask)
                        : 0.0;
      if (!refl_window.empty() && cv::countNonZero(refl_window) > 0)
        row.refl[1] = bench::MeanFlip(cube_map, refl_window);
      std::vector<double> cube_ms;
      for (int i = 0; i < args.timing_frames; ++i) {
        in.water.change_counter += 1;
        if (!cube->Render(in))
          return Fail(kExitRuntime, "scene '" + s.name + "': render failed");
        cube->Finish();
        cube_ms.push_back(cube->timings().main_ms);
      }
      row.main_ms[1] = bench::Percentile(cube_ms, 50);
    }
    // Pass times: the surface changes every frame (its counter moves), so
    // the caustics and the main pass run each time; the pen (when there is
    // one) moves by 1.5 mm, so the shadow map is redrawn too.
    std::vector<double> main_ms, caustics_ms, shadow_ms, envmap_ms;
    for (int i = 0; i < args.timing_frames; ++i) {
      in.water.change_counter += 1;
      in.tank_from_pen[3][0] += i % 2 ? 0.0015 : -0.0015;
      if (!renderer->Render(in))
        return Fail(kExitRuntime, "scene '" + s.name + "': render failed");
      renderer->Finish();
      main_ms.push_back(renderer->timings().main_ms);
      caustics_ms.push_back(renderer->timings().caustics_ms);
      shadow_ms.push_back(renderer->timings().shadow_ms);
      // Rebuilt only when the frame changes enough: the time of one.
      if (renderer->timings().envmap_rebuilt)
        envmap_ms.push_back(renderer->timings().envmap_ms);
    }
    res.main_ms = bench::Percentile(main_ms, 50);
    res.caustics_ms = bench::Percentile(caustics_ms, 50);
    res.shadow_ms = bench::Percentile(shadow_ms, 50);
    if (!envmap_ms.empty()) res.envmap_ms = bench::Percentile(envmap_ms, 50);

    row.main_ms[0] = res.main_ms;
    if (both_maps) map_rows.push_back(row);
    std::printf("%-8s %7d %6.4f %6.4f |", s.name.c_str(), res.water_pixels,
                res.flip, res.flip_open);
    csv << s.name << ',' << res.water_pixels << ',' << res.flip << ','
        << res.flip_open;
    for (int e = 0; e < kNumEffects; ++e) {
      std::printf(" %6.4f", res.flip_off[e]);
      csv << ',' << res.flip_off[e];
    }
    auto window = [](double v) {
      char b[16];
      if (v < 0)
        std::snprintf(b, sizeof(b), "%6s", "-");
      else
        std::snprintf(b, sizeof(b), "%6.4f", v);
      return std::string(b);
    };
    std::printf(
        " | %6.4f | %s %s %s %s %s %s | %s %s | %6.2f %6.2f %6.2f %6.2f | "
        "%6.1f | %6.3f %6.4f %6.4f\n",
        res.noise_floor, window(res.flip_pen).c_str(),
        window(res.flip_hand).c_str(), window(res.flip_pen_plain).c_str(),
        window(res.flip_hand_plain).c_str(), window(res.flip_shadow).c_str(),
        window(res.flip_reflection).c_str(), window(res.flip_board).c_str(),
        window(res.flip_board_off).c_str(), res.main_ms, res.caustics_ms,
        res.shadow_ms, res.envmap_ms, res.reference_s, res.best_gain,
        res.flip_at_best_gain, res.flip_resolution_loss);
    csv << ',' << res.noise_floor << ',' << res.flip_pen << ',' << res.flip_hand
        << ',' << res.flip_pen_plain << ',' << res.flip_hand_plain << ','
        << res.flip_shadow << ',' << res.flip_reflection << ','
        << res.flip_board << ',' << res.flip_board_off << ',' << res.main_ms
        << ',' << res.caustics_ms << ',' << res.shadow_ms << ','
        << res.envmap_ms << ',' << res.reference_s << ',' << res.best_gain
        << ',' << res.flip_at_best_gain << ',' << res.flip_resolution_loss
        << '\n';
    std::fflush(stdout);

    cv::Mat heat = bench::FlipHeatmap(flip_map);
    cv::Mat edges;
    cv::Canny(mask, edges, 100, 200);
    heat.setTo(cv::Scalar(255, 255, 255), edges);
    cv::Mat panel;
    cv::hconcat(std::vector<cv::Mat>{reference, realtime, heat}, panel);
    const char* labels[] = {"reference", "real-time", "FLIP"};
    for (int i = 0; i < 3; ++i) {
      cv::putText(panel, labels[i], {i * size.width + 8, 20},
                  cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 3);
      cv::putText(panel, labels[i], {i * size.width + 8, 20},
                  cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255), 1);
    }
    const std::string png = args.out + "/" + s.name + ".png";
    if (!cv::imwrite(png, panel))
      return Fail(kExitRuntime, "cannot write '" + png + "'");
    if (both_maps) {
      // reference | fold | cube map | the cube map's FLIP
      cv::Mat four, cube_heat = bench::FlipHeatmap(cube_map);
      cube_heat.setTo(cv::Scalar(255, 255, 255), edges);
      cv::hconcat(
          std::vector<cv::Mat>{reference, realtime, cube_image, cube_heat},
          four);
      const char* names[] = {"reference", "fold", "cube map", "FLIP (cube)"};
      for (int i = 0; i < 4; ++i) {
        cv::putText(four, names[i], {i * size.width + 8, 20},
                    cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 3);
        cv::putText(four, names[i], {i * size.width + 8, 20},
                    cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255),
                    1);
      }
      const std::string png4 = args.out + "/" + s.name + "_reflection.png";
      if (!cv::imwrite(png4, four))
        return Fail(kExitRuntime, "cannot write '" + png4 + "'");
    }
    if (!args.export_dir.empty() &&
        !WriteSceneFiles(args.export_dir + "/" + s.name, s, ro, video,
                         reference, realtime, flip_map, mask, open_mask,
                         &error))
      return Fail(kExitRuntime, error);
  }
  csv.close();
  if (!csv) return Fail(kExitRuntime, "cannot write '" + csv_path + "'");
  if (both_maps) {
    const std::string path = args.out + "/bench_reflection.csv";
    std::ofstream rc(path);
    rc << "scene,flip_fold,flip_cubemap,open_fold,open_cubemap,refl_fold,"
          "refl_cubemap,main_ms_fold,main_ms_cubemap,envmap_rebuild_ms\n";
    std::printf(
        "\nreflection maps against the same reference (FLIP: water, open "
        "water, where reflections matter; main pass ms; one rebuild ms)\n"
        "%-8s %13s %13s %13s %13s %7s\n",
        "scene", "FLIP f/c", "open f/c", "refl f/c", "main f/c", "rebuild");
    for (const MapRow& r : map_rows) {
      std::printf(
          "%-8s %6.4f/%6.4f %6.4f/%6.4f %6.4f/%6.4f %6.2f/%6.2f %7.2f\n",
          r.scene.c_str(), r.flip[0], r.flip[1], r.open[0], r.open[1],
          r.refl[0], r.refl[1], r.main_ms[0], r.main_ms[1], r.envmap_ms);
      rc << r.scene << ',' << r.flip[0] << ',' << r.flip[1] << ',' << r.open[0]
         << ',' << r.open[1] << ',' << r.refl[0] << ',' << r.refl[1] << ','
         << r.main_ms[0] << ',' << r.main_ms[1] << ',' << r.envmap_ms << '\n';
    }
    rc.close();
    if (!rc) return Fail(kExitRuntime, "cannot write '" + path + "'");
  }
  std::printf("wrote %s and one PNG per scene in %s/%s\n", csv_path.c_str(),
              args.out.c_str(),
              args.export_dir.empty()
                  ? ""
                  : ("; scene files in " + args.export_dir).c_str());
  return kExitOk;
}

CommandAction SetupBenchRender(CLI::App* sub) {
  auto args = std::make_shared<RenderBenchArgs>();
  sub->add_option("--out", args->out, "Output folder")->capture_default_str();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--size", args->size,
                  "Image size WxH (intrinsics scaled from --camera)")
      ->capture_default_str()
      ->check(WxHValidator(WxHLimits::Size()));
  sub->add_option("--gl", args->gl, "GL backend: egl or osmesa")
      ->capture_default_str();
  sub->add_option("--scenes", args->scenes,
                  "Scenes to run (flat ring demo_a demo_b demo_c tiles pen "
                  "hand grazing lens room; default all)");
  sub->add_option("--export", args->export_dir,
                  "Also write each scene's inputs and both renders here");
  sub->add_option("--water-look", args->water_look,
                  "The real-time renderer's optics: clear or pool (the "
                  "reference is always pure water)")
      ->capture_default_str();
  sub->add_option("--shadows", args->shadows,
                  "The real-time renderer's shadow filter: pcf, gauss or "
                  "hard (the reference's shadows are soft by construction)")
      ->capture_default_str();
  sub->add_option("--refraction-filter", args->refraction_filter,
                  "The real-time renderer's lookup of the refracted video: "
                  "cubic or linear")
      ->capture_default_str();
  sub->add_option("--reflection", args->reflection,
                  "The real-time renderer's reflection map: fold, cubemap or "
                  "both (the fold's table, then the cube map against the same "
                  "reference: bench_reflection.csv, <scene>_reflection.png) "
                  "(the reference traces the reflected rays to the sky, the "
                  "pen, the obstacles and, in the room scene, the room's "
                  "walls)")
      ->capture_default_str();
  sub->add_option("--water-columns", args->water_columns,
                  "The real-time renderer shades the water on a grid of "
                  "this many columns: auto, full or N >= 64")
      ->capture_default_str()
      ->check(WaterColumnsValidator());
  sub->add_option("--tank-shadow", args->tank_shadow,
                  "The real-time renderer's shadow of the tank on the board "
                  "around it: auto (on up to 640 columns, as the pipeline), "
                  "on or off (the reference always has it)")
      ->capture_default_str();
  sub->add_option("--ambient", args->ambient,
                  "The sky's share of the board's light in both renderers, "
                  "0..1 (the light's disc has the rest)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--spp", args->samples_per_pixel,
                  "Reference samples per pixel")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  sub->add_option("--light-paths", args->light_paths_per_texel,
                  "Reference light paths per caustic texel")
      ->capture_default_str()
      ->check(CLI::Range(64, 65536));
  sub->add_option("--sky-rays", args->sky_rays,
                  "Reference sky rays per sample at the first diffuse point")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  sub->add_option("--diffuse-bounces", args->diffuse_bounces,
                  "Reference diffuse bounces (0: the disc's light on what the "
                  "camera sees; fewer than the default split the light by "
                  "order)")
      ->capture_default_str()
      ->check(CLI::Range(0, 16));
  sub->add_option("--timing-frames", args->timing_frames,
                  "Real-time frames timed per scene")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  return [args] { return RunBenchRender(*args); };
}

}  // namespace

RIPPLE_REGISTER_BENCH(render,
                      "Real-time renderer against the physically based "
                      "reference: FLIP per scene and effect, pass times",
                      SetupBenchRender);

}  // namespace ripple::app
