// The capillary-gravity model against the physics it claims: the dispersion
// relation and viscous decay of every mode, an analytic drop in open water,
// volume conservation, reflecting obstacles, frame-rate independence, the
// pen's displaced volume, rest and bad input.
#include "sim/spectral_water.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "sim/cosine_transform.h"
#include "sim/dispersion.h"
#include "sim/water_factory.h"

namespace ripple::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

GridSpec Grid(int nx, int ny, double cell_m, double level_m = 0.025) {
  GridSpec g;
  g.nx = nx;
  g.ny = ny;
  g.cell_m = cell_m;
  g.rest_level_m = level_m;
  return g;
}

WaterModelOptions Options(double nu = 1e-6) {
  WaterModelOptions o;
  o.waves = WaveModel::kCapillaryGravity;
  o.spectral.physics.kinematic_viscosity_m2_per_s = nu;
  o.spectral.rest_speed_m_per_s = 0;  // never snap in these tests
  o.spectral.rest_height_m = 0;
  o.spectral.shortest_wavelength_m = 1e-6;  // every mode of the grid
  return o;
}

std::unique_ptr<SpectralWater> Make(const GridSpec& g,
                                    const WaterModelOptions& o) {
  std::string error;
  auto w = SpectralWater::Create(g, o, &error);
  EXPECT_TRUE(w) << error;
  return w;
}

TEST(CapillaryGravityTest, PublishedSpeeds) {
  CapillaryGravity water;
  water.depth_m = 1.0;  // deep water
  // Minimum phase speed 0.231 m/s at 17.1 mm; 5 mm ripples 0.315 m/s.
  double best_c = 1e9, best_lambda = 0;
  for (double lambda = 0.010; lambda < 0.030; lambda += 1e-5) {
    const double c = water.PhaseSpeed(2 * kPi / lambda);
    if (c < best_c) best_c = c, best_lambda = lambda;
  }
  EXPECT_NEAR(best_c, 0.231, 0.001);
  EXPECT_NEAR(best_lambda, 0.0171, 0.0002);
  EXPECT_NEAR(water.PhaseSpeed(2 * kPi / 0.005), 0.315, 0.001);
  EXPECT_NEAR(water.PhaseSpeed(2 * kPi / 0.004), 0.347, 0.001);
  // Short capillary waves: group speed 1.5x phase speed.
  const double k = 2 * kPi / 0.001;
  EXPECT_NEAR(water.GroupSpeed(k) / water.PhaseSpeed(k), 1.5, 0.01);
  // 5 mm ripples e-fold in 0.32 s at nu = 1e-6.
  EXPECT_NEAR(1.0 / water.DampingRate(2 * kPi / 0.005), 0.317, 0.002);
  // Shallow limit sqrt(g H).
  water.depth_m = 0.025;
  water.tension_m3_per_s2 = 0;
  EXPECT_NEAR(water.PhaseSpeed(1e-3), std::sqrt(9.81 * 0.025), 1e-4);
}

TEST(CosineTransformTest, BasisAndRoundTrip) {
  const int nx = 12, ny = 10;
  CosineTransform2D t(nx, ny);
  AlignedFloats coeff = t.NewBuffer(), samples = t.NewBuffer(),
                scratch = t.NewBuffer(), back = t.NewBuffer();
  coeff[3 * nx + 5] = 2.0f;  // a = 5, b = 3
  coeff[0] = 0.5f;
  t.Synthesize(coeff.data(), samples.data(), scratch.data());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      EXPECT_NEAR(samples[j * nx + i],
                  0.5 + 2.0 * std::cos(kPi * 5 * (i + 0.5) / nx) *
                            std::cos(kPi * 3 * (j + 0.5) / ny),
                  1e-5);
  t.Analyze(samples.data(), back.data());
  for (int c = 0; c < nx * ny; ++c) EXPECT_NEAR(back[c], coeff[c], 1e-5);
  // Row-limited synthesis of the same coefficients (nonzero in rows < 4).
  AlignedFloats rows = t.NewBuffer(), scratch2 = t.NewBuffer();
  t.SynthesizeRows(coeff.data(), 4, rows.data(), scratch2.data());
  for (int c = 0; c < nx * ny; ++c) EXPECT_NEAR(rows[c], samples[c], 1e-6);
  // The sparse 1-D analysis agrees with the dense one.
  std::vector<float> row = {0.3f, -1.0f, 2.0f}, c1(nx);
  CosineTransform2D::AnalyzeSparse1D(nx, 4, row.data(), 3, c1.data());
  for (int i = 0; i < nx; ++i) {
    double v = 0;
    for (int a = 0; a < nx; ++a)
      v += c1[a] * std::cos(kPi * a * (i + 0.5) / nx);
    const double want = i >= 4 && i < 7 ? row[i - 4] : 0.0;
    EXPECT_NEAR(v, want, 1e-5) << i;
  }
}

