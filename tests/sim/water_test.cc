// Behaviour and physics of sim/water.h: options, time stepping, pen force,
// rest, and the invariants (dispersion, viscosity decay, energy, volume).
#include "sim/water.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace ripple::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

GridSpec Grid(int nx, int ny, double cell_m = 0.002, double level = 0.025) {
  GridSpec g;
  g.nx = nx;
  g.ny = ny;
  g.cell_m = cell_m;
  g.rest_level_m = level;
  return g;
}

// Options for invariant tests: no damping, never rests.
WaterOptions Lossless() {
  WaterOptions o;
  o.viscosity_per_s = 0;
  o.rest_speed_m_per_s = 0;
  o.rest_height_m = 0;
  o.max_substeps = 1000000;
  return o;
}

// A standing mode cos(theta_x (i+1/2)) cos(theta_y (j+1/2)) of the mirrored
// (Neumann) grid, theta = pi*p/n.
template <typename T>
std::vector<T> Mode(const GridSpec& g, int p, int q, double amplitude) {
  std::vector<T> h(static_cast<size_t>(g.nx) * g.ny);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      h[static_cast<size_t>(j) * g.nx + i] =
          static_cast<T>(amplitude * std::cos(kPi * p * (i + 0.5) / g.nx) *
                         std::cos(kPi * q * (j + 0.5) / g.ny));
  return h;
}

// Discrete dispersion relation of the scheme for that mode:
// cos(omega dt) = 1 - kappa/2, kappa = k * 4 (sin^2(tx/2) + sin^2(ty/2)).
double ModeOmega(const GridSpec& g, const WaterOptions& o, int p, int q) {
  const double dt = o.courant * g.cell_m / o.wave_speed_m_per_s;
  const double k = o.courant * o.courant;
  const double sx = std::sin(0.5 * kPi * p / g.nx);
  const double sy = std::sin(0.5 * kPi * q / g.ny);
  const double kappa = 4 * k * (sx * sx + sy * sy);
  return std::acos(1 - 0.5 * kappa) / dt;
}

// Times of the sign changes of a sampled signal (linear interpolation).
std::vector<double> ZeroCrossings(const std::vector<double>& x, double dt) {
  std::vector<double> t;
  for (size_t n = 1; n < x.size(); ++n) {
    if ((x[n - 1] < 0) != (x[n] < 0)) {
      const double f = x[n - 1] / (x[n - 1] - x[n]);
      t.push_back((n - 1 + f) * dt);
    }
  }
  return t;
}

TEST(GridSpecTest, ForTankKeepsCellsSquare) {
  const GridSpec g = GridSpec::ForTank(0.17, 0.11, 0.025, 128);
  EXPECT_EQ(g.nx, 128);
  EXPECT_EQ(g.ny, 83);  // round(0.11 / (0.17/128)) = round(82.8)
  EXPECT_DOUBLE_EQ(g.cell_m, 0.17 / 128);
  std::string error;
  EXPECT_TRUE(g.IsValid(&error)) << error;
  EXPECT_EQ(GridSpec::ForTank(0.17, 0.0001, 0.02, 64).ny, 2);
}

TEST(GridSpecTest, RejectsNonsense) {
  std::string error;
  GridSpec g = Grid(1, 10);
  EXPECT_FALSE(g.IsValid(&error));
  EXPECT_NE(error.find("2x2"), std::string::npos);
  g = Grid(10, 10, std::nan(""));
  EXPECT_FALSE(g.IsValid(&error));
  g = Grid(10, 10, -1);
  EXPECT_FALSE(g.IsValid(&error));
  g = Grid(10, 10, 0.01, INFINITY);
  EXPECT_FALSE(g.IsValid(&error));
  g = Grid(16385, 10);
  EXPECT_FALSE(g.IsValid(&error));
}

TEST(WaterOptionsTest, DefaultsAreValid) {
  std::string error;
  EXPECT_TRUE(WaterOptions().IsValid(&error)) << error;
}

