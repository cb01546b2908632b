#include "sim/spectral_water.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ripple::sim {
namespace {

constexpr double kCutoffSigmas = 4.0;  // Gaussian support, standard deviations
constexpr double kPi = 3.14159265358979323846;

bool Finite(double v) { return std::isfinite(v); }

// Exact propagator of x'' + 2 g x' + w^2 x = 0 over t: (x, v) <- M (x, v).
void Oscillator(double w, double g, double t, double m[4]) {
  const double disc = w * w - g * g;
  const double e = std::exp(-g * t);
  if (disc > 0 && std::sqrt(disc) * t > 1e-9) {  // under-damped
    const double wd = std::sqrt(disc);
    const double c = std::cos(wd * t), s = std::sin(wd * t);
    m[0] = e * (c + g / wd * s);
    m[1] = e * s / wd;
    m[2] = -e * w * w / wd * s;
    m[3] = e * (c - g / wd * s);
  } else if (disc < 0 && std::sqrt(-disc) * t > 1e-9) {  // over-damped
    const double q = std::sqrt(-disc);
    // Roots r1 = -g + q (computed without cancellation), r2 = -g - q.
    const double r2 = -g - q;
    const double r1 = -(w * w) / (g + q);
    const double e1 = std::exp(r1 * t), e2 = std::exp(r2 * t);
    const double den = r1 - r2;
    m[0] = (-r2 * e1 + r1 * e2) / den;
    m[1] = (e1 - e2) / den;
    m[2] = r1 * r2 * (e2 - e1) / den;
    m[3] = (r1 * e1 - r2 * e2) / den;
  } else {  // critically damped (or w = g = 0)
    m[0] = e * (1 + g * t);
    m[1] = e * t;
    m[2] = -e * g * g * t;
    m[3] = e * (1 - g * t);
  }
}

// Sources of one sub-step: a volume dX = vol * ax[a] * by[b] and an
// acceleration dY = acc * w[i] * pa[a] * pb[b] (w: per-mode weights, or 1).
struct Sources {
  const float *ax = nullptr, *by = nullptr;
  float vol = 0;
  const float *pa = nullptr, *pb = nullptr, *w = nullptr;
  float acc = 0;
};

template <bool kVolume, bool kAccel, bool kWeighted>
inline void PropagateRow(int nx, float* __restrict x, float* __restrict y,
                         const float* __restrict a11,
                         const float* __restrict a12,
                         const float* __restrict a21,
                         const float* __restrict a22, float cv,
                         const float* __restrict fv, float ca,
                         const float* __restrict fa,
                         const float* __restrict w) {
  for (int a = 0; a < nx; ++a) {
    float xi = x[a], yi = y[a];
    if (kVolume) xi += cv * fv[a];
    if (kAccel) yi += kWeighted ? ca * fa[a] * w[a] : ca * fa[a];
    x[a] = a11[a] * xi + a12[a] * yi;
    y[a] = a21[a] * xi + a22[a] * yi;
  }
}

// One sub-step over all modes: the sources, then each mode's propagator.
// Only the band [0, na) x [0, nb) of the row-major (stride) arrays.
__attribute__((target_clones("avx2", "default"))) void PropagateModes(
    int na, int nb, int stride, float* X, float* Y, const float* m11,
    const float* m12, const float* m21, const float* m22, const Sources& s) {
  const int nx = na;
  for (int b = 0; b < nb; ++b) {
    const std::size_t r = static_cast<std::size_t>(b) * stride;
    const float cv = s.ax ? s.vol * s.by[b] : 0.0f;
    const float ca = s.pa ? s.acc * s.pb[b] : 0.0f;
    const float* w = s.w ? s.w + r : nullptr;
    auto row = [&](auto vol, auto acc, auto weighted) {
      PropagateRow<decltype(vol)::value, decltype(acc)::value,
                   decltype(weighted)::value>(nx, X + r, Y + r, m11 + r,
                                              m12 + r, m21 + r, m22 + r, cv,
                                              s.ax, ca, s.pa, w);
    };
    using T = std::true_type;
    using F = std::false_type;
    if (s.ax && s.pa && w)
      row(T(), T(), T());
    else if (s.ax && s.pa)
      row(T(), T(), F());
    else if (s.ax)
      row(T(), F(), F());
    else if (s.pa && w)
      row(F(), T(), T());
    else if (s.pa)
      row(F(), T(), F());
    else
      row(F(), F(), F());
  }
}

}  // namespace

