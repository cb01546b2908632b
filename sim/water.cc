#include "sim/water.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "geometry/check.h"

namespace ripple::sim {
namespace {

constexpr double kMinSigmaCells = 0.5;  // sigma >= half a cell
constexpr double kCutoffSigmas = 4.0;   // exp(-8) ~ 3e-4 beyond

bool Finite(double v) { return std::isfinite(v); }

enum KernelMode { kPlain = 0, kZeroMask = 1, kReflectMask = 2 };

// One row of the velocity update u = m * D * (u + k*lap(h) + add).
// up/dn are the rows j-1 and j+1 (or ghosts), left/right the ghost values
// beyond i = 0 and i = nx-1. The inner loop has no branches so that the
// compiler vectorises it.
template <typename T, int M>
__attribute__((always_inline)) inline void VelocityRow(
    int nx, const T* __restrict up, const T* __restrict c,
    const T* __restrict dn, T left, T right, const T* __restrict mu,
    const T* __restrict mc, const T* __restrict md, T* __restrict u, T k,
    T damp, T add) {
  auto cell = [&](int i, T l, T r, T ml, T mr) {
    const T ci = c[i];
    T lap;
    if (M == kReflectMask) {
      lap = mu[i] * (up[i] - ci) + md[i] * (dn[i] - ci) + ml * (l - ci) +
            mr * (r - ci);
    } else {
      lap = up[i] + dn[i] + l + r - T(4) * ci;
    }
    T v = damp * (u[i] + k * lap + add);
    if (M != kPlain) v *= mc[i];
    u[i] = v;
  };
  const T one = 1;
  if (nx == 1) {
    cell(0, left, right, one, one);
    return;
  }
  cell(0, left, c[1], one, M == kReflectMask ? mc[1] : one);
  for (int i = 1; i < nx - 1; ++i) {
    const T ci = c[i];
    T lap;
    if (M == kReflectMask) {
      lap = mu[i] * (up[i] - ci) + md[i] * (dn[i] - ci) +
            mc[i - 1] * (c[i - 1] - ci) + mc[i + 1] * (c[i + 1] - ci);
    } else {
      lap = up[i] + dn[i] + c[i - 1] + c[i + 1] - T(4) * ci;
    }
    T v = damp * (u[i] + k * lap + add);
    if (M != kPlain) v *= mc[i];
    u[i] = v;
  }
  cell(nx - 1, c[nx - 2], right, M == kReflectMask ? mc[nx - 2] : one, one);
}

template <typename T>
__attribute__((always_inline)) inline void AddRow(int nx, T* __restrict h,
                                                  const T* __restrict u) {
  for (int i = 0; i < nx; ++i) h[i] += u[i];
}

// One full sub-step over the grid, fused: the height of row j-1 is updated
// right after the velocity of row j, which is the last reader of the old
// heights of row j-1. One sweep over memory per sub-step.
template <typename T, int M>
__attribute__((always_inline)) inline void StepGridImpl(
    int nx, int ny, T* h, T* u, const T* mask, const T* ones, bool absorbing,
    const T* ghost_top, const T* ghost_bottom, const T* ghost_left,
    const T* ghost_right, T k, T damp, T add) {
  const size_t snx = static_cast<size_t>(nx);
  for (int j = 0; j < ny; ++j) {
    T* c = h + j * snx;
    const T* up = j > 0 ? c - snx : (absorbing ? ghost_top : c);
    const T* dn = j + 1 < ny ? c + snx : (absorbing ? ghost_bottom : c);
    const T left = absorbing ? ghost_left[j] : c[0];
    const T right = absorbing ? ghost_right[j] : c[nx - 1];
    const T* mc = mask + j * snx;
    const T* mu = j > 0 ? mc - snx : ones;
    const T* md = j + 1 < ny ? mc + snx : ones;
    VelocityRow<T, M>(nx, up, c, dn, left, right, mu, mc, md, u + j * snx, k,
                      damp, add);
    if (j > 0) AddRow<T>(nx, c - snx, u + (j - 1) * snx);
  }
  AddRow<T>(nx, h + (ny - 1) * snx, u + (ny - 1) * snx);
}

#define RIPPLE_STEP_ARGS                                                    \
  int nx, int ny, T *h, T *u, const T *mask, const T *ones, bool absorbing, \
      const T *ghost_top, const T *ghost_bottom, const T *ghost_left,       \
      const T *ghost_right, T k, T damp, T add
#define RIPPLE_STEP_PASS                                                    \
  nx, ny, h, u, mask, ones, absorbing, ghost_top, ghost_bottom, ghost_left, \
      ghost_right, k, damp, add

// The same kernel compiled for the baseline ISA and for AVX2, picked at run
// time (no FMA contraction either way, so both give identical results).
template <typename T, int M>
void StepGridBase(RIPPLE_STEP_ARGS) {
  StepGridImpl<T, M>(RIPPLE_STEP_PASS);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <typename T, int M>
__attribute__((target("avx2"))) void StepGridAvx2(RIPPLE_STEP_ARGS) {
  StepGridImpl<T, M>(RIPPLE_STEP_PASS);
}
bool HasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

template <typename T, int M>
void StepGrid(RIPPLE_STEP_ARGS) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (HasAvx2()) return StepGridAvx2<T, M>(RIPPLE_STEP_PASS);
#endif
  StepGridBase<T, M>(RIPPLE_STEP_PASS);
}
#undef RIPPLE_STEP_ARGS
#undef RIPPLE_STEP_PASS

// Sums over the grid for the statistics (see ComputeStats).
struct Sums {
  double vol, absvol, maxabs, maxu, hmin, hmax, uu, usum, ehh, euh;
};

template <typename T>
__attribute__((always_inline)) inline Sums SumGridImpl(int nx, int ny,
                                                       const T* h0, const T* u0,
                                                       const T* mask,
                                                       const T* ones,
                                                       bool reflect_mask) {
  double vol = 0, absvol = 0, maxabs = 0, maxu = 0;
  double hmin = std::numeric_limits<double>::infinity();
  double hmax = -hmin;
  double uu = 0, ehh = 0, euh = 0, usum = 0;
  // Zero treatment: blocked cells hold 0, so summing every edge gives the
  // Dirichlet form; the reflecting treatment counts water-water edges only
  // (weights from the mask; otherwise a row of ones).
  const double inf = std::numeric_limits<double>::infinity();
  for (int j = 0; j < ny; ++j) {
    const size_t r = static_cast<size_t>(j) * nx;
    const T* h = h0 + r;
    const T* u = u0 + r;
    const T* m = mask + r;
    // The row above; the last row pairs with itself (zero differences).
    const size_t up = j + 1 < ny ? nx : 0;
    const T* wm = reflect_mask ? m : ones;
    const T* wm_up = reflect_mask ? m + up : ones;
    // Right-hand edges exist for i < nx - 1; the last cell is done after.
#pragma omp simd reduction(+ : vol, absvol, uu, usum, ehh, euh) \
    reduction(max : maxabs, maxu, hmax) reduction(min : hmin)
    for (int i = 0; i < nx - 1; ++i) {
      const double hi = h[i], ui = u[i], mi = m[i];
      vol += mi * hi;
      absvol += mi * std::abs(hi);
      maxabs = std::max(maxabs, mi * std::abs(hi));
      hmin = std::min(hmin, mi != 0 ? hi : inf);
      hmax = std::max(hmax, mi != 0 ? hi : -inf);
      maxu = std::max(maxu, std::abs(ui));
      uu += ui * ui;
      usum += ui;
      const double wr = double(wm[i]) * wm[i + 1];
      const double dh = double(h[i + 1]) - hi, du = double(u[i + 1]) - ui;
      const double wu = double(wm[i]) * wm_up[i];
      const double dhu = double(h[i + up]) - hi, duu = double(u[i + up]) - ui;
      ehh += wr * dh * dh + wu * dhu * dhu;
      euh += wr * du * dh + wu * duu * dhu;
    }
    const int i = nx - 1;
    const double hi = h[i], ui = u[i], mi = m[i];
    vol += mi * hi;
    absvol += mi * std::abs(hi);
    maxabs = std::max(maxabs, mi * std::abs(hi));
    if (mi != 0) {
      hmin = std::min(hmin, hi);
      hmax = std::max(hmax, hi);
    }
    maxu = std::max(maxu, std::abs(ui));
    uu += ui * ui;
    usum += ui;
    const double wu = double(wm[i]) * wm_up[i];
    const double dhu = double(h[i + up]) - hi, duu = double(u[i + up]) - ui;
    ehh += wu * dhu * dhu;
    euh += wu * duu * dhu;
  }
  return {vol, absvol, maxabs, maxu, hmin, hmax, uu, usum, ehh, euh};
}

template <typename T>
Sums SumGridBase(int nx, int ny, const T* h0, const T* u0, const T* mask,
                 const T* ones, bool reflect_mask) {
  return SumGridImpl<T>(nx, ny, h0, u0, mask, ones, reflect_mask);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <typename T>
__attribute__((target("avx2"))) Sums SumGridAvx2(int nx, int ny, const T* h0,
                                                 const T* u0, const T* mask,
                                                 const T* ones,
                                                 bool reflect_mask) {
  return SumGridImpl<T>(nx, ny, h0, u0, mask, ones, reflect_mask);
}
#endif

template <typename T>
Sums SumGrid(int nx, int ny, const T* h0, const T* u0, const T* mask,
             const T* ones, bool reflect_mask) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (HasAvx2())
    return SumGridAvx2<T>(nx, ny, h0, u0, mask, ones, reflect_mask);
#endif
  return SumGridBase<T>(nx, ny, h0, u0, mask, ones, reflect_mask);
}

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
void BasicWater<T>::PushPenSample(bool present,
                                  const std::array<double, 3>& tip) {
  PenSample s;
  s.time_s = time_s_;
  s.present = present;
  s.tip = tip;
  if (pen_count_ < static_cast<int>(pen_history_.size())) {
    pen_history_[pen_count_++] = s;
  } else {
    std::move(pen_history_.begin() + 1, pen_history_.end(),
              pen_history_.begin());
    pen_history_.back() = s;
  }
}

template <typename T>
bool BasicWater<T>::PenAt(double time_s, std::array<double, 3>* tip) const {
  if (pen_count_ == 0) return false;
  const PenSample& first = pen_history_[0];
  const PenSample& last = pen_history_[pen_count_ - 1];
  if (time_s <= first.time_s) {
    *tip = first.tip;
    return first.present;
  }
  if (time_s >= last.time_s) {
    *tip = last.tip;
    return last.present;
  }
  for (int s = 1; s < pen_count_; ++s) {
    const PenSample& b = pen_history_[s];
    if (time_s > b.time_s) continue;
    const PenSample& a = pen_history_[s - 1];
    if (time_s == b.time_s) {
      *tip = b.tip;
      return b.present;
    }
    if (!a.present || !b.present) return false;
    const double span = b.time_s - a.time_s;
    const double w = span > 0 ? (time_s - a.time_s) / span : 1.0;
    for (int c = 0; c < 3; ++c)
      (*tip)[c] = a.tip[c] + w * (b.tip[c] - a.tip[c]);
    return true;
  }
  *tip = last.tip;
  return last.present;
}

template <typename T>
double BasicWater<T>::HeightAtPoint(double x_m, double y_m) const {
  const int nx = grid_.nx, ny = grid_.ny;
  const double fx =
      std::clamp(x_m / grid_.cell_m + 0.5 * nx - 0.5, 0.0, nx - 1.0);
  const double fy =
      std::clamp(y_m / grid_.cell_m + 0.5 * ny - 0.5, 0.0, ny - 1.0);
  const int i0 = std::min(static_cast<int>(fx), nx - 2);
  const int j0 = std::min(static_cast<int>(fy), ny - 2);
  const double ax = fx - i0, ay = fy - j0;
  const T* r0 = h_.data() + static_cast<size_t>(j0) * nx;
  const T* r1 = r0 + nx;
  return (1 - ay) * ((1 - ax) * r0[i0] + ax * r0[i0 + 1]) +
         ay * ((1 - ax) * r1[i0] + ax * r1[i0 + 1]);
}

template <typename T>
bool BasicWater<T>::PenTouches(double time_s,
                               std::array<double, 3>* tip) const {
  if (!PenAt(time_s, tip)) return false;
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
  PushPenSample(pending_present_, pending_tip_);

  if (at_rest_ && !wake_pending_) {
    std::array<double, 3> tip;
    if (!PenTouches(start_s, &tip) && !PenTouches(time_s_, &tip)) {
      // Nothing to do: the surface is flat and nobody touches it. The
      // accumulator keeps its phase so that sub-step times stay on the same
      // absolute grid whatever the frame rate.
      accumulator_s_ = std::fmod(accumulator_s_ + dt_frame_s, dt_);
      stats_.at_rest = true;
      stats_.counter = counter_;
      return true;
    }
  }
  const bool was_pending = wake_pending_;
  at_rest_ = false;
  wake_pending_ = false;

  accumulator_s_ += dt_frame_s;
  const double due = std::floor(accumulator_s_ / dt_ + 1e-7);
  const int n = static_cast<int>(std::min<double>(due, options_.max_substeps));
  stats_.dropped_s = (due - n) * dt_;
  accumulator_s_ = std::max(0.0, accumulator_s_ - due * dt_);
  const double end_s = time_s_ - accumulator_s_;
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
  accumulator_s_ = 0;
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

// ---------------------------------------------------------------- obstacles

template <typename T>
void BasicWater<T>::Rasterize(ObstacleState* state) const {
  const Obstacle& o = state->obstacle;
  const int nx = grid_.nx, ny = grid_.ny;
  const double d = grid_.cell_m, level = grid_.rest_level_m;
  state->i0 = state->i1 = state->j0 = state->j1 = 0;
  state->covers.clear();
  // Tank-frame bounds of the shape from its 8 local corners.
  const auto local = o.LocalBounds();
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (int corner = 0; corner < 8; ++corner) {
    const std::array<double, 3> p = {local[corner & 1][0],
                                     local[(corner >> 1) & 1][1],
                                     local[(corner >> 2) & 1][2]};
    const auto q = o.tank_from_obstacle.Apply(p);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], q[a]);
      hi[a] = std::max(hi[a], q[a]);
    }
  }
  if (!(lo[2] <= level && hi[2] >= level)) return;  // misses the surface
  auto index_range = [&](double a, double b, int n, int* i0, int* i1) {
    // Cells whose centre (i + 0.5 - n/2) * d lies in [a, b].
    const double f0 = std::ceil(a / d + 0.5 * n - 0.5);
    const double f1 = std::floor(b / d + 0.5 * n - 0.5);
    *i0 = static_cast<int>(std::clamp(f0, 0.0, double(n)));
    *i1 = static_cast<int>(std::clamp(f1 + 1, 0.0, double(n)));
  };
  index_range(lo[0], hi[0], nx, &state->i0, &state->i1);
  index_range(lo[1], hi[1], ny, &state->j0, &state->j1);
  if (state->i0 >= state->i1 || state->j0 >= state->j1) {
    state->i0 = state->i1 = state->j0 = state->j1 = 0;
    return;
  }
  const RigidTransform obstacle_from_tank = o.tank_from_obstacle.Inverse();
  const int w = state->i1 - state->i0;
  state->covers.assign(static_cast<size_t>(w) * (state->j1 - state->j0), 0);
  for (int j = state->j0; j < state->j1; ++j) {
    for (int i = state->i0; i < state->i1; ++i) {
      const std::array<double, 3> p_in_tank = {(i + 0.5 - 0.5 * nx) * d,
                                               (j + 0.5 - 0.5 * ny) * d, level};
      state->covers[static_cast<size_t>(j - state->j0) * w + (i - state->i0)] =
          o.ContainsInObstacle(obstacle_from_tank.Apply(p_in_tank));
    }
  }
}

