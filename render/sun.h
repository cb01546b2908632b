// The sun for outdoor lighting: the instant from an ISO 8601 date-time, the
// solar position of NOAA's Solar Calculator (Meeus' low-accuracy equations)
// and the daylight sky of Preetham, Shirley & Smits (1999) as CIE xyY and
// linear sRGB. Standard library only (no GL), so tools and tests use it
// without a context.
//
// Frames and units: angles in degrees unless a name says radians; local
// directions in East-North-Up (ENU): x east, y north, z up (the zenith),
// unit length. Azimuth is clockwise from true north, seen from above: north
// 0, east 90, south 180, west 270.
#ifndef RIPPLE_RENDER_SUN_H_
#define RIPPLE_RENDER_SUN_H_

#include <string>

namespace ripple::render {

// A direction (or any 3-vector) in the local East-North-Up frame.
struct EnuDirection {
  double east = 0;
  double north = 0;
  double up = 0;
};

// The unit ENU vector at `azimuth_deg` (clockwise from north) and
// `elevation_deg` above the horizon.
EnuDirection EnuFromAzimuthElevation(double azimuth_deg, double elevation_deg);

// The ENU direction of the vector (x, y, z) of a frame with z up whose +y
// axis points at compass bearing `north_deg` (clockwise from true north):
// the tank frame of a board laid out that way.
EnuDirection EnuFromBoard(double x, double y, double z, double north_deg);

// ---- Time ----

// Julian Day of an instant in UTC, on the proleptic Gregorian calendar:
// Meeus, "Astronomical Algorithms" (2nd ed., 1998), eq. 7.1. Fields are
// taken as given (no range checks; ParseIsoDateTime checks them). UTC is used
// in place of UT1 (|UT1 - UTC| < 0.9 s, under 0.004 deg of hour angle).
double JulianDayUtc(int year, int month, int day, int hour, int minute,
                    double second);

// Parses an ISO 8601 (RFC 3339 profile) date-time with a zone and returns the
// instant as a UTC Julian Day:
//   YYYY-MM-DDThh:mm[:ss[.fff...]](Z | +hh:mm | -hh:mm | +hhmm | +hh)
// 'T' and 'Z' may be lower case, the decimal sign '.' or ','. Years 0001-9999,
// the day checked against the month (leap years by the Gregorian rule), hours
// 00-23, minutes and seconds 00-59 (no leap second), zone offsets up to 14:00
// either way. A time without a zone is rejected: local time is ambiguous. On
// failure returns false and sets `error` (when given) to one sentence naming
// the bad part.
bool ParseIsoDateTime(const std::string& text, double* julian_day_utc,
                      std::string* error);

// ---- Solar position ----

// Where the sun stands for an observer. NOAA's Solar Calculator (the
// spreadsheet "NOAA_Solar_Calculations_day.xls", Global Monitoring
// Laboratory), i.e. Meeus ch. 25 (low-accuracy sun), ch. 22 (obliquity) and
// ch. 28 (equation of time, Smart's formula); geocentric (no parallax, at
// most 0.0025 deg), UT for dynamical time (Delta T ignored, about 0.001 deg).
// Within 0.02 deg of NREL SPA and ERFA at the places in render/sun_test.
struct SolarPosition {
  // Clockwise from true north, [0, 360).
  double azimuth_deg = 0;
  // True (geometric) elevation of the sun's centre above the horizon, no
  // atmosphere; negative below the horizon.
  double elevation_deg = 0;
  // Apparent elevation: elevation_deg plus refraction_deg, where an observer
  // sees the sun through a standard atmosphere.
  double apparent_elevation_deg = 0;
  // NOAA's atmospheric refraction correction, >= 0, with no pressure or
  // temperature input: in arcseconds 58.1/t - 0.07/t^3 + 0.000086/t^5 (t = tan
  // h) for h in (5, 85] deg, a quartic in h down to -0.575 deg, -20.772/t
  // below, 0 above 85 deg (h the true elevation).
  double refraction_deg = 0;
  // The sun's apparent declination and the observer's local hour angle
  // (west of the meridian positive, [-180, 180)).
  double declination_deg = 0;
  double hour_angle_deg = 0;
  // Apparent minus mean solar time, minutes.
  double equation_of_time_min = 0;
  // Unit vectors towards the sun in ENU: the true direction (azimuth_deg,
  // elevation_deg) and the apparent one (azimuth_deg,
  // apparent_elevation_deg), the direction its light arrives from.
  EnuDirection direction_enu;
  EnuDirection apparent_direction_enu;