std::unique_ptr<SpectralWater> SpectralWater::Create(
    const GridSpec& grid, const WaterModelOptions& options,
    std::string* error) {
  if (!grid.IsValid(error)) return nullptr;
  if (!(grid.rest_level_m > 0)) {
    if (error) *error = "water depth (rest level) must be > 0 m";
    return nullptr;
  }
  if (options.waves != WaveModel::kCapillaryGravity) {
    if (error) *error = "SpectralWater runs the capillary-gravity model only";
    return nullptr;
  }
  if (!options.IsValid(error)) return nullptr;
  return std::unique_ptr<SpectralWater>(new SpectralWater(grid, options));
}

SpectralWater::SpectralWater(const GridSpec& grid,
                             const WaterModelOptions& options)
    : grid_(grid), options_(options), transform_(grid.nx, grid.ny) {
  n_ = static_cast<std::size_t>(grid_.nx) * grid_.ny;
  X_ = transform_.NewBuffer();
  Y_ = transform_.NewBuffer();
  m11_ = transform_.NewBuffer();
  m12_ = transform_.NewBuffer();
  m21_ = transform_.NewBuffer();
  m22_ = transform_.NewBuffer();
  omega2_ = transform_.NewBuffer();
  h_ = transform_.NewBuffer();
  v_ = transform_.NewBuffer();
  scratch_ = transform_.NewBuffer();
  kx_.assign(grid_.nx, 0.0f);
  px_.assign(grid_.nx, 0.0f);
  ky_.assign(grid_.ny, 0.0f);
  py_.assign(grid_.ny, 0.0f);
  pressure_weight_ = transform_.NewBuffer();
  water_.assign(n_, 1);
  cover_count_.assign(n_, 0);
  num_water_ = static_cast<int>(n_);
  BuildPropagator();
  ChooseCoarseGrid();
  RebuildMask();
  stats_.at_rest = true;
  stats_.substep_s = options_.spectral.substep_s;
}

double SpectralWater::ModeWaveNumber(int a, int b) const {
  const double lx = grid_.nx * grid_.cell_m, ly = grid_.ny * grid_.cell_m;
  return kPi * std::hypot(a / lx, b / ly);
}

double SpectralWater::ModeAmplitude(int a, int b) const {
  return X_[static_cast<std::size_t>(b) * grid_.nx + a];
}

void SpectralWater::BuildPropagator() {
  CapillaryGravity physics = options_.spectral.physics;
  physics.depth_m = grid_.rest_level_m;
  const double dt = options_.spectral.substep_s;
  // The simulated band: modes with k <= 2 pi / shortest_wavelength, within
  // the box [0, band_nx_) x [0, band_ny_) that bounds them.
  const double k_band = 2 * kPi / options_.spectral.shortest_wavelength_m;
  const double lx = grid_.nx * grid_.cell_m, ly = grid_.ny * grid_.cell_m;
  band_nx_ = std::clamp(static_cast<int>(std::floor(k_band * lx / kPi)) + 1, 1,
                        grid_.nx);
  band_ny_ = std::clamp(static_cast<int>(std::floor(k_band * ly / kPi)) + 1, 1,
                        grid_.ny);
  for (int b = 0; b < grid_.ny; ++b) {
    for (int a = 0; a < grid_.nx; ++a) {
      const std::size_t i = static_cast<std::size_t>(b) * grid_.nx + a;
      const double k = ModeWaveNumber(a, b);
      const double w = physics.Omega(k);
      double m[4] = {0, 0, 0, 0};  // out of the band: held at zero
      if (k <= k_band * (1 + 1e-12))
        Oscillator(w, physics.DampingRate(k), dt, m);
      m11_[i] = static_cast<float>(m[0]);
      m12_[i] = static_cast<float>(m[1]);
      m21_[i] = static_cast<float>(m[2]);
      m22_[i] = static_cast<float>(m[3]);
      omega2_[i] = static_cast<float>(w * w);
      pressure_weight_[i] =
          static_cast<float>(k * std::tanh(k * physics.depth_m));
    }
  }
  // Sponge factors for absorbing walls over one boundary step.
  sponge_.clear();
  if (options_.spectral.walls == WallMode::kAbsorb &&
      options_.spectral.sponge_width_m > 0) {
    sponge_.assign(n_, 1.0f);
    const double width = options_.spectral.sponge_width_m;
    const double t = BoundaryEverySteps() * dt;
    const double d = grid_.cell_m;
    for (int j = 0; j < grid_.ny; ++j) {
      for (int i = 0; i < grid_.nx; ++i) {
        const double dist = d * std::min({i + 0.5, grid_.nx - i - 0.5, j + 0.5,
                                          grid_.ny - j - 0.5});
        if (dist >= width) continue;
        const double u = 1.0 - dist / width;
        sponge_[static_cast<std::size_t>(j) * grid_.nx + i] =
            static_cast<float>(
                std::exp(-options_.spectral.sponge_rate_per_s * u * u * t));
      }
    }
  }
}