template <typename T>
void BasicWater<T>::ApplyCover(const ObstacleState& state, int sign) {
  const int w = state.i1 - state.i0;
  for (int j = state.j0; j < state.j1; ++j) {
    for (int i = state.i0; i < state.i1; ++i) {
      if (!state.covers[static_cast<size_t>(j - state.j0) * w + (i - state.i0)])
        continue;
      cover_count_[static_cast<size_t>(j) * grid_.nx + i] += sign;
    }
  }
}

template <typename T>
bool BasicWater<T>::UpdateMaskRegion(int i0, int i1, int j0, int j1) {
  bool changed = false;
  double removed = 0, removed_u = 0;
  for (int j = j0; j < j1; ++j) {
    for (int i = i0; i < i1; ++i) {
      const size_t c = static_cast<size_t>(j) * grid_.nx + i;
      const bool wet = cover_count_[c] == 0;
      if (wet == (water_[c] != 0)) continue;
      changed = true;
      if (!wet) {
        removed += h_[c];
        removed_u += u_[c];
      }
      h_[c] = 0;
      u_[c] = 0;
      water_[c] = wet;
      mask_[c] = wet ? T(1) : T(0);
      num_water_ += wet ? 1 : -1;
    }
  }
  if (changed && options_.obstacles == ObstacleMode::kReflect &&
      num_water_ > 0 && (removed != 0 || removed_u != 0)) {
    // Give the displaced volume (and its velocity, whose sum Σh integrates)
    // back to the water, evenly.
    const T dh = static_cast<T>(removed / num_water_);
    const T du = static_cast<T>(removed_u / num_water_);
    for (size_t c = 0; c < h_.size(); ++c) {
      h_[c] += dh * mask_[c];
      u_[c] += du * mask_[c];
    }
  }
  if (changed && !Conserving()) ResetVolumeTarget();
  return changed;
}

