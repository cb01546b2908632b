#include "sim/water.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "geometry/check.h"
#include "sim/water_kernels.h"

namespace ripple::sim {
namespace {

constexpr double kMinSigmaCells = 0.5;  // sigma >= half a cell
constexpr double kCutoffSigmas = 4.0;   // exp(-8) ~ 3e-4 beyond

bool Finite(double v) { return std::isfinite(v); }

using internal::kPlain;
using internal::kReflectMask;
using internal::kZeroMask;
using internal::StepGrid;
using internal::SumGrid;
using internal::Sums;

}  // namespace

bool WaterOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!Finite(wave_speed_m_per_s) || !(wave_speed_m_per_s > 0) ||
      wave_speed_m_per_s > 1e3)
    return fail("wave speed must be in (0, 1000] m/s");
  if (!Finite(viscosity_per_s) || viscosity_per_s < 0 || viscosity_per_s > 1e6)
    return fail("viscosity must be in [0, 1e6] 1/s");
  if (!Finite(courant) || !(courant > 0) || courant > 0.5)
    return fail("courant number c*dt/d must be in (0, 0.5]");
  if (walls != WallMode::kReflect && walls != WallMode::kAbsorb)
    return fail("unknown wall mode");
  if (obstacles != ObstacleMode::kReflect && obstacles != ObstacleMode::kZero)
    return fail("unknown obstacle treatment");
  if (max_substeps < 1 || max_substeps > 1000000)
    return fail("max sub-steps must be in [1, 1000000]");
  if (!Finite(pen_strength_m_per_s2) || pen_strength_m_per_s2 < 0 ||
      pen_strength_m_per_s2 > 1e12)
    return fail("pen strength must be in [0, 1e12] m/s^2");
  if (!Finite(pen_radius_m) || !(pen_radius_m > 0) || pen_radius_m > 1e3)
    return fail("pen radius must be in (0, 1000] m");
  if (!Finite(rest_speed_m_per_s) || rest_speed_m_per_s < 0)
    return fail("rest speed threshold must be >= 0 m/s");
  if (!Finite(rest_height_m) || rest_height_m < 0)
    return fail("rest height threshold must be >= 0 m");
  return true;
}

std::string AdvanceStats::BriefReport() const {
  char buf[320];
  std::snprintf(buf, sizeof(buf),
                "substeps %d (dt %.3g s, dropped %.3g s) volume %.3e m^3 "
                "energy %.4e max|h| %.3e m max|v| %.3e m/s%s%s%s",
                substeps, substep_s, dropped_s, volume_m3, energy,
                max_abs_height_m, max_speed_m_per_s, pen_touched ? " pen" : "",
                changed ? " changed" : "", at_rest ? " rest" : "");
  return buf;
}

template <typename T>
BasicWater<T>::BasicWater(const GridSpec& grid, const WaterOptions& options)
    : grid_(grid), options_(options) {
  std::string error;
  RIPPLE_CHECK(grid.IsValid(&error) && options.IsValid(&error),
               "ripple::sim::BasicWater: " + error);
  const size_t n = static_cast<size_t>(grid_.nx) * grid_.ny;
  h_.assign(n, T(0));
  u_.assign(n, T(0));
  mask_.assign(n, T(1));
  water_.assign(n, 1);
  cover_count_.assign(n, 0);
  num_water_ = static_cast<int>(n);
  ghost_top_.assign(grid_.nx, T(0));
  ghost_bottom_.assign(grid_.nx, T(0));
  ghost_left_.assign(grid_.ny, T(0));
  ghost_right_.assign(grid_.ny, T(0));
  ones_.assign(std::max(grid_.nx, grid_.ny), T(1));
  SetOptions(options, nullptr);
  stats_.at_rest = true;
  stats_.substep_s = dt_;
}

