// The sun's direction in the tank frame (app_sun.h): the ENU -> tank
// rotation for the board's bearing, and --sun's parsing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "app/app_sun.h"

namespace ripple::app {
namespace {

using ::testing::HasSubstr;

constexpr double kS = 0.70710678118654752;  // cos 45 deg = sin 45 deg

void ExpectNear(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  EXPECT_LT((a - b).norm(), 1e-12) << a.transpose() << " vs " << b.transpose();
}

TEST(SunLightTest, TankFromEnuFollowsTheBoardsBearing) {
  // A sun due south at 45 deg with the board's +y to the north.
  const render::EnuDirection south = render::EnuFromAzimuthElevation(180, 45);
  ExpectNear(TankFromEnu(south, 0), {0, -kS, kS});
  // +y pointing east (bearing 90): +x, a quarter turn clockwise from it,
  // points south.
  ExpectNear(TankFromEnu({1, 0, 0}, 90), {0, 1, 0});
  ExpectNear(TankFromEnu({0, -1, 0}, 90), {1, 0, 0});
  ExpectNear(TankFromEnu({0, 1, 0}, 90), {-1, 0, 0});
  // +y pointing south: the southern sun is along +y.
  ExpectNear(TankFromEnu(south, 180), {0, kS, kS});
  // Up stays up; a full turn changes nothing.
  ExpectNear(TankFromEnu({0, 0, 1}, 37), {0, 0, 1});
  const render::EnuDirection d{0.3, -0.5, 0.81};
  ExpectNear(TankFromEnu(d, 360), TankFromEnu(d, 0));
  // A rotation: lengths are kept.
  EXPECT_NEAR(TankFromEnu(d, 123).norm(),
              Eigen::Vector3d(0.3, -0.5, 0.81).norm(), 1e-12);
}

TEST(SunLightTest, SunIsTheApparentSolarDirection) {
  // Munich near the June solstice's solar noon: the sun stands high in the
  // south (azimuth ~180, elevation ~65 deg).
  Eigen::Vector3d light;
  render::Daylight day;
  const render::SkyOptions sky;
  std::string error;
  ASSERT_TRUE(SunLightInTank("48.14,11.58,2026-06-21T13:15+02:00", 0, sky,
                             &light, &day, &error))
      << error;
  EXPECT_NEAR(light.norm(), 1.0, 1e-12);
  EXPECT_NEAR(std::asin(light.z()) * 180 / M_PI, 65.3, 0.5);
  EXPECT_LT(light.y(), -0.3);            // towards the south
  EXPECT_LT(std::abs(light.x()), 0.05);  // near the meridian
  // The same with the board turned: the direction turns with it.
  Eigen::Vector3d turned;
  ASSERT_TRUE(SunLightInTank("48.14,11.58,2026-06-21T13:15+02:00", 90, sky,
                             &turned, &day, &error));
  EXPECT_NEAR(turned.x(), -light.y(), 1e-12);
  EXPECT_NEAR(turned.y(), light.x(), 1e-12);
  // A decimal comma in the seconds is part of the date-time.
  EXPECT_TRUE(SunLightInTank("48.14,11.58,2026-06-21T13:15:00,5+02:00", 0, sky,
                             &light, &day, &error))
      << error;
}

TEST(SunLightTest, BelowTheHorizonTheSunIsOff) {
  // Munich at 23:30 local time in June: the sun is about 17 degrees down.
  Eigen::Vector3d light;
  render::Daylight day;
  std::string error;
  ASSERT_TRUE(SunLightInTank("48.14,11.58,2026-06-21T23:30+02:00", 0, {},
                             &light, &day, &error))
      << error;
  EXPECT_FALSE(day.sun_up);
  EXPECT_EQ(day.sun_klx, 0.0);
  EXPECT_EQ(day.ambient_share, 1.0);
  EXPECT_GT(light.z(), 0.0);  // a direction the shadow pass can take
  // By day the direct light has its share.
  ASSERT_TRUE(SunLightInTank("48.14,11.58,2026-06-21T13:15+02:00", 0, {},
                             &light, &day, &error));
  EXPECT_TRUE(day.sun_up);
  EXPECT_LT(day.ambient_share, 0.5);
}

TEST(SunLightTest, BadInputIsOneSentence) {
  Eigen::Vector3d light;
  render::Daylight day;
  const render::SkyOptions sky;
  std::string error;
  EXPECT_FALSE(SunLightInTank("48.14,11.58", 0, sky, &light, &day, &error));
  EXPECT_THAT(error, HasSubstr("LAT,LON,DATETIME"));
  EXPECT_FALSE(SunLightInTank("north,11.58,2026-06-21T12:00Z", 0, sky, &light,
                              &day, &error));
  EXPECT_THAT(error, HasSubstr("'north' is not a number"));
  EXPECT_FALSE(SunLightInTank("95,11.58,2026-06-21T12:00Z", 0, sky, &light,
                              &day, &error));
  EXPECT_FALSE(
      SunLightInTank("48,11,2026-06-21T12:00", 0, sky, &light, &day, &error));
  EXPECT_THAT(error, HasSubstr("--sun '48,11,2026-06-21T12:00'"));
  render::SkyOptions hazy;
  hazy.turbidity = 20;
  EXPECT_FALSE(SunLightInTank("48.14,11.58,2026-06-21T13:15+02:00", 0, hazy,
                              &light, &day, &error));
  EXPECT_THAT(error, HasSubstr("turbidity"));
}

}  // namespace
}  // namespace ripple::app
