#include "app/app_sun.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace ripple::app {

Eigen::Vector3d TankFromEnu(const render::EnuDirection& d, double north_deg) {
  const double n = north_deg * M_PI / 180.0;
  const Eigen::Vector3d x_in_enu(std::cos(n), -std::sin(n), 0.0);
  const Eigen::Vector3d y_in_enu(std::sin(n), std::cos(n), 0.0);
  const Eigen::Vector3d v(d.east, d.north, d.up);
  return {v.dot(x_in_enu), v.dot(y_in_enu), d.up};
}

bool SunLightInTank(const std::string& text, double north_deg,
                    const render::SkyOptions& sky, Eigen::Vector3d* light,
                    render::Daylight* daylight, std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "--sun '" + text + "': " + why;
    return false;
  };
  // The date-time may hold a comma itself (a decimal sign): split at the
  // first two.
  const size_t a = text.find(',');
  const size_t b = a == std::string::npos ? a : text.find(',', a + 1);
  if (b == std::string::npos)
    return fail("use LAT,LON,DATETIME (e.g. 48.1,11.6,2026-06-21T12:00+02:00)");
  double lat = 0, lon = 0;
  const std::string parts[2] = {text.substr(0, a),
                                text.substr(a + 1, b - a - 1)};
  double* outs[2] = {&lat, &lon};
  for (int i = 0; i < 2; ++i) {
    size_t used = 0;
    try {
      *outs[i] = std::stod(parts[i], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (parts[i].empty() || used != parts[i].size() || !std::isfinite(*outs[i]))
      return fail("'" + parts[i] + "' is not a number");
  }
  double jd = 0;
  std::string why;
  if (!render::ParseIsoDateTime(text.substr(b + 1), &jd, &why))
    return fail(why);
  render::SolarPosition sun;
  if (!render::ComputeSolarPosition(lat, lon, jd, &sun, &why)) return fail(why);
  if (!render::ComputeDaylight(sky, sun.apparent_direction_enu, daylight, &why))
    return fail(why);
  const double elevation = std::max(sun.apparent_elevation_deg, 1.0);
  *light =
      TankFromEnu(render::EnuFromAzimuthElevation(sun.azimuth_deg, elevation),
                  north_deg)
          .normalized();
  return true;
}

}  // namespace ripple::app