bool SpectralWater::SetOptions(const WaterModelOptions& options,
                               std::string* error) {
  if (options.waves != WaveModel::kCapillaryGravity) {
    if (error) *error = "the wave model cannot change at run time";
    return false;
  }
  if (!options.IsValid(error)) return false;
  if (options.spectral.pen != options_.spectral.pen && pen_.volume_m3 > 0) {
    // Leaving the displacement model: the shaft's volume leaves the mean
    // level with it, so the water keeps its own volume.
    X_[0] -=
        static_cast<float>(pen_.volume_m3 / (n_ * grid_.cell_m * grid_.cell_m));
    pen_ = PenState();
    pen_volume_m3_ = 0;
  }
  options_ = options;
  BuildPropagator();
  ClearOutOfBand();  // modes the band no longer holds
  ChooseCoarseGrid();
  RebuildMask();  // the obstacle box follows the band
  stats_.substep_s = options_.spectral.substep_s;
  wake_pending_ = true;
  return true;
}

bool SpectralWater::SetPenTip(const std::array<double, 3>& tip_in_tank) {
  for (double v : tip_in_tank)
    if (!Finite(v)) {
      pending_present_ = false;  // an unusable pose: the pen is not seen
      return false;
    }
  pending_present_ = true;
  pending_tip_ = tip_in_tank;
  return true;
}

// --------------------------------------------------------------------- pen

double SpectralWater::KernelCoefficients(double centre_m, int n, int band,
                                         double sigma_m, float* out) {
  const double d = grid_.cell_m;
  const double c = centre_m / d + 0.5 * n - 0.5;  // fractional cell index
  const double reach = kCutoffSigmas * sigma_m / d;
  const int i0 = std::max(0, static_cast<int>(std::ceil(c - reach)));
  const int i1 = std::min(n - 1, static_cast<int>(std::floor(c + reach)));
  cell_scratch_.clear();
  if (i0 > i1) {
    std::fill(out, out + n, 0.0f);
    return 0.0;
  }
  const double inv2s2 = 1.0 / (2 * sigma_m * sigma_m);
  double sum = 0;
  for (int i = i0; i <= i1; ++i) {
    const double x = (i - c) * d;
    const double g = std::exp(-x * x * inv2s2);
    cell_scratch_.push_back(static_cast<float>(g));
    sum += g;
  }
  for (float& g : cell_scratch_) g = static_cast<float>(g / (sum * d));
  // Only the simulated band is read by the propagation.
  CosineTransform2D::AnalyzeSparse1D(n, i0, cell_scratch_.data(), i1 - i0 + 1,
                                     out, band);
  return sum * d;
}