  // The sun's centre is under the horizon as seen (apparent elevation < 0).
  bool BelowHorizon() const { return apparent_elevation_deg < 0; }
};

// The sun's position at `latitude_deg` (north positive, [-90, 90]),
// `longitude_deg` (east positive, [-180, 180]) at the UTC Julian Day
// `julian_day_utc`. Returns false (and sets `error` when given) for a
// coordinate out of range or not finite.
bool ComputeSolarPosition(double latitude_deg, double longitude_deg,
                          double julian_day_utc, SolarPosition* position,
                          std::string* error);

// ---- Daylight sky ----
// A. J. Preetham, P. Shirley, B. Smits, "A Practical Analytic Model for
// Daylight", SIGGRAPH 1999, appendix A.2: the sky's luminance Y and
// chromaticity x, y in a view direction each follow Perez et al.'s (1993)
// all-weather distribution F relative to the zenith,
//   Y(view) = Y_zenith * F(theta, gamma) / F(0, theta_sun),
// with theta the view's zenith angle and gamma its angle to the sun, and
// coefficients linear in turbidity T.

struct SkyOptions {
  // Preetham's atmospheric turbidity T: the haze's optical thickness
  // relative to a pure molecular atmosphere. About 2 is a very clear sky, 3
  // clear, 6 hazy, 10 thin overcast; the model is fitted for [1.7, 10].
  double turbidity = 3.0;

