#include "tracking/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "tests/shipped_data.h"
#include "tracking/camera.h"
#include "tracking/rig.h"
#include "tracking/synth/synth.h"
#include "tracking/tracker.h"

namespace ripple::tracking {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Quaterniond Rot(const Eigen::Vector3d& v) {
  const double a = v.norm();
  if (a == 0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, v / a));
}

// A pure low-pass of cut-off `hz` (no speed adaptation, no lag bound).
PoseFilterOptions LowPass(double hz) {
  PoseFilterOptions o;
  o.min_cutoff_translation_hz = hz;
  o.min_cutoff_rotation_hz = hz;
  o.beta_translation_hz_per_m_s = 0;
  o.beta_rotation_hz_per_rad_s = 0;
  o.max_lag_s = 10;
  o.reset_rotation_deg = 90;
  o.reset_translation_m = 1;
  return o;
}

// Standard deviation of the first-order-hold low-pass's output over that of
// white input noise: x_k = q x_(k-1) + b0 z_k + b1 z_(k-1), an ARMA(1,1)
// process with variance (b0^2 + b1^2 + 2 q b0 b1) / (1 - q^2).
double PredictedStdFactor(double hz, double dt) {
  const double tau = 1 / (2 * M_PI * hz), q = std::exp(-dt / tau);
  const double c = tau / dt * (1 - q);
  const double b0 = 1 - c, b1 = c - q;
  return std::sqrt((b0 * b0 + b1 * b1 + 2 * q * b0 * b1) / (1 - q * q));
}

TEST(PoseFilterTest, StaticNoisyPoseStdDropsByThePredictedFactor) {
  const double dt = 1 / 30.0, hz = 1.0;
  const Eigen::Vector3d pivot(0, 0, -0.1);  // a tip 10 cm from the origin
  PoseFilter filter(LowPass(hz), pivot);
  const Pose truth(Rot(Eigen::Vector3d(0.3, -0.2, 0.1)),
                   Eigen::Vector3d(0.01, 0.02, 0.4));
  std::mt19937 rng(3);
  std::normal_distribution<double> t_noise(0, 3e-4), r_noise(0, 0.1 * kDeg);
  double raw_t = 0, out_t = 0, raw_r = 0, out_r = 0;
  Eigen::Vector3d mean_err = Eigen::Vector3d::Zero();
  int n = 0;
  for (int f = 0; f < 6000; ++f) {
    const Eigen::Vector3d dr(r_noise(rng), r_noise(rng), r_noise(rng));
    const Eigen::Vector3d dp(t_noise(rng), t_noise(rng), t_noise(rng));
    // Noise on the pivot's position and on the rotation, independently.
    Pose z;
    z.rotation = Rot(dr) * truth.rotation;
    z.translation = truth * pivot + dp - z.rotation * pivot;
    const Pose out = filter.Filter(z, f * dt);
    if (f < 60) continue;  // 2 s to forget the first sample
    raw_t += dp.squaredNorm();
    const Eigen::Vector3d e = out * pivot - truth * pivot;
    out_t += e.squaredNorm();
    mean_err += e;
    raw_r += dr.squaredNorm();
    out_r += std::pow(out.rotation.angularDistance(truth.rotation), 2);
    ++n;
  }
  const double predicted = PredictedStdFactor(hz, dt);
  const double ratio_t = std::sqrt(out_t / raw_t);
  const double ratio_r = std::sqrt(out_r / raw_r);
  std::printf("std factor: predicted %.4f, pivot %.4f, rotation %.4f\n",
              predicted, ratio_t, ratio_r);
  EXPECT_NEAR(ratio_t, predicted, 0.1 * predicted);
  EXPECT_NEAR(ratio_r, predicted, 0.1 * predicted);
  EXPECT_LT((mean_err / n).norm(), 3e-5);  // converges on the truth
  EXPECT_LT(predicted, 0.35);
}