template <typename T>
bool BasicWater<T>::SetOptions(const WaterOptions& options,
                               std::string* error) {
  if (!options.IsValid(error)) return false;
  const double old_dt = dt_;
  const WallMode old_walls = options_.walls;
  const ObstacleMode old_obstacles = options_.obstacles;
  options_ = options;
  dt_ = options_.courant * grid_.cell_m / options_.wave_speed_m_per_s;
  k_ = static_cast<T>(options_.courant * options_.courant);
  damp_ = static_cast<T>(std::exp(-options_.viscosity_per_s * dt_));
  sigma_m_ =
      std::max(0.2 * options_.pen_radius_m, kMinSigmaCells * grid_.cell_m);
  if (old_dt > 0 && old_dt != dt_) {
    // u = dt*v: keep v continuous.
    const T scale = static_cast<T>(dt_ / old_dt);
    for (T& v : u_) v *= scale;
    target_usum_ *= dt_ / old_dt;
  }
  if (options_.walls == WallMode::kAbsorb && old_walls != WallMode::kAbsorb)
    SeedGhosts();
  if (options_.walls != old_walls || options_.obstacles != old_obstacles)
    ResetVolumeTarget();
  stats_.substep_s = dt_;
  return true;
}

template <typename T>
bool BasicWater<T>::SetPenTip(const std::array<double, 3>& tip_in_tank) {
  for (double v : tip_in_tank)
    if (!Finite(v)) return false;
  pending_present_ = true;
  pending_tip_ = tip_in_tank;
  return true;
}

template <typename T>
void BasicWater<T>::ClearPen() {
  pending_present_ = false;
}

template <typename T>
double BasicWater<T>::HeightAtPoint(double x_m, double y_m) const {
  return HeightAt(View(), x_m, y_m);
}

template <typename T>
bool BasicWater<T>::PenTouches(double time_s,
                               std::array<double, 3>* tip) const {
  if (!pen_path_.At(time_s, tip)) return false;
  const double hx = 0.5 * grid_.nx * grid_.cell_m;
  const double hy = 0.5 * grid_.ny * grid_.cell_m;
  if (!(std::abs((*tip)[0]) <= hx && std::abs((*tip)[1]) <= hy)) return false;
  return (*tip)[2] < grid_.rest_level_m + HeightAtPoint((*tip)[0], (*tip)[1]);
}

template <typename T>
bool BasicWater<T>::ApplyPen(double time_s, T* compensation) {
  std::array<double, 3> tip;
  const bool touching = PenTouches(time_s, &tip) && num_water_ > 0 &&
                        options_.pen_strength_m_per_s2 != 0;
  double applied = 0;  // sum of the float increments actually added to u
  if (touching) {
    const int nx = grid_.nx, ny = grid_.ny;
    const double d = grid_.cell_m;
    const double reach = kCutoffSigmas * sigma_m_;
    // Cell centres within reach of the tip.
    const double cx = tip[0] / d + 0.5 * nx - 0.5;
    const double cy = tip[1] / d + 0.5 * ny - 0.5;
    const int i0 = static_cast<int>(std::max(0.0, std::ceil(cx - reach / d)));
    const int i1 =
        static_cast<int>(std::min(nx - 1.0, std::floor(cx + reach / d)));
    const int j0 = static_cast<int>(std::max(0.0, std::ceil(cy - reach / d)));
    const int j1 =
        static_cast<int>(std::min(ny - 1.0, std::floor(cy + reach / d)));
    if (i0 <= i1 && j0 <= j1) {
      const double inv2s2 = 1.0 / (2 * sigma_m_ * sigma_m_);
      pen_gx_.resize(i1 - i0 + 1);
      for (int i = i0; i <= i1; ++i) {
        const double dx = (i - cx) * d;
        pen_gx_[i - i0] = static_cast<T>(std::exp(-dx * dx * inv2s2));
      }
      // Per-step velocity increment: dt^2 * s, pushing down.
      const double scale = -dt_ * dt_ * options_.pen_strength_m_per_s2;
      const bool masked = num_water_ < static_cast<int>(h_.size());
      for (int j = j0; j <= j1; ++j) {
        const double dy = (j - cy) * d;
        const T amp = static_cast<T>(scale * std::exp(-dy * dy * inv2s2));
        T* u = u_.data() + static_cast<size_t>(j) * nx;
        const T* m = mask_.data() + static_cast<size_t>(j) * nx;
        double row = 0;
        for (int i = i0; i <= i1; ++i) {
          T du = amp * pen_gx_[i - i0];
          if (masked) du *= m[i];
          u[i] += du;
          row += du;
        }
        applied += row;
      }
    }
  }
  // Uniform compensation over the water cells, carrying last step's rounding
  // so that the net volume injected stays at one step's rounding.
  const double want = applied + volume_debt_;
  T comp = 0;
  if (want != 0 && num_water_ > 0) comp = static_cast<T>(-want / num_water_);
  volume_debt_ = want + static_cast<double>(comp) * num_water_;
  *compensation = comp;
  return touching;
}

