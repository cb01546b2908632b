#include "render/sun.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ripple::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerDeg = kPi / 180.0;

double Sind(double deg) { return std::sin(deg * kRadPerDeg); }
double Cosd(double deg) { return std::cos(deg * kRadPerDeg); }
double Tand(double deg) { return std::tan(deg * kRadPerDeg); }

// x wrapped into [0, 360).
double Wrap360(double x) {
  double r = std::fmod(x, 360.0);
  if (r < 0) r += 360.0;
  return r >= 360.0 ? 0.0 : r;
}

bool IsLeapYear(int year) {
  return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int DaysInMonth(int year, int month) {
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30,
                                  31, 31, 30, 31, 30, 31};
  return month == 2 && IsLeapYear(year) ? 29 : kDays[month - 1];
}

// Reads exactly `count` decimal digits at s[*pos].
bool ReadDigits(const std::string& s, size_t* pos, int count, int* value) {
  if (*pos + count > s.size()) return false;
  int v = 0;
  for (int i = 0; i < count; ++i) {
    const char c = s[*pos + i];
    if (c < '0' || c > '9') return false;
    v = 10 * v + (c - '0');
  }
  *pos += count;
  *value = v;
  return true;
}

bool Expect(const std::string& s, size_t* pos, const char* any_of) {
  if (*pos >= s.size()) return false;
  for (const char* c = any_of; *c; ++c) {
    if (s[*pos] == *c) {
      ++*pos;
      return true;
    }
  }
  return false;
}

// NOAA's refraction correction (degrees) at true elevation h (degrees).
double NoaaRefractionDeg(double h) {
  double arcsec = 0;
  if (h > 85.0) {
    arcsec = 0;
  } else if (h > 5.0) {
    const double t = Tand(h);
    arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
  } else if (h > -0.575) {
    arcsec = 1735.0 + h * (-518.2 + h * (103.4 + h * (-12.79 + h * 0.711)));
  } else {
    arcsec = -20.772 / Tand(h);
  }
  return arcsec / 3600.0;
}

EnuDirection Normalized(const EnuDirection& v) {
  const double n = std::sqrt(v.east * v.east + v.north * v.north + v.up * v.up);
  if (!(n > 0)) return {0, 0, 1};
  return {v.east / n, v.north / n, v.up / n};
}

double Dot(const EnuDirection& a, const EnuDirection& b) {
  return a.east * b.east + a.north * b.north + a.up * b.up;
}

// CIE XYZ from xyY; black for a degenerate y.
void XyzFromXyy(const CieXyy& c, double* x, double* y, double* z) {
  if (!(c.y > 0)) {
    *x = *y = *z = 0;
    return;
  }
  *x = c.x * c.Y / c.y;
  *y = c.Y;
  *z = (1.0 - c.x - c.y) * c.Y / c.y;
}

// IEC 61966-2-1 (sRGB), XYZ (D65) to linear RGB.
LinearRgb LinearSrgbFromXyz(double x, double y, double z) {
  return {3.2406 * x - 1.5372 * y - 0.4986 * z,
          -0.9689 * x + 1.8758 * y + 0.0415 * z,
          0.0557 * x - 0.2040 * y + 1.0570 * z};
}

LinearRgb ClipNegative(const LinearRgb& c) {
  return {std::max(c.r, 0.0), std::max(c.g, 0.0), std::max(c.b, 0.0)};
}

}  // namespace

EnuDirection EnuFromAzimuthElevation(double azimuth_deg, double elevation_deg) {
  const double ce = Cosd(elevation_deg);
  return {ce * Sind(azimuth_deg), ce * Cosd(azimuth_deg), Sind(elevation_deg)};
}

double JulianDayUtc(int year, int month, int day, int hour, int minute,
                    double second) {
  // Meeus eq. 7.1 with the Gregorian correction B; January and February
  // count as months 13 and 14 of the year before.
  int y = year, m = month;
  if (m <= 2) {
    y -= 1;
    m += 12;
  }
  const int a = static_cast<int>(std::floor(y / 100.0));
  const int b = 2 - a + static_cast<int>(std::floor(a / 4.0));
  const double day_start = std::floor(365.25 * (y + 4716)) +
                           std::floor(30.6001 * (m + 1)) + day + b - 1524.5;
  return day_start + (hour * 3600.0 + minute * 60.0 + second) / 86400.0;
}