// After a restart the first samples of a pose at rest are weighted about
// equally: the output's error a few frames on is near the running mean's,
// sigma / sqrt(k + 1), where a plain low-pass still holds the restart's
// sample with most of its weight.
TEST(PoseFilterTest, GrowingMemoryAveragesTheFirstSamples) {
  const double dt = 1 / 30.0, sigma = 1e-4;
  constexpr int kSamples = 16, kRuns = 4000;
  std::vector<double> growing_ss(kSamples, 0), plain_ss(kSamples, 0);
  for (const bool growing : {true, false}) {
    PoseFilterOptions o = LowPass(1.0);
    o.growing_memory = growing;
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0, sigma);
    std::vector<double>& ss = growing ? growing_ss : plain_ss;
    for (int run = 0; run < kRuns; ++run) {
      PoseFilter filter(o);
      for (int k = 0; k < kSamples; ++k) {
        const Pose z(Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
        const Pose out = filter.Filter(z, 100 + k * dt);
        ss[k] += out.translation.squaredNorm() / 3;
      }
    }
  }
  for (int k = 1; k < kSamples; ++k) {
    const double growing = std::sqrt(growing_ss[k] / kRuns) / sigma;
    const double plain = std::sqrt(plain_ss[k] / kRuns) / sigma;
    const double mean = 1 / std::sqrt(k + 1.0);
    std::printf(
        "sample %2d: error / sigma %.3f growing, %.3f plain, %.3f "
        "running mean\n",
        k, growing, plain, mean);
    EXPECT_LT(growing, 1.3 * mean) << k;
    // Until the cut-off's own memory (tau = 0.16 s, 4.8 frames) takes over.
    if (k <= 8) {
      EXPECT_LT(growing, plain) << k;
    }
  }
  // One frame after the restart the plain low-pass keeps 0.9 of the first
  // sample (error 0.91 sigma against the mean's 0.71).
  EXPECT_GT(std::sqrt(plain_ss[1] / kRuns),
            1.15 * std::sqrt(growing_ss[1] / kRuns));
}

TEST(PoseFilterTest, DefaultsSmoothAtRestNearTheirMinimumCutoff) {
  // The speed adaptation must not be driven by the noise itself.
  for (const double fps : {30.0, 60.0}) {
    PoseFilterOptions o;
    PoseFilter filter(o);
    std::mt19937 rng(4);
    // Below the reset bound, as a pen's tip at rest on several faces.
    std::normal_distribution<double> noise(0, 1e-4);
    double raw = 0, out = 0;
    for (int f = 0; f < 3000; ++f) {
      const Eigen::Vector3d dp(noise(rng), noise(rng), noise(rng));
      const Pose z(Eigen::Quaterniond::Identity(),
                   Eigen::Vector3d(0, 0, 0.4) + dp);
      const Pose p = filter.Filter(z, f / fps);
      if (f < 60) continue;
      raw += dp.squaredNorm();
      out += (p.translation - Eigen::Vector3d(0, 0, 0.4)).squaredNorm();
    }
    const double ratio = std::sqrt(out / raw);
    const double floor =
        PredictedStdFactor(o.min_cutoff_translation_hz, 1 / fps);
    std::printf(
        "defaults at %g fps: std factor %.3f (minimum cut-off alone "
        "%.3f)\n",
        fps, ratio, floor);
    EXPECT_GE(ratio, 0.95 * floor);
    EXPECT_LT(ratio, 1.6 * floor);
  }
}

TEST(PoseFilterTest, FollowsARampWithTheLagOfItsTimeConstant) {
  const double v = 0.1;  // m/s
  for (const double fps : {30.0, 60.0, 25.0}) {
    for (const bool bounded : {false, true}) {
      PoseFilterOptions o = LowPass(bounded ? 0.1 : 1.0);
      if (bounded) o.max_lag_s = 0.05;
      const double tau = bounded ? 0.05 : 1 / (2 * M_PI);
      PoseFilter filter(o);
      double lag_s = 0;
      for (int f = 0; f <= 3 * fps; ++f) {
        const double t = f / fps;
        const Pose out = filter.Filter(
            Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(v * t, 0, 0)),
            t);
        const double lag = v * t - out.translation.x();
        EXPECT_LE(lag, v * tau * (1 + 1e-9)) << fps << " fps, frame " << f;
        lag_s = lag / v;
      }
      EXPECT_NEAR(lag_s, tau, 1e-6) << fps << " fps";
    }
  }
}