bool SpectralWater::PenStateAt(double time_s, double dt_s,
                               PenState* state) const {
  const SpectralWaterOptions& o = options_.spectral;
  std::array<double, 3> tip;
  const bool present = path_.At(time_s, &tip);
  const double hx = 0.5 * grid_.nx * grid_.cell_m;
  const double hy = 0.5 * grid_.ny * grid_.cell_m;
  const bool inside =
      present && std::abs(tip[0]) <= hx && std::abs(tip[1]) <= hy;
  *state = pen_;
  state->push = false;
  state->pressure = 0;
  if (o.pen == PenModel::kPaperPush) {
    state->volume_m3 = 0;
    if (inside && o.pen_strength_m_per_s2 > 0 &&
        tip[2] < grid_.rest_level_m + HeightAtPoint(tip[0], tip[1])) {
      state->push = true;
      state->x_m = tip[0];
      state->y_m = tip[1];
    }
    return state->push;
  }
  const double r = o.pen_shaft_radius_m;
  const double area = kPi * r * r;
  double depth = 0;
  if (present) {
    const double surface = grid_.rest_level_m + MeanDisplacement();
    depth =
        inside ? std::clamp(surface - tip[2], 0.0, o.pen_shaft_length_m) : 0.0;
    const double step = area * o.pen_max_speed_m_per_s * dt_s;
    state->volume_m3 =
        std::clamp(area * depth, pen_.volume_m3 - step, pen_.volume_m3 + step);
    if (inside) {
      state->x_m = tip[0];
      state->y_m = tip[1];
    }
    // The shaft's horizontal speed over the sub-step sets the pressure it
    // puts on the surface.
    std::array<double, 3> before;
    if (depth > 0 && path_.At(time_s - dt_s, &before)) {
      // Capped like the volume, so a tracking jump does not splash.
      const double u =
          std::min(std::hypot(tip[0] - before[0], tip[1] - before[1]) / dt_s,
                   o.pen_max_speed_m_per_s);
      const double wet = std::min(1.0, depth / (2 * r + 1e-12));
      state->pressure = o.pen_pressure_coefficient * 0.5 * u * u * wet;
    }
  } else {
    // Lost from view: withdraw where it was last seen.
    state->volume_m3 = std::max(
        0.0, pen_.volume_m3 - area * o.pen_withdraw_speed_m_per_s * dt_s);
  }
  return state->volume_m3 != pen_.volume_m3 || state->pressure > 0;
}

// ------------------------------------------------------------------ stepping

void SpectralWater::StepModes(const PenState& next) {
  const SpectralWaterOptions& o = options_.spectral;
  Sources s;
  const double sigma = std::max(0.5 * o.pen_radius_m, 0.5 * grid_.cell_m);
  if (o.pen == PenModel::kDisplace) {
    // One unit-volume kernel serves both sources: each axis' coefficients
    // sum to 1/d over its cells, so dV * kx * ky adds exactly dV (h summed
    // times d^2), and times the returned scales it is the peak-1 Gaussian
    // the pressure acts through.
    const bool volume = next.volume_m3 != pen_.volume_m3;
    const bool pressure = next.pressure > 0;
    double scale_x = 0, scale_y = 0;
    if (volume || pressure) {
      scale_x =
          KernelCoefficients(next.x_m, grid_.nx, band_nx_, sigma, kx_.data());
      scale_y =
          KernelCoefficients(next.y_m, grid_.ny, band_ny_, sigma, ky_.data());
    }
    if (volume) {
      // The volume the shaft gained (or gave back) enters where it is.
      s.ax = kx_.data();
      s.by = ky_.data();
      s.vol = static_cast<float>(next.volume_m3 - pen_.volume_m3);
    }
    if (pressure) {
      // Surface pressure p/rho accelerates mode k by -k tanh(kH) p_k/rho.
      s.pa = kx_.data();
      s.pb = ky_.data();
      s.w = pressure_weight_.data();
      s.acc =
          static_cast<float>(-next.pressure * o.substep_s * scale_x * scale_y);
    }
  } else if (next.push) {
    const double push_sigma =
        std::max(0.2 * o.pen_radius_m, 0.5 * grid_.cell_m);
    const double scale_x = KernelCoefficients(next.x_m, grid_.nx, band_nx_,
                                              push_sigma, px_.data());
    const double scale_y = KernelCoefficients(next.y_m, grid_.ny, band_ny_,
                                              push_sigma, py_.data());
    s.pa = px_.data();
    s.pb = py_.data();
    s.acc = static_cast<float>(-o.pen_strength_m_per_s2 * o.substep_s *
                               scale_x * scale_y);
  }
  const float x0 = X_[0], y0 = Y_[0];
  PropagateModes(band_nx_, band_ny_, grid_.nx, X_.data(), Y_.data(),
                 m11_.data(), m12_.data(), m21_.data(), m22_.data(), s);
  if (s.pa && !s.w) {
    // The push's uniform compensation: its mean (the volume mode) is not
    // applied, so the mean level moves only as it did without the push.
    X_[0] = x0 + m12_[0] * y0;
    Y_[0] = y0;
  }
  pen_ = next;
  pen_volume_m3_ = pen_.volume_m3;
}