template <typename T>
int BasicWater<T>::AddObstacle(const Obstacle& obstacle, std::string* error) {
  if (!obstacle.IsValid(error)) return -1;
  ObstacleState state;
  state.obstacle = obstacle;
  Rasterize(&state);
  ApplyCover(state, +1);
  if (UpdateMaskRegion(state.i0, state.i1, state.j0, state.j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  obstacles_.push_back(std::move(state));
  return static_cast<int>(obstacles_.size()) - 1;
}

template <typename T>
bool BasicWater<T>::SetObstaclePose(int id,
                                    const RigidTransform& tank_from_obstacle) {
  if (id < 0 || id >= num_obstacles() || !tank_from_obstacle.IsFinite() ||
      obstacles_[id].removed)
    return false;
  ObstacleState& state = obstacles_[id];
  if (state.obstacle.tank_from_obstacle == tank_from_obstacle) return true;
  const int oi0 = state.i0, oi1 = state.i1, oj0 = state.j0, oj1 = state.j1;
  ApplyCover(state, -1);
  state.obstacle.tank_from_obstacle = tank_from_obstacle;
  Rasterize(&state);
  ApplyCover(state, +1);
  // The union of the old and new regions holds every cell that may flip.
  int i0 = state.i0, i1 = state.i1, j0 = state.j0, j1 = state.j1;
  if (oi0 < oi1 && oj0 < oj1) {
    if (i0 < i1 && j0 < j1) {
      i0 = std::min(i0, oi0);
      i1 = std::max(i1, oi1);
      j0 = std::min(j0, oj0);
      j1 = std::max(j1, oj1);
    } else {
      i0 = oi0, i1 = oi1, j0 = oj0, j1 = oj1;
    }
  }
  if (UpdateMaskRegion(i0, i1, j0, j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  return true;
}

template <typename T>
bool BasicWater<T>::RemoveObstacle(int id) {
  if (id < 0 || id >= num_obstacles() || obstacles_[id].removed) return false;
  ObstacleState& state = obstacles_[id];
  ApplyCover(state, -1);
  state.removed = true;
  if (UpdateMaskRegion(state.i0, state.i1, state.j0, state.j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  state.i0 = state.i1 = state.j0 = state.j1 = 0;
  state.covers.clear();
  return true;
}

template class BasicWater<float>;
template class BasicWater<double>;

}  // namespace ripple::sim
