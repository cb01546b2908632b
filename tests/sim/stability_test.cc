// Numerical stability under stress: never a NaN or an infinity, whatever the
// force scale, radius, frame dt, grid size, obstacle cover, wall mode and
// obstacle treatment. Asserts invariants only, never timings.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "sim/water.h"

namespace ripple::sim {
namespace {

double LogUniform(std::mt19937* rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
  return std::exp(u(*rng));
}

template <typename T>
void ExpectFinite(const BasicWater<T>& water, const std::string& what) {
  const GridSpec& g = water.grid();
  const size_t n = static_cast<size_t>(g.nx) * g.ny;
  for (size_t c = 0; c < n; ++c) {
    ASSERT_TRUE(std::isfinite(water.heights()[c]))
        << what << " cell " << c << " = " << water.heights()[c];
  }
  const AdvanceStats& s = water.stats();
  for (double v : {s.volume_m3, s.abs_volume_m3, s.energy, s.max_abs_height_m,
                   s.max_deviation_m, s.max_speed_m_per_s, s.dropped_s}) {
    ASSERT_TRUE(std::isfinite(v)) << what << ": " << s.BriefReport();
  }
}

struct Scenario {
  int nx, ny;
  double strength;  // m/s^2
  double radius;    // m
  int cover;        // 0 none, 1 random obstacles, 2 everything
  WallMode walls;
  ObstacleMode treatment;
};

std::string Describe(const Scenario& s) {
  char buf[200];
  std::snprintf(buf, sizeof(buf),
                "%dx%d s=%.3g r=%.3g cover=%d walls=%d treatment=%d", s.nx,
                s.ny, s.strength, s.radius, s.cover, static_cast<int>(s.walls),
                static_cast<int>(s.treatment));
  return buf;
}

// Random strokes with random frame dt in [0, 10] s.
void RunScenario(const Scenario& sc, std::mt19937* rng, int frames,
                 int max_substeps) {
  const std::string what = Describe(sc);
  std::uniform_real_distribution<double> u01(0, 1);
  const double size_x = 0.17, size_y = 0.11, level = 0.025;
  GridSpec g;
  g.nx = sc.nx;
  g.ny = sc.ny;
  g.cell_m = size_x / sc.nx;
  g.rest_level_m = level;
  WaterOptions o;
  o.pen_strength_m_per_s2 = sc.strength;
  o.pen_radius_m = sc.radius;
  o.walls = sc.walls;
  o.obstacles = sc.treatment;
  o.max_substeps = max_substeps;
  o.wave_speed_m_per_s = LogUniform(rng, 0.01, 100);
  o.viscosity_per_s = u01(*rng) < 0.3 ? 0 : LogUniform(rng, 1e-3, 1e5);
  o.courant = 0.5 * (0.2 + 0.8 * u01(*rng));
  std::string error;
  ASSERT_TRUE(o.IsValid(&error)) << error;
  ASSERT_TRUE(g.IsValid(&error)) << error;
  Water water(g, o);
  std::vector<int> ids;
  if (sc.cover == 2) {
    Obstacle all;
    all.shape = Obstacle::Shape::kBox;
    all.box_size_m = {10, 10, 10};
    ids.push_back(water.AddObstacle(all, &error));
  } else if (sc.cover == 1) {
    for (int k = 0; k < 3; ++k) {
      Obstacle c;
      c.shape = k == 1 ? Obstacle::Shape::kBox : Obstacle::Shape::kCylinder;
      c.radius_m = LogUniform(rng, 1e-4, 0.05);
      c.height_m = 0.05;
      c.box_size_m = {LogUniform(rng, 1e-4, 0.1), LogUniform(rng, 1e-4, 0.1),
                      0.1};
      c.tank_from_obstacle = RigidTransform::FromQuaternion(
          u01(*rng), 0, 0, u01(*rng),
          {(u01(*rng) - 0.5) * size_x, (u01(*rng) - 0.5) * size_y, 0});
      ids.push_back(water.AddObstacle(c, &error));
    }
  }
  for (int id : ids) ASSERT_GE(id, 0) << error;
  for (int f = 0; f < frames; ++f) {
    // Tip anywhere from well outside the tank to inside, above or below.
    const std::array<double, 3> tip = {(u01(*rng) - 0.5) * 1.2 * size_x,
                                       (u01(*rng) - 0.5) * 1.2 * size_y,
                                       level + (u01(*rng) - 0.7) * 0.04};
    if (u01(*rng) < 0.8) {
      ASSERT_TRUE(water.SetPenTip(tip));
    } else {
      water.ClearPen();
    }
    // NaN and infinite tips are rejected and change nothing.
    ASSERT_FALSE(water.SetPenTip({tip[0], std::nan(""), tip[2]}));
    ASSERT_FALSE(water.SetPenTip({INFINITY, tip[1], tip[2]}));
    if (!ids.empty() && sc.cover == 1 && u01(*rng) < 0.5) {
      water.SetObstaclePose(
          ids[f % ids.size()],
          RigidTransform::FromQuaternion(
              u01(*rng), 0, 0, u01(*rng),
              {(u01(*rng) - 0.5) * size_x, (u01(*rng) - 0.5) * size_y, 0}));
    }
    const double r = u01(*rng);
    const double dt = r < 0.1   ? 0.0
                      : r < 0.2 ? 10.0
                                : LogUniform(rng, 1e-5, 10);
    ASSERT_TRUE(water.Advance(dt)) << what;
    ASSERT_LE(water.stats().substeps, max_substeps);
    ASSERT_GE(water.stats().dropped_s, 0);
    ExpectFinite(water, what + " frame " + std::to_string(f));
    // Runtime changes of s, r and viscosity within the stress ranges.
    if (u01(*rng) < 0.2) {
      WaterOptions changed = water.options();
      changed.pen_strength_m_per_s2 = LogUniform(rng, 1e-6, 1e9);
      changed.pen_radius_m = LogUniform(rng, 1e-5, 10);
      changed.viscosity_per_s = LogUniform(rng, 1e-3, 1e3);
      ASSERT_TRUE(water.SetOptions(changed, &error)) << error;
    }
  }
}

TEST(StabilityTest, RandomStrokesNeverProduceNanOrInf) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u01(0, 1);
  const int sides[] = {2, 3, 5, 17, 64, 150};
  int runs = 0;
  for (double strength : {1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9}) {
    for (double radius : {1e-5, 1e-3, 0.02, 0.5, 10.0}) {
      Scenario sc;
      sc.nx = sides[rng() % 6];
      sc.ny = sides[rng() % 6];
      sc.strength = strength;
      sc.radius = radius;
      sc.cover = static_cast<int>(rng() % 3);
      sc.walls = rng() % 2 ? WallMode::kAbsorb : WallMode::kReflect;
      sc.treatment = rng() % 2 ? ObstacleMode::kZero : ObstacleMode::kReflect;
      RunScenario(sc, &rng, 12, 200);
      if (HasFatalFailure()) return;
      ++runs;
    }
  }
  EXPECT_EQ(runs, 30);
}

TEST(StabilityTest, EveryModeCombinationAtExtremeForce) {
  std::mt19937 rng(777);
  for (WallMode walls : {WallMode::kReflect, WallMode::kAbsorb}) {
    for (ObstacleMode t : {ObstacleMode::kReflect, ObstacleMode::kZero}) {
      for (int cover = 0; cover < 3; ++cover) {
        RunScenario({33, 21, 1e9, 0.01, cover, walls, t}, &rng, 20, 500);
        RunScenario({2, 2, 1e9, 10.0, cover, walls, t}, &rng, 20, 500);
        if (HasFatalFailure()) return;
      }
    }
  }
}

// The largest grid of the stress range: a few sub-steps only, so the test
// stays fast.
TEST(StabilityTest, HugeGridFewSteps) {
  std::mt19937 rng(99);
  RunScenario(
      {2048, 2048, 1e9, 0.05, 1, WallMode::kAbsorb, ObstacleMode::kReflect},
      &rng, 3, 2);
}

// Many sub-steps under a stirring pen at the largest legal Courant number,
// with no viscosity: the energy stays bounded by what the pen put in (the
// scheme is stable, so nothing grows on its own).
TEST(StabilityTest, LongUndampedRunStaysBounded) {
  WaterOptions o;
  o.viscosity_per_s = 0;
  o.courant = 0.5;
  o.rest_speed_m_per_s = 0;
  o.rest_height_m = 0;
  o.max_substeps = 1000;
  Water water(GridSpec::ForTank(0.17, 0.11, 0.025, 48), o);
  water.SetPenTip({0, 0, 0.02});
  water.Advance(0);
  water.Advance(0.3);
  water.ClearPen();
  water.Advance(10 * water.substep_s());  // the pen acted until t = 0.3 s
  const double e0 = water.stats().energy;
  ASSERT_GT(e0, 0);
  for (int f = 0; f < 20; ++f) {
    water.Advance(1000 * water.substep_s());
    ASSERT_LE(water.stats().energy, e0 * (1 + 1e-4));
    ASSERT_GE(water.stats().energy, e0 * (1 - 1e-4));
  }
}

}  // namespace
}  // namespace ripple::sim