void SpectralWater::ClearOutOfBand() {
  const std::size_t nx = grid_.nx;
  for (int b = 0; b < grid_.ny; ++b) {
    float* x = X_.data() + b * nx;
    float* y = Y_.data() + b * nx;
    const std::size_t from = b < band_ny_ ? band_nx_ : 0;
    std::fill(x + from, x + nx, 0.0f);
    std::fill(y + from, y + nx, 0.0f);
    // Inside the band's box, the corners beyond k_band (held at zero by a
    // zero propagator).
    for (std::size_t a = 0; a < from; ++a) {
      const std::size_t i = b * nx + a;
      if (i != 0 && m11_[i] == 0 && m12_[i] == 0) x[a] = y[a] = 0.0f;
    }
  }
}

bool SpectralWater::Advance(double dt_frame_s) {
  if (!Finite(dt_frame_s) || dt_frame_s < 0) return false;
  const SpectralWaterOptions& o = options_.spectral;
  const double dt = o.substep_s;
  stats_.substeps = 0;
  stats_.dropped_s = 0;
  stats_.pen_touched = false;
  stats_.changed = false;
  stats_.substep_s = dt;
  const double start_s = time_s_;
  time_s_ += dt_frame_s;
  path_.Push(time_s_, pending_present_, pending_tip_);

  if (at_rest_ && !wake_pending_) {
    PenState probe;
    if (!PenStateAt(start_s, dt, &probe) && !PenStateAt(time_s_, dt, &probe)) {
      clock_.Idle(dt_frame_s, dt);
      stats_.at_rest = true;
      stats_.counter = counter_;
      return true;
    }
  }
  const bool was_pending = wake_pending_;
  at_rest_ = false;
  wake_pending_ = false;

  const SubstepClock::Due due =
      clock_.Advance(dt_frame_s, time_s_, dt, o.max_substeps);
  const int n = due.substeps;
  stats_.dropped_s = due.dropped_s;
  const double end_s = due.end_s;
  const bool boundary = BoundaryActive();
  const int every = BoundaryEverySteps();
  bool touched = false;
  for (int s = 0; s < n; ++s) {
    const double t = end_s - (n - s - 1) * dt;
    PenState next;
    touched |= PenStateAt(t, dt, &next);
    StepModes(next);
    if (boundary && ++steps_since_boundary_ >= every) {
      ImposeBoundaries();
      steps_since_boundary_ = 0;
    }
  }
  stats_.substeps = n;
  stats_.pen_touched = touched;
  if (n > 0 || was_pending) {
    ++counter_;
    stats_.changed = true;
    Synthesize();
    ComputeStats();
    if (!touched && stats_.max_speed_m_per_s <= o.rest_speed_m_per_s &&
        stats_.max_deviation_m <= o.rest_height_m) {
      SnapToRest();
    }
  }
  stats_.at_rest = at_rest_;
  stats_.counter = counter_;
  return true;
}

void SpectralWater::Synthesize() {
  transform_.SynthesizeRows(X_.data(), band_ny_, h_.data(), scratch_.data());
  // Obstacle cells are drawn at the mean level.
  if (!obstacle_cells_.empty()) {
    const float mean = X_[0];
    for (std::int32_t c : obstacle_cells_) h_[c] = mean;
  }
}

