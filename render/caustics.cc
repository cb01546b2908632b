#include "render/caustics.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace ripple::render {
namespace {

// Texels of margin around the map in the accumulation buffer: light landing
// there is counted as outside the map.
constexpr int kMargin = 8;
// Projected triangles smaller than this (texels^2) are splatted.
constexpr float kMinArea = 0.1f;

// Per surface corner: the floor hit in accumulation-buffer coordinates
// (texel edges at integers, the map's texel a spanning [a + kMargin,
// a + kMargin + 1)), the relative attenuation of its path, and its position.
struct Corner {
  float u, v;
  float atten;
  float x, y, z;
};

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
// closed polygon the lines bound). After font-rs (Raph Levien, 2016).
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
  float x = x0p;
  const int y_begin = static_cast<int>(y0p);
  const int y_end = std::min(buf->height, CeilPositive(y1p));
  float* a = buf->edges.data();
  for (int y = y_begin; y < y_end; ++y) {
    float* row = a + static_cast<size_t>(y) * buf->stride;
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
      const float s = 1.0f / (xb - xa);
      const float xa_f = xa - xa_floor;
      const float a0 = 0.5f * s * (1.0f - xa_f) * (1.0f - xa_f);
      const float xb_f = xb - xb_ceil + 1.0f;
      const float am = 0.5f * s * xb_f * xb_f;
      row[xa_i] += d * a0;
      if (xb_i == xa_i + 2) {
        row[xa_i + 1] += d * (1.0f - a0 - am);
      } else {
        const float a1 = s * (1.5f - xa_f);
        row[xa_i + 1] += d * (a1 - a0);
        for (int xi = xa_i + 2; xi < xb_i - 1; ++xi) row[xi] += d * s;
        const float a2 = a1 + static_cast<float>(xb_i - xa_i - 3) * s;
        row[xb_i - 1] += d * (1.0f - a2 - am);
      }
      row[xb_i] += d * am;
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

struct CausticsWorkspace::Buffers {
  std::vector<float> hc;
  std::vector<Corner> corners;
  std::vector<float> weights;
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
  std::vector<float>& hc = ws.hc;
  std::vector<Corner>& corners = ws.corners;
  hc.resize(static_cast<size_t>(cx) * cy);
  corners.resize(hc.size());
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    for (int j = j_begin; j < j_end; ++j) {
      const int j0 = std::max(j - 1, 0), j1 = std::min(j, ny - 1);
      const float* r0 = h + static_cast<size_t>(j0) * nx;
      const float* r1 = h + static_cast<size_t>(j1) * nx;
      float* out = &hc[static_cast<size_t>(j) * cx];
      for (int i = 0; i < cx; ++i) {
        const int i0 = std::max(i - 1, 0), i1 = std::min(i, nx - 1);
        out[i] = 0.25f * (r0[i0] + r0[i1] + r1[i0] + r1[i1]);
      }
    }
  });
  ParallelRows(cy, threads, [&](int, int j_begin, int j_end) {
    for (int j = j_begin; j < j_end; ++j) {
      const int jm = std::max(j - 1, 0), jp = std::min(j + 1, cy - 1);
      const float* row = &hc[static_cast<size_t>(j) * cx];
      const float* up = &hc[static_cast<size_t>(jp) * cx];
      const float* down = &hc[static_cast<size_t>(jm) * cx];
      const float gy_scale = 1.0f / ((jp - jm) * dy);
      for (int i = 0; i < cx; ++i) {
        const int im = std::max(i - 1, 0), ip = std::min(i + 1, cx - 1);
        const float gx = (row[ip] - row[im]) / ((ip - im) * dx);
        const float gy = (up[i] - down[i]) * gy_scale;
        const glm::vec3 n = glm::normalize(glm::vec3(-gx, -gy, 1.0f));
        const glm::vec3 t = Refract(-l, n, eta);
        Corner& c = corners[static_cast<size_t>(j) * cx + i];
        c.x = x0 + i * dx;
        c.y = y0 + j * dy;
        c.z = std::max(level + row[i], 0.0f);
        const float len = c.z / std::max(-t.z, 1e-4f);
        c.u = (c.x + t.x * len + 0.5f * tank.size_x) * su + kMargin;
        c.v = (c.y + t.y * len + 0.5f * tank.size_y) * sv + kMargin;
        c.atten = att > 0 ? std::exp(-att * (len - len_flat)) : 1.0f;
      }
    }
  });

