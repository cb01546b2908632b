#include "app/app_options.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "app/app_floor.h"
#include "app/app_sun.h"

namespace ripple::app {

void AddPipelineOptions(CLI::App* sub, PipelineArgs* args) {
  sub->add_option("--gl", args->gl,
                  "GL backend: glfw (window), egl or osmesa (headless)");
  AddWaterOptions(sub, &args->water);
  AddSmoothingOptions(sub, &args->smoothing);
  sub->add_flag("--no-caustics", args->no_caustics,
                "Disable the caustics pass");
  sub->add_flag("--no-shadows", args->no_shadows, "Disable the shadow pass");
  sub->add_option("--tank-shadow", args->tank_shadow,
                  "The tank's shadow on the board around it (the water "
                  "column's shadow, the light its glass sends down, the sky "
                  "it hides): auto (on for frames up to 640 columns), on or "
                  "off; a bare --tank-shadow is on. At 1280x720 it costs "
                  "about 5 ms a frame")
      ->expected(0, 1)
      ->default_str("auto");
  sub->add_option("--shadows", args->shadows,
                  "Shadow map filter: pcf (4 bilinear taps; the default), "
                  "gauss (Gaussian-weighted 3x3 taps, a smooth semi-soft "
                  "edge) or hard (one tap, aliased)")
      ->capture_default_str();
  sub->add_option("--shadow-sigma", args->shadow_sigma_texels,
                  "--shadows gauss: the Gaussian's standard deviation, shadow "
                  "map texels, 0.5..4 (default 1.5)");
  sub->add_option("--refraction-filter", args->refraction_filter,
                  "How the water reads the video where refracted rays land: "
                  "cubic (Catmull-Rom, keeps the magnified floor sharp; the "
                  "default) or linear (one bilinear fetch, about 7% less "
                  "main-pass work)")
      ->capture_default_str();
  sub->add_flag("--no-reflection", args->no_reflection, "Disable reflection");
  sub->add_flag("--no-refraction", args->no_refraction, "Disable refraction");
  sub->add_option("--water-look", args->water_look,
                  "Water optics: clear (pure water, Pope & Fry absorption; "
                  "default) or pool (stylised cyan tint)");
  sub->add_option(
      "--ambient", args->ambient,
      "Share of the board's light from the sky, 0..1 (default "
      "0.3; with --sun the daylight model's): the floor's brightness in full "
      "shadow");
  sub->add_option("--light-size", args->light_size_deg,
                  "Angular radius of the light, degrees (default 2): the "
                  "size of the glints on the ripples");
  AddFloorOption(sub, &args->floor);
  sub->add_option("--light", args->light,
                  "The light: auto (from the real pen's shadow on the board, "
                  "held over time; the default) or AZ,EL in degrees, tank "
                  "frame: azimuth from the board's +x towards +y, elevation "
                  "above the board")
      ->capture_default_str();
  sub->add_option("--sun", args->sun,
                  "The light from the sun: LAT,LON,DATETIME (degrees north "
                  "and east; ISO 8601 with a zone, e.g. "
                  "48.14,11.58,2026-06-21T12:00+02:00); not with --light");
  sub->add_option("--north", args->north_deg,
                  "With --sun: compass bearing of the board's +y axis, "
                  "degrees clockwise from true north (default 0: +y north, "
                  "+x east)");
  sub->add_option("--turbidity", args->turbidity,
                  "With --sun: atmospheric turbidity of the Preetham sky, "
                  "1.7..10 (2 very clear, 3 clear, 6 hazy)")
      ->capture_default_str();
  sub->add_option("--reflection", args->reflection,
                  "Where reflections find the surroundings: fold (the frame "
                  "folded flat around the reflected ray's point; the default) "
                  "or cubemap (an environment cube map folded from the frame, "
                  "rebuilt when the view changes)")
      ->capture_default_str();
  sub->add_flag("--no-occluders", args->no_occluders,
                "Draw the water over everything: no clean plate of the "
                "board, no hands or objects kept in front of the tank");
  sub->add_flag("--no-overlap", args->no_overlap,
                "Track each frame before its render instead of beside the "
                "last frame's (lower latency, lower frame rate)");
  sub->add_option(
         "--water-columns", args->water_columns,
         "Shade the water on a grid of this many columns and "
         "upsample it inside the water (its edges stay sharp): auto "
         "(every pixel up to 640 columns, a grid of 640 above), full (every "
         "pixel) or N >= 64")
      ->capture_default_str()
      ->check(WaterColumnsValidator());
  sub->add_flag("--full-frame", args->full_frame,
                "Draw every pixel through GL (by default only the tank's "
                "part of the frame is; the rest is the video as it came)");
}

bool ParseTankShadow(const std::string& text, bool* by_resolution, bool* on) {
  if (text == "auto") {
    *by_resolution = true;
    return true;
  }
  if (text == "on" || text.empty() || text == "off") {
    *by_resolution = false;
    *on = text != "off";
    return true;
  }
  return false;
}

bool ParseWaterColumns(const std::string& text, int* columns) {
  if (text == "auto") {
    *columns = render::kWaterColumnsAuto;
    return true;
  }
  if (text == "full") {
    *columns = 0;
    return true;
  }
  size_t used = 0;
  long n = -1;
  try {
    n = std::stol(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  if (used != text.size() || !(n == 0 || (n >= 64 && n <= 16384))) return false;
  *columns = static_cast<int>(n);
  return true;
}

CLI::Validator WaterColumnsValidator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        int columns = 0;
        if (ParseWaterColumns(value, &columns)) return "";
        return "'" + value + "': expected auto, full or 64 to 16384 columns";
      },
      "");
}