void SpectralWater::ComputeStats() {
  const float* h = h_.data();
  double vol = 0, absvol = 0, maxabs = 0;
  double hmin = std::numeric_limits<double>::infinity(), hmax = -hmin;
  for (std::size_t c = 0; c < n_; ++c) {
    if (!water_[c]) continue;
    const double v = h[c];
    vol += v;
    absvol += std::abs(v);
    maxabs = std::max(maxabs, std::abs(v));
    hmin = std::min(hmin, v);
    hmax = std::max(hmax, v);
  }
  const double d2 = grid_.cell_m * grid_.cell_m;
  stats_.volume_m3 = vol * d2;
  stats_.abs_volume_m3 = absvol * d2;
  stats_.max_abs_height_m = maxabs;
  if (num_water_ > 0) {
    const double mean = vol / num_water_;
    stats_.max_deviation_m = std::max(hmax - mean, mean - hmin);
  } else {
    stats_.max_deviation_m = 0;
  }
  // A modal energy norm (Parseval over the cosine basis, a mode's mean
  // square over the cells being 1, 1/2 or 1/4): d^2/2 * sum(X'^2 +
  // omega^2 X^2); it falls exactly as the modes decay but is not the
  // physical energy (that weights each mode by 1/(k tanh kH)). The speed is
  // a bound on max|dh/dt|: the sum of |X'|.
  double energy = 0, speed = 0;
  const int nx = grid_.nx;
  for (int b = 0; b < band_ny_; ++b) {
    const double wb = b == 0 ? 1.0 : 0.5;
    for (int a = 0; a < band_nx_; ++a) {
      const std::size_t i = static_cast<std::size_t>(b) * nx + a;
      if (i == 0) continue;
      const double w = wb * (a == 0 ? 1.0 : 0.5);
      const double x = X_[i], y = Y_[i];
      energy += w * (y * y + omega2_[i] * x * x);
      speed += std::abs(y);
    }
  }
  stats_.energy = 0.5 * energy * n_ * d2;
  stats_.max_speed_m_per_s = speed;
}

void SpectralWater::SnapToRest() {
  double vol = 0;
  for (std::size_t c = 0; c < n_; ++c)
    if (water_[c]) vol += h_[c];
  const float mean = num_water_ > 0 ? static_cast<float>(vol / num_water_) : 0;
  X_.Fill(0.0f);
  Y_.Fill(0.0f);
  X_[0] = mean;
  h_.Fill(mean);
  at_rest_ = true;
  stats_.max_speed_m_per_s = 0;
  stats_.max_deviation_m = 0;
  stats_.max_abs_height_m = std::abs(static_cast<double>(mean));
  stats_.energy = 0;
}

double SpectralWater::WaterVolume() const {
  double vol = 0;
  for (std::size_t c = 0; c < n_; ++c)
    if (water_[c]) vol += h_[c];
  return vol * grid_.cell_m * grid_.cell_m - pen_volume_m3_;
}

void SpectralWater::Reset() {
  X_.Fill(0.0f);
  Y_.Fill(0.0f);
  h_.Fill(0.0f);
  pen_ = PenState();
  pen_volume_m3_ = 0;
  water_volume_m3_ = 0;
  clock_ = SubstepClock();
  steps_since_boundary_ = 0;
  at_rest_ = true;
  wake_pending_ = false;
  stats_ = AdvanceStats();
  stats_.at_rest = true;
  stats_.substep_s = options_.spectral.substep_s;
  ++counter_;
  stats_.counter = counter_;
}

bool SpectralWater::SetState(const std::vector<float>& heights_m,
                             const std::vector<float>* velocities_m_per_s) {
  if (heights_m.size() != n_) return false;
  if (velocities_m_per_s && velocities_m_per_s->size() != n_) return false;
  for (float v : heights_m)
    if (!std::isfinite(v)) return false;
  if (velocities_m_per_s)
    for (float v : *velocities_m_per_s)
      if (!std::isfinite(v)) return false;
  std::copy(heights_m.begin(), heights_m.end(), h_.data());
  if (velocities_m_per_s)
    std::copy(velocities_m_per_s->begin(), velocities_m_per_s->end(),
              v_.data());
  else
    v_.Fill(0.0f);
  transform_.Analyze(h_.data(), X_.data());
  transform_.Analyze(v_.data(), Y_.data());
  StateReplaced();
  return true;
}