template <typename T>
void BasicWater<T>::SeedGhosts() {
  // A flat continuation of the edges.
  const int nx = grid_.nx, ny = grid_.ny;
  for (int i = 0; i < nx; ++i) {
    ghost_top_[i] = h_[i];
    ghost_bottom_[i] = h_[static_cast<size_t>(ny - 1) * nx + i];
  }
  for (int j = 0; j < ny; ++j) {
    ghost_left_[j] = h_[static_cast<size_t>(j) * nx];
    ghost_right_[j] = h_[static_cast<size_t>(j) * nx + nx - 1];
  }
}

template <typename T>
void BasicWater<T>::UpdateGhosts(bool before_step) {
  if (options_.walls != WallMode::kAbsorb) return;
  const int nx = grid_.nx, ny = grid_.ny;
  const T* h = h_.data();
  const T* last = h + static_cast<size_t>(ny - 1) * nx;
  if (before_step) {
    edge_top_.assign(h, h + nx);
    edge_bottom_.assign(last, last + nx);
    edge_left_.resize(ny);
    edge_right_.resize(ny);
    for (int j = 0; j < ny; ++j) {
      edge_left_[j] = h[static_cast<size_t>(j) * nx];
      edge_right_[j] = h[static_cast<size_t>(j) * nx + nx - 1];
    }
    return;
  }
  if (edge_top_.size() != static_cast<size_t>(nx)) return;
  // Mur (1981) first order: g' = e + R (e' - g), R = (C - 1) / (C + 1).
  const T c = static_cast<T>(options_.courant);
  const T r = (c - T(1)) / (c + T(1));
  for (int i = 0; i < nx; ++i) {
    ghost_top_[i] = edge_top_[i] + r * (h[i] - ghost_top_[i]);
    ghost_bottom_[i] = edge_bottom_[i] + r * (last[i] - ghost_bottom_[i]);
  }
  for (int j = 0; j < ny; ++j) {
    const T* row = h + static_cast<size_t>(j) * nx;
    ghost_left_[j] = edge_left_[j] + r * (row[0] - ghost_left_[j]);
    ghost_right_[j] = edge_right_[j] + r * (row[nx - 1] - ghost_right_[j]);
  }
}

template <typename T>
void BasicWater<T>::SubStep(T compensation) {
  const bool absorbing = options_.walls == WallMode::kAbsorb;
  UpdateGhosts(/*before_step=*/true);
  const int nx = grid_.nx, ny = grid_.ny;
  const bool masked = num_water_ < static_cast<int>(h_.size());
  auto run = [&](auto mode) {
    StepGrid<T, decltype(mode)::value>(
        nx, ny, h_.data(), u_.data(), mask_.data(), ones_.data(), absorbing,
        ghost_top_.data(), ghost_bottom_.data(), ghost_left_.data(),
        ghost_right_.data(), k_, damp_, compensation);
  };
  if (!masked) {
    run(std::integral_constant<int, kPlain>());
  } else if (options_.obstacles == ObstacleMode::kZero) {
    run(std::integral_constant<int, kZeroMask>());
  } else {
    run(std::integral_constant<int, kReflectMask>());
  }
  UpdateGhosts(/*before_step=*/false);
  // The mean mode of a conserving set-up, exactly: sum(u) decays by D and
  // sum(h) integrates it (the pen's net input is zero).
  target_usum_ *= static_cast<double>(damp_);
  target_volume_ += target_usum_;
}