// A standing wave cos(k x) along a 120 mm tank: its period and decay,
// measured from the synthesised heights at one cell.
struct ModeFit {
  double omega = 0;  // rad/s, from zero crossings
};

ModeFit MeasureMode(double lambda_m, double nu, double duration_s) {
  const int nx = 240, ny = 4;
  const double d = 0.0005;
  const int a = static_cast<int>(std::lround(2 * nx * d / lambda_m));
  WaterModelOptions o = Options(nu);
  const double dt = 1.0 / 4000.0;
  o.spectral.substep_s = dt;
  auto water = Make(Grid(nx, ny, d), o);
  std::vector<float> h(nx * ny);
  const double amp = 1e-4;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      h[j * nx + i] =
          static_cast<float>(amp * std::cos(kPi * a * (i + 0.5) / nx));
  EXPECT_TRUE(water->SetState(h, nullptr));
  // A cell near an antinode.
  const int probe = 0;
  std::vector<double> t_cross;
  double prev = water->View().heights[probe], t = 0;
  const int steps = static_cast<int>(duration_s / dt);
  for (int s = 0; s < steps; ++s) {
    water->Advance(dt);
    t += dt;
    const double cur = water->View().heights[probe];
    if ((prev > 0) != (cur > 0)) t_cross.push_back(t - dt * cur / (cur - prev));
    prev = cur;
  }
  ModeFit fit;
  if (t_cross.size() >= 3) {
    const double half_periods = t_cross.size() - 1;
    fit.omega = kPi * half_periods / (t_cross.back() - t_cross.front());
  }
  return fit;
}

TEST(SpectralWaterTest, PhaseSpeedFollowsTheDispersionRelation) {
  CapillaryGravity physics;
  physics.depth_m = 0.025;
  for (double lambda_mm :
       {4.0, 5.0, 8.0, 120.0 / 7.0, 30.0, 40.0, 60.0, 80.0}) {
    const double lambda = lambda_mm * 1e-3;
    const double k = 2 * kPi / lambda;
    const double expected = physics.PhaseSpeed(k);
    // About 20 periods.
    const double period = lambda / expected;
    const ModeFit fit = MeasureMode(lambda, 0.0, 20 * period);
    const double measured = fit.omega / k;
    EXPECT_NEAR(measured / expected, 1.0, 0.02)
        << "lambda " << lambda_mm << " mm: expected " << expected
        << " m/s, measured " << measured << " m/s";
  }
}

TEST(SpectralWaterTest, AmplitudeDecaysAtTwiceNuKSquared) {
  for (double lambda_mm : {4.0, 8.0, 20.0}) {
    for (double nu : {1e-6, 1e-5}) {
      const int nx = 240, ny = 4;
      const double d = 0.0005, lambda = lambda_mm * 1e-3;
      const int a = static_cast<int>(std::lround(2 * nx * d / lambda));
      WaterModelOptions o = Options(nu);
      auto water = Make(Grid(nx, ny, d), o);
      std::vector<float> h(nx * ny);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          h[j * nx + i] =
              static_cast<float>(1e-4 * std::cos(kPi * a * (i + 0.5) / nx));
      water->SetState(h, nullptr);
      water->Advance(0.0);  // computes the statistics of the new state
      const double energy0 = water->stats().energy;
      ASSERT_GT(energy0, 0);
      const double t = 0.5;
      for (int f = 0; f < 15; ++f) water->Advance(t / 15);
      const double k = water->ModeWaveNumber(a, 0);
      const double gamma = 2 * nu * k * k;
      // Energy ~ amplitude^2 falls as exp(-2 gamma t).
      const double measured =
          -std::log(water->stats().energy / energy0) / (2 * t);
      EXPECT_NEAR(measured / gamma, 1.0, 0.05) << lambda_mm << " mm, nu " << nu;
    }
  }
}

