// The paper scheme's grid kernels (sim/water.h): the fused velocity and
// height sweep of one sub-step and the statistics sums, compiled for the
// baseline ISA and for AVX2 and picked at run time. Internal to water.cc.
#ifndef RIPPLE_SIM_WATER_KERNELS_H_
#define RIPPLE_SIM_WATER_KERNELS_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace ripple::sim::internal {

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
inline bool HasAvx2() {
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

}  // namespace ripple::sim::internal

#endif  // RIPPLE_SIM_WATER_KERNELS_H_