  bool IsValid(std::string* error) const;
};

// CIE 1931 chromaticity (x, y) and luminance Y.
struct CieXyy {
  double x = 0;
  double y = 0;
  double Y = 0;
};

// Linear (not gamma-encoded) sRGB: ITU-R BT.709 primaries, D65 white.
struct LinearRgb {
  double r = 0;
  double g = 0;
  double b = 0;
};

// The five Perez coefficients A..E of one quantity.
struct PerezCoefficients {
  double a = 0, b = 0, c = 0, d = 0, e = 0;
};

// Perez et al.'s distribution
//   F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma)
//                     + E cos^2 gamma),
// theta the view's zenith angle and gamma its angle to the sun (radians).
// cos theta is clamped to >= 1e-6: at the horizon exp(B / cos theta) -> 0
// for the model's negative B, so the horizon's value is the limit.
double PerezDistribution(const PerezCoefficients& coefficients,
                         double theta_rad, double gamma_rad);

// One sun position and turbidity, everything view-independent precomputed.
struct PreethamSky {
  EnuDirection sun_enu;       // unit, towards the sun, up >= 0
  double sun_zenith_rad = 0;  // theta_s, [0, pi/2]
  double turbidity = 0;
  PerezCoefficients perez_Y, perez_x, perez_y;
  // The zenith's chromaticity and luminance (kcd/m^2), the paper's
  // polynomials in T and theta_s.
  CieXyy zenith;
};

// Builds the sky for the sun towards `sun_enu` (normalised inside). Returns
// false (and sets `error` when given) for invalid options or a sun below the
// horizon (up < 0): the model describes daylight only.
bool MakePreethamSky(const SkyOptions& options, const EnuDirection& sun_enu,
                     PreethamSky* sky, std::string* error);

// The sky's xyY towards `view` (normalised inside), Y in kcd/m^2. A
// direction below the horizon gets the value of the horizon point above it
// (the nadir the north horizon's).
CieXyy SkyXyy(const PreethamSky& sky, const EnuDirection& view);

// CIE xyY to linear sRGB (IEC 61966-2-1 matrix, D65). Components may be
// negative for colours outside the sRGB gamut.
LinearRgb LinearSrgbFromXyy(const CieXyy& xyy);

// The sky's linear sRGB towards `view`, in units of the zenith's luminance:
// the zenith itself has luminance (0.2126 r + 0.7152 g + 0.0722 b) 1.
// Negative components (out of gamut) are clipped to 0.
LinearRgb SkyRgbRelativeToZenith(const PreethamSky& sky,
                                 const EnuDirection& view);

// The cosine-weighted mean of SkyRgbRelativeToZenith over the upper
// hemisphere, (1/pi) * integral of L cos(theta) d(omega): the radiance of a
// uniform sky that gives a horizontal surface the same irradiance, for an
// ambient term. Averaged in CIE XYZ and converted once (negatives clipped);
// quadrature on a fixed 64 x 128 grid (deterministic).
LinearRgb MeanSkyRgbRelativeToZenith(const PreethamSky& sky);

// ---- Daylight on the board ----
// The sun's beam through the atmosphere and the Preetham sky together, as the
// renderer's light: how the board's light splits between the sky and the sun
// and the colour of each, in the renderer's convention (render/optics.h: the
// dry board's light is the unit of radiance, split into a sky share a and
// the sun's 1 - a).
//
// The sun's beam: the luminous solar constant E0 = 133.8 klx (Darula,
// Kittler & Gueymard, "Reference luminous solar constant and solar
// luminance for illuminance calculations", Solar Energy 79, 2005) through
// Preetham et al.'s (1999, section 3.1 and appendix) Rayleigh
// exp(-0.008735 lambda^-4.08 m) and aerosol (Angstrom, alpha 1.3, beta =
// 0.04608 T - 0.04586) transmittances, lambda in micrometres, at 450, 550
// and 650 nm for the camera's blue, green and red bands, with Kasten's
// (1966) air mass m = 1 / (cos z + 0.15 (93.885 - z_deg)^-1.253). The sun
// outside the atmosphere is taken as white in the three bands; ozone, water
// vapour and mixed gases (a few per cent, mostly in the red) are left out.
// The sky: pi times the cosine-weighted mean of the Preetham luminance
// (MeanSkyRgbRelativeToZenith times the zenith's kcd/m^2) on a horizontal
// surface.
struct Daylight {
  // The sun's centre is above the horizon (apparent elevation >= 0); when it
  // is not, the direct light is off: sun_klx = 0, ambient_share = 1, and the
  // sky is the model's with the sun on the horizon (the twilight's colour,
  // an approximation: Preetham's model describes daylight only).
  bool sun_up = false;
  double sun_klx = 0;  // the beam's illuminance on a horizontal surface
  double sky_klx = 0;  // the sky's illuminance on a horizontal surface
  // The sky's share of the board's light: sky_klx / (sky_klx + sun_klx).
  double ambient_share = 1;
  // Colours of unit luminance (0.2126 r + 0.7152 g + 0.0722 b = 1), linear
  // sRGB: the sky's cosine-weighted mean and the sun's beam.
  LinearRgb sky_rgb{1, 1, 1};
  LinearRgb sun_rgb{1, 1, 1};
  PreethamSky sky;  // for the sky's radiance per direction
  // The luminance of MeanSkyRgbRelativeToZenith(sky): the sky's
  // cosine-weighted mean over its zenith's.
  double sky_mean_relative = 1;
};

// The daylight for the sun towards `apparent_sun_enu` (normalised inside;
// below the horizon when up < 0). False (with `error`) for invalid options.
bool ComputeDaylight(const SkyOptions& options,
                     const EnuDirection& apparent_sun_enu, Daylight* daylight,
                     std::string* error);

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_SUN_H_