bool ParseIsoDateTime(const std::string& text, double* julian_day_utc,
                      std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "bad date-time '" + text + "': " + why;
    return false;
  };
  const char* kShape =
      "expected YYYY-MM-DDThh:mm[:ss[.fff]] and a zone (Z or +hh:mm)";
  size_t pos = 0;
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, whole_second = 0;
  double second = 0;
  if (!ReadDigits(text, &pos, 4, &year) || !Expect(text, &pos, "-") ||
      !ReadDigits(text, &pos, 2, &month) || !Expect(text, &pos, "-") ||
      !ReadDigits(text, &pos, 2, &day) || !Expect(text, &pos, "Tt") ||
      !ReadDigits(text, &pos, 2, &hour) || !Expect(text, &pos, ":") ||
      !ReadDigits(text, &pos, 2, &minute))
    return fail(kShape);
  if (Expect(text, &pos, ":")) {
    if (!ReadDigits(text, &pos, 2, &whole_second)) return fail(kShape);
    second = whole_second;
    if (Expect(text, &pos, ".,")) {
      double scale = 0.1;
      int digits = 0;
      while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') {
        second += (text[pos++] - '0') * scale;
        scale *= 0.1;
        ++digits;
      }
      if (digits == 0) return fail("no digits after the decimal point");
    }
  }
  if (pos == text.size())
    return fail("no time zone: append Z (UTC) or an offset such as +02:00");
  int offset_min = 0;
  if (!Expect(text, &pos, "Zz")) {
    const char sign = text[pos];
    if (!Expect(text, &pos, "+-")) return fail(kShape);
    int zone_hour = 0, zone_minute = 0;
    if (!ReadDigits(text, &pos, 2, &zone_hour))
      return fail("zone offset must be +hh:mm or -hh:mm");
    if (pos < text.size()) {
      Expect(text, &pos, ":");
      if (!ReadDigits(text, &pos, 2, &zone_minute))
        return fail("zone offset must be +hh:mm or -hh:mm");
    }
    if (zone_minute > 59) return fail("zone offset minutes must be 00-59");
    offset_min = zone_hour * 60 + zone_minute;
    if (offset_min > 14 * 60) return fail("zone offset is beyond +-14:00");
    if (sign == '-') offset_min = -offset_min;
  }
  if (pos != text.size()) return fail(kShape);
  char buf[96];
  if (year < 1) return fail("year 0000 is not in 0001-9999");
  if (month < 1 || month > 12) {
    std::snprintf(buf, sizeof buf, "month %02d is not in 01-12", month);
    return fail(buf);
  }
  if (day < 1 || day > DaysInMonth(year, month)) {
    std::snprintf(buf, sizeof buf,
                  "day %02d does not exist in %04d-%02d (%d days)", day, year,
                  month, DaysInMonth(year, month));
    return fail(buf);
  }
  if (hour > 23) {
    std::snprintf(buf, sizeof buf, "hour %02d is not in 00-23", hour);
    return fail(buf);
  }
  if (minute > 59) {
    std::snprintf(buf, sizeof buf, "minute %02d is not in 00-59", minute);
    return fail(buf);
  }
  if (whole_second > 59) {
    std::snprintf(buf, sizeof buf,
                  "second %02d is not in 00-59 (no leap seconds)",
                  whole_second);
    return fail(buf);
  }
  // Local time = UTC + offset.
  *julian_day_utc = JulianDayUtc(year, month, day, hour, minute, second) -
                    offset_min / 1440.0;
  return true;
}