// A Gaussian drop released from rest in open water (no wall reached yet),
// against the Hankel-transform solution
//   h(r, t) = A s^2 int_0^inf k exp(-k^2 s^2 / 2) cos(omega(k) t) J0(k r) dk.
TEST(SpectralWaterTest, DropMatchesTheAnalyticSolution) {
  const int n = 400;
  const double d = 0.0005;  // 200 mm tank: no reflection reaches the probes
  const double amp = 2e-4, sigma = 0.0015, t_end = 0.1;
  WaterModelOptions o = Options(0.0);
  auto water = Make(Grid(n, n, d, 0.025), o);
  std::vector<float> h(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5 - 0.5 * n) * d, y = (j + 0.5 - 0.5 * n) * d;
      h[j * n + i] = static_cast<float>(
          amp * std::exp(-(x * x + y * y) / (2 * sigma * sigma)));
    }
  ASSERT_TRUE(water->SetState(h, nullptr));
  for (int f = 0; f < 3; ++f) water->Advance(t_end / 3);
  CapillaryGravity physics;
  physics.depth_m = 0.025;
  physics.kinematic_viscosity_m2_per_s = 0;
  const HeightFieldView view = water->View();
  double err2 = 0, ref2 = 0, ref_max = 0;
  const int jc = n / 2;  // the row through y = +d/2
  for (int i = n / 2; i < n / 2 + 100; i += 2) {
    const double x = (i + 0.5 - 0.5 * n) * d, y = (jc + 0.5 - 0.5 * n) * d;
    const double r = std::hypot(x, y);
    double integral = 0;
    const double kmax = 10.0 / sigma, dk = kmax / 6000;
    for (int s = 0; s < 6000; ++s) {
      const double k = (s + 0.5) * dk;
      integral += k * std::exp(-0.5 * k * k * sigma * sigma) *
                  std::cos(physics.Omega(k) * t_end) *
                  std::cyl_bessel_j(0.0, k * r) * dk;
    }
    const double want = amp * sigma * sigma * integral;
    const double got = view.heights[jc * n + i];
    err2 += (got - want) * (got - want);
    ref2 += want * want;
    ref_max = std::max(ref_max, std::abs(want));
  }
  ASSERT_GT(ref_max, 1e-6);  // there are waves on the probed line
  EXPECT_LT(std::sqrt(err2 / ref2), 0.02);
}

TEST(SpectralWaterTest, VolumeIsConservedWithPenAndObstacles) {
  const GridSpec g = GridSpec::ForTankFast(0.17, 0.11, 0.025, 64);
  WaterModelOptions o = Options();
  auto water = Make(g, o);
  Obstacle pillar;
  pillar.shape = Obstacle::Shape::kCylinder;
  pillar.radius_m = 0.012;
  pillar.height_m = 0.05;
  pillar.tank_from_obstacle = RigidTransform::FromTranslation(0.045, 0.015, 0);
  std::string error;
  ASSERT_GE(water->AddObstacle(pillar, &error), 0) << error;
  const double tank_volume = 0.17 * 0.11 * 0.025;
  const double v0 = water->WaterVolume();
  double worst = 0;
  for (int f = 0; f < 10000; ++f) {
    const double t = f / 30.0;
    const double phase = std::fmod(t, 4.0);
    if (phase < 2.0) {
      water->SetPenTip({-0.05 + 0.04 * phase, 0.02 * std::sin(3 * t),
                        0.025 - 0.01 * std::sin(kPi * phase / 2)});
    } else {
      water->ClearPen();
    }
    ASSERT_TRUE(water->Advance(1.0 / 30.0));
    worst = std::max(worst, std::abs(water->WaterVolume() - v0));
    ASSERT_TRUE(std::isfinite(water->stats().max_abs_height_m));
  }
  EXPECT_LT(worst / tank_volume, 1e-6);
}

TEST(SpectralWaterTest, PaperPushKeepsTheVolume) {
  const GridSpec g = Grid(96, 64, 0.17 / 96);
  WaterModelOptions o = Options();
  o.spectral.pen = PenModel::kPaperPush;
  auto water = Make(g, o);
  for (int f = 0; f < 200; ++f) {
    water->SetPenTip({0.03 * std::sin(0.1 * f), 0.01, 0.02});
    water->Advance(1.0 / 30);
  }
  EXPECT_GT(water->stats().max_deviation_m, 1e-5);  // it pushed
  EXPECT_NEAR(water->ModeAmplitude(0, 0), 0.0, 1e-12);
}

