// `ripple sun`: where the sun stands for a place and an instant (NOAA's
// solar position), and the colour of the daylight sky there (Preetham's
// model): azimuth, true and apparent elevation, and the zenith's and the
// hemisphere's mean colour as linear sRGB ratios for lighting a scene.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "app/command.h"
#include "render/sun.h"

namespace ripple::app {
namespace {

struct SunArgs {
  std::string latitude;
  std::string longitude;
  std::string datetime;
  std::string turbidity = "3";
};

// A finite number filling all of `text`; false on anything else.
bool ParseNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

int RunSun(const SunArgs& args) {
  double lat = 0, lon = 0;
  if (!ParseNumber(args.latitude, &lat) || lat < -90 || lat > 90)
    return Fail(kExitBadInput, "LAT '" + args.latitude +
                                   "' must be a number of degrees in "
                                   "[-90, 90] (north positive)");
  if (!ParseNumber(args.longitude, &lon) || lon < -180 || lon > 180)
    return Fail(kExitBadInput, "LON '" + args.longitude +
                                   "' must be a number of degrees in "
                                   "[-180, 180] (east positive)");
  render::SkyOptions sky_options;
  std::string error;
  if (!ParseNumber(args.turbidity, &sky_options.turbidity) ||
      !sky_options.IsValid(&error))
    return Fail(kExitBadInput, "--turbidity '" + args.turbidity +
                                   "': must be a number in [1.7, 10]");
  double jd = 0;
  if (!render::ParseIsoDateTime(args.datetime, &jd, &error))
    return Fail(kExitBadInput, error);
  render::SolarPosition sun;
  if (!render::ComputeSolarPosition(lat, lon, jd, &sun, &error))
    return Fail(kExitBadInput, error);

  std::printf("sun at %.6f %s, %.6f %s, %s (UTC Julian Day %.6f)\n",
              std::abs(lat), lat < 0 ? "S" : "N", std::abs(lon),
              lon < 0 ? "W" : "E", args.datetime.c_str(), jd);
  std::printf("azimuth:             %.3f deg (clockwise from true north)\n",
              sun.azimuth_deg);
  std::printf("elevation, true:     %.3f deg (geometric, no atmosphere)\n",
              sun.elevation_deg);
  std::printf(
      "elevation, apparent: %.3f deg (refraction included: +%.3f deg, "
      "NOAA's standard atmosphere)\n",
      sun.apparent_elevation_deg, sun.refraction_deg);
  std::printf("declination:         %.3f deg, equation of time %+.2f min\n",
              sun.declination_deg, sun.equation_of_time_min);
  std::printf("below horizon:       %s\n", sun.BelowHorizon() ? "yes" : "no");

  // The sky as seen: the sun's apparent direction, where its light comes
  // from (within 0.6 deg of the true one, and only near the horizon).
  render::PreethamSky sky;
  if (!render::MakePreethamSky(sky_options, sun.apparent_direction_enu, &sky,
                               &error)) {
    std::printf(
        "sky:                 none (the sun is below the horizon; the "
        "daylight model needs it above)\n");
    return kExitOk;
  }
  const render::LinearRgb zenith =
      render::SkyRgbRelativeToZenith(sky, {0, 0, 1});
  const render::LinearRgb mean = render::MeanSkyRgbRelativeToZenith(sky);
  std::printf(
      "sky (Preetham, turbidity %.2f): zenith luminance %.3f kcd/m^2, "
      "chromaticity x %.4f y %.4f\n",
      sky.turbidity, sky.zenith.Y, sky.zenith.x, sky.zenith.y);
  std::printf(
      "zenith colour:       %.4f %.4f %.4f (linear sRGB, zenith luminance "
      "1)\n",
      zenith.r, zenith.g, zenith.b);
  std::printf(
      "ambient colour:      %.4f %.4f %.4f (cosine-weighted mean over the "
      "sky, same scale)\n",
      mean.r, mean.g, mean.b);
  return kExitOk;
}

CommandAction SetupSun(CLI::App* sub) {
  auto args = std::make_shared<SunArgs>();
  sub->add_option("LAT", args->latitude,
                  "Latitude, degrees, north positive [-90, 90]")
      ->required();
  sub->add_option("LON", args->longitude,
                  "Longitude, degrees, east positive [-180, 180]")
      ->required();
  sub->add_option("DATETIME", args->datetime,
                  "ISO 8601 date-time with a zone, e.g. "
                  "2026-06-21T12:00:00+02:00 or 2026-06-21T10:00Z")
      ->required();
  sub->add_option("--turbidity", args->turbidity,
                  "Atmospheric turbidity of the sky model [1.7, 10]: 2 very "
                  "clear, 3 clear, 6 hazy")
      ->capture_default_str();
  return [args] { return RunSun(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(
    sun,
    "Sun position (NOAA) and daylight sky colour (Preetham) for a place and "
    "an instant",
    SetupSun);

}  // namespace ripple::app
