// Internals of ComputeCaustics shared by caustics.cc (corners, triangles,
// the driver) and caustics_raster.cc (the edge rasteriser and the resolve):
// the 8-lane vector helpers, the accumulation buffer and the kernels'
// shared context. Not part of render/'s interface.
//
// The kernels below are written once with GCC/Clang vector extensions
// (8 floats, one AVX register) and compiled twice, for the baseline ISA and
// for AVX2, picked at run time as in sim/water.cc. Neither build contracts
// to FMA, so both give bit-identical maps.
#ifndef RIPPLE_RENDER_CAUSTICS_KERNELS_H_
#define RIPPLE_RENDER_CAUSTICS_KERNELS_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#define RIPPLE_INLINE inline __attribute__((always_inline))
// All vector helpers are inlined, so the ABI of 32-byte vectors does not
// matter.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <glm/glm.hpp>

#include "render/scene.h"

namespace ripple::render::caustics_internal {

constexpr int kLanes = 8;
typedef float F8 __attribute__((vector_size(32)));
typedef std::int32_t I8 __attribute__((vector_size(32)));

RIPPLE_INLINE F8 Bc(float x) { return F8{} + x; }
RIPPLE_INLINE I8 Bci(std::int32_t x) { return I8{} + x; }
RIPPLE_INLINE F8 Min(F8 a, F8 b) { return a < b ? a : b; }
RIPPLE_INLINE F8 Max(F8 a, F8 b) { return a > b ? a : b; }
RIPPLE_INLINE F8 Abs(F8 a) { return a < F8{} ? -a : a; }
RIPPLE_INLINE F8 ToF(I8 i) { return __builtin_convertvector(i, F8); }
RIPPLE_INLINE I8 ToI(F8 f) { return __builtin_convertvector(f, I8); }
RIPPLE_INLINE F8 Load(const float* p) {
  F8 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
RIPPLE_INLINE void Store(float* p, F8 v) { std::memcpy(p, &v, sizeof(v)); }
RIPPLE_INLINE I8 Lanes() { return I8{0, 1, 2, 3, 4, 5, 6, 7}; }
// Stores the first n (<= 8) lanes.
RIPPLE_INLINE void StoreN(float* p, F8 v, int n) {
  if (n == kLanes) {
    Store(p, v);
  } else {
    alignas(32) float t[kLanes];
    std::memcpy(t, &v, sizeof(t));
    std::memcpy(p, t, n * sizeof(float));
  }
}

// The accumulation buffer: three planes of `rows` x `stride` floats (each
// with room for two texels of spill right of and below the buffer proper),
// then a scratch area that masked-off SIMD lanes write into.
//  - R, prefix-summed along x: edges at most 45 degrees from vertical
//    (font-rs' accumulation rasteriser) and splats;
//  - C, prefix-summed along y: the other edges, rasterised the same way
//    with x and y swapped;
//  - Q, prefix-summed along y and then x: the corner terms that make C
//    edges equivalent to R edges (see EdgesRows).
struct AccumBuffer {
  int width = 0, height = 0, stride = 0, rows = 0;
  size_t plane = 0;
  std::vector<float> data;
  float* r() { return data.data(); }
  float* c() { return data.data() + plane; }
  float* q() { return data.data() + 2 * plane; }
  size_t dummy() const { return 3 * plane; }
  void Reset(int w, int h) {
    width = w;
    height = h;
    stride = (w + 2 + kLanes - 1) / kLanes * kLanes;
    rows = h + 2;
    plane = static_cast<size_t>(stride) * rows;
    data.resize(3 * plane + 4 * kLanes);
    std::fill(data.begin(), data.end(), 0.0f);
  }
};

// Bilinear splat of `flux` at (u, v) in buffer coordinates (texel centres at
// half-integers) into R; weights sum to one, so the flux is conserved.
inline void Splat(float u, float v, float flux, AccumBuffer* buf) {
  const float cu = u - 0.5f, cv = v - 0.5f;
  const int iu = static_cast<int>(std::floor(cu));
  const int iv = static_cast<int>(std::floor(cv));
  const float fu = cu - iu, fv = cv - iv;
  const int s = buf->stride;
  for (int r = 0; r < 2; ++r) {
    float* row = buf->r() + static_cast<size_t>(iv + r) * s + iu;
    const float f = flux * (r ? fv : 1 - fv);
    row[0] += f * (1 - fu);           // texel iu gets f (1 - fu)
    row[1] += f * fu - f * (1 - fu);  // texel iu + 1 gets f fu
    row[2] -= f * fu;
  }
}

// Everything the kernels share. Corner arrays (u, v, atten, z) are indexed
// j * cx + i and readable from -(cx + 1) to cx * (cy + 1) + kLanes (zero
// padding); triangle weights w0, w1 at wi(i, j) = (j + 1) * wx + i + 1 for
// i in [-1, nx], j in [-1, ny] (a zero border), plus kLanes of padding.
struct Ctx {
  int nx, ny, cx, cy, wx;
  const float* hc;
  float *u, *v, *atten, *z;
  float *w0, *w1;
  // Corner constants.
  float lx, ly, lz, eta, level, att, len_flat, su, sv, u_off, v_off, x0, y0, dx,
      dy;
  int bw, bh;
  size_t wi(int i, int j) const {
    return static_cast<size_t>(j + 1) * wx + (i + 1);
  }
};

inline bool HasAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

// Defines kernel `Name` twice from `Name##Impl`, for the baseline ISA and for
// AVX2, and `Name(bool simd, Params...)`, which picks one at run time.
#define RIPPLE_CAUSTICS_KERNEL(Name, Params, Args)                            \
  void Name##Base Params { Name##Impl Args; }                                 \
  __attribute__((target("avx2"))) void Name##Avx2 Params { Name##Impl Args; } \
  void Name(bool simd, RIPPLE_UNPAREN Params) {                               \
    if (simd && HasAvx2()) return Name##Avx2 Args;                            \
    Name##Base Args;                                                          \
  }
#define RIPPLE_UNPAREN(...) __VA_ARGS__

// caustics_raster.cc: step 3, each mesh edge once and each corner's Q term,
// for corner rows j0..j1 into `buf`.
void EdgesRows(bool simd, const Ctx& c, AccumBuffer* buf, int j0, int j1);
// caustics_raster.cc: step 4, texel coverage of buffer rows y_first..y_last
// (see ResolveImpl).
void Resolve(bool simd, AccumBuffer* buf, int y_first, int y_last, float* col_c,
             float* col_q, float* out);

// Flat water's map: the fraction of each texel inside the tank's surface
// rectangle shifted by the refracted light (1 inside the lit area, 0 in the
// strip along the walls facing the light). `l` unit, towards the light.
void FlatSurfaceMap(const TankGeometry& tank, const glm::dvec3& l, double ior,
                    int mx, int my, float* map);

// What the glass walls do to the surface's light near them, for the rest
// level, per texel, light-traced through the tank with its glass slabs
// `glass_thickness_m` thick (tank_paths.h) from the centre of the light's
// disc, `paths_per_axis`^2 paths per texel, relative to flat open water's
// light (caustics_walls.cc; CausticsOptions::glass_near_walls):
// - `gain` multiplies the light the surface refracts straight onto the floor
//   (the surface's map): the glass above the water transmits part of it,
//   reflects some onto the surface near the wall facing away, and turns
//   away what meets a wall's top face (total reflection guides it down the
//   slab), which leaves a dark line along the walls facing the light. Where
//   the surface's map holds a quarter of a texel or less, the gain is 0 and
//   that light is in `add`;
// - `add`: the surface's light that a wall then sent back onto the floor
//   (below the water a wall facing away mirrors it, the glass-air face
//   totally beyond its critical angle; a thick slab shifts it down, so it
//   lands nearer the wall, and what reaches the slab's foot is lost to the
//   floor), the light that crossed the wall facing away above the water,
//   was reflected by its outer face and came back in below the water line
//   (it lands about a depth from that wall), and what a wall facing the
//   light lets in after reflections between its faces (AddWallLight adds
//   the straight beam).
// Texels farther from every wall than the glass can reach keep gain 1 and
// add 0; both are overwritten over the whole map. Returns the change of
// the surface's light in flux (CausticsSummary's units).
double NearWallGlassMaps(const TankGeometry& tank, double glass_thickness_m,
                         const glm::dvec3& l, double ior, double glass_ior,
                         double attenuation_per_m, int mx, int my,
                         int paths_per_axis, float* gain, float* add);

// Adds the relative irradiance of the light entering through the side walls
// below the rest level (caustics_walls.cc; CausticsOptions), analytically
// per texel (4 x 4 samples). A slab of any thickness gives the same light
// on the floor: what leaves its inner face below the water entered the
// outer face higher up, so the inner face passes the same beam, moved
// along the wall. Returns the flux added, in CausticsSummary's units.
double AddWallLight(const TankGeometry& tank, const glm::dvec3& l, double ior,
                    double glass_ior, double attenuation_per_m, int mx, int my,
                    float* map);

// The penumbra of a light of angular radius `alpha` (radians): each
// direction within alpha of `l` lights the floor with the same pattern,
// moved by the shift of its refracted ray over the rest depth (exact for
// flat water, the usual approximation under ripples). The kernel is the
// share of the disc's directions whose shift rounds to each texel offset
// (i, j) in [-r, r]^2 (row-major, (2r + 1)^2 weights summing to 1): the
// disc convolved with the map's texel-constant irradiance and read at the
// texel centres. r is at most `max_r`; 0 for alpha 0. tx, ty: texel size
// (metres).
std::vector<float> PenumbraKernel(const TankGeometry& tank, const glm::dvec3& l,
                                  double ior, double alpha, double tx,
                                  double ty, int max_r, int* r);

// out = map convolved with the kernel (edges clamped: a texel beyond the
// map reads its nearest edge texel), mx x my, row-major.
void ApplyPenumbra(const std::vector<float>& kernel, int r, int mx, int my,
                   const float* map, float* out);

}  // namespace ripple::render::caustics_internal

#endif  // RIPPLE_RENDER_CAUSTICS_KERNELS_H_