TEST(SpectralWaterTest, SlowDipRaisesTheLevelByTheDisplacedVolume) {
  const GridSpec g = GridSpec::ForTankFast(0.17, 0.11, 0.025, 96);
  WaterModelOptions o = Options(1e-4);  // damp the sloshing
  auto water = Make(g, o);
  const double depth = 0.01;
  for (int f = 0; f <= 300; ++f) {
    const double z = 0.025 + 0.005 - std::min(1.0, f / 150.0) * (0.005 + depth);
    water->SetPenTip({0.01, -0.01, z});
    water->Advance(1.0 / 30.0);
  }
  // The shaft is submerged below the raised mean surface.
  const double r = o.spectral.pen_shaft_radius_m;
  const double rise = water->ModeAmplitude(0, 0);
  const double volume = kPi * r * r * (depth + rise);
  EXPECT_NEAR(water->pen_volume_m3(), volume, 1e-12);
  EXPECT_NEAR(rise, volume / (g.nx * g.ny * g.cell_m * g.cell_m), 1e-3 * rise);
  // Quasi-static: the surface stays nearly flat.
  EXPECT_LT(water->stats().max_deviation_m, 0.1 * rise);
}

TEST(SpectralWaterTest, ObstacleReflectsWaves) {
  // A wall-to-wall box across a 1-D channel: a pulse from the left comes
  // back. Without the box the pulse passes at ~0.45 of its height; the
  // surface-only model lets long-wave motion through an obstacle (measured
  // 0.18 for 2-20 mm boxes), so the bound is 0.25.
  const int nx = 400, ny = 4;
  const double d = 0.0005;
  WaterModelOptions o = Options(0.0);
  o.spectral.boundary_step_s = 1.0 / 240.0;
  auto water = Make(Grid(nx, ny, d), o);
  Obstacle wall;
  wall.shape = Obstacle::Shape::kBox;
  wall.box_size_m = {0.02, 0.05, 0.1};
  wall.tank_from_obstacle = RigidTransform::FromTranslation(0.03, 0, 0);
  std::string error;
  ASSERT_GE(water->AddObstacle(wall, &error), 0) << error;
  std::vector<float> h(nx * ny);
  const double x0 = -0.03, s = 0.004, amp = 1e-4;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 - 0.5 * nx) * d;
      h[j * nx + i] = static_cast<float>(
          amp * std::exp(-(x - x0) * (x - x0) / (2 * s * s)));
    }
  ASSERT_TRUE(water->SetState(h, nullptr));
  const double v0 = water->WaterVolume();
  double beyond = 0;
  for (int f = 0; f < 30; ++f) {
    water->Advance(1.0 / 60.0);
    const HeightFieldView v = water->View();
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 - 0.5 * nx) * d;
      if (x > 0.045) beyond = std::max(beyond, std::abs(double(v.heights[i])));
    }
  }
  // The pulse reached the wall and came back (the left half holds it).
  double left = 0;
  const double mean = water->ModeAmplitude(0, 0);
  for (int i = 0; i < nx / 2; ++i)
    left = std::max(left, std::abs(water->View().heights[i] - mean));
  EXPECT_GT(left, 0.1 * amp);
  EXPECT_LT(beyond, 0.25 * amp);
  // Volume of the channel: 200 x 2 mm; conserved to float rounding.
  EXPECT_NEAR(water->WaterVolume(), v0, 1e-6 * 0.2 * 0.002 * 0.025);
}

TEST(SpectralWaterTest, BandLimitKeepsLongWavesExact) {
  // With the default 3 mm band, a 4 mm mode runs exactly as with every mode
  // simulated, and a 2 mm one is not simulated at all.
  const int nx = 240, ny = 4;
  const double d = 0.0005;
  auto run = [&](double lambda, double shortest) {
    WaterModelOptions o = Options(1e-6);
    o.spectral.shortest_wavelength_m = shortest;
    auto water = Make(Grid(nx, ny, d), o);
    const int a = static_cast<int>(std::lround(2 * nx * d / lambda));
    std::vector<float> h(nx * ny);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        h[j * nx + i] =
            static_cast<float>(1e-4 * std::cos(kPi * a * (i + 0.5) / nx));
    water->SetState(h, nullptr);
    for (int f = 0; f < 7; ++f) water->Advance(1.0 / 30);
    return std::vector<float>(water->View().heights,
                              water->View().heights + nx * ny);
  };
  const auto band = run(0.004, 0.003), full = run(0.004, 1e-6);
  for (int i = 0; i < nx * ny; ++i) ASSERT_NEAR(band[i], full[i], 1e-9);
  const auto cut = run(0.002, 0.003);
  for (float v : cut) ASSERT_NEAR(v, 0.0f, 1e-9);
}