TEST(PoseFilterTest, FollowsAStepWithinItsTimeConstant) {
  const double fps = 30, dt = 1 / fps;
  PoseFilterOptions o;  // defaults: speed adaptation on
  const double tau_max = 1 / (2 * M_PI * o.min_cutoff_translation_hz);
  PoseFilter filter(o);
  const double step = 0.5 * o.reset_translation_m;
  ASSERT_LT(step, o.reset_translation_m);
  for (int f = 0; f < 90; ++f) {
    const double x = f < 30 ? 0 : step;
    const Pose out = filter.Filter(
        Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, 0, 0.4)),
        f * dt);
    EXPECT_FALSE(f > 0 && filter.restarted());
    if (f < 30) continue;
    const double remaining = (step - out.translation.x()) / step;
    EXPECT_GE(remaining, -1e-9) << f;  // no overshoot
    // The slowest the filter may be: the minimum cut-off's decay.
    EXPECT_LE(remaining, std::exp(-(f - 30) * dt / tau_max) + 1e-9) << f;
  }
}

TEST(PoseFilterTest, RestartsOnAJumpBeyondItsBounds) {
  const PoseFilterOptions o;
  PoseFilter filter(o, Eigen::Vector3d(0, 0, -0.1));
  const Pose a(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0.4));
  for (int f = 0; f < 30; ++f) filter.Filter(a, f / 30.0);
  // Translation: 5 cm > reset_translation_m.
  const Pose moved(a.rotation, a.translation + Eigen::Vector3d(0.05, 0, 0));
  Pose out = filter.Filter(moved, 1.0);
  EXPECT_TRUE(filter.restarted());
  EXPECT_LT(TranslationDistance(out, moved), 1e-12);
  // Rotation: a 40 degree flip about the x axis.
  const Pose flipped(Rot(Eigen::Vector3d(40 * kDeg, 0, 0)), moved.translation);
  out = filter.Filter(flipped, 1.0 + 1 / 30.0);
  EXPECT_TRUE(filter.restarted());
  EXPECT_LT(RotationDistance(out, flipped), 1e-12);
  // A small move is smoothed, not restarted.
  ASSERT_GT(o.reset_rotation_deg, 0.5);
  const Pose nudged(Rot(Eigen::Vector3d(40.5 * kDeg, 0, 0)), moved.translation);
  out = filter.Filter(nudged, 1.0 + 2 / 30.0);
  EXPECT_FALSE(filter.restarted());
  EXPECT_GT(RotationDistance(out, nudged), 0.05 * kDeg);
  // Reset: the next sample passes through.
  filter.Reset();
  out = filter.Filter(a, 2.0);
  EXPECT_TRUE(filter.restarted());
  EXPECT_LT(RotationDistance(out, a) + TranslationDistance(out, a), 1e-12);
  // Time not advancing restarts too.
  out = filter.Filter(moved, 2.0);
  EXPECT_LT(TranslationDistance(out, moved), 1e-12);
}

// A smooth motion of the pivot and the rotation.
Pose Motion(double t) {
  const Eigen::Vector3d p(0.03 * std::sin(2 * M_PI * 0.7 * t),
                          0.02 * std::cos(2 * M_PI * 0.4 * t), 0.4);
  const Eigen::Quaterniond r =
      Rot(Eigen::Vector3d(0.3 * std::sin(2 * M_PI * 0.5 * t), 0.2, 0.1 * t));
  return Pose(r, p);
}

TEST(PoseFilterTest, SameMotionAt30And60FpsGivesTheSameOutput) {
  PoseFilterOptions o;        // speed adaptation on
  o.reset_rotation_deg = 90;  // never restarted by this motion
  o.reset_translation_m = 1;
  PoseFilter f30(o), f60(o);
  double max_diff_m = 0, max_diff_rad = 0, max_lag_m = 0, max_lag_rad = 0;
  for (int k = 0; k <= 180; ++k) {
    const double t = k / 30.0;
    const Pose a = f30.Filter(Motion(t), t);
    if (k > 0) f60.Filter(Motion(t - 1 / 60.0), t - 1 / 60.0);
    const Pose b = f60.Filter(Motion(t), t);
    max_diff_m = std::max(max_diff_m, TranslationDistance(a, b));
    max_diff_rad = std::max(max_diff_rad, RotationDistance(a, b));
    max_lag_m = std::max(max_lag_m, TranslationDistance(a, Motion(t)));
    max_lag_rad = std::max(max_lag_rad, RotationDistance(a, Motion(t)));
  }
  std::printf(
      "30 vs 60 fps: %.4f mm, %.4f deg apart; lag up to %.3f mm, %.3f deg\n",
      1e3 * max_diff_m, max_diff_rad / kDeg, 1e3 * max_lag_m,
      max_lag_rad / kDeg);
  // The filter does smooth this motion, and both rates lag it alike.
  EXPECT_GT(max_lag_m, 1e-3);
  EXPECT_GT(max_lag_rad, 0.5 * kDeg);
  EXPECT_LT(max_diff_m, 0.1 * max_lag_m);
  EXPECT_LT(max_diff_rad, 0.1 * max_lag_rad);
}