template <typename T>
void BasicWater<T>::Step(int n) {
  for (int s = 0; s < n; ++s) {
    SubStep(T(0));
  }
  if (n > 0) {
    ++counter_;
    at_rest_ = false;
  }
}

template <typename T>
bool BasicWater<T>::Advance(double dt_frame_s) {
  if (!Finite(dt_frame_s) || dt_frame_s < 0) return false;
  stats_.substeps = 0;
  stats_.dropped_s = 0;
  stats_.pen_touched = false;
  stats_.changed = false;
  stats_.substep_s = dt_;
  const double start_s = time_s_;
  time_s_ += dt_frame_s;
  pen_path_.Push(time_s_, pending_present_, pending_tip_);

  if (at_rest_ && !wake_pending_) {
    std::array<double, 3> tip;
    if (!PenTouches(start_s, &tip) && !PenTouches(time_s_, &tip)) {
      // Nothing to do: the surface is flat and nobody touches it. The
      // accumulator keeps its phase so that sub-step times stay on the same
      // absolute grid whatever the frame rate.
      clock_.Idle(dt_frame_s, dt_);
      stats_.at_rest = true;
      stats_.counter = counter_;
      return true;
    }
  }
  const bool was_pending = wake_pending_;
  at_rest_ = false;
  wake_pending_ = false;

  const SubstepClock::Due due =
      clock_.Advance(dt_frame_s, time_s_, dt_, options_.max_substeps);
  const int n = due.substeps;
  stats_.dropped_s = due.dropped_s;
  const double end_s = due.end_s;
  bool touched = false;
  for (int s = 0; s < n; ++s) {
    const double mid_s = end_s - (n - s - 0.5) * dt_;
    T comp = 0;
    touched |= ApplyPen(mid_s, &comp);
    SubStep(comp);
  }
  stats_.substeps = n;
  stats_.pen_touched = touched;
  if (n > 0 || was_pending) {
    ++counter_;
    stats_.changed = true;
    ComputeStats();
    if (!touched && stats_.max_speed_m_per_s <= options_.rest_speed_m_per_s &&
        stats_.max_deviation_m <= options_.rest_height_m) {
      SnapToRest();
    }
  }
  stats_.at_rest = at_rest_;
  stats_.counter = counter_;
  return true;
}

template <typename T>
void BasicWater<T>::ComputeStats() {
  const int nx = grid_.nx, ny = grid_.ny;
  const bool reflect_mask = num_water_ < static_cast<int>(h_.size()) &&
                            options_.obstacles == ObstacleMode::kReflect;
  const Sums sums = SumGrid<T>(nx, ny, h_.data(), u_.data(), mask_.data(),
                               ones_.data(), reflect_mask);
  const double vol = sums.vol, absvol = sums.absvol, maxabs = sums.maxabs,
               maxu = sums.maxu, hmin = sums.hmin, hmax = sums.hmax,
               uu = sums.uu, usum = sums.usum, ehh = sums.ehh, euh = sums.euh;
  const double d2 = grid_.cell_m * grid_.cell_m;
  const double k = static_cast<double>(k_);
  stats_.volume_m3 = vol * d2;
  stats_.abs_volume_m3 = absvol * d2;
  stats_.max_abs_height_m = maxabs;
  stats_.max_speed_m_per_s = maxu / dt_;
  if (num_water_ > 0) {
    const double mean = vol / num_water_;
    stats_.max_deviation_m = std::max(hmax - mean, mean - hmin);
  } else {
    stats_.max_deviation_m = 0;
  }
  stats_.energy = 0.5 * (uu + k * (ehh - euh)) * d2 / (dt_ * dt_);

  // Float rounding makes sum(u) random-walk and sum(h) integrates it, so the
  // volume error of a conserving set-up would grow like steps^1.5. Remove the
  // measured drift of both sums, evenly over the water, once per Advance.
  // The statistics above describe the state before this correction.
  if (Conserving() && num_water_ > 0) {
    const T dh = static_cast<T>((target_volume_ - vol) / num_water_);
    const T du = static_cast<T>((target_usum_ - usum) / num_water_);
    if (dh != T(0) || du != T(0)) {
      const size_t n = h_.size();
      T* h = h_.data();
      T* u = u_.data();
      const T* m = mask_.data();
      for (size_t c = 0; c < n; ++c) {
        h[c] += dh * m[c];
        u[c] += du * m[c];
      }
    }
  } else {
    target_volume_ = vol;
    target_usum_ = usum;
  }
}

