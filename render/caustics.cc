#include "render/caustics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <thread>

#include "render/caustics_kernels.h"

namespace ripple::render {

using caustics_internal::AccumBuffer;

namespace {

using namespace caustics_internal;  // NOLINT: the kernels' vector helpers

// Texels of margin around the map in the accumulation buffer: light landing
// there is counted as outside the map.
constexpr int kMargin = 8;
// Projected triangles smaller than this (texels^2) are splatted.
constexpr float kMinArea = 0.1f;

// Lane-wise sqrt (sqrtps once vectorised; no generic vector builtin).
RIPPLE_INLINE F8 Sqrt8(F8 x) {
  alignas(32) float t[kLanes];
  std::memcpy(t, &x, sizeof(t));
  for (int l = 0; l < kLanes; ++l) t[l] = std::sqrt(t[l]);
  std::memcpy(&x, t, sizeof(t));
  return x;
}

// exp(x) for |x| < 80 to ~2 ulp, eight lanes: 2^n times a degree-6
// polynomial of 2^f, f in [-1/2, 1/2] (no libm call).
RIPPLE_INLINE F8 Exp8(F8 x) {
  x = Min(Max(x, Bc(-80.0f)), Bc(80.0f));
  const F8 t = x * 1.44269504f;
  // Round to nearest by the 1.5 * 2^23 trick (|t| < 2^22): roundps needs
  // SSE4.1.
  const F8 n = (t + 12582912.0f) - 12582912.0f;
  const F8 f = (t - n) * 0.693147181f;  // ln 2
  F8 p = Bc(1.0f / 720);
  p = p * f + 1.0f / 120;
  p = p * f + 1.0f / 24;
  p = p * f + 1.0f / 6;
  p = p * f + 0.5f;
  p = p * f + 1.0f;
  p = p * f + 1.0f;
  const I8 bits = (ToI(n) + 127) << 23;
  F8 scale;
  std::memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

// Unnormalised refraction (Snell) of unit `d` at unit normal `n`, eta =
// n1 / n2 (< 1 here, so never total internal reflection).
inline glm::vec3 Refract(const glm::vec3& d, const glm::vec3& n, float eta) {
  const float cosi = -glm::dot(n, d);
  const float k = 1.0f - eta * eta * (1.0f - cosi * cosi);
  return eta * d + (eta * cosi - std::sqrt(std::max(k, 0.0f))) * n;
}

template <typename F>
void ParallelRows(int rows, int threads, F&& f) {
  threads = std::max(1, std::min(threads, rows));
  if (threads == 1) {
    f(0, 0, rows);
    return;
  }
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) {
    pool.emplace_back(f, k, rows * k / threads, rows * (k + 1) / threads);
  }
  f(0, 0, rows / threads);
  for (auto& t : pool) t.join();
}

//    refracted ray, its floor hit in buffer coordinates, the attenuation of
//    its path relative to flat water, and its height.
RIPPLE_INLINE void CornersRowsImpl(const Ctx& c, int j_begin, int j_end) {
  const F8 lx = Bc(c.lx), ly = Bc(c.ly), lz = Bc(c.lz), eta = Bc(c.eta),
           level = Bc(c.level), su = Bc(c.su), sv = Bc(c.sv),
           u_off = Bc(c.u_off), v_off = Bc(c.v_off), one = Bc(1.0f);
  const float att = c.att, len_flat = c.len_flat, x0 = c.x0, dx = c.dx;
  const int cx = c.cx, cy = c.cy;
  // One-sided slopes at the ends, central inside.
  const F8 gx_inner = Bc(1.0f / (2.0f * dx)), gx_end = Bc(1.0f / dx);
  for (int j = j_begin; j < j_end; ++j) {
    const int jm = std::max(j - 1, 0), jp = std::min(j + 1, cy - 1);
    const size_t o = static_cast<size_t>(j) * cx;
    const float* row = &c.hc[o];
    const float* up = &c.hc[static_cast<size_t>(jp) * cx];
    const float* down = &c.hc[static_cast<size_t>(jm) * cx];
    const F8 gy_scale = Bc(1.0f / ((jp - jm) * c.dy));
    const F8 y = Bc(c.y0 + j * c.dy);
    for (int i = 0; i < cx; i += kLanes) {
      const I8 ii = Lanes() + i;
      const F8 h = Load(row + i);
      const I8 first = ii == I8{}, last = ii == Bci(cx - 1);
      const F8 left = first ? h : Load(row + i - 1);
      const F8 right = last ? h : Load(row + i + 1);
      const F8 gx = (right - left) * ((first | last) ? gx_end : gx_inner);
      const F8 gy = (Load(up + i) - Load(down + i)) * gy_scale;
      // n = normalize(-gx, -gy, 1); t = Refract(-l, n, eta), inlined.
      const F8 inv_n = one / Sqrt8(gx * gx + gy * gy + one);
      const F8 nx_ = -gx * inv_n, ny_ = -gy * inv_n, nz_ = inv_n;
      const F8 cosi = nx_ * lx + ny_ * ly + nz_ * lz;
      const F8 k = one - eta * eta * (one - cosi * cosi);
      const F8 m = eta * cosi - Sqrt8(Max(k, F8{}));
      const F8 tx = -eta * lx + m * nx_;
      const F8 ty = -eta * ly + m * ny_;
      const F8 tz = -eta * lz + m * nz_;
      const F8 z = Max(level + h, F8{});
      const F8 len = z / Max(-tz, Bc(1e-4f));
      const F8 x = x0 + ToF(ii) * dx;
      const int n = std::min(kLanes, cx - i);
      StoreN(&c.u[o + i], (x + tx * len) * su + u_off, n);
      StoreN(&c.v[o + i], (y + ty * len) * sv + v_off, n);
      // 1 when att = 0.
      StoreN(&c.atten[o + i], Exp8(-att * (len - len_flat)), n);
      StoreN(&c.z[o + i], z, n);
    }
  }
}

// 2. Triangles of quad rows j0..j1: flux in, and the weight of their edges
//    (flux over projected area, signed by the winding), or a splat if tiny.
//    Quad (i, j) has corners a = (i, j), b = (i+1, j), c = (i+1, j+1),
//    d = (i, j+1) and triangles T0 = abc, T1 = acd.
RIPPLE_INLINE void TrianglesRowsImpl(const Ctx& c, float* tmp, AccumBuffer* buf,
                                     CausticsSummary* sum, bool summary,
                                     int j_begin, int j_end) {
  const float hdx = 0.5f * c.dx, hdy = 0.5f * c.dy,
              hdxdy = 0.5f * c.dx * c.dy * c.lz, lx = c.lx, ly = c.ly;
  const F8 bw_max = Bc(c.bw - 1.0f), bh_max = Bc(c.bh - 1.0f);
  const int nx = c.nx, cx = c.cx;
  float* __restrict pf0 = tmp;  // floor flux of T0, T1
  float* __restrict pf1 = pf0 + nx;
  float* __restrict ar0 = pf1 + nx;  // projected areas (texels^2)
  float* __restrict ar1 = ar0 + nx;
  // 1 when the quad needs the rare-case pass.
  float* __restrict rare = ar1 + nx;
  for (int j = j_begin; j < j_end; ++j) {
    const size_t o = static_cast<size_t>(j) * cx;
    const float* __restrict ua = &c.u[o];
    const float* __restrict ud = &c.u[o + cx];
    const float* __restrict va = &c.v[o];
    const float* __restrict vd = &c.v[o + cx];
    const float* __restrict za = &c.z[o];
    const float* __restrict zd = &c.z[o + cx];
    const float* __restrict aa = &c.atten[o];
    const float* __restrict ad = &c.atten[o + cx];
    float* __restrict w0 = &c.w0[c.wi(0, j)];
    float* __restrict w1 = &c.w1[c.wi(0, j)];
    const F8 zero = {}, one = Bc(1.0f), min_area = Bc(kMinArea);
    for (int i = 0; i < nx; i += kLanes) {
      const F8 au = Load(ua + i), bu = Load(ua + i + 1);
      const F8 cu = Load(ud + i + 1), du = Load(ud + i);
      const F8 av = Load(va + i), bv = Load(va + i + 1);
      const F8 cv = Load(vd + i + 1), dv = Load(vd + i);
      const F8 z_a = Load(za + i), z_b = Load(za + i + 1);
      const F8 z_c = Load(zd + i + 1), z_d = Load(zd + i);
      // Intercepted flux (unit irradiance facing the light): the area
      // vector dotted with the light, e.g. T0: (b - a) x (c - a) =
      // (-(zb - za) dy, (zb - zc) dx, dx dy).
      const F8 phi0 =
          Max(-(z_b - z_a) * hdy * lx + (z_b - z_c) * hdx * ly + hdxdy, zero);
      const F8 phi1 =
          Max((z_d - z_c) * hdy * lx - (z_d - z_a) * hdx * ly + hdxdy, zero);
      const F8 a_a = Load(aa + i), a_b = Load(aa + i + 1);
      const F8 a_c = Load(ad + i + 1), a_d = Load(ad + i);
      const F8 f0 = phi0 * (a_a + a_b + a_c) * (1.0f / 3.0f);
      const F8 f1 = phi1 * (a_a + a_c + a_d) * (1.0f / 3.0f);
      const F8 a0 = 0.5f * ((bu - au) * (cv - av) - (bv - av) * (cu - au));
      const F8 a1 = 0.5f * ((cu - au) * (dv - av) - (cv - av) * (du - au));
      const I8 big0 = Abs(a0) >= min_area, big1 = Abs(a1) >= min_area;
      const F8 min_u = Min(Min(au, bu), Min(cu, du));
      const F8 max_u = Max(Max(au, bu), Max(cu, du));
      const F8 min_v = Min(Min(av, bv), Min(cv, dv));
      const F8 max_v = Max(Max(av, bv), Max(cv, dv));
      const I8 in = (min_u >= one) & (max_u <= bw_max) & (min_v >= one) &
                    (max_v <= bh_max);
      const int n = std::min(kLanes, nx - i);
      StoreN(pf0 + i, f0, n);
      StoreN(pf1 + i, f1, n);
      StoreN(ar0 + i, a0, n);
      StoreN(ar1 + i, a1, n);
      StoreN(w0 + i, big0 ? -f0 / (big0 ? a0 : one) : zero, n);
      StoreN(w1 + i, big1 ? -f1 / (big1 ? a1 : one) : zero, n);
      StoreN(rare + i, (in & big0 & big1) ? zero : one, n);
    }
    // The rare cases: a quad reaching outside the buffer (handled per
    // triangle) or a triangle focused below kMinArea.
    for (int i = 0; i < nx; ++i) {
      if (rare[i] == 0.0f) continue;
      const size_t c00 = o + i, c10 = c00 + 1, c01 = c00 + cx, c11 = c01 + 1;
      const size_t tris[2][3] = {{c00, c10, c11}, {c00, c11, c01}};
      for (int t = 0; t < 2; ++t) {
        float& w = t == 0 ? w0[i] : w1[i];
        const float pf = t == 0 ? pf0[i] : pf1[i];
        const float area = t == 0 ? ar0[i] : ar1[i];
        const size_t a = tris[t][0], b = tris[t][1], d = tris[t][2];
        const float* u = c.u;
        const float* v = c.v;
        const float min_u = std::min({u[a], u[b], u[d]});
        const float max_u = std::max({u[a], u[b], u[d]});
        const float min_v = std::min({v[a], v[b], v[d]});
        const float max_v = std::max({v[a], v[b], v[d]});
        if (!(min_u >= 1.0f && max_u <= c.bw - 1.0f && min_v >= 1.0f &&
              max_v <= c.bh - 1.0f)) {
          sum->flux_outside += pf;  // beyond the margin too
          w = 0.0f;
        } else if (std::abs(area) < kMinArea) {
          Splat((u[a] + u[b] + u[d]) / 3.0f, (v[a] + v[b] + v[d]) / 3.0f, pf,
                buf);
          w = 0.0f;
        }
        // else: a counter-clockwise triangle accumulates -1 inside (w).
      }
    }
    if (summary) {
      // The flux entering the surface, before attenuation.
      double phi = 0;
      for (int i = 0; i < nx; ++i) {
        const float z_a = za[i], z_b = za[i + 1], z_c = zd[i + 1], z_d = zd[i];
        phi += std::max(
            -(z_b - z_a) * hdy * lx + (z_b - z_c) * hdx * ly + hdxdy, 0.0f);
        phi += std::max((z_d - z_c) * hdy * lx - (z_d - z_a) * hdx * ly + hdxdy,
                        0.0f);
      }
      sum->flux_in += phi;
      sum->triangles += 2 * nx;
    }
  }
}

RIPPLE_CAUSTICS_KERNEL(CornersRows, (const Ctx& c, int j0, int j1), (c, j0, j1))
RIPPLE_CAUSTICS_KERNEL(TrianglesRows,
                       (const Ctx& c, float* tmp, AccumBuffer* buf,
                        CausticsSummary* sum, bool summary, int j0, int j1),
                       (c, tmp, buf, sum, summary, j0, j1))

}  // namespace

struct CausticsWorkspace::Buffers {
  // The light through the walls depends on the tank, the light and the map
  // only (rest level): kept until one of them changes.
  std::vector<float> walls;
  std::vector<float> near_gain, near_add;  // NearWallGlassMaps
  std::vector<std::uint32_t> near_texels;  // where they are not 1 and 0
  std::array<double, 16> walls_key{};
  bool walls_valid = false;
  double walls_flux = 0;
  std::vector<float> hc;
  // Corner arrays with zero padding before and after (see Ctx).
  std::vector<float> u, v, atten, z;
  // Per quad, with a zero border: the edge weights of its two triangles.
  std::vector<float> w0, w1;
  // Per quad of one row: the two triangles' floor flux and projected area.
  std::vector<std::vector<float>> rows;
  std::vector<AccumBuffer> bufs;
  // Resolve: column sums and the resolved rows.
  std::vector<float> col_c, col_q, resolved;
  std::vector<float> penumbra;  // the map before the light's disc blurs it
  // The disc's kernel depends on the tank, the light and the map only.
  std::vector<float> penumbra_kernel;
  int penumbra_r = 0;
  std::array<double, 8> penumbra_key{};
  bool penumbra_valid = false;
};
CausticsWorkspace::CausticsWorkspace() : buffers(new Buffers) {}
CausticsWorkspace::~CausticsWorkspace() = default;
bool CausticsOptions::IsValid(std::string* error) const {
  if (map_nx < 1 || map_ny < 1) {
    if (error) *error = "caustics: map size must be positive";
    return false;
  }
  if (!(ior >= 1.0)) {
    if (error) *error = "caustics: ior must be >= 1";
    return false;
  }
  if (!(light_angular_radius_rad >= 0 && light_angular_radius_rad < 0.2)) {
    if (error)
      *error = "caustics: light angular radius must be in [0, 0.2) rad";
    return false;
  }
  if (attenuation_per_m < 0 || threads < 1) {
    if (error) *error = "caustics: attenuation >= 0 and threads >= 1";
    return false;
  }
  if (!(glass_ior >= 1.0) ||
      !(glass_thickness_m >= 0 && glass_thickness_m <= 0.05) ||
      glass_paths_per_axis < 1 || glass_paths_per_axis > 16) {
    if (error)
      *error =
          "caustics: glass ior >= 1, thickness in [0, 0.05] m and 1-16 paths "
          "per axis";
    return false;
  }
  return true;
}

namespace {

void AddWalls(const CausticsOptions& o, const TankGeometry& tank,
              const glm::dvec3& l, CausticsWorkspace::Buffers* ws,
              std::vector<float>* map, CausticsSummary* summary) {
  if (!o.light_through_walls && !o.glass_near_walls) return;
  const std::array<double, 16> key = {tank.size_x,
                                      tank.size_y,
                                      tank.water_level,
                                      tank.wall_height,
                                      l.x,
                                      l.y,
                                      l.z,
                                      o.ior,
                                      o.glass_ior,
                                      o.attenuation_per_m,
                                      double(o.map_nx),
                                      double(o.map_ny),
                                      o.glass_thickness_m,
                                      double(o.glass_paths_per_axis),
                                      double(o.light_through_walls),
                                      double(o.glass_near_walls)};
  // The maps depend on the tank and the light only: cached.
  if (!ws->walls_valid || ws->walls_key != key) {
    ws->walls.assign(map->size(), 0.0f);
    ws->walls_flux = 0;
    ws->near_gain.assign(map->size(), 1.0f);
    ws->near_add.assign(map->size(), 0.0f);
    if (o.light_through_walls) {
      ws->walls_flux = caustics_internal::AddWallLight(
          tank, l, o.ior, o.glass_ior, o.attenuation_per_m, o.map_nx, o.map_ny,
          ws->walls.data());
    }
    if (o.glass_near_walls) {
      caustics_internal::NearWallGlassMaps(
          tank, o.glass_thickness_m, l, o.ior, o.glass_ior, o.attenuation_per_m,
          o.map_nx, o.map_ny, o.glass_paths_per_axis, ws->near_gain.data(),
          ws->near_add.data());
    }
    // Only texels near the walls differ: a list keeps the per-frame pass
    // to them.
    ws->near_texels.clear();
    for (size_t i = 0; i < map->size(); ++i) {
      if (ws->near_gain[i] != 1.0f || ws->near_add[i] != 0.0f)
        ws->near_texels.push_back(static_cast<std::uint32_t>(i));
    }
    ws->walls_key = key;
    ws->walls_valid = true;
  }
  double near = 0;
  float* m = map->data();
  const float* gain = ws->near_gain.data();
  const float* add = ws->near_add.data();
  for (const std::uint32_t i : ws->near_texels) {
    const float glass = m[i] * gain[i] + add[i];
    near += glass - m[i];
    m[i] = glass;
  }
  if (o.light_through_walls) {
    for (size_t i = 0; i < map->size(); ++i) m[i] += ws->walls[i];
  }
  if (summary) {
    summary->flux_walls = ws->walls_flux;
    summary->flux_near_walls =
        near * l.z * (tank.size_x / o.map_nx) * (tank.size_y / o.map_ny);
  }
}

// Convolves the map with the light's disc (CausticsOptions::
// light_angular_radius_rad).
void AddPenumbra(const CausticsOptions& o, const TankGeometry& tank,
                 const glm::dvec3& l, CausticsWorkspace::Buffers* ws,
                 std::vector<float>* map) {
  if (!(o.light_angular_radius_rad > 0)) return;
  const double tx = static_cast<double>(tank.size_x) / o.map_nx;
  const double ty = static_cast<double>(tank.size_y) / o.map_ny;
  const std::array<double, 8> key = {
      l.x, l.y, l.z, o.ior, o.light_angular_radius_rad, tank.water_level,
      tx,  ty};
  if (!ws->penumbra_valid || ws->penumbra_key != key) {
    ws->penumbra_kernel = caustics_internal::PenumbraKernel(
        tank, l, o.ior, o.light_angular_radius_rad, tx, ty, /*max_r=*/4,
        &ws->penumbra_r);
    ws->penumbra_key = key;
    ws->penumbra_valid = true;
  }
  const int r = ws->penumbra_r;
  const std::vector<float>& kernel = ws->penumbra_kernel;
  if (r == 0) return;
  ws->penumbra.swap(*map);
  map->resize(ws->penumbra.size());
  caustics_internal::ApplyPenumbra(kernel, r, o.map_nx, o.map_ny,
                                   ws->penumbra.data(), map->data());
}

}  // namespace

bool ComputeCaustics(const CausticsOptions& options,
                     const HeightFieldView& water, const TankGeometry& tank,
                     const glm::dvec3& light_in_tank, std::vector<float>* map,
                     CausticsSummary* summary, CausticsWorkspace* workspace) {
  if (!options.IsValid(nullptr) || map == nullptr) return false;
  CausticsWorkspace local;
  CausticsWorkspace::Buffers& ws =
      workspace ? *workspace->buffers : *local.buffers;
  const int mx = options.map_nx, my = options.map_ny;
  map->resize(static_cast<size_t>(mx) * my);
  if (summary) *summary = CausticsSummary{};
  const glm::vec3 l = glm::normalize(glm::vec3(light_in_tank));
  if (!(l.z > 1e-3f)) {
    std::fill(map->begin(), map->end(), 0.0f);
    return false;
  }
  if (water.heights == nullptr || water.nx <= 0 || water.ny <= 0 ||
      !(water.cell_size > 0)) {
    // Flat water: the map reads 1 wherever the refracted light lands.
    const glm::dvec3 ld = glm::normalize(light_in_tank);
    caustics_internal::FlatSurfaceMap(tank, ld, options.ior, mx, my,
                                      map->data());
    if (summary) {
      summary->flux_in = static_cast<double>(tank.size_x) * tank.size_y * ld.z;
      summary->flux_deposited = std::accumulate(map->begin(), map->end(), 0.0) *
                                ld.z * (static_cast<double>(tank.size_x) / mx) *
                                (tank.size_y / my);
      summary->flux_outside = summary->flux_in - summary->flux_deposited;
    }
    AddWalls(options, tank, ld, &ws, map, summary);
    AddPenumbra(options, tank, ld, &ws, map);
    return true;
  }
  const bool simd = options.simd;
  const float* h = water.heights;
  const int nx = water.nx, ny = water.ny;
  const float dx = water.cell_size, dy = water.cell_size;
  const int cx = nx + 1, cy = ny + 1;
  const int threads = options.threads;
  const int bw = mx + 2 * kMargin, bh = my + 2 * kMargin;

  Ctx c;
  c.nx = nx;
  c.ny = ny;
  c.cx = cx;
  c.cy = cy;
  c.wx = nx + 2;
  c.bw = bw;
  c.bh = bh;
  const float eta = static_cast<float>(1.0 / options.ior);
  const glm::vec3 t_flat = Refract(-l, glm::vec3(0, 0, 1), eta);
  c.lx = l.x;
  c.ly = l.y;
  c.lz = l.z;
  c.eta = eta;
  c.level = tank.water_level;
  c.len_flat = c.level / -t_flat.z;
  c.att = static_cast<float>(options.attenuation_per_m);
  c.x0 = -0.5f * nx * dx;
  c.y0 = -0.5f * ny * dy;
  c.dx = dx;
  c.dy = dy;
  c.su = mx / tank.size_x;
  c.sv = my / tank.size_y;
  c.u_off = 0.5f * tank.size_x * c.su + kMargin;
  c.v_off = 0.5f * tank.size_y * c.sv + kMargin;

  // 1. Corner heights (mean of the adjacent cells), then the corners.
  const size_t n_corners = static_cast<size_t>(cx) * cy;
  const size_t pad = cx + kLanes;
  std::vector<float>& hc = ws.hc;
  hc.assign(kLanes + n_corners + 2 * kLanes, 0.0f);
  for (std::vector<float>* a : {&ws.u, &ws.v, &ws.atten, &ws.z}) {
    a->assign(pad + n_corners + pad + cx, 0.0f);
  }
  c.hc = hc.data() + kLanes;
  c.u = ws.u.data() + pad;
  c.v = ws.v.data() + pad;
  c.atten = ws.atten.data() + pad;
  c.z = ws.z.data() + pad;
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    for (int j = j_begin; j < j_end; ++j) {
      const int j0 = std::max(j - 1, 0), j1 = std::min(j, ny - 1);
      const float* r0 = h + static_cast<size_t>(j0) * nx;
      const float* r1 = h + static_cast<size_t>(j1) * nx;
      float* out = &hc[kLanes + static_cast<size_t>(j) * cx];
      out[0] = 0.5f * (r0[0] + r1[0]);
      for (int i = 1; i < nx; ++i) {
        out[i] = 0.25f * (r0[i - 1] + r0[i] + r1[i - 1] + r1[i]);
      }
      out[nx] = 0.5f * (r0[nx - 1] + r1[nx - 1]);
    }
  });
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    CornersRows(simd, c, j_begin, j_end);
  });

  // 2. Triangles: weights, splats and the light outside the buffer.
  const float texel_area = 1.0f / (c.su * c.sv);  // m^2
  ws.w0.assign(static_cast<size_t>(c.wx) * (ny + 2) + 2 * kLanes, 0.0f);
  ws.w1.assign(ws.w0.size(), 0.0f);
  c.w0 = ws.w0.data();
  c.w1 = ws.w1.data();
  std::vector<AccumBuffer>& bufs = ws.bufs;
  bufs.resize(std::max(1, std::min(threads, ny)));
  ws.rows.resize(bufs.size());
  std::vector<CausticsSummary> sums(bufs.size());
  ParallelRows(ny, threads, [&](int k, int j_begin, int j_end) {
    bufs[k].Reset(bw, bh);
    ws.rows[k].resize(static_cast<size_t>(nx) * 5);
    TrianglesRows(simd, c, ws.rows[k].data(), &bufs[k], &sums[k],
                  summary != nullptr, j_begin, j_end);
  });

  // 3. Edges and corner terms.
  ParallelRows(cy, static_cast<int>(bufs.size()),
               [&](int k, int j_begin, int j_end) {
                 EdgesRows(simd, c, &bufs[k], j_begin, j_end);
               });

  // 4. Resolve the planes, then the map region and relative irradiance:
  //    flux over (texel area * flat-water irradiance l.z).
  AccumBuffer& total = bufs[0];
  for (size_t k = 1; k < bufs.size(); ++k) {
    for (size_t i = 0; i < total.data.size(); ++i) {
      total.data[i] += bufs[k].data[i];
    }
  }
  const int stride = total.stride;
  // Without a summary only the map's rows matter.
  const int y_first = summary ? 0 : kMargin;
  const int y_last = summary ? bh : kMargin + my;
  ws.col_c.assign(stride, 0.0f);
  ws.col_q.assign(stride, 0.0f);
  ws.resolved.resize(static_cast<size_t>(y_last - y_first) * stride);
  Resolve(simd, &total, y_first, y_last, ws.col_c.data(), ws.col_q.data(),
          ws.resolved.data());
  const float to_map = 1.0f / (texel_area * c.lz);
  double in_map = 0, in_buffer = 0;
  for (int y = y_first; y < y_last; ++y) {
    const float* row =
        ws.resolved.data() + static_cast<size_t>(y - y_first) * stride;
    const bool map_row = y >= kMargin && y < kMargin + my;
    if (map_row) {
      float* out = map->data() + static_cast<size_t>(y - kMargin) * mx;
      for (int a = 0; a < mx; ++a) out[a] = row[kMargin + a] * to_map;
    }
    if (summary) {
      float row_sum = 0, map_sum = 0;
      for (int x = 0; x < kMargin; ++x) row_sum += row[x];
      for (int x = kMargin; x < kMargin + mx; ++x) map_sum += row[x];
      for (int x = kMargin + mx; x < stride; ++x) row_sum += row[x];
      in_buffer += static_cast<double>(row_sum) + map_sum;
      if (map_row) in_map += map_sum;
    }
  }
  if (summary) {
    for (const CausticsSummary& s : sums) {
      summary->triangles += s.triangles;
      summary->flux_in += s.flux_in;
      summary->flux_outside += s.flux_outside;
    }
    summary->flux_deposited = in_map;
    summary->flux_outside += in_buffer - in_map;  // in the margin
  }
  AddWalls(options, tank, glm::normalize(light_in_tank), &ws, map, summary);
  AddPenumbra(options, tank, glm::normalize(light_in_tank), &ws, map);
  return true;
}

}  // namespace ripple::render