TEST(SpectralWaterTest, CoarseViewSamplesTheSameSurface) {
  // The default tank grid with its 3 mm band: the coarse view's cells are
  // exact samples of the fine surface's band-limited function.
  const GridSpec g =
      DefaultGrid(WaveModel::kCapillaryGravity, 0.17, 0.11, 0.025, 256);
  WaterModelOptions o;
  auto water = Make(g, o);
  for (int f = 0; f < 20; ++f) {
    water->SetPenTip(
        {0.03 * std::cos(f * 0.3), 0.02 * std::sin(f * 0.3), 0.015});
    water->Advance(1.0 / 30);
  }
  const HeightFieldView fine = water->View(), coarse = water->CoarseView();
  ASSERT_LT(coarse.nx, fine.nx);
  EXPECT_NEAR(coarse.nx * coarse.cell_m, fine.nx * fine.cell_m, 1e-12);
  EXPECT_NEAR(coarse.ny * coarse.cell_m, fine.ny * fine.cell_m, 1e-9);
  EXPECT_EQ(coarse.counter, fine.counter);
  // Compare at coarse cell centres, evaluating the fine surface there from
  // its own modes (a direct sum over the band).
  const int bx = water->band_nx(), by = water->band_ny();
  double worst = 0, peak = 0;
  for (int j = 3; j < coarse.ny; j += 17) {
    for (int i = 5; i < coarse.nx; i += 23) {
      const double fx = (i + 0.5) * coarse.cell_m / fine.cell_m - 0.5;
      const double fy = (j + 0.5) * coarse.cell_m / fine.cell_m - 0.5;
      double h = 0;
      for (int b = 0; b < by; ++b)
        for (int a = 0; a < bx; ++a)
          h += water->ModeAmplitude(a, b) *
               std::cos(kPi * a * (fx + 0.5) / fine.nx) *
               std::cos(kPi * b * (fy + 0.5) / fine.ny);
      worst = std::max(worst, std::abs(h - coarse.heights[j * coarse.nx + i]));
      peak = std::max(peak, std::abs(h));
    }
  }
  ASSERT_GT(peak, 1e-6);
  EXPECT_LT(worst, 1e-3 * peak + 1e-9);
}

// Frequency control: the same stroke with a smaller push radius puts its
// energy into shorter waves (a larger energy-weighted mean wave number).
TEST(SpectralWaterTest, PushRadiusSetsTheDominantWavelength) {
  auto mean_k = [](double radius) {
    const GridSpec g =
        DefaultGrid(WaveModel::kCapillaryGravity, 0.17, 0.11, 0.025, 256);
    WaterModelOptions o;
    o.spectral.pen_radius_m = radius;
    auto water = Make(g, o);
    for (int f = 0; f < 20; ++f) {
      water->SetPenTip({-0.05 + 0.004 * f, 0.0, 0.015});  // 0.12 m/s
      water->Advance(1.0 / 30);
    }
    double wk = 0, w = 0;
    for (int b = 0; b < water->band_ny(); ++b)
      for (int a = 0; a < water->band_nx(); ++a) {
        if (a == 0 && b == 0) continue;
        const double x = water->ModeAmplitude(a, b);
        wk += x * x * water->ModeWaveNumber(a, b);
        w += x * x;
      }
    return wk / w;
  };
  const double small = mean_k(0.002), large = mean_k(0.008);
  std::printf("mean k: r 2 mm %.0f, r 8 mm %.0f rad/m\n", small, large);
  EXPECT_GT(small, 1.3 * large) << small << " vs " << large << " rad/m";
}