template <typename T>
bool BasicWater<T>::Conserving() const {
  return options_.walls == WallMode::kReflect &&
         (num_water_ == static_cast<int>(h_.size()) ||
          options_.obstacles == ObstacleMode::kReflect);
}

template <typename T>
void BasicWater<T>::ResetVolumeTarget() {
  double vol = 0, usum = 0;
  for (size_t c = 0; c < h_.size(); ++c) {
    if (water_[c]) {
      vol += h_[c];
      usum += u_[c];
    }
  }
  target_volume_ = vol;
  target_usum_ = usum;
}

template <typename T>
void BasicWater<T>::SnapToRest() {
  const size_t n = h_.size();
  double vol = 0;
  for (size_t c = 0; c < n; ++c)
    if (water_[c]) vol += h_[c];
  const T mean = num_water_ > 0 ? static_cast<T>(vol / num_water_) : T(0);
  for (size_t c = 0; c < n; ++c) {
    h_[c] = water_[c] ? mean : T(0);
    u_[c] = 0;
  }
  std::fill(ghost_top_.begin(), ghost_top_.end(), mean);
  std::fill(ghost_bottom_.begin(), ghost_bottom_.end(), mean);
  std::fill(ghost_left_.begin(), ghost_left_.end(), mean);
  std::fill(ghost_right_.begin(), ghost_right_.end(), mean);
  volume_debt_ = 0;
  target_volume_ = static_cast<double>(mean) * num_water_;
  target_usum_ = 0;
  at_rest_ = true;
  stats_.max_speed_m_per_s = 0;
  stats_.max_deviation_m = 0;
  stats_.max_abs_height_m = std::abs(static_cast<double>(mean));
  stats_.energy = 0;
}

template <typename T>
bool BasicWater<T>::SetState(const std::vector<T>& heights_m,
                             const std::vector<T>* velocities_m_per_s) {
  const size_t n = h_.size();
  if (heights_m.size() != n) return false;
  if (velocities_m_per_s && velocities_m_per_s->size() != n) return false;
  for (T v : heights_m)
    if (!std::isfinite(static_cast<double>(v))) return false;
  if (velocities_m_per_s)
    for (T v : *velocities_m_per_s)
      if (!std::isfinite(static_cast<double>(v))) return false;
  for (size_t c = 0; c < n; ++c) {
    h_[c] = water_[c] ? heights_m[c] : T(0);
    u_[c] = water_[c] && velocities_m_per_s
                ? static_cast<T>((*velocities_m_per_s)[c] * dt_)
                : T(0);
  }
  SeedGhosts();
  ResetVolumeTarget();
  volume_debt_ = 0;
  ++counter_;
  at_rest_ = false;
  wake_pending_ = true;
  return true;
}

template <typename T>
void BasicWater<T>::Reset() {
  std::fill(h_.begin(), h_.end(), T(0));
  std::fill(u_.begin(), u_.end(), T(0));
  SnapToRest();
  ++counter_;
  wake_pending_ = false;
  clock_ = SubstepClock();
}

template <typename T>
double BasicWater<T>::VelocityAt(int i, int j) const {
  return u_[static_cast<size_t>(j) * grid_.nx + i] / dt_;
}

template <typename T>
BasicHeightFieldView<T> BasicWater<T>::View() const {
  BasicHeightFieldView<T> v;
  v.heights = h_.data();
  v.water = water_.data();
  v.nx = grid_.nx;
  v.ny = grid_.ny;
  v.cell_m = grid_.cell_m;
  v.rest_level_m = grid_.rest_level_m;
  v.counter = counter_;
  return v;
}

template class BasicWater<float>;
template class BasicWater<double>;

}  // namespace ripple::sim
