#include "render/caustics.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace ripple::render {
namespace {

// Per surface corner: floor hit in texel coordinates (texel a's centre at
// u = a), the relative attenuation of its path, and its surface position.
struct Corner {
  float u, v;
  float atten;
  float x, y, z;
};

struct Accumulator {
  std::vector<float> flux;  // per texel, m^2 (unit irradiance)
  CausticsSummary summary;
};

// Deposits `phi` over the triangle (a, b, c) given in texel coordinates.
inline void Deposit(const Corner& a, const Corner& b, const Corner& c,
                    float phi, int mx, int my, Accumulator* acc) {
  const float min_u = std::min({a.u, b.u, c.u}),
              max_u = std::max({a.u, b.u, c.u});
  const float min_v = std::min({a.v, b.v, c.v}),
              max_v = std::max({a.v, b.v, c.v});
  const int a0 = static_cast<int>(std::ceil(min_u));
  const int a1 = static_cast<int>(std::floor(max_u));
  const int b0 = static_cast<int>(std::ceil(min_v));
  const int b1 = static_cast<int>(std::floor(max_v));
  const float area2 = (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
  constexpr int kMaxTexels = 256;
  int inside[kMaxTexels];
  int n = 0, n_outside = 0;
  bool fits = a1 >= a0 && b1 >= b0 &&
              (a1 - a0 + 1) * (b1 - b0 + 1) <= 64 * 64 && area2 != 0.0f;
  if (fits) {
    const float s = area2 > 0 ? 1.0f : -1.0f;
    bool overflow = false;
    for (int tb = b0; tb <= b1; ++tb) {
      const float pv = static_cast<float>(tb);
      for (int ta = a0; ta <= a1; ++ta) {
        const float pu = static_cast<float>(ta);
        const float w0 =
            s * ((c.u - b.u) * (pv - b.v) - (c.v - b.v) * (pu - b.u));
        const float w1 =
            s * ((a.u - c.u) * (pv - c.v) - (a.v - c.v) * (pu - c.u));
        const float w2 =
            s * ((b.u - a.u) * (pv - a.v) - (b.v - a.v) * (pu - a.u));
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        if (ta < 0 || tb < 0 || ta >= mx || tb >= my) {
          ++n_outside;
        } else if (n < kMaxTexels) {
          inside[n++] = tb * mx + ta;
        } else {
          overflow = true;
          ++n;
        }
      }
    }
    if (overflow) {
      // Rare (a wide triangle): deposit in a second scan.
      const float share = phi / static_cast<float>(n + n_outside);
      for (int tb = std::max(b0, 0); tb <= std::min(b1, my - 1); ++tb) {
        for (int ta = std::max(a0, 0); ta <= std::min(a1, mx - 1); ++ta) {
          const float pu = ta, pv = tb;
          const float w0 =
              s * ((c.u - b.u) * (pv - b.v) - (c.v - b.v) * (pu - b.u));
          const float w1 =
              s * ((a.u - c.u) * (pv - c.v) - (a.v - c.v) * (pu - c.u));
          const float w2 =
              s * ((b.u - a.u) * (pv - a.v) - (b.v - a.v) * (pu - a.u));
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          acc->flux[tb * mx + ta] += share;
        }
      }
      acc->summary.flux_deposited += static_cast<double>(share) * n;
      acc->summary.flux_outside += static_cast<double>(share) * n_outside;
      return;
    }
    fits = n + n_outside > 0;
  }
  if (!fits) {
    // Smaller than a texel (or degenerate, or huge): all of it goes to the
    // texel under the centroid, so focusing stays finite.
    const int ta = static_cast<int>(std::lround((a.u + b.u + c.u) / 3.0f));
    const int tb = static_cast<int>(std::lround((a.v + b.v + c.v) / 3.0f));
    if (ta < 0 || tb < 0 || ta >= mx || tb >= my) {
      acc->summary.flux_outside += phi;
    } else {
      acc->flux[tb * mx + ta] += phi;
      acc->summary.flux_deposited += phi;
    }
    return;
  }
  const float share = phi / static_cast<float>(n + n_outside);
  for (int i = 0; i < n; ++i) acc->flux[inside[i]] += share;
  acc->summary.flux_deposited += static_cast<double>(share) * n;
  acc->summary.flux_outside += static_cast<double>(share) * n_outside;
}

// Unnormalised refraction (Snell) of unit `d` at unit normal `n`, eta =
// n1 / n2 (< 1 here, so never total internal reflection).
inline glm::vec3 Refract(const glm::vec3& d, const glm::vec3& n, float eta) {
  const float cosi = -glm::dot(n, d);
  const float k = 1.0f - eta * eta * (1.0f - cosi * cosi);
  return eta * d + (eta * cosi - std::sqrt(std::max(k, 0.0f))) * n;
}

}  // namespace

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
                     CausticsSummary* summary) {
  if (!options.IsValid(nullptr) || map == nullptr) return false;
  const int mx = options.map_nx, my = options.map_ny;
  map->assign(static_cast<size_t>(mx) * my, 0.0f);
  const glm::vec3 l = glm::normalize(glm::vec3(light_in_tank));
  if (!(l.z > 1e-3f)) return false;

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
  // Corner heights: mean of the (up to four) adjacent cells.
  std::vector<float> hc(static_cast<size_t>(cx) * cy);
  for (int j = 0; j < cy; ++j) {
    const int j0 = std::max(j - 1, 0), j1 = std::min(j, ny - 1);
    for (int i = 0; i < cx; ++i) {
      const int i0 = std::max(i - 1, 0), i1 = std::min(i, nx - 1);
      hc[j * cx + i] = 0.25f * (h[j0 * nx + i0] + h[j0 * nx + i1] +
                                h[j1 * nx + i0] + h[j1 * nx + i1]);
    }
  }
  const float eta = static_cast<float>(1.0 / options.ior);
  const glm::vec3 t_flat = Refract(-l, glm::vec3(0, 0, 1), eta);
  const float level = tank.water_level;
  const float len_flat = level / -t_flat.z;
  const float att = static_cast<float>(options.attenuation_per_m);
  const float x0 = -0.5f * nx * dx, y0 = -0.5f * ny * dy;
  const float su = mx / tank.size_x, sv = my / tank.size_y;
  std::vector<Corner> corners(hc.size());
  for (int j = 0; j < cy; ++j) {
    const int jm = std::max(j - 1, 0), jp = std::min(j + 1, cy - 1);
    for (int i = 0; i < cx; ++i) {
      const int im = std::max(i - 1, 0), ip = std::min(i + 1, cx - 1);
      const float gx = (hc[j * cx + ip] - hc[j * cx + im]) / ((ip - im) * dx);
      const float gy = (hc[jp * cx + i] - hc[jm * cx + i]) / ((jp - jm) * dy);
      const glm::vec3 n = glm::normalize(glm::vec3(-gx, -gy, 1.0f));
      const glm::vec3 t = Refract(-l, n, eta);
      Corner& c = corners[j * cx + i];
      c.x = x0 + i * dx;
      c.y = y0 + j * dy;
      c.z = std::max(level + hc[j * cx + i], 0.0f);
      const float len = c.z / std::max(-t.z, 1e-4f);
      c.u = (c.x + t.x * len + 0.5f * tank.size_x) * su - 0.5f;
      c.v = (c.y + t.y * len + 0.5f * tank.size_y) * sv - 0.5f;
      c.atten = att > 0 ? std::exp(-att * (len - len_flat)) : 1.0f;
    }
  }

  // Triangles, split by rows of quads among the threads.
  const int threads = std::min(options.threads, ny);
  std::vector<Accumulator> accs(threads);
  auto work = [&](int k) {
    Accumulator& acc = accs[k];
    acc.flux.assign(static_cast<size_t>(mx) * my, 0.0f);
    const int j_begin = ny * k / threads, j_end = ny * (k + 1) / threads;
    for (int j = j_begin; j < j_end; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Corner& c00 = corners[j * cx + i];
        const Corner& c10 = corners[j * cx + i + 1];
        const Corner& c01 = corners[(j + 1) * cx + i];
        const Corner& c11 = corners[(j + 1) * cx + i + 1];
        const Corner* tris[2][3] = {{&c00, &c10, &c11}, {&c00, &c11, &c01}};
        for (const auto& tri : tris) {
          const Corner &a = *tri[0], &b = *tri[1], &c = *tri[2];
          // Flux intercepted: the triangle's area vector dotted with the
          // light direction (unit irradiance facing the light).
          const glm::vec3 e1(b.x - a.x, b.y - a.y, b.z - a.z);
          const glm::vec3 e2(c.x - a.x, c.y - a.y, c.z - a.z);
          const float phi =
              std::max(0.5f * glm::dot(glm::cross(e1, e2), l), 0.0f);
          acc.summary.flux_in += phi;
          ++acc.summary.triangles;
          const float phi_floor = phi * (a.atten + b.atten + c.atten) / 3.0f;
          Deposit(a, b, c, phi_floor, mx, my, &acc);
        }
      }
    }
  };
  if (threads == 1) {
    work(0);
  } else {
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) pool.emplace_back(work, k);
    work(0);
    for (auto& t : pool) t.join();
  }

  // Relative irradiance: flux / (texel area * flat-water irradiance l.z).
  const float scale = (mx * my) / (tank.size_x * tank.size_y * l.z);
  CausticsSummary total;
  std::vector<float>& out = *map;
  for (int k = 0; k < threads; ++k) {
    const std::vector<float>& f = accs[k].flux;
    if (k == 0) {
      for (size_t i = 0; i < out.size(); ++i) out[i] = f[i] * scale;
    } else {
      for (size_t i = 0; i < out.size(); ++i) out[i] += f[i] * scale;
    }
    total.triangles += accs[k].summary.triangles;
    total.flux_in += accs[k].summary.flux_in;
    total.flux_deposited += accs[k].summary.flux_deposited;
    total.flux_outside += accs[k].summary.flux_outside;
  }
  if (summary) *summary = total;
  return true;
}

}  // namespace ripple::render