TEST(SpectralWaterTest, ThinObstaclesStayBounded) {
  // The same stroke with and without a thin wall in its way: the wall may
  // reflect but must not feed energy into the water.
  auto run = [](double width) {
    const int nx = 200, ny = 40;
    WaterModelOptions o = Options(0.0);
    auto water = Make(Grid(nx, ny, 0.0005), o);
    if (width > 0) {
      Obstacle wall;
      wall.shape = Obstacle::Shape::kBox;
      wall.box_size_m = {width, 0.01, 0.1};
      wall.tank_from_obstacle =
          RigidTransform::FromTranslation(0.01, -0.005, 0);
      std::string error;
      EXPECT_GE(water->AddObstacle(wall, &error), 0) << error;
    }
    double worst = 0;
    for (int f = 0; f < 240; ++f) {
      if (f < 120)
        water->SetPenTip({0.03 * std::sin(f * 0.2), 0.004, 0.03 - 0.0001 * f});
      else
        water->ClearPen();
      water->Advance(1.0 / 30);
      worst = std::max(worst, water->stats().max_deviation_m);
    }
    return worst;
  };
  const double open = run(0);
  for (double width : {0.001, 0.002, 0.005}) {
    const double walled = run(width);
    EXPECT_TRUE(std::isfinite(walled));
    EXPECT_LT(walled, 2 * open) << width << " m";
  }
}

TEST(SpectralWaterTest, FrameRateIndependent) {
  const GridSpec g = Grid(64, 48, 0.001);
  WaterModelOptions o = Options();
  auto a = Make(g, o), b = Make(g, o);
  std::vector<float> h(64 * 48);
  for (int i = 0; i < 64 * 48; ++i) h[i] = 1e-4f * std::sin(0.37f * i);
  a->SetState(h, nullptr);
  b->SetState(h, nullptr);
  for (int f = 0; f < 30; ++f) a->Advance(1.0 / 30);
  for (int f = 0; f < 120; ++f) b->Advance(1.0 / 120);
  for (int i = 0; i < 64 * 48; ++i)
    ASSERT_NEAR(a->View().heights[i], b->View().heights[i], 1e-9);
}

TEST(SpectralWaterTest, RestsAndReportsUnchanged) {
  const GridSpec g = Grid(64, 48, 0.001);
  WaterModelOptions o;
  o.spectral.physics.kinematic_viscosity_m2_per_s = 1e-4;
  auto water = Make(g, o);
  for (int f = 0; f < 10; ++f) {
    water->SetPenTip({0, 0, 0.02 - 0.001 * f});
    water->Advance(1.0 / 30);
  }
  EXPECT_FALSE(water->at_rest());
  water->ClearPen();
  int f = 0;
  for (; f < 3000 && !water->at_rest(); ++f) water->Advance(1.0 / 30);
  EXPECT_TRUE(water->at_rest()) << "still moving after " << f << " frames";
  const auto counter = water->counter();
  water->Advance(1.0 / 30);
  EXPECT_FALSE(water->stats().changed);
  EXPECT_EQ(water->counter(), counter);
}

TEST(SpectralWaterTest, HoneyIsStableAndOverDamped) {
  // nu = 1e-2 m^2/s: every resolved mode but the longest is over-damped, so
  // the energy only falls and the surface creeps flat.
  const GridSpec g = Grid(64, 48, 0.001);
  auto water = Make(g, Options(1e-2));
  std::vector<float> h(64 * 48);
  for (int i = 0; i < 64 * 48; ++i) h[i] = 1e-3f * ((i * 7919) % 13 - 6) / 6.0f;
  water->SetState(h, nullptr);
  water->Advance(0.0);
  double last_energy = water->stats().energy;
  const double first_dev = water->stats().max_deviation_m;
  for (int f = 0; f < 60; ++f) {
    water->Advance(1.0 / 30);
    ASSERT_TRUE(std::isfinite(water->stats().energy));
    EXPECT_LE(water->stats().energy, last_energy * (1 + 1e-6)) << f;
    last_energy = water->stats().energy;
  }
  EXPECT_LT(water->stats().max_deviation_m, 0.5 * first_dev);
}