bool ComputeSolarPosition(double latitude_deg, double longitude_deg,
                          double julian_day_utc, SolarPosition* position,
                          std::string* error) {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!(latitude_deg >= -90.0 && latitude_deg <= 90.0))
    return fail("latitude must be in [-90, 90] degrees");
  if (!(longitude_deg >= -180.0 && longitude_deg <= 180.0))
    return fail("longitude must be in [-180, 180] degrees (east positive)");
  if (!std::isfinite(julian_day_utc)) return fail("julian day is not finite");

  // The spreadsheet's columns, in its order (Julian centuries from J2000).
  const double t = (julian_day_utc - 2451545.0) / 36525.0;
  const double mean_longitude =
      Wrap360(280.46646 + t * (36000.76983 + t * 0.0003032));
  const double mean_anomaly = 357.52911 + t * (35999.05029 - 0.0001537 * t);
  const double eccentricity =
      0.016708634 - t * (0.000042037 + 0.0000001267 * t);
  const double center =
      Sind(mean_anomaly) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
      Sind(2 * mean_anomaly) * (0.019993 - 0.000101 * t) +
      Sind(3 * mean_anomaly) * 0.000289;
  const double true_longitude = mean_longitude + center;
  // Nutation and aberration through the Moon's node (Meeus 25.8).
  const double node = 125.04 - 1934.136 * t;
  const double apparent_longitude =
      true_longitude - 0.00569 - 0.00478 * Sind(node);
  const double mean_obliquity =
      23.0 +
      (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) /
          60.0;
  const double obliquity = mean_obliquity + 0.00256 * Cosd(node);
  const double declination =
      std::asin(Sind(obliquity) * Sind(apparent_longitude)) / kRadPerDeg;
  const double var_y = std::pow(Tand(obliquity / 2), 2);
  const double e = eccentricity;
  const double eot_rad =
      var_y * Sind(2 * mean_longitude) - 2 * e * Sind(mean_anomaly) +
      4 * e * var_y * Sind(mean_anomaly) * Cosd(2 * mean_longitude) -
      0.5 * var_y * var_y * Sind(4 * mean_longitude) -
      1.25 * e * e * Sind(2 * mean_anomaly);
  const double eot_min = 4.0 * eot_rad / kRadPerDeg;

  // True solar time from the UTC time of day (Julian days start at noon).
  const double day_fraction =
      julian_day_utc + 0.5 - std::floor(julian_day_utc + 0.5);
  const double true_solar_min =
      std::fmod(day_fraction * 1440.0 + eot_min + 4.0 * longitude_deg, 1440.0);
  double hour_angle = Wrap360(true_solar_min / 4.0 - 180.0);
  if (hour_angle >= 180.0) hour_angle -= 360.0;

  // The sun in ENU; the same zenith angle and azimuth as the spreadsheet's
  // arccos forms, by atan2 so that the zenith and the poles stay defined.
  const double sin_lat = Sind(latitude_deg), cos_lat = Cosd(latitude_deg);
  const double sin_dec = Sind(declination), cos_dec = Cosd(declination);
  const double cos_ha = Cosd(hour_angle);
  const EnuDirection sun =
      Normalized({-cos_dec * Sind(hour_angle),
                  cos_lat * sin_dec - sin_lat * cos_dec * cos_ha,
                  sin_lat * sin_dec + cos_lat * cos_dec * cos_ha});
  const double elevation =
      std::asin(std::clamp(sun.up, -1.0, 1.0)) / kRadPerDeg;
  const double azimuth = Wrap360(std::atan2(sun.east, sun.north) / kRadPerDeg);

  SolarPosition p;
  p.azimuth_deg = azimuth;
  p.elevation_deg = elevation;
  p.refraction_deg = NoaaRefractionDeg(elevation);
  p.apparent_elevation_deg = elevation + p.refraction_deg;
  p.declination_deg = declination;
  p.hour_angle_deg = hour_angle;
  p.equation_of_time_min = eot_min;
  p.direction_enu = sun;
  p.apparent_direction_enu =
      EnuFromAzimuthElevation(azimuth, p.apparent_elevation_deg);
  *position = p;
  return true;
}