TEST(WaterOptionsTest, RejectsEachNonsensicalValue) {
  const double nan = std::nan("");
  const double inf = INFINITY;
  struct Case {
    const char* what;
    void (*set)(WaterOptions*, double);
    std::vector<double> bad;
  };
  const std::vector<Case> cases = {
      {"wave speed",
       [](WaterOptions* o, double v) { o->wave_speed_m_per_s = v; },
       {0, -1, nan, inf, 1e4}},
      {"viscosity",
       [](WaterOptions* o, double v) { o->viscosity_per_s = v; },
       {-1e-9, nan, inf}},
      {"courant",
       [](WaterOptions* o, double v) { o->courant = v; },
       {0, 0.51, 0.8, nan}},
      {"pen strength",
       [](WaterOptions* o, double v) { o->pen_strength_m_per_s2 = v; },
       {nan, inf, -inf, -1}},
      {"pen radius",
       [](WaterOptions* o, double v) { o->pen_radius_m = v; },
       {0, -0.01, nan, inf}},
      {"rest speed",
       [](WaterOptions* o, double v) { o->rest_speed_m_per_s = v; },
       {-1, nan}},
      {"rest height",
       [](WaterOptions* o, double v) { o->rest_height_m = v; },
       {-1, nan}},
      {"sub-steps",
       [](WaterOptions* o, double v) { o->max_substeps = static_cast<int>(v); },
       {0, -5, 2e6}},
  };
  for (const Case& c : cases) {
    for (double v : c.bad) {
      WaterOptions o;
      c.set(&o, v);
      std::string error;
      EXPECT_FALSE(o.IsValid(&error)) << c.what << " = " << v;
      EXPECT_NE(error.find(c.what), std::string::npos) << error;
    }
  }
  WaterOptions o;
  o.walls = static_cast<WallMode>(7);
  EXPECT_FALSE(o.IsValid(nullptr));
  o = WaterOptions();
  o.obstacles = static_cast<ObstacleMode>(7);
  EXPECT_FALSE(o.IsValid(nullptr));
}

TEST(WaterTest, SubStepKeepsCourantAtMostHalf) {
  for (double c : {0.01, 0.3, 5.0, 300.0}) {
    WaterOptions o;
    o.wave_speed_m_per_s = c;
    Water water(Grid(16, 8), o);
    EXPECT_LE(c * water.substep_s() / water.grid().cell_m, 0.5 + 1e-12);
  }
}