bool ParseLightDirection(const std::string& text, Eigen::Vector3d* light,
                         std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "--light '" + text + "': " + why;
    return false;
  };
  const size_t comma = text.find(',');
  if (comma == std::string::npos ||
      text.find(',', comma + 1) != std::string::npos)
    return fail("use auto or AZ,EL in degrees (e.g. 30,60)");
  double az = 0, el = 0;
  for (auto [part, out] :
       {std::pair<std::string, double*>{text.substr(0, comma), &az},
        {text.substr(comma + 1), &el}}) {
    size_t used = 0;
    try {
      *out = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size() || !std::isfinite(*out))
      return fail("'" + part + "' is not a number");
  }
  if (!(az >= -360 && az <= 360))
    return fail("azimuth must be in [-360, 360] degrees");
  if (!(el > 0 && el <= 90))
    return fail("elevation must be in (0, 90] degrees");
  const double a = az * M_PI / 180.0, e = el * M_PI / 180.0;
  *light = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  return true;
}

bool SetBoardFloor(PipelineArgs* args, const tracking::Rig& rig) {
  if (args->options.occluders) {
    auto floor = MakeFloorOrReport(args->floor, rig);
    if (!floor) return false;
    args->options.board_floor = std::move(*floor);
  }
  return true;
}