bool SkyOptions::IsValid(std::string* error) const {
  if (!(turbidity >= 1.7 && turbidity <= 10.0)) {
    if (error) *error = "turbidity must be in [1.7, 10] (the model's range)";
    return false;
  }
  return true;
}

double PerezDistribution(const PerezCoefficients& k, double theta_rad,
                         double gamma_rad) {
  const double cos_theta = std::max(std::cos(theta_rad), 1e-6);
  const double cos_gamma = std::cos(gamma_rad);
  return (1.0 + k.a * std::exp(k.b / cos_theta)) *
         (1.0 + k.c * std::exp(k.d * gamma_rad) + k.e * cos_gamma * cos_gamma);
}

bool MakePreethamSky(const SkyOptions& options, const EnuDirection& sun_enu,
                     PreethamSky* sky, std::string* error) {
  if (!options.IsValid(error)) return false;
  const EnuDirection sun = Normalized(sun_enu);
  if (sun.up < 0) {
    if (error)
      *error = "the sun is below the horizon (the daylight model needs it up)";
    return false;
  }
  const double t = options.turbidity;
  PreethamSky s;
  s.sun_enu = sun;
  s.sun_zenith_rad = std::acos(std::clamp(sun.up, 0.0, 1.0));
  s.turbidity = t;
  // Preetham et al. 1999, appendix A.2: distribution coefficients.
  s.perez_Y = {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251,
               0.1206 * t - 2.5771, -0.0670 * t + 0.3703};
  s.perez_x = {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125,
               -0.0641 * t - 0.8989, -0.0033 * t + 0.0452};
  s.perez_y = {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102,
               -0.0441 * t - 1.6537, -0.0109 * t + 0.0529};
  // Zenith luminance (kcd/m^2) and chromaticity: the paper's fits in T and
  // theta_s (radians).
  const double th = s.sun_zenith_rad;
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * th);
  s.zenith.Y = (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
  const double th2 = th * th, th3 = th2 * th;
  s.zenith.x = t * t * (0.00166 * th3 - 0.00375 * th2 + 0.00209 * th) +
               t * (-0.02903 * th3 + 0.06377 * th2 - 0.03202 * th + 0.00394) +
               (0.11693 * th3 - 0.21196 * th2 + 0.06052 * th + 0.25886);
  s.zenith.y = t * t * (0.00275 * th3 - 0.00610 * th2 + 0.00317 * th) +
               t * (-0.04214 * th3 + 0.08970 * th2 - 0.04153 * th + 0.00516) +
               (0.15346 * th3 - 0.26756 * th2 + 0.06670 * th + 0.26688);
  *sky = s;
  return true;
}

CieXyy SkyXyy(const PreethamSky& sky, const EnuDirection& view) {
  EnuDirection v = Normalized(view);
  if (v.up < 0) {
    // Below the horizon: the horizon point straight above it (north for
    // the nadir).
    v = std::hypot(v.east, v.north) > 1e-12 ? Normalized({v.east, v.north, 0})
                                            : EnuDirection{0, 1, 0};
  }
  const double theta = std::acos(std::clamp(v.up, 0.0, 1.0));
  const double gamma = std::acos(std::clamp(Dot(v, sky.sun_enu), -1.0, 1.0));
  const double ts = sky.sun_zenith_rad;
  auto relative = [&](const PerezCoefficients& k) {
    return PerezDistribution(k, theta, gamma) / PerezDistribution(k, 0.0, ts);
  };
  return {sky.zenith.x * relative(sky.perez_x),
          sky.zenith.y * relative(sky.perez_y),
          sky.zenith.Y * relative(sky.perez_Y)};
}

LinearRgb LinearSrgbFromXyy(const CieXyy& xyy) {
  double x, y, z;
  XyzFromXyy(xyy, &x, &y, &z);
  return LinearSrgbFromXyz(x, y, z);
}

LinearRgb SkyRgbRelativeToZenith(const PreethamSky& sky,
                                 const EnuDirection& view) {
  CieXyy c = SkyXyy(sky, view);
  c.Y /= sky.zenith.Y;
  return ClipNegative(LinearSrgbFromXyy(c));
}