// The stress ranges of the paper scheme's stability tests, on this model:
// random grids, radii from below a cell to beyond the tank, viscosities from
// none to honey, frame times 0 to 10 s, obstacles covering nothing to
// everything, both walls and both pens: never a NaN or an infinity.
TEST(SpectralWaterTest, RandomStressNeverProducesNanOrInf) {
  std::mt19937 rng(7);
  auto log_uniform = [&](double lo, double hi) {
    std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
    return std::exp(u(rng));
  };
  for (int trial = 0; trial < 40; ++trial) {
    const int nx = 2 + static_cast<int>(log_uniform(1, 200));
    const int ny = 2 + static_cast<int>(log_uniform(1, 150));
    const GridSpec g = Grid(nx, ny, 0.17 / nx);
    WaterModelOptions o;
    o.spectral.physics.kinematic_viscosity_m2_per_s =
        trial % 5 == 0 ? 0.0 : log_uniform(1e-7, 1e-2);
    o.spectral.pen_radius_m = log_uniform(1e-5, 1.0);
    o.spectral.pen_pressure_coefficient = log_uniform(1e-3, 100);
    o.spectral.pen_strength_m_per_s2 = log_uniform(1e-6, 1e9);
    o.spectral.pen =
        trial % 3 == 0 ? PenModel::kPaperPush : PenModel::kDisplace;
    o.spectral.walls = trial % 2 ? WallMode::kAbsorb : WallMode::kReflect;
    o.spectral.shortest_wavelength_m = trial % 4 == 0 ? 1e-6 : 0.003;
    auto water = Make(g, o);
    ASSERT_TRUE(water);
    const int cover = trial % 3;
    if (cover > 0) {
      Obstacle box;
      box.shape = Obstacle::Shape::kBox;
      box.box_size_m = cover == 2 ? std::array<double, 3>{1, 1, 1}
                                  : std::array<double, 3>{0.02, 0.01, 0.1};
      std::string error;
      ASSERT_GE(water->AddObstacle(box, &error), 0) << error;
    }
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    for (int f = 0; f < 30; ++f) {
      if (f % 7 == 6)
        water->ClearPen();
      else
        water->SetPenTip({u(rng), u(rng), 0.025 + u(rng) * 0.2});
      const double dt = f % 10 == 9 ? log_uniform(1e-6, 10.0) : 1.0 / 30;
      ASSERT_TRUE(water->Advance(dt));
      const HeightFieldView v = water->View();
      for (int c = 0; c < nx * ny; ++c)
        ASSERT_TRUE(std::isfinite(v.heights[c]))
            << "trial " << trial << " frame " << f;
      const AdvanceStats& s = water->stats();
      for (double x :
           {s.volume_m3, s.energy, s.max_abs_height_m, s.max_speed_m_per_s})
        ASSERT_TRUE(std::isfinite(x))
            << "trial " << trial << ": " << s.BriefReport();
    }
  }
}

TEST(SpectralWaterTest, RejectsBadInput) {
  std::string error;
  WaterModelOptions o;
  o.spectral.physics.kinematic_viscosity_m2_per_s = -1;
  EXPECT_FALSE(SpectralWater::Create(Grid(8, 8, 0.001), o, &error));
  EXPECT_NE(error.find("viscosity"), std::string::npos);
  o = WaterModelOptions();
  EXPECT_FALSE(SpectralWater::Create(Grid(8, 8, 0.001, 0.0), o, &error));
  EXPECT_NE(error.find("depth"), std::string::npos);
  auto water = SpectralWater::Create(Grid(8, 8, 0.001), o, &error);
  ASSERT_TRUE(water);
  EXPECT_FALSE(water->Advance(-1));
  EXPECT_FALSE(water->Advance(std::nan("")));
  EXPECT_FALSE(water->SetPenTip({0, std::nan(""), 0}));
  EXPECT_FALSE(water->SetState(std::vector<float>(3), nullptr));
  EXPECT_FALSE(water->RemoveObstacle(0));
  o.waves = WaveModel::kPaper;
  EXPECT_FALSE(water->SetOptions(o, &error));
}

TEST(WaterFactoryTest, MakesBothModels) {
  std::string error;
  WaterModelOptions o;
  const GridSpec g = DefaultGrid(o.waves, 0.17, 0.11, 0.025, 256);
  EXPECT_GE(g.nx, 256);
  EXPECT_LE(std::abs(g.ny * g.cell_m - 0.11), 0.5 * g.cell_m);
  EXPECT_LE(4e-3 / g.cell_m, 7.0);
  EXPECT_GE(4e-3 / g.cell_m, 6.0);
  EXPECT_TRUE(CreateWater(g, o, &error)) << error;
  o.waves = WaveModel::kPaper;
  EXPECT_TRUE(
      CreateWater(GridSpec::ForTank(0.17, 0.11, 0.025, 128), o, &error));
}

}  // namespace
}  // namespace ripple::sim