void SpectralWater::StateReplaced() {
  ClearOutOfBand();
  Synthesize();
  // The volume target is the band-limited state's own volume.
  water_volume_m3_ = WaterVolume();
  ++counter_;
  at_rest_ = false;
  wake_pending_ = true;
}

bool SpectralWater::AddHeights(const std::vector<float>& dh_m) {
  if (dh_m.size() != n_) return false;
  for (float v : dh_m)
    if (!std::isfinite(v)) return false;
  for (std::size_t c = 0; c < n_; ++c) scratch_[c] = water_[c] ? dh_m[c] : 0.0f;
  transform_.Analyze(scratch_.data(), v_.data());
  for (std::size_t c = 0; c < n_; ++c) X_[c] += v_[c];
  StateReplaced();
  return true;
}

void SpectralWater::ChooseCoarseGrid() {
  coarse_transform_.reset();
  coarse_counter_ = ~std::uint64_t{0};
  auto smooth = [](int n) {
    for (int p : {2, 3, 5, 7})
      while (n > 1 && n % p == 0) n /= p;
    return n == 1;
  };
  // Grids with the tank's exact aspect: multiples of (nx, ny) / gcd.
  int a = grid_.nx, b = grid_.ny;
  while (b != 0) std::swap(a %= b, b);
  const int ux = grid_.nx / a, uy = grid_.ny / a;
  for (int m = 1; m * ux < grid_.nx; ++m) {
    const int cx = m * ux, cy = m * uy;
    if (cx < band_nx_ || cy < band_ny_ || !smooth(cx) || !smooth(cy)) continue;
    if (static_cast<double>(cx) * cy > 0.7 * n_) break;  // not worth it
    coarse_transform_ = std::make_unique<CosineTransform2D>(cx, cy);
    coarse_cell_m_ = grid_.nx * grid_.cell_m / cx;
    const std::size_t n = static_cast<std::size_t>(cx) * cy;
    coarse_h_ = AlignedFloats(n);
    coarse_x_ = AlignedFloats(n);
    coarse_scratch_ = AlignedFloats(n);
    coarse_water_.assign(n, 1);
    return;
  }
}

HeightFieldView SpectralWater::CoarseView() const {
  if (!coarse_transform_) return View();
  const int cx = coarse_transform_->nx(), cy = coarse_transform_->ny();
  if (coarse_counter_ != counter_) {
    // The band's coefficients evaluated at the coarse cell centres: the
    // cosine basis of the coarse grid is the fine one sampled there.
    coarse_x_.Fill(0.0f);
    for (int b = 0; b < band_ny_; ++b)
      std::copy(X_.data() + static_cast<std::size_t>(b) * grid_.nx,
                X_.data() + static_cast<std::size_t>(b) * grid_.nx + band_nx_,
                coarse_x_.data() + static_cast<std::size_t>(b) * cx);
    coarse_transform_->SynthesizeRows(coarse_x_.data(), band_ny_,
                                      coarse_h_.data(), coarse_scratch_.data());
    coarse_counter_ = counter_;
  }
  HeightFieldView v;
  v.heights = coarse_h_.data();
  v.water = coarse_water_.data();
  v.nx = cx;
  v.ny = cy;
  v.cell_m = coarse_cell_m_;
  v.rest_level_m = grid_.rest_level_m;
  v.counter = counter_;
  return v;
}

HeightFieldView SpectralWater::View() const {
  HeightFieldView v;
  v.heights = h_.data();
  v.water = water_.data();
  v.nx = grid_.nx;
  v.ny = grid_.ny;
  v.cell_m = grid_.cell_m;
  v.rest_level_m = grid_.rest_level_m;
  v.counter = counter_;
  return v;
}

double SpectralWater::HeightAtPoint(double x_m, double y_m) const {
  return HeightAt(View(), x_m, y_m);
}

}  // namespace ripple::sim