LinearRgb MeanSkyRgbRelativeToZenith(const PreethamSky& sky) {
  // With s = cos^2(theta), cos(theta) d(omega) = ds d(phi) / 2, so the
  // cosine-weighted mean is the plain mean over (s, phi) in [0,1] x [0,2pi):
  // midpoints of a 64 x 128 grid. Averaged in XYZ, converted once.
  constexpr int kRings = 64, kSectors = 128;
  double sx = 0, sy = 0, sz = 0;
  for (int i = 0; i < kRings; ++i) {
    const double s = (i + 0.5) / kRings;
    const double cos_theta = std::sqrt(s), sin_theta = std::sqrt(1.0 - s);
    for (int j = 0; j < kSectors; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / kSectors;
      CieXyy c = SkyXyy(sky, {sin_theta * std::sin(phi),
                              sin_theta * std::cos(phi), cos_theta});
      c.Y /= sky.zenith.Y;
      double x, y, z;
      XyzFromXyy(c, &x, &y, &z);
      sx += x;
      sy += y;
      sz += z;
    }
  }
  const double n = double(kRings) * kSectors;
  return ClipNegative(LinearSrgbFromXyz(sx / n, sy / n, sz / n));
}

namespace {

double Luminance(const LinearRgb& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

LinearRgb UnitLuminance(const LinearRgb& c) {
  const double y = std::max(Luminance(c), 1e-12);
  return {c.r / y, c.g / y, c.b / y};
}

}  // namespace

EnuDirection EnuFromBoard(double x, double y, double z, double north_deg) {
  // The board's +x and +y in ENU: +y at bearing n, +x at bearing n + 90.
  const double n = north_deg * kRadPerDeg;
  const double c = std::cos(n), s = std::sin(n);
  return {x * c + y * s, -x * s + y * c, z};
}

bool ComputeDaylight(const SkyOptions& options,
                     const EnuDirection& apparent_sun_enu, Daylight* daylight,
                     std::string* error) {
  if (!options.IsValid(error)) return false;
  const EnuDirection sun = Normalized(apparent_sun_enu);
  Daylight d;
  d.sun_up = sun.up >= 0;
  // Below the horizon: the sky with the sun on it.
  const EnuDirection sky_sun =
      d.sun_up ? sun : Normalized({sun.east, sun.north, 0.0});
  if (!MakePreethamSky(options, sky_sun, &d.sky, error)) return false;
  const LinearRgb mean = MeanSkyRgbRelativeToZenith(d.sky);
  d.sky_mean_relative = Luminance(mean);
  d.sky_klx = kPi * d.sky.zenith.Y * d.sky_mean_relative;
  d.sky_rgb = UnitLuminance(mean);
  const double t = options.turbidity;
  const double cos_z = std::clamp(sun.up, 0.0, 1.0);
  const double z_deg = std::acos(cos_z) * 180.0 / kPi;
  // Kasten (1966); finite at the horizon (m = 38).
  const double m =
      1.0 / (cos_z + 0.15 * std::pow(std::max(93.885 - z_deg, 1e-3), -1.253));
  const double beta = 0.04608 * t - 0.04586;
  auto transmittance = [&](double lambda_um) {
    const double rayleigh = 0.008735 * std::pow(lambda_um, -4.08);
    const double aerosol = beta * std::pow(lambda_um, -1.3);
    return std::exp(-(rayleigh + aerosol) * m);
  };
  const LinearRgb beam{transmittance(0.65), transmittance(0.55),
                       transmittance(0.45)};
  d.sun_rgb = UnitLuminance(beam);
  constexpr double kLuminousSolarConstantKlx = 133.8;
  d.sun_klx =
      d.sun_up ? kLuminousSolarConstantKlx * Luminance(beam) * cos_z : 0;
  d.ambient_share = d.sky_klx / std::max(d.sky_klx + d.sun_klx, 1e-12);
  *daylight = d;
  return true;
}

}  // namespace ripple::render
