// Daylight on the board (render/sun.h, ComputeDaylight) and how it lights the
// water's model (render/optics.h, SetDaylight, ComputeWaterShading,
// DaylightSkyRadiance): a lower sun is dimmer and warmer and leaves the sky a
// larger share; below the horizon there is no direct light at all.
#include <gtest/gtest.h>

#include <cmath>

#include "render/optics.h"
#include "render/sun.h"

namespace ripple::render {
namespace {

double Luminance(const LinearRgb& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

Daylight At(double elevation_deg, double turbidity = 3.0) {
  SkyOptions o;
  o.turbidity = turbidity;
  Daylight d;
  std::string error;
  EXPECT_TRUE(ComputeDaylight(o, EnuFromAzimuthElevation(180.0, elevation_deg),
                              &d, &error))
      << error;
  return d;
}

TEST(DaylightTest, IlluminancesAreThoseOfAClearDay) {
  // A clear sky (T = 3), sun 60 degrees up: the beam's normal illuminance
  // is near 100 klx (clear days measure 95-110 klx at that height). The
  // Preetham sky gives about 31 klx on a horizontal surface, on the bright
  // side of measured clear skies (10-25 klx): the model's zenith fit is
  // known to run bright at high sun. The sky's share is then 0.2-0.3.
  const Daylight d = At(60);
  EXPECT_TRUE(d.sun_up);
  const double normal = d.sun_klx / std::sin(60 * M_PI / 180);
  EXPECT_GT(normal, 85);
  EXPECT_LT(normal, 115);
  EXPECT_GT(d.sky_klx, 10);
  EXPECT_LT(d.sky_klx, 40);
  EXPECT_GT(d.ambient_share, 0.15);
  EXPECT_LT(d.ambient_share, 0.35);
  EXPECT_NEAR(d.ambient_share, d.sky_klx / (d.sky_klx + d.sun_klx), 1e-12);
  EXPECT_NEAR(Luminance(d.sky_rgb), 1.0, 1e-9);
  EXPECT_NEAR(Luminance(d.sun_rgb), 1.0, 1e-9);
  // The sky is bluer than the sun.
  EXPECT_GT(d.sky_rgb.b / d.sky_rgb.r, d.sun_rgb.b / d.sun_rgb.r);
}

TEST(DaylightTest, ALowerSunIsDimmerAndWarmerAndTheSkysShareGrows) {
  const double elevations[] = {70, 45, 25, 10, 3};
  Daylight prev = At(elevations[0]);
  for (int i = 1; i < 5; ++i) {
    const Daylight d = At(elevations[i]);
    SCOPED_TRACE(elevations[i]);
    // Dimmer: both the beam and the sky give the board less light.
    EXPECT_LT(d.sun_klx, prev.sun_klx);
    EXPECT_LT(d.sky_klx, prev.sky_klx);
    // Warmer: the longer path through the air reddens the beam.
    EXPECT_GT(d.sun_rgb.r / d.sun_rgb.b, prev.sun_rgb.r / prev.sun_rgb.b);
    // The sky's share of the board's light grows (softer shadows).
    EXPECT_GT(d.ambient_share, prev.ambient_share);
    prev = d;
  }
}

TEST(DaylightTest, HazeWarmsTheBeamAndRaisesTheSkysShare) {
  const Daylight clear = At(40, 2.0), hazy = At(40, 6.0);
  EXPECT_LT(hazy.sun_klx, clear.sun_klx);
  EXPECT_GT(hazy.ambient_share, clear.ambient_share);
  EXPECT_GT(hazy.sun_rgb.r / hazy.sun_rgb.b, clear.sun_rgb.r / clear.sun_rgb.b);
}

TEST(DaylightTest, BelowTheHorizonThereIsNoDirectLight) {
  const Daylight d = At(-6);
  EXPECT_FALSE(d.sun_up);
  EXPECT_EQ(d.sun_klx, 0.0);
  EXPECT_EQ(d.ambient_share, 1.0);
  EXPECT_GT(d.sky_klx, 0.0);  // the twilight sky (the sun on the horizon)
  WaterOptics optics;
  SetDaylight(d, &optics);
  EXPECT_EQ(optics.ambient_share, 1.0f);
  const WaterShading s =
      ComputeWaterShading(optics, 0.025, glm::dvec3(0.0, -1.0, 0.02));
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(s.floor_sun[c], 0.0f);
    EXPECT_GT(s.floor_sky[c], 0.5f);
  }
  EXPECT_EQ(s.glint_peak, 0.0f);
}

TEST(DaylightTest, TheAmbientTermTakesTheSkysColourAndTheBoardStaysWhite) {
  for (double elevation : {60.0, 20.0, 5.0}) {
    SCOPED_TRACE(elevation);
    const Daylight d = At(elevation);
    WaterOptics optics;
    SetDaylight(d, &optics);
    const double a = optics.ambient_share;
    EXPECT_NEAR(a, d.ambient_share, 1e-6);
    // The dry board keeps the video's colour: the two shares add up to
    // the board's light in every band.
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a * optics.sky_tint[c] + (1 - a) * optics.sun_tint[c], 1.0,
                  1e-5);
    // Without water (depth 0, no absorption) the floor's two terms are the
    // shares times the colours (less the surface's Fresnel loss): the
    // shadowed floor (the ambient term alone) is bluer than the sunlit.
    const WaterShading s = ComputeWaterShading(
        optics, 0.0,
        glm::dvec3(EnuFromAzimuthElevation(0, elevation).east,
                   EnuFromAzimuthElevation(0, elevation).north,
                   EnuFromAzimuthElevation(0, elevation).up));
    EXPECT_GT(s.floor_sky.b / s.floor_sky.r, s.floor_sun.b / s.floor_sun.r);
    EXPECT_NEAR(s.floor_sky.b / s.floor_sky.r,
                optics.sky_tint.b / optics.sky_tint.r, 1e-4);
  }
  // A lower sun: the ambient term is a larger share of the board's light.
  WaterOptics high, low;
  SetDaylight(At(60), &high);
  SetDaylight(At(5), &low);
  const glm::dvec3 l(0, -0.5, 1);
  EXPECT_GT(ComputeWaterShading(low, 0.025, l).floor_sky.g,
            ComputeWaterShading(high, 0.025, l).floor_sky.g);
}

TEST(DaylightTest, SkyRadianceAveragesToTheAmbientTerm) {
  // The reflection's sky (display units): its cosine-weighted mean over the
  // hemisphere is a * sky_tint, the ambient term's radiance.
  const Daylight d = At(35);
  WaterOptics optics;
  SetDaylight(d, &optics);
  constexpr int kRings = 48, kSectors = 96;
  glm::dvec3 mean(0.0);
  for (int i = 0; i < kRings; ++i) {
    const double s = (i + 0.5) / kRings;  // cos^2 theta
    for (int j = 0; j < kSectors; ++j) {
      const double phi = 2 * M_PI * (j + 0.5) / kSectors;
      const double st = std::sqrt(1 - s);
      mean += glm::dvec3(DaylightSkyRadiance(
          d, {st * std::sin(phi), st * std::cos(phi), std::sqrt(s)}));
    }
  }
  mean /= double(kRings) * kSectors;
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(mean[c], d.ambient_share * optics.sky_tint[c],
                0.03 * d.ambient_share * optics.sky_tint[c]);
  // Brighter near the sun than opposite it, at the same height.
  const glm::vec3 towards =
      DaylightSkyRadiance(d, EnuFromAzimuthElevation(180, 40));
  const glm::vec3 away = DaylightSkyRadiance(d, EnuFromAzimuthElevation(0, 40));
  EXPECT_GT(towards.g, away.g);
}

TEST(DaylightTest, BoardBearingTurnsDirections) {
  // +y at bearing 90 (east): the board's +y is ENU east, its +x south.
  const EnuDirection y = EnuFromBoard(0, 1, 0, 90);
  EXPECT_NEAR(y.east, 1, 1e-12);
  EXPECT_NEAR(y.north, 0, 1e-12);
  const EnuDirection x = EnuFromBoard(1, 0, 0, 90);
  EXPECT_NEAR(x.north, -1, 1e-12);
  const EnuDirection z = EnuFromBoard(0, 0, 1, 37);
  EXPECT_NEAR(z.up, 1, 1e-12);
}

}  // namespace
}  // namespace ripple::render