TEST(WaterTest, RejectsBadInputWithoutChangingState) {
  Water water(Grid(16, 8), WaterOptions());
  EXPECT_FALSE(water.SetPenTip({std::nan(""), 0, 0}));
  EXPECT_FALSE(water.SetPenTip({0, INFINITY, 0}));
  EXPECT_FALSE(water.SetPenTip({0, 0, -INFINITY}));
  EXPECT_FALSE(water.Advance(-0.1));
  EXPECT_FALSE(water.Advance(std::nan("")));
  EXPECT_FALSE(water.Advance(INFINITY));
  std::vector<float> h(16 * 8, 0.f);
  h[5] = std::nanf("");
  EXPECT_FALSE(water.SetState(h));
  EXPECT_FALSE(water.SetState(std::vector<float>(3, 0.f)));
  WaterOptions bad;
  bad.viscosity_per_s = -1;
  std::string error;
  EXPECT_FALSE(water.SetOptions(bad, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(water.options().viscosity_per_s, WaterOptions().viscosity_per_s);
  EXPECT_EQ(water.counter(), 0u);
  EXPECT_TRUE(water.at_rest());
}

TEST(WaterTest, AtRestAdvanceDoesNothingUntilTouched) {
  Water water(Grid(64, 40), WaterOptions());
  water.SetPenTip({0, 0, 0.05});  // above the water
  for (int f = 0; f < 10; ++f) {
    ASSERT_TRUE(water.Advance(1.0 / 60));
    EXPECT_EQ(water.stats().substeps, 0);
    EXPECT_FALSE(water.stats().changed);
    EXPECT_TRUE(water.stats().at_rest);
  }
  EXPECT_EQ(water.counter(), 0u);
  // The tip goes under the surface: it wakes and makes waves.
  water.SetPenTip({0, 0, 0.02});
  ASSERT_TRUE(water.Advance(1.0 / 60));
  EXPECT_GT(water.stats().substeps, 0);
  EXPECT_TRUE(water.stats().pen_touched);
  EXPECT_TRUE(water.stats().changed);
  EXPECT_FALSE(water.stats().at_rest);
  EXPECT_NE(water.counter(), 0u);
  EXPECT_LT(water.HeightAtPoint(0, 0), 0);  // pushed down
}

TEST(WaterTest, ViscousWaterComesBackToRestAndStays) {
  WaterOptions o;
  o.viscosity_per_s = 20;
  Water water(Grid(48, 32), o);
  water.SetPenTip({0.01, 0, 0.02});
  for (int f = 0; f < 10; ++f) water.Advance(1.0 / 60);
  water.ClearPen();
  int frames = 0;
  while (!water.at_rest() && frames < 6000) {
    water.Advance(1.0 / 60);
    ++frames;
  }
  ASSERT_TRUE(water.at_rest()) << water.stats().BriefReport();
  // Snapped flat: every water cell at the same height, volume kept.
  const float h0 = water.heights()[0];
  for (int c = 0; c < 48 * 32; ++c) ASSERT_EQ(water.heights()[c], h0);
  EXPECT_NEAR(h0, 0, 1e-7);
  const auto counter = water.counter();
  for (int f = 0; f < 100; ++f) {
    water.Advance(1.0 / 60);
    EXPECT_FALSE(water.stats().changed);
  }
  EXPECT_EQ(water.counter(), counter);
}

TEST(WaterTest, CounterChangesWheneverTheSurfaceDoes) {
  Water water(Grid(32, 32), Lossless());
  auto last = water.counter();
  water.SetState(Mode<float>(water.grid(), 1, 0, 1e-3));
  EXPECT_NE(water.counter(), last);
  for (int f = 0; f < 20; ++f) {
    last = water.counter();
    water.Advance(1.0 / 60);
    EXPECT_EQ(water.stats().changed, water.counter() != last);
    EXPECT_EQ(water.stats().changed, water.stats().substeps > 0);
    EXPECT_EQ(water.View().counter, water.counter());
  }
  // A frame shorter than a sub-step changes nothing.
  last = water.counter();
  water.Advance(0.1 * water.substep_s());
  if (water.stats().substeps == 0) {
    EXPECT_EQ(water.counter(), last);
  }
}

TEST(WaterTest, SurplusTimeIsDroppedAndReported) {
  WaterOptions o = Lossless();
  o.max_substeps = 3;
  Water water(Grid(16, 16), o);
  water.SetState(Mode<float>(water.grid(), 1, 1, 1e-3));
  ASSERT_TRUE(water.Advance(1.0));
  const double dt = water.substep_s();
  EXPECT_EQ(water.stats().substeps, 3);
  EXPECT_NEAR(water.stats().dropped_s, std::floor(1.0 / dt) * dt - 3 * dt,
              1e-9);
  // Frame dt of 0 runs nothing and drops nothing.
  ASSERT_TRUE(water.Advance(0));
  EXPECT_EQ(water.stats().substeps, 0);
  EXPECT_EQ(water.stats().dropped_s, 0);
}

// Runs a straight pen stroke (linear in time, so any frame rate samples it
// exactly) for `duration` seconds at `fps`; returns the heights.
std::vector<float> RunStroke(double fps, double duration) {
  WaterOptions o;
  o.viscosity_per_s = 0.5;
  o.pen_radius_m = 0.01;
  o.pen_strength_m_per_s2 = 30;
  Water water(GridSpec::ForTank(0.17, 0.11, 0.025, 96), o);
  auto tip = [&](double t) -> std::array<double, 3> {
    const double a = t / duration;
    return {-0.06 + 0.11 * a, -0.03 + 0.05 * a, 0.028 - 0.012 * a};
  };
  water.SetPenTip(tip(0));
  water.Advance(0);
  const int frames = static_cast<int>(std::lround(duration * fps));
  for (int f = 1; f <= frames; ++f) {
    water.SetPenTip(tip(f / fps));
    water.Advance(1 / fps);
  }
  return std::vector<float>(water.heights(),
                            water.heights() + 96 * water.grid().ny);
}

// Frame-rate independence: the same stroke at 30, 60 and 144 Hz gives the
// same waves. Stated tolerance: max |h_a - h_b| <= 1e-4 * max |h| (float
// rounding; the sub-step sequence and the interpolated tip are the same).
TEST(WaterTest, ResultsDoNotDependOnFrameRate) {
  const std::vector<float> h30 = RunStroke(30, 1.0);
  const std::vector<float> h60 = RunStroke(60, 1.0);
  const std::vector<float> h144 = RunStroke(144, 1.0);
  double max_h = 0, d60 = 0, d144 = 0;
  for (size_t c = 0; c < h30.size(); ++c) {
    max_h = std::max(max_h, std::abs(double(h30[c])));
    d60 = std::max(d60, std::abs(double(h60[c]) - h30[c]));
    d144 = std::max(d144, std::abs(double(h144[c]) - h30[c]));
  }
  ASSERT_GT(max_h, 1e-5);  // the stroke did make waves
  EXPECT_LE(d60, 1e-4 * max_h);
  EXPECT_LE(d144, 1e-4 * max_h);
}

// A stroke of 10 cm within ONE frame leaves a continuous trough: every cell
// centre along the path is pushed down, not just the frame's end points.
TEST(WaterTest, FastStrokeLeavesContinuousWake) {
  WaterOptions o;
  o.pen_radius_m = 0.01;  // sigma = 2 mm
  o.pen_strength_m_per_s2 = 50;
  o.viscosity_per_s = 0;
  Water water(GridSpec::ForTank(0.17, 0.11, 0.025, 128), o);
  water.SetPenTip({-0.05, 0, 0.02});
  water.Advance(0);
  water.SetPenTip({0.05, 0, 0.02});
  water.Advance(0.1);  // 1 m/s
  ASSERT_GT(water.stats().substeps, 20);
  // Sample the path away from its ends. Waves move 3 cm in 0.1 s, so check
  // the trough right after the pen passed: the newest part of the path.
  for (double x = 0.035; x <= 0.048; x += 0.001)
    EXPECT_LT(water.HeightAtPoint(x, 0), -1e-7) << "x = " << x;
}

TEST(WaterTest, PenForceConservesVolumeAndScalesWithStrength) {
  WaterOptions o = Lossless();
  o.pen_strength_m_per_s2 = 10;
  Water a(Grid(40, 30), o);
  o.pen_strength_m_per_s2 = 20;
  Water b(Grid(40, 30), o);
  for (Water* w : {&a, &b}) {
    w->SetPenTip({0.003, -0.002, 0.01});
    w->Advance(0);
    w->Advance(0.05);
    EXPECT_TRUE(w->stats().pen_touched);
    EXPECT_NEAR(w->stats().volume_m3, 0, 1e-6 * w->stats().abs_volume_m3);
  }
  // Linear in s (same sub-steps, the tip stays under the surface).
  for (int c = 0; c < 40 * 30; c += 37)
    EXPECT_NEAR(b.heights()[c], 2 * a.heights()[c],
                1e-4 * std::abs(b.heights()[c]) + 1e-12);
}

TEST(WaterTest, RadiusControlsFrequency) {
  // A small radius puts more of the energy into short waves: compare the
  // mean squared slope per unit mean squared height.
  auto roughness = [](double radius) {
    WaterOptions o = Lossless();
    o.pen_radius_m = radius;
    Water w(GridSpec::ForTank(0.17, 0.11, 0.025, 128), o);
    w.SetPenTip({0, 0, 0.01});
    w.Advance(0);
    w.Advance(0.02);
    w.ClearPen();
    w.Advance(0.1);
    std::vector<float> gx, gy;
    ComputeGradients(w.View(), &gx, &gy);
    double s2 = 0, h2 = 0;
    for (size_t c = 0; c < gx.size(); ++c) {
      s2 += gx[c] * gx[c] + gy[c] * gy[c];
      h2 += w.heights()[c] * w.heights()[c];
    }
    return s2 / h2;
  };
  EXPECT_GT(roughness(0.01), 4 * roughness(0.04));
}

TEST(WaterTest, RuntimeChangesOfStrengthRadiusViscosityAndSpeed) {
  Water water(Grid(40, 30), Lossless());
  water.SetState(Mode<float>(water.grid(), 2, 1, 1e-3));
  water.Advance(0.05);
  const double v_before = water.VelocityAt(3, 4);
  WaterOptions o = water.options();
  o.wave_speed_m_per_s *= 2;
  o.pen_strength_m_per_s2 = 5;
  o.pen_radius_m = 0.002;
  o.viscosity_per_s = 3;
  std::string error;
  ASSERT_TRUE(water.SetOptions(o, &error)) << error;
  EXPECT_NEAR(water.substep_s() * o.wave_speed_m_per_s / 0.002, 0.5, 1e-12);
  // v (m/s) is continuous across the change of sub-step.
  EXPECT_NEAR(water.VelocityAt(3, 4), v_before, 1e-6 * std::abs(v_before));
  EXPECT_EQ(water.options().pen_radius_m, 0.002);
  EXPECT_TRUE(water.Advance(0.05));
}

// Wave speed: standing modes oscillate at the frequency the discrete
// dispersion relation predicts, within 1 %.
TEST(WaterPhysicsTest, StandingModesMatchDiscreteDispersion) {
  const GridSpec g = Grid(64, 48, 0.0025);
  struct M {
    int p, q;
  };
  for (const M m : {M{1, 0}, M{5, 0}, M{3, 2}, M{0, 7}}) {
    for (double c : {0.2, 0.6}) {
      WaterOptions o = Lossless();
      o.wave_speed_m_per_s = c;
      Water water(g, o);
      ASSERT_TRUE(water.SetState(Mode<float>(g, m.p, m.q, 1e-3)));
      const double omega = ModeOmega(g, o, m.p, m.q);
      const double period = 2 * kPi / omega;
      const int steps = static_cast<int>(8 * period / water.substep_s());
      std::vector<double> x;
      for (int n = 0; n < steps; ++n) {
        x.push_back(water.heights()[0]);
        water.Step(1);
      }
      const std::vector<double> t = ZeroCrossings(x, water.substep_s());
      ASSERT_GE(t.size(), 10u);
      const double measured =
          kPi * (t.size() - 1) / (t.back() - t.front());  // rad/s
      EXPECT_NEAR(measured, omega, 0.01 * omega)
          << "mode " << m.p << "," << m.q << " c " << c;
      // And the long-wave limit is the continuum c*|k_wave| (within 1 % for
      // p = 1 on 64 cells).
      if (m.p == 1 && m.q == 0) {
        EXPECT_NEAR(measured, c * kPi / (g.nx * g.cell_m),
                    0.01 * c * kPi / (g.nx * g.cell_m));
      }
    }
  }
}

// Amplitude of |h| extrema over time, refined by a parabola through the
// three samples around each extremum.
std::vector<std::pair<double, double>> Peaks(const std::vector<double>& x,
                                             double dt) {
  std::vector<std::pair<double, double>> peaks;
  for (size_t n = 1; n + 1 < x.size(); ++n) {
    const double a = std::abs(x[n - 1]), b = std::abs(x[n]),
                 c = std::abs(x[n + 1]);
    if (b > a && b >= c) {
      const double den = a - 2 * b + c;
      const double off = den != 0 ? 0.5 * (a - c) / den : 0;
      peaks.push_back({(n + off) * dt, b - 0.25 * (a - c) * off});
    }
  }
  return peaks;
}

// Viscosity: the measured amplitude decay rate of an oscillating mode is the
// documented viscosity/2 per second, within 2 %, for several wave speeds
// (sub-step sizes) and modes.
TEST(WaterPhysicsTest, AmplitudeDecaysAtHalfTheViscosity) {
  const GridSpec g = Grid(48, 32, 0.003);
  // Underdamped cases (omega >= ~5 * viscosity): {viscosity, c, mode p}.
  struct Case {
    double viscosity, c;
    int p;
  };
  for (const Case cs : {Case{0.5, 0.15, 1}, Case{2, 0.5, 1}, Case{2, 0.15, 4},
                        Case{8, 0.5, 4}, Case{8, 0.3, 12}}) {
    {
      {
        const double viscosity = cs.viscosity, c = cs.c;
        const int p = cs.p;
        WaterOptions o = Lossless();
        o.viscosity_per_s = viscosity;
        o.wave_speed_m_per_s = c;
        Water water(g, o);
        ASSERT_TRUE(water.SetState(Mode<float>(g, p, 0, 1e-2)));
        // Until the amplitude has fallen by e^-3 (further down, the float
        // rounding left in the undamped mean would dominate the peaks).
        const double duration = 6.0 / viscosity;
        const int steps = static_cast<int>(duration / water.substep_s());
        std::vector<double> x;
        for (int n = 0; n < steps; ++n) {
          x.push_back(water.heights()[0]);
          water.Step(1);
        }
        const auto peaks = Peaks(x, water.substep_s());
        ASSERT_GE(peaks.size(), 6u);
        // Least-squares slope of log amplitude against time.
        double st = 0, sl = 0, stt = 0, stl = 0;
        for (const auto& [t, a] : peaks) {
          const double l = std::log(a);
          st += t;
          sl += l;
          stt += t * t;
          stl += t * l;
        }
        const double n = peaks.size();
        const double slope = (n * stl - st * sl) / (n * stt - st * st);
        EXPECT_NEAR(-slope, viscosity / 2, 0.02 * viscosity / 2)
            << "viscosity " << viscosity << " c " << c << " p " << p;
      }
    }
  }
}

template <typename T>
std::vector<T> SmoothRandom(const GridSpec& g, unsigned seed, double amp) {
  std::vector<T> h(static_cast<size_t>(g.nx) * g.ny, T(0));
  unsigned s = seed;
  auto rnd = [&]() {
    s = s * 1664525u + 1013904223u;
    return (s >> 8) / double(1 << 24) - 0.5;
  };
  for (int m = 0; m < 6; ++m) {
    const double a = rnd() * amp, fx = rnd() * 0.8, fy = rnd() * 0.8,
                 ph = rnd() * 6;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        h[static_cast<size_t>(j) * g.nx + i] +=
            static_cast<T>(a * std::sin(fx * i + fy * j + ph));
  }
  return h;
}

// Energy: with no viscosity and no input, the scheme's discrete invariant
// drifts by less than 1e-9 relative over 1e5 sub-steps (double kernel), for
// open water and for both obstacle treatments.
TEST(WaterPhysicsTest, EnergyInvariantHoldsOver1e5Steps) {
  const GridSpec g = Grid(24, 16, 0.004);
  for (int variant = 0; variant < 3; ++variant) {
    WaterOptions o = Lossless();
    o.obstacles = variant == 2 ? ObstacleMode::kZero : ObstacleMode::kReflect;
    WaterD water(g, o);
    if (variant > 0) {
      Obstacle box;
      box.shape = Obstacle::Shape::kBox;
      box.box_size_m = {0.02, 0.012, 0.1};
      box.tank_from_obstacle = RigidTransform::FromQuaternion(
          0.96, 0, 0, 0.28, {0.01, -0.004, 0.02});
      ASSERT_GE(water.AddObstacle(box, nullptr), 0);
      ASSERT_LT(water.num_water_cells(), g.nx * g.ny);
    }
    std::vector<double> v = SmoothRandom<double>(g, 7, 0.05);
    ASSERT_TRUE(water.SetState(SmoothRandom<double>(g, 3, 1e-3), &v));
    ASSERT_TRUE(water.Advance(0));  // statistics of the initial state
    const double e0 = water.stats().energy;
    ASSERT_GT(e0, 0);
    const double dt = water.substep_s();
    double worst = 0;
    for (int chunk = 0; chunk < 100; ++chunk) {
      ASSERT_TRUE(water.Advance(1000 * dt));
      ASSERT_EQ(water.stats().substeps, 1000);
      worst = std::max(worst, std::abs(water.stats().energy - e0) / e0);
    }
    EXPECT_LT(worst, 1e-9) << "variant " << variant;
  }
}

// The float kernel keeps the invariant to float rounding too (informative
// bound: 1e-4 over 1e4 steps).
TEST(WaterPhysicsTest, EnergyInvariantFloat) {
  const GridSpec g = Grid(32, 24, 0.004);
  Water water(g, Lossless());
  ASSERT_TRUE(water.SetState(SmoothRandom<float>(g, 5, 1e-3)));
  water.Advance(0);
  const double e0 = water.stats().energy;
  for (int chunk = 0; chunk < 10; ++chunk) {
    water.Advance(1000 * water.substep_s());
    EXPECT_NEAR(water.stats().energy, e0, 1e-4 * e0);
  }
}

// Volume: under pen forces and reflecting obstacles the net change of
// sum(h) d^2 over 1e4 sub-steps stays below 1e-6 of sum(|h|) d^2.
TEST(WaterPhysicsTest, VolumeConservedUnderForcesAndReflectingObstacles) {
  WaterOptions o;
  o.obstacles = ObstacleMode::kReflect;
  o.viscosity_per_s = 0.2;
  o.pen_strength_m_per_s2 = 40;
  o.pen_radius_m = 0.008;
  o.rest_speed_m_per_s = 0;
  o.rest_height_m = 0;
  o.max_substeps = 100000;
  Water water(GridSpec::ForTank(0.17, 0.11, 0.025, 64), o);
  Obstacle pillar;
  pillar.shape = Obstacle::Shape::kCylinder;
  pillar.radius_m = 0.012;
  pillar.height_m = 0.05;
  pillar.tank_from_obstacle = RigidTransform::FromTranslation(0.045, 0.015, 0);
  Obstacle box;
  box.shape = Obstacle::Shape::kBox;
  box.box_size_m = {0.03, 0.01, 0.06};
  box.tank_from_obstacle =
      RigidTransform::FromQuaternion(0.92, 0, 0, 0.39, {-0.04, -0.02, 0.02});
  ASSERT_GE(water.AddObstacle(pillar, nullptr), 0);
  const int moving = water.AddObstacle(box, nullptr);
  ASSERT_GE(moving, 0);
  const double dt = water.substep_s();
  int steps = 0;
  double t = 0;
  while (steps < 10000) {
    t += 10 * dt;
    water.SetPenTip({0.06 * std::cos(2 * t), 0.035 * std::sin(3 * t),
                     std::sin(5 * t) > -0.3 ? 0.015 : 0.04});
    // The box wanders too (reflecting treatment redistributes its volume).
    water.SetObstaclePose(moving,
                          RigidTransform::FromQuaternion(
                              std::cos(t), 0, 0, std::sin(t),
                              {-0.04 + 0.01 * std::sin(t), -0.02, 0.02}));
    ASSERT_TRUE(water.Advance(10 * dt));
    steps += water.stats().substeps;
  }
  const AdvanceStats& s = water.stats();
  ASSERT_GT(s.abs_volume_m3, 0);
  EXPECT_LT(std::abs(s.volume_m3), 1e-6 * s.abs_volume_m3) << s.BriefReport();
}

TEST(WaterPhysicsTest, AbsorbingWallsDrainTheEnergy) {
  auto energy_after = [](WallMode walls) {
    WaterOptions o = Lossless();
    o.walls = walls;
    const GridSpec g = Grid(64, 64, 0.002);
    Water water(g, o);
    // A bump in the middle spreads out and meets the walls.
    std::vector<float> h(64 * 64);
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i)
        h[j * 64 + i] =
            1e-3f *
            std::exp(-((i - 31.5) * (i - 31.5) + (j - 31.5) * (j - 31.5)) /
                     18.f);
    water.SetState(h);
    water.Advance(0);
    const double e0 = water.stats().energy;
    // Three crossings of the tank.
    water.Advance(3 * 64 * 0.002 / o.wave_speed_m_per_s);
    return water.stats().energy / e0;
  };
  EXPECT_NEAR(energy_after(WallMode::kReflect), 1.0, 1e-3);
  EXPECT_LT(energy_after(WallMode::kAbsorb), 0.1);
}

}  // namespace
}  // namespace ripple::sim
