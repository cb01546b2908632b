#include "render/caustics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <thread>

namespace ripple::render {
namespace {

// Texels of margin around the map in the accumulation buffer: light landing
// there is counted as outside the map.
constexpr int kMargin = 8;
// Projected triangles smaller than this (texels^2) are splatted.
constexpr float kMinArea = 0.1f;

// exp(x) for |x| < 80 to ~2 ulp: 2^n times a degree-6 polynomial of 2^f,
// f in [-1/2, 1/2]. Unlike std::exp it vectorises (no libm call).
inline float Exp(float x) {
  x = std::min(std::max(x, -80.0f), 80.0f);
  const float t = x * 1.44269504f;
  // Round to nearest by the 1.5 * 2^23 trick (|t| < 2^22): roundps needs
  // SSE4.1, and nearbyint is a libm call on plain x86-64.
  const float n = (t + 12582912.0f) - 12582912.0f;
  const float f = (t - n) * 0.693147181f;  // ln 2
  float p = 1.0f / 720;
  p = p * f + 1.0f / 120;
  p = p * f + 1.0f / 24;
  p = p * f + 1.0f / 6;
  p = p * f + 0.5f;
  p = p * f + 1.0f;
  p = p * f + 1.0f;
  std::int32_t bits = (static_cast<std::int32_t>(n) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

// The accumulation buffer: `stride` = width + 2 columns so that an edge's
// contribution may spill one column right of its last touched texel.
struct Buffer {
  int width = 0, height = 0, stride = 0;
  // Per-edge signed area, prefix-summed per row. Splats add a value at x
  // and subtract it at x + 1, so the prefix sum leaves it in one texel.
  std::vector<float> edges;
  void Reset(int w, int h) {
    width = w;
    height = h;
    stride = w + 2;
    const size_t n = static_cast<size_t>(stride) * h;
    edges.resize(n);
    std::fill(edges.begin(), edges.end(), 0.0f);
  }
};

// ceil() for x >= 0 without SSE4.1's roundss.
inline int CeilPositive(float x) {
  const int i = static_cast<int>(x);
  return i + (static_cast<float>(i) < x ? 1 : 0);
}

// Adds `weight` times the signed area to the right of the line p0 -> p1
// within each row (after the row prefix sum: exact area coverage of the
// closed polygon the lines bound). After font-rs (Raph Levien, 2016), with
// two changes for speed: the per-row 1 / (x extent) is the per-edge
// constant |dy/dx| (one division per edge, not per row), and edges no
// more than 45 degrees from vertical (a row's piece spans at most two
// columns) take a branch-free path writing three texels. (Branch-free
// paths for wider pieces, 5 texels a row, and a fixed 3-row trip count
// were measured slower: the kernel is bound by arithmetic, not branches.)
// Precondition: 0 <= x <= width - 1 and 0 <= y <= height on both points.
inline void AccumulateLine(float x0p, float y0p, float x1p, float y1p,
                           float weight, Buffer* buf) {
  if (y0p == y1p || weight == 0.0f) return;
  float dir = weight;
  if (y0p > y1p) {
    std::swap(x0p, x1p);
    std::swap(y0p, y1p);
    dir = -weight;
  }
  // All coordinates are >= 0 here, so truncation is floor.
  const float dxdy = (x1p - x0p) / (y1p - y0p);
  const float adxdy = std::abs(dxdy);
  float x = x0p;
  const int y_begin = static_cast<int>(y0p);
  const int y_end = std::min(buf->height, CeilPositive(y1p));
  float* row = buf->edges.data() + static_cast<size_t>(y_begin) * buf->stride;
  if (adxdy <= 1.0f) {
    // A row's piece spans at most two columns: split it at the column
    // boundary X and deposit both parts (each in one column) by their mean
    // x, branch-free. Weight per unit of x extent (unused when dx = 0):
    const float ds = adxdy > 0.0f ? dir / adxdy : 0.0f;
    for (int y = y_begin; y < y_end; ++y, row += buf->stride) {
      const float dy = std::min(float(y + 1), y1p) - std::max(float(y), y0p);
      const float xnext = x + dxdy * dy;
      const float d = dy * dir;
      const float xa = std::min(x, xnext), xb = std::max(x, xnext);
      const int xa_i = static_cast<int>(xa);
      const float xa_floor = static_cast<float>(xa_i);
      const float bx = xa_floor + 1.0f;
      const float xm = std::min(xb, bx);
      const float d_left = xb > bx ? ds * (xm - xa) : d;
      const float d_right = d - d_left;
      const float f_left = 0.5f * (xa + xm) - xa_floor;
      const float f_right = 0.5f * (xb - xm);
      row[xa_i] += d_left - d_left * f_left;
      row[xa_i + 1] += d_left * f_left + d_right - d_right * f_right;
      row[xa_i + 2] += d_right * f_right;
      x = xnext;
    }
    return;
  }
  const float ds = dir / adxdy;  // d / (xb - xa) in every row
  for (int y = y_begin; y < y_end; ++y, row += buf->stride) {
    const float dy = std::min(float(y + 1), y1p) - std::max(float(y), y0p);
    const float xnext = x + dxdy * dy;
    const float d = dy * dir;
    const float xa = std::min(x, xnext), xb = std::max(x, xnext);
    const int xa_i = static_cast<int>(xa);
    const float xa_floor = static_cast<float>(xa_i);
    const int xb_i = CeilPositive(xb);
    const float xb_ceil = static_cast<float>(xb_i);
    if (xb_i <= xa_i + 1) {
      // Within one column: split by the mean x.
      const float xmf = 0.5f * (x + xnext) - xa_floor;
      row[xa_i] += d - d * xmf;
      row[xa_i + 1] += d * xmf;
    } else {
      const float xa_f = xa - xa_floor;
      const float da0 = 0.5f * ds * (1.0f - xa_f) * (1.0f - xa_f);
      const float xb_f = xb - xb_ceil + 1.0f;
      const float dam = 0.5f * ds * xb_f * xb_f;
      row[xa_i] += da0;
      if (xb_i == xa_i + 2) {
        row[xa_i + 1] += d - da0 - dam;
      } else {
        const float da1 = ds * (1.5f - xa_f);
        row[xa_i + 1] += da1 - da0;
        for (int xi = xa_i + 2; xi < xb_i - 1; ++xi) row[xi] += ds;
        const float da2 = da1 + static_cast<float>(xb_i - xa_i - 3) * ds;
        row[xb_i - 1] += d - da2 - dam;
      }
      row[xb_i] += dam;
    }
    x = xnext;
  }
}

// Bilinear splat of `flux` at (u, v) in buffer coordinates (texel centres at
// half-integers); weights sum to one, so the flux is conserved.
inline void Splat(float u, float v, float flux, Buffer* buf) {
  const float cu = u - 0.5f, cv = v - 0.5f;
  const int iu = static_cast<int>(std::floor(cu));
  const int iv = static_cast<int>(std::floor(cv));
  const float fu = cu - iu, fv = cv - iv;
  const int s = buf->stride;
  for (int r = 0; r < 2; ++r) {
    float* row = buf->edges.data() + static_cast<size_t>(iv + r) * s + iu;
    const float f = flux * (r ? fv : 1 - fv);
    row[0] += f * (1 - fu);           // texel iu gets f (1 - fu)
    row[1] += f * fu - f * (1 - fu);  // texel iu + 1 gets f fu
    row[2] -= f * fu;
  }
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

}  // namespace

// Per surface corner (structure of arrays, so the corner and triangle loops
// vectorise): the floor hit (u, v) in accumulation-buffer coordinates
// (texel edges at integers, the map's texel a spanning [a + kMargin,
// a + kMargin + 1)), the relative attenuation of its path, and its height
// above the floor.
struct CausticsWorkspace::Buffers {
  std::vector<float> hc;
  std::vector<float> u, v, atten, z;
  // Per quad, with a zero border so that edge weights need no bounds
  // checks: the edge weights of its two triangles.
  std::vector<float> w0, w1;
  // Per quad of one row: the two triangles' floor flux and projected area.
  std::vector<std::vector<float>> rows;
  std::vector<Buffer> bufs;
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
  if (attenuation_per_m < 0 || threads < 1) {
    if (error) *error = "caustics: attenuation >= 0 and threads >= 1";
    return false;
  }
  return true;
}

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

  // The field (a single flat cell over the tank when there is none).
  const float zero = 0.0f;
  const float* h = &zero;
  int nx = 1, ny = 1;
  float dx = tank.size_x, dy = tank.size_y;
  if (water.heights != nullptr && water.nx > 0 && water.ny > 0 &&
      water.cell_size > 0) {
    h = water.heights;
    nx = water.nx;
    ny = water.ny;
    dx = dy = water.cell_size;
  }
  const int cx = nx + 1, cy = ny + 1;
  const int threads = options.threads;

  // 1. Corners: height (mean of the adjacent cells), normal, refracted ray
  //    and its floor hit.
  const float eta = static_cast<float>(1.0 / options.ior);
  const glm::vec3 t_flat = Refract(-l, glm::vec3(0, 0, 1), eta);
  const float level = tank.water_level;
  const float len_flat = level / -t_flat.z;
  const float att = static_cast<float>(options.attenuation_per_m);
  const float x0 = -0.5f * nx * dx, y0 = -0.5f * ny * dy;
  const float su = mx / tank.size_x, sv = my / tank.size_y;
  const size_t n_corners = static_cast<size_t>(cx) * cy;
  std::vector<float>& hc = ws.hc;
  hc.resize(n_corners);
  ws.u.resize(n_corners);
  ws.v.resize(n_corners);
  ws.atten.resize(n_corners);
  ws.z.resize(n_corners);
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    for (int j = j_begin; j < j_end; ++j) {
      const int j0 = std::max(j - 1, 0), j1 = std::min(j, ny - 1);
      const float* r0 = h + static_cast<size_t>(j0) * nx;
      const float* r1 = h + static_cast<size_t>(j1) * nx;
      float* out = &hc[static_cast<size_t>(j) * cx];
      out[0] = 0.5f * (r0[0] + r1[0]);
      for (int i = 1; i < nx; ++i) {
        out[i] = 0.25f * (r0[i - 1] + r0[i] + r1[i - 1] + r1[i]);
      }
      out[nx] = 0.5f * (r0[nx - 1] + r1[nx - 1]);
    }
  });
  const float lz = l.z;
  const float u_off = 0.5f * tank.size_x * su + kMargin;
  const float v_off = 0.5f * tank.size_y * sv + kMargin;
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    // Local copies: the loop below stores floats, which could alias
    // anything captured by reference and so would block vectorisation.
    const float lx_ = l.x, ly_ = l.y, lz_ = l.z, eta_ = eta, level_ = level,
                att_ = att, len_flat_ = len_flat, su_ = su, sv_ = sv,
                u_off_ = u_off, v_off_ = v_off, x0_ = x0, dx_ = dx;
    const int cx_ = cx;
    for (int j = j_begin; j < j_end; ++j) {
      const int jm = std::max(j - 1, 0), jp = std::min(j + 1, cy - 1);
      const size_t o = static_cast<size_t>(j) * cx_;
      const float* __restrict row = &hc[o];
      const float* __restrict up = &hc[static_cast<size_t>(jp) * cx_];
      const float* __restrict down = &hc[static_cast<size_t>(jm) * cx_];
      float* __restrict out_u = &ws.u[o];
      float* __restrict out_v = &ws.v[o];
      float* __restrict out_a = &ws.atten[o];
      float* __restrict out_z = &ws.z[o];
      const float gy_scale = 1.0f / ((jp - jm) * dy);
      const float y = y0 + j * dy;
      const auto corner = [&](int i, float gx) __attribute__((always_inline)) {
        const float gy = (up[i] - down[i]) * gy_scale;
        // n = normalize(-gx, -gy, 1); t = Refract(-l, n, eta), inlined.
        const float inv_n = 1.0f / std::sqrt(gx * gx + gy * gy + 1.0f);
        const float nx_ = -gx * inv_n, ny_ = -gy * inv_n, nz_ = inv_n;
        const float cosi = nx_ * lx_ + ny_ * ly_ + nz_ * lz_;
        const float k = 1.0f - eta_ * eta_ * (1.0f - cosi * cosi);
        const float m = eta_ * cosi - std::sqrt(std::max(k, 0.0f));
        const float tx = -eta_ * lx_ + m * nx_;
        const float ty = -eta_ * ly_ + m * ny_;
        const float tz = -eta_ * lz_ + m * nz_;
        const float z = std::max(level_ + row[i], 0.0f);
        const float len = z / std::max(-tz, 1e-4f);
        const float x = x0_ + i * dx_;
        out_u[i] = (x + tx * len) * su_ + u_off_;
        out_v[i] = (y + ty * len) * sv_ + v_off_;
        out_a[i] = Exp(-att_ * (len - len_flat_));  // 1 when att = 0
        out_z[i] = z;
      };
      // One-sided slopes at the ends, central inside (vectorised).
      const float gx_inner = 1.0f / (2.0f * dx_);
      corner(0, (row[1] - row[0]) / dx_);
      for (int i = 1; i < cx_ - 1; ++i) {
        corner(i, (row[i + 1] - row[i - 1]) * gx_inner);
      }
      corner(cx_ - 1, (row[cx_ - 1] - row[cx_ - 2]) / dx_);
    }
  });

  // 2. Per triangle: flux in, and the weight of its edges (flux over its
  //    projected area, signed by its winding), or a splat if it is tiny.
  //    Quad (i, j) has corners a = (i, j), b = (i+1, j), c = (i+1, j+1),
  //    d = (i, j+1) and triangles T0 = abc, T1 = acd.
  const int bw = mx + 2 * kMargin, bh = my + 2 * kMargin;
  const float texel_area = 1.0f / (su * sv);  // m^2
  const int wx = nx + 2;
  ws.w0.assign(static_cast<size_t>(wx) * (ny + 2), 0.0f);
  ws.w1.assign(ws.w0.size(), 0.0f);
  auto wi = [wx](int i, int j) {
    return static_cast<size_t>(j + 1) * wx + (i + 1);
  };
  std::vector<Buffer>& bufs = ws.bufs;
  bufs.resize(std::max(1, std::min(threads, ny)));
  ws.rows.resize(bufs.size());
  std::vector<CausticsSummary> sums(bufs.size());
  const float hdx = 0.5f * dx, hdy = 0.5f * dy, hdxdy = 0.5f * dx * dy * lz;
  ParallelRows(ny, threads, [&](int k, int j_begin, int j_end) {
    // Local copies (see the corner loop).
    const float lx = l.x, ly = l.y, hdx_ = hdx, hdy_ = hdy, hdxdy_ = hdxdy;
    const float bw_max = bw - 1.0f, bh_max = bh - 1.0f;
    const int nx_ = nx;
    Buffer& buf = bufs[k];
    buf.Reset(bw, bh);
    CausticsSummary& sum = sums[k];
    std::vector<float>& tmp = ws.rows[k];
    tmp.resize(static_cast<size_t>(nx) * 5);
    float* __restrict pf0 = tmp.data();  // floor flux of T0, T1
    float* __restrict pf1 = pf0 + nx;
    float* __restrict ar0 = pf1 + nx;  // projected areas (texels^2)
    float* __restrict ar1 = ar0 + nx;
    // 1 when both triangles lie inside the buffer.
    float* __restrict in = ar1 + nx;
    for (int j = j_begin; j < j_end; ++j) {
      const size_t o = static_cast<size_t>(j) * cx;
      const float* __restrict ua = &ws.u[o], * __restrict ud = &ws.u[o + cx];
      const float* __restrict va = &ws.v[o], * __restrict vd = &ws.v[o + cx];
      const float* __restrict za = &ws.z[o], * __restrict zd = &ws.z[o + cx];
      const float* __restrict aa = &ws.atten[o], * __restrict ad =
                                                     &ws.atten[o + cx];
      // Vectorisable: no branches, no calls.
      for (int i = 0; i < nx_; ++i) {
        const float au = ua[i], bu = ua[i + 1], cu = ud[i + 1], du = ud[i];
        const float av = va[i], bv = va[i + 1], cv = vd[i + 1], dv = vd[i];
        const float z_a = za[i], z_b = za[i + 1], z_c = zd[i + 1], z_d = zd[i];
        // Intercepted flux (unit irradiance facing the light): the area
        // vector dotted with the light, e.g. T0: (b - a) x (c - a) =
        // (-(zb - za) dy, (zb - zc) dx, dx dy).
        const float phi0 = std::max(
            -(z_b - z_a) * hdy_ * lx + (z_b - z_c) * hdx_ * ly + hdxdy_, 0.0f);
        const float phi1 = std::max(
            (z_d - z_c) * hdy_ * lx - (z_d - z_a) * hdx_ * ly + hdxdy_, 0.0f);
        pf0[i] = phi0 * (aa[i] + aa[i + 1] + ad[i + 1]) * (1.0f / 3.0f);
        pf1[i] = phi1 * (aa[i] + ad[i + 1] + ad[i]) * (1.0f / 3.0f);
        ar0[i] = 0.5f * ((bu - au) * (cv - av) - (bv - av) * (cu - au));
        ar1[i] = 0.5f * ((cu - au) * (dv - av) - (cv - av) * (du - au));
        const float min_u = std::min(std::min(au, bu), std::min(cu, du));
        const float max_u = std::max(std::max(au, bu), std::max(cu, du));
        const float min_v = std::min(std::min(av, bv), std::min(cv, dv));
        const float max_v = std::max(std::max(av, bv), std::max(cv, dv));
        in[i] = (min_u >= 1.0f) & (max_u <= bw_max) & (min_v >= 1.0f) &
                        (max_v <= bh_max)
                    ? 1.0f
                    : 0.0f;
      }
      float* w0 = &ws.w0[wi(0, j)];
      float* w1 = &ws.w1[wi(0, j)];
      for (int i = 0; i < nx; ++i) {
        w0[i] = std::abs(ar0[i]) >= kMinArea ? -pf0[i] / ar0[i] : 0.0f;
        w1[i] = std::abs(ar1[i]) >= kMinArea ? -pf1[i] / ar1[i] : 0.0f;
      }
      // The rare cases: a quad reaching outside the buffer (handled per
      // triangle, as before) or a triangle focused below kMinArea.
      for (int i = 0; i < nx; ++i) {
        if (in[i] != 0.0f && std::abs(ar0[i]) >= kMinArea &&
            std::abs(ar1[i]) >= kMinArea) {
          continue;
        }
        const size_t c00 = o + i, c10 = c00 + 1, c01 = c00 + cx, c11 = c01 + 1;
        const size_t tris[2][3] = {{c00, c10, c11}, {c00, c11, c01}};
        for (int t = 0; t < 2; ++t) {
          float& w = t == 0 ? w0[i] : w1[i];
          const float pf = t == 0 ? pf0[i] : pf1[i];
          const float area = t == 0 ? ar0[i] : ar1[i];
          const size_t a = tris[t][0], b = tris[t][1], c = tris[t][2];
          const float* u = ws.u.data();
          const float* v = ws.v.data();
          const float min_u = std::min({u[a], u[b], u[c]});
          const float max_u = std::max({u[a], u[b], u[c]});
          const float min_v = std::min({v[a], v[b], v[c]});
          const float max_v = std::max({v[a], v[b], v[c]});
          if (!(min_u >= 1.0f && max_u <= bw - 1.0f && min_v >= 1.0f &&
                max_v <= bh - 1.0f)) {
            sum.flux_outside += pf;  // beyond the margin too
            w = 0.0f;
          } else if (std::abs(area) < kMinArea) {
            Splat((u[a] + u[b] + u[c]) / 3.0f, (v[a] + v[b] + v[c]) / 3.0f, pf,
                  &buf);
            w = 0.0f;
          }
          // else: a counter-clockwise triangle accumulates -1 inside (w).
        }
      }
      if (summary) {
        // The flux entering the surface, before attenuation.
        double phi = 0;
        for (int i = 0; i < nx; ++i) {
          const float z_a = za[i], z_b = za[i + 1], z_c = zd[i + 1],
                      z_d = zd[i];
          phi += std::max(
              -(z_b - z_a) * hdy * lx + (z_b - z_c) * hdx * ly + hdxdy, 0.0f);
          phi += std::max(
              (z_d - z_c) * hdy * lx - (z_d - z_a) * hdx * ly + hdxdy, 0.0f);
        }
        sum.flux_in += phi;
        sum.triangles += 2 * nx;
      }
    }
  });

  // 3. Each mesh edge once, weighted by the difference of the two triangles
  //    it separates (their opposite traversals cancel in the rest).
  ParallelRows(
      cy, static_cast<int>(bufs.size()), [&](int k, int j_begin, int j_end) {
        Buffer& buf = bufs[k];
        const float* u = ws.u.data();
        const float* v = ws.v.data();
        for (int j = j_begin; j < j_end; ++j) {
          const size_t o = static_cast<size_t>(j) * cx;
          // Weights of the quads above (row j) and below (row j - 1).
          const float* w0 = &ws.w0[wi(0, j)];
          const float* w1 = &ws.w1[wi(0, j)];
          const float* w1_below = &ws.w1[wi(0, j - 1)];
          for (int i = 0; i < cx; ++i) {
            const float cu = u[o + i], cv = v[o + i];
            if (i < nx) {  // (i, j) -> (i + 1, j): T0 of (i, j), T1 of (i, j-1)
              AccumulateLine(cu, cv, u[o + i + 1], v[o + i + 1],
                             w0[i] - w1_below[i], &buf);
            }
            if (j < ny) {  // (i, j) -> (i, j + 1): T0 of (i-1, j), T1 of (i, j)
              AccumulateLine(cu, cv, u[o + cx + i], v[o + cx + i],
                             w0[i - 1] - w1[i], &buf);
              if (i < nx) {  // diagonal (i, j) -> (i + 1, j + 1)
                AccumulateLine(cu, cv, u[o + cx + i + 1], v[o + cx + i + 1],
                               w1[i] - w0[i], &buf);
              }
            }
          }
        }
      });

  // 4. Prefix sums, the map region, and relative irradiance: flux over
  //    (texel area * flat-water irradiance l.z). Four rows at a time, so
  //    that the four running sums hide each other's add latency.
  Buffer& total = bufs[0];
  for (size_t k = 1; k < bufs.size(); ++k) {
    for (size_t i = 0; i < total.edges.size(); ++i) {
      total.edges[i] += bufs[k].edges[i];
    }
  }
  const float to_map = 1.0f / (texel_area * lz);
  double in_map = 0, in_buffer = 0;
  const int stride = total.stride;
  // Without a summary only the map's rows matter.
  const int y_first = summary ? 0 : kMargin;
  const int y_last = summary ? bh : kMargin + my;
  constexpr int kRows = 4;
  float acc[kRows], row_sum[kRows], map_sum[kRows];
  for (int y = y_first; y < y_last; y += kRows) {
    const int n = std::min(kRows, y_last - y);
    const float* e[kRows];
    float* out[kRows];
    for (int r = 0; r < kRows; ++r) {
      const int yr = y + std::min(r, n - 1);
      e[r] = &total.edges[static_cast<size_t>(yr) * stride];
      const bool map_row = yr >= kMargin && yr < kMargin + my;
      out[r] = map_row ? map->data() + static_cast<size_t>(yr - kMargin) * mx
                       : nullptr;
      acc[r] = row_sum[r] = map_sum[r] = 0.0f;
    }
    for (int x = 0; x < kMargin; ++x) {
      for (int r = 0; r < kRows; ++r) {
        acc[r] += e[r][x];
        row_sum[r] += acc[r];
      }
    }
    for (int x = kMargin; x < kMargin + mx; ++x) {
      for (int r = 0; r < kRows; ++r) {
        acc[r] += e[r][x];
        map_sum[r] += acc[r];
        if (out[r]) out[r][x - kMargin] = acc[r] * to_map;
      }
    }
    if (summary) {
      for (int x = kMargin + mx; x < stride; ++x) {
        for (int r = 0; r < kRows; ++r) {
          acc[r] += e[r][x];
          row_sum[r] += acc[r];
        }
      }
      for (int r = 0; r < n; ++r) {
        in_buffer += static_cast<double>(row_sum[r]) + map_sum[r];
        if (out[r]) in_map += map_sum[r];
      }
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
  return true;
}

}  // namespace ripple::render