// The pen tip on synth's scripted demo (the fast stroke: 110 mm in 0.4 s,
// peaking near 0.4 m/s), noise-free through the tracker's pen filter and
// through the same One Euro filter without its 1 mm reset bound: the lag
// each adds at the peak speed (mm, ms of delay) and at its largest.
TEST(PoseFilterTest, DemoStrokeLagIsBounded) {
  const Rig rig = test_data::DefaultRig();
  ASSERT_TRUE(rig.pen.has_value());
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  const PoseFilterOptions gated = SmoothingOptions::DefaultPenFilter();
  PoseFilterOptions ungated = gated;
  ungated.reset_translation_m = 1;
  ungated.reset_rotation_deg = 90;
  for (const double fps : {30.0, 60.0}) {
    synth::SequenceOptions seq;
    seq.preset = "demo";
    seq.fps = fps;
    seq.frames = seq.segment_frames = static_cast<int>(8 * fps);
    std::vector<synth::FrameSpec> frames;
    std::string error;
    ASSERT_TRUE(synth::MakeSequence(camera, rig, seq, &frames, &error))
        << error;
    for (const bool gate : {true, false}) {
      const PoseFilterOptions& o = gate ? gated : ungated;
      PoseFilter filter(o, rig.pen->tip_in_pen);
      double max_lag_m = 0, lag_at_peak_m = 0, max_speed = 0;
      Eigen::Vector3d last_tip = Eigen::Vector3d::Zero();
      for (size_t i = 0; i < frames.size(); ++i) {
        const Pose& tank_from_pen = *frames[i].scene.tank_from_pen;
        const Pose out = filter.Filter(tank_from_pen, frames[i].time_s);
        const Eigen::Vector3d tip = tank_from_pen * rig.pen->tip_in_pen;
        const double lag = (out * rig.pen->tip_in_pen - tip).norm();
        max_lag_m = std::max(max_lag_m, lag);
        if (i > 0) {
          const double speed = (tip - last_tip).norm() * fps;
          if (speed > max_speed) {
            max_speed = speed;
            lag_at_peak_m = lag;
          }
        }
        last_tip = tip;
      }
      const double delay_ms = 1e3 * lag_at_peak_m / max_speed;
      std::printf(
          "demo at %g fps, %s: peak tip speed %.2f m/s, lag there %.2f mm "
          "(%.2f ms), largest lag %.2f mm\n",
          fps, gate ? "pen default (1 mm reset)" : "without the reset bound",
          max_speed, 1e3 * lag_at_peak_m, delay_ms, 1e3 * max_lag_m);
      EXPECT_GT(max_speed, 0.3);
      EXPECT_LE(delay_ms, 1e3 * o.max_lag_s);
      EXPECT_LT(delay_ms, 15.0);
      // The reset bound caps the lag: a frame's step beyond it restarts.
      if (gate) {
        EXPECT_LT(max_lag_m, o.reset_translation_m);
      }
    }
  }
}

TEST(PoseFilterTest, ValidatesOptions) {
  PoseFilterOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.min_cutoff_translation_hz = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = PoseFilterOptions{};
  o.max_lag_s = -1;
  EXPECT_FALSE(o.IsValid(&error));
  o = PoseFilterOptions{};
  o.reset_rotation_deg = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = PoseFilterOptions{};
  o.beta_translation_hz_per_m_s = -1;
  EXPECT_FALSE(o.IsValid(&error));
}

}  // namespace
}  // namespace ripple::tracking