  // 2. Per triangle: flux in, and the weight of its edges (flux over its
  //    projected area, signed by its winding), or a splat if it is tiny.
  const int bw = mx + 2 * kMargin, bh = my + 2 * kMargin;
  const float texel_area = 1.0f / (su * sv);  // m^2
  // Per quad (with a zero border, so that edge weights need no bounds
  // checks): the edge weights of its two triangles.
  std::vector<float>& weights = ws.weights;
  const int wx = nx + 2;
  weights.assign(static_cast<size_t>(wx) * (ny + 2) * 2, 0.0f);
  auto wi = [wx](int i, int j, int t) {
    return (static_cast<size_t>(j + 1) * wx + (i + 1)) * 2 + t;
  };
  std::vector<Buffer>& bufs = ws.bufs;
  bufs.resize(std::max(1, std::min(threads, ny)));
  std::vector<CausticsSummary> sums(bufs.size());
  ParallelRows(ny, threads, [&](int k, int j_begin, int j_end) {
    Buffer& buf = bufs[k];
    buf.Reset(bw, bh);
    CausticsSummary& sum = sums[k];
    for (int j = j_begin; j < j_end; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Corner* c00 = &corners[static_cast<size_t>(j) * cx + i];
        const Corner* c10 = c00 + 1;
        const Corner* c01 = c00 + cx;
        const Corner* c11 = c01 + 1;
        const Corner* tris[2][3] = {{c00, c10, c11}, {c00, c11, c01}};
        for (int t = 0; t < 2; ++t) {
          const Corner &a = *tris[t][0], &b = *tris[t][1], &c = *tris[t][2];
          // Flux intercepted (unit irradiance facing the light): the
          // triangle's area vector dotted with the light direction.
          const glm::vec3 e1(b.x - a.x, b.y - a.y, b.z - a.z);
          const glm::vec3 e2(c.x - a.x, c.y - a.y, c.z - a.z);
          const float phi =
              std::max(0.5f * glm::dot(glm::cross(e1, e2), l), 0.0f);
          sum.flux_in += phi;
          ++sum.triangles;
          const float phi_floor = phi * (a.atten + b.atten + c.atten) / 3.0f;
          float& w = weights[wi(i, j, t)];
          const float min_u = std::min({a.u, b.u, c.u});
          const float max_u = std::max({a.u, b.u, c.u});
          const float min_v = std::min({a.v, b.v, c.v});
          const float max_v = std::max({a.v, b.v, c.v});
          if (!(min_u >= 1.0f && max_u <= bw - 1.0f && min_v >= 1.0f &&
                max_v <= bh - 1.0f)) {
            sum.flux_outside += phi_floor;  // beyond the margin too
            continue;
          }
          const float area =
              0.5f * ((b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u));
          if (std::abs(area) < kMinArea) {
            Splat((a.u + b.u + c.u) / 3.0f, (a.v + b.v + c.v) / 3.0f, phi_floor,
                  &buf);
          } else {
            // A counter-clockwise triangle accumulates -1 inside.
            w = -phi_floor / area;
          }
        }
      }
    }
  });

  // 3. Each mesh edge once, weighted by the difference of the two triangles
  //    it separates (their opposite traversals cancel in the rest).
  auto weight = [&](int i, int j, int t) { return weights[wi(i, j, t)]; };
  ParallelRows(
      cy, static_cast<int>(bufs.size()), [&](int k, int j_begin, int j_end) {
        Buffer& buf = bufs[k];
        for (int j = j_begin; j < j_end; ++j) {
          for (int i = 0; i < cx; ++i) {
            const Corner& c = corners[static_cast<size_t>(j) * cx + i];
            if (i < nx) {  // (i, j) -> (i + 1, j): T1 of (i, j), T2 of (i, j-1)
              const Corner& e = corners[static_cast<size_t>(j) * cx + i + 1];
              AccumulateLine(c.u, c.v, e.u, e.v,
                             weight(i, j, 0) - weight(i, j - 1, 1), &buf);
            }
            if (j < ny) {  // (i, j) -> (i, j + 1): T1 of (i-1, j), T2 of (i, j)
              const Corner& e = corners[static_cast<size_t>(j + 1) * cx + i];
              AccumulateLine(c.u, c.v, e.u, e.v,
                             weight(i - 1, j, 0) - weight(i, j, 1), &buf);
            }
            if (i < nx && j < ny) {  // diagonal (i, j) -> (i + 1, j + 1)
              const Corner& e =
                  corners[static_cast<size_t>(j + 1) * cx + i + 1];
              AccumulateLine(c.u, c.v, e.u, e.v,
                             weight(i, j, 1) - weight(i, j, 0), &buf);
            }
          }
        }
      });

  // 4. Prefix sums, the map region, and relative irradiance: flux over
  //    (texel area * flat-water irradiance l.z).
  Buffer& total = bufs[0];
  for (size_t k = 1; k < bufs.size(); ++k) {
    for (size_t i = 0; i < total.edges.size(); ++i) {
      total.edges[i] += bufs[k].edges[i];
    }
  }
  const float to_map = 1.0f / (texel_area * l.z);
  double in_map = 0, in_buffer = 0;
  for (int y = 0; y < bh; ++y) {
    const float* e = &total.edges[static_cast<size_t>(y) * total.stride];
    const bool map_row = y >= kMargin && y < kMargin + my;
    float acc = 0.0f;
    double row_sum = 0;
    for (int x = 0; x < total.stride; ++x) {
      acc += e[x];
      const float flux = acc;
      row_sum += flux;
      if (map_row && x >= kMargin && x < kMargin + mx) {
        (*map)[static_cast<size_t>(y - kMargin) * mx + (x - kMargin)] =
            flux * to_map;
        in_map += flux;
      }
    }
    in_buffer += row_sum;
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