bool FinishPipelineOptions(PipelineArgs* args, const std::string& default_gl,
                           std::string* error) {
  const std::string gl = args->gl.empty() ? default_gl : args->gl;
  const auto backend = render::ParseBackend(gl);
  if (!backend) {
    if (error) *error = "--gl '" + gl + "': use glfw, egl or osmesa";
    return false;
  }
  PipelineOptions& o = args->options;
  if (!ResolveWaterOptions(args->water, &o.water, &o.sim_cells_x, error))
    return false;
  if (!ApplySmoothingOptions(args->smoothing, &o.tracker.smoothing, error))
    return false;
  o.keep_push_radius = args->water.radius_m.given;
  o.backend = *backend;
  o.window = *backend == render::Backend::kGlfw;
  o.effects.caustics = !args->no_caustics;
  o.effects.shadows = !args->no_shadows;
  if (!ParseTankShadow(args->tank_shadow, &o.tank_shadow_by_resolution,
                       &o.effects.tank_shadow)) {
    if (error)
      *error = "--tank-shadow '" + args->tank_shadow + "': use auto, on or off";
    return false;
  }
  o.effects.reflection = !args->no_reflection;
  o.effects.refraction = !args->no_refraction;
  o.occluders = !args->no_occluders;
  o.overlap_tracking = !args->no_overlap;
  o.renderer.full_frame_output = args->full_frame;
  // Checked by WaterColumnsValidator when given; the default is valid.
  if (!ParseWaterColumns(args->water_columns,
                         &o.renderer.water_shading_columns)) {
    if (error) *error = "--water-columns '" + args->water_columns + "'";
    return false;
  }
  if (!render::ParseShadowFilter(args->shadows, &o.renderer.shadow_filter)) {
    if (error)
      *error = "--shadows '" + args->shadows + "': use pcf, gauss or hard";
    return false;
  }
  if (!render::ParseRefractionFilter(args->refraction_filter,
                                     &o.renderer.refraction_filter)) {
    if (error)
      *error = "--refraction-filter '" + args->refraction_filter +
               "': use cubic or linear";
    return false;
  }
  if (!std::isnan(args->shadow_sigma_texels)) {
    if (!(args->shadow_sigma_texels >= 0.5 && args->shadow_sigma_texels <= 4)) {
      if (error) *error = "--shadow-sigma must be in [0.5, 4] texels";
      return false;
    }
    o.renderer.shadow_gauss_sigma_texels =
        static_cast<float>(args->shadow_sigma_texels);
  }
  if (!args->sun.empty() && args->light != "auto") {
    if (error) *error = "--sun and --light both set the light: give one";
    return false;
  }
  if (!(args->north_deg >= -360 && args->north_deg <= 360)) {
    if (error) *error = "--north must be in [-360, 360] degrees";
    return false;
  }
  if (args->light != "auto") {
    Eigen::Vector3d light;
    if (!ParseLightDirection(args->light, &light, error)) return false;
    o.fixed_light = light;
  }
  if (!render::ParseReflectionMap(args->reflection,
                                  &o.renderer.reflection_map)) {
    if (error)
      *error = "--reflection '" + args->reflection + "': use fold or cubemap";
    return false;
  }
  std::optional<render::Daylight> daylight;
  if (!args->sun.empty()) {
    Eigen::Vector3d light;
    render::SkyOptions sky;
    sky.turbidity = args->turbidity;
    std::string why;
    if (!sky.IsValid(&why)) {
      if (error) *error = "--turbidity: " + why;
      return false;
    }
    daylight.emplace();
    if (!SunLightInTank(args->sun, args->north_deg, sky, &light, &*daylight,
                        error))
      return false;
    o.fixed_light = light;
  }
  o.renderer.timing = render::RendererOptions::Timing::kCpuFinish;
  render::WaterLook look;
  if (!render::ParseWaterLook(args->water_look, &look)) {
    if (error)
      *error = "--water-look '" + args->water_look + "': use clear or pool";
    return false;
  }
  render::WaterOptics& optics = o.renderer.optics;
  optics = render::WaterOptics::ForLook(look);
  if (!std::isnan(args->ambient)) {
    if (!(args->ambient >= 0 && args->ambient <= 1)) {
      if (error) *error = "--ambient must be in [0, 1]";
      return false;
    }
    optics.ambient_share = static_cast<float>(args->ambient);
  }
  if (daylight) {
    // The sky's share from the model unless --ambient gives it.
    // Below the horizon there is no direct light whatever --ambient says.
    if (!std::isnan(args->ambient) && daylight->sun_up)
      daylight->ambient_share = optics.ambient_share;
    render::SetDaylight(*daylight, &optics);
    o.renderer.daylight = daylight;
    o.renderer.daylight_north_deg = args->north_deg;
  }
  if (!std::isnan(args->light_size_deg)) {
    if (!(args->light_size_deg >= 0.01 && args->light_size_deg <= 20)) {
      if (error) *error = "--light-size must be in [0.01, 20] degrees";
      return false;
    }
    optics.light_angular_radius_rad =
        static_cast<float>(args->light_size_deg * M_PI / 180.0);
  }
  return o.IsValid(error);
}

bool MatchCameraToFrames(cv::Size frames, const std::string& camera_path,
                         tracking::Camera* camera, std::string* error) {
  if (frames.width == camera->width && frames.height == camera->height)
    return true;
  const double a = double(frames.width) / frames.height;
  const double b = double(camera->width) / camera->height;
  if (std::abs(a - b) < 1e-3) {
    std::fprintf(stderr,
                 "ripple: warning: frames are %dx%d but '%s' is calibrated at "
                 "%dx%d; scaling the "
                 "intrinsics\n",
                 frames.width, frames.height, camera_path.c_str(),
                 camera->width, camera->height);
    *camera = camera->Scaled(frames.width, frames.height);
    return true;
  }
  if (error)
    *error = "frames are " + std::to_string(frames.width) + "x" +
             std::to_string(frames.height) + " but camera file '" +
             camera_path + "' is calibrated at " +
             std::to_string(camera->width) + "x" +
             std::to_string(camera->height) +
             " (another aspect ratio): calibrate this size with `ripple calib "
             "camera`";
  return false;
}

void PrintProgress(int done, int total, double fps) {
  const int width = 30;
  if (total > 0) {
    const int filled = std::min(width, done * width / total);
    std::fprintf(stderr, "\r[%.*s%s%*s] %d/%d frames %.1f fps", filled,
                 "==============================", filled < width ? ">" : "",
                 std::max(0, width - filled - 1), "", done, total, fps);
  } else {
    std::fprintf(stderr, "\r%d frames %.1f fps", done, fps);
  }
  std::fflush(stderr);
}

}  // namespace ripple::app
