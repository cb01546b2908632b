#include "render/reference/surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ripple::reference::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Catmull-Rom basis (tension 1/2): row m holds the coefficients of s^m for
// the points p[-1], p[0], p[1], p[2] (Catmull & Rom 1974).
constexpr double kCatmullRom[4][4] = {{0.0, 1.0, 0.0, 0.0},
                                      {-0.5, 0.0, 0.5, 0.0},
                                      {1.0, -2.5, 2.0, -0.5},
                                      {-0.5, 1.5, -1.5, 0.5}};

// Node index k mirrored into [0, n): the cells reflect about the grid edge.
int Mirror(int k, int n) {
  const int period = 2 * n;
  int m = k % period;
  if (m < 0) m += period;
  return m < n ? m : period - 1 - m;
}

}  // namespace

void WaterSurface::Init(const render::HeightFieldView& view, double level,
                        double half_x, double half_y) {
  level_ = level;
  flat_ = view.heights == nullptr || view.nx <= 0 || view.ny <= 0 ||
          !(view.cell_size > 0);
  patches_.clear();
  tile_lo_.clear();
  tile_hi_.clear();
  z_min_ = z_max_ = level;
  if (flat_) return;
  const int nx = view.nx, ny = view.ny;
  cell_ = view.cell_size;
  u_offset_ = 0.5 * nx - 0.5;
  v_offset_ = 0.5 * ny - 0.5;
  pi0_ = static_cast<int>(std::floor(-half_x / cell_ + u_offset_)) - 1;
  pj0_ = static_cast<int>(std::floor(-half_y / cell_ + v_offset_)) - 1;
  npx_ = static_cast<int>(std::floor(half_x / cell_ + u_offset_)) + 2 - pi0_;
  npy_ = static_cast<int>(std::floor(half_y / cell_ + v_offset_)) + 2 - pj0_;
  auto node = [&](int i, int j) {
    return double(
        view.heights[static_cast<size_t>(Mirror(j, ny)) * nx + Mirror(i, nx)]);
  };
  patches_.resize(static_cast<size_t>(npx_) * npy_);
  for (int pj = 0; pj < npy_; ++pj) {
    for (int pi = 0; pi < npx_; ++pi) {
      double p[4][4];
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
          p[a][b] = node(pi0_ + pi - 1 + a, pj0_ + pj - 1 + b);
        }
      }
      // C = M P M^T.
      double mp[4][4];
      for (int m = 0; m < 4; ++m) {
        for (int b = 0; b < 4; ++b) {
          double s = 0;
          for (int a = 0; a < 4; ++a) s += kCatmullRom[m][a] * p[a][b];
          mp[m][b] = s;
        }
      }
      std::array<double, 16>& c = patches_[static_cast<size_t>(pj) * npx_ + pi];
      for (int m = 0; m < 4; ++m) {
        for (int n = 0; n < 4; ++n) {
          double s = 0;
          for (int b = 0; b < 4; ++b) s += mp[m][b] * kCatmullRom[n][b];
          c[m * 4 + n] = s;
        }
      }
    }
  }
  // Tile bounds: a cubic patch lies inside the convex hull of its Bernstein
  // control net (Farin, Curves and Surfaces for CAGD, 5th ed., sec. 2.8),
  // b = Q a per dimension for power coefficients a.
  constexpr double kToBernstein[4][4] = {
      {1, 0, 0, 0}, {1, 1.0 / 3, 0, 0}, {1, 2.0 / 3, 1.0 / 3, 0}, {1, 1, 1, 1}};
  ntx_ = (npx_ + kTile - 1) / kTile;
  nty_ = (npy_ + kTile - 1) / kTile;
  tile_lo_.assign(static_cast<size_t>(ntx_) * nty_, kInf);
  tile_hi_.assign(tile_lo_.size(), -kInf);
  for (int pj = 0; pj < npy_; ++pj) {
    for (int pi = 0; pi < npx_; ++pi) {
      const std::array<double, 16>& c =
          patches_[static_cast<size_t>(pj) * npx_ + pi];
      double lo = kInf, hi = -kInf;
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
          double v = 0;
          for (int m = 0; m <= a; ++m) {
            for (int n = 0; n <= b; ++n) {
              v += kToBernstein[a][m] * kToBernstein[b][n] * c[m * 4 + n];
            }
          }
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
      const size_t k = static_cast<size_t>(pj / kTile) * ntx_ + pi / kTile;
      tile_lo_[k] = std::min(tile_lo_[k], lo);
      tile_hi_[k] = std::max(tile_hi_[k], hi);
    }
  }
  z_min_ = kInf;
  z_max_ = -kInf;
  for (size_t k = 0; k < tile_lo_.size(); ++k) {
    // Rounding margin.
    const double margin =
        1e-12 + 1e-9 * std::max(std::abs(tile_lo_[k]), std::abs(tile_hi_[k]));
    tile_lo_[k] += level - margin;
    tile_hi_[k] += level + margin;
    z_min_ = std::min(z_min_, tile_lo_[k]);
    z_max_ = std::max(z_max_, tile_hi_[k]);
  }
}

double WaterSurface::Z(double x, double y, double* gx, double* gy) const {
  if (flat_) {
    if (gx != nullptr) *gx = 0;
    if (gy != nullptr) *gy = 0;
    return level_;
  }
  const double u = x / cell_ + u_offset_ - pi0_;
  const double v = y / cell_ + v_offset_ - pj0_;
  int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  double s = u - i, t = v - j;
  if (i < 0) i = 0, s = 0;
  if (i >= npx_) i = npx_ - 1, s = 1;
  if (j < 0) j = 0, t = 0;
  if (j >= npy_) j = npy_ - 1, t = 1;
  const double* c = patches_[static_cast<size_t>(j) * npx_ + i].data();
  double r[4], dr[4];
  for (int m = 0; m < 4; ++m) {
    const double* q = c + 4 * m;
    r[m] = q[0] + t * (q[1] + t * (q[2] + t * q[3]));
    dr[m] = q[1] + t * (2 * q[2] + 3 * t * q[3]);
  }
  if (gx != nullptr) {
    *gx = (r[1] + s * (2 * r[2] + 3 * s * r[3])) / cell_;
    *gy = (dr[0] + s * (dr[1] + s * (dr[2] + s * dr[3]))) / cell_;
  }
  return level_ + r[0] + s * (r[1] + s * (r[2] + s * r[3]));
}

glm::dvec3 WaterSurface::Normal(double x, double y) const {
  double gx = 0, gy = 0;
  Z(x, y, &gx, &gy);
  return glm::normalize(glm::dvec3(-gx, -gy, 1.0));
}

double WaterSurface::F(const glm::dvec3& o, const glm::dvec3& d,
                       double t) const {
  return o.z + t * d.z - Z(o.x + t * d.x, o.y + t * d.y);
}

double WaterSurface::Refine(const glm::dvec3& o, const glm::dvec3& d, double a,
                            double fa, double b, double fb) const {
  // Illinois false position (Dowell & Jarratt 1971): a keeps the starting
  // side's sign, b the other.
  int side = 0;
  double c = b;
  for (int it = 0; it < 100; ++it) {
    c = b - fb * (b - a) / (fb - fa);
    if (!(c > std::min(a, b) && c < std::max(a, b))) c = 0.5 * (a + b);
    const double fc = F(o, d, c);
    if (std::abs(fc) < 1e-13 || std::abs(b - a) < 1e-12) return c;
    if ((fc > 0) == (fb > 0) || fc == 0) {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c;
      fa = fc;
      if (side == +1) fb *= 0.5;
      side = +1;
    }
  }
  return c;
}

bool WaterSurface::Intersect(const glm::dvec3& o, const glm::dvec3& d,
                             double t0, double t1, bool from_above,
                             double* t_hit) const {
  if (!(t1 > t0)) return false;
  if (flat_) {
    if (from_above ? !(d.z < 0) : !(d.z > 0)) return false;
    const double t = (level_ - o.z) / d.z;
    if (t < t0 || t > t1) return false;
    *t_hit = t;
    return true;
  }
  // Clip to the slab between the surface's z bounds.
  double ts = t0, te = t1;
  if (d.z != 0) {
    const double ta = (z_min_ - o.z) / d.z, tb = (z_max_ - o.z) / d.z;
    ts = std::max(ts, std::min(ta, tb));
    te = std::min(te, std::max(ta, tb));
  } else if (o.z < z_min_ || o.z > z_max_) {
    return false;
  }
  if (!(te >= ts)) return false;
  auto target = [from_above](double f) { return from_above ? f <= 0 : f >= 0; };
  double t_prev = ts, f_prev = F(o, d, ts);
  if (target(f_prev)) {
    *t_hit = ts;
    return true;
  }
  const double vxy = std::hypot(d.x, d.y);
  const double step = vxy > 0 ? cell_ / (4.0 * vxy) : kInf;
  // 2D DDA over the tiles.
  auto tile_x = [&](double x) {
    const int k =
        static_cast<int>(std::floor((x / cell_ + u_offset_ - pi0_) / kTile));
    return std::clamp(k, 0, ntx_ - 1);
  };
  auto tile_y = [&](double y) {
    const int k =
        static_cast<int>(std::floor((y / cell_ + v_offset_ - pj0_) / kTile));
    return std::clamp(k, 0, nty_ - 1);
  };
  auto edge_x = [&](int k) { return (k * kTile + pi0_ - u_offset_) * cell_; };
  auto edge_y = [&](int k) { return (k * kTile + pj0_ - v_offset_) * cell_; };
  int tx = tile_x(o.x + ts * d.x), ty = tile_y(o.y + ts * d.y);
  const int sx = d.x > 0 ? 1 : -1, sy = d.y > 0 ? 1 : -1;
  auto next_x = [&](int k) {
    if (d.x == 0 || (sx > 0 && k >= ntx_ - 1) || (sx < 0 && k <= 0))
      return kInf;
    return (edge_x(sx > 0 ? k + 1 : k) - o.x) / d.x;
  };
  auto next_y = [&](int k) {
    if (d.y == 0 || (sy > 0 && k >= nty_ - 1) || (sy < 0 && k <= 0))
      return kInf;
    return (edge_y(sy > 0 ? k + 1 : k) - o.y) / d.y;
  };
  double tnx = next_x(tx), tny = next_y(ty);
  double t_cur = ts;
  while (t_cur < te) {
    const double t_next = std::min({tnx, tny, te});
    const size_t k = static_cast<size_t>(ty) * ntx_ + tx;
    const double lo = tile_lo_[k], hi = tile_hi_[k];
    double ua = t_cur, ub = t_next;
    if (d.z != 0) {
      const double tl = (lo - o.z) / d.z, th = (hi - o.z) / d.z;
      ua = std::max(ua, std::min(tl, th));
      ub = std::min(ub, std::max(tl, th));
    } else if (o.z < lo || o.z > hi) {
      ub = ua - 1;  // outside this tile's bounds all along
    }
    if (ub >= ua) {
      double t = ua;
      while (true) {
        const double f = F(o, d, t);
        if (target(f)) {
          *t_hit = Refine(o, d, t_prev, f_prev, t, f);
          return true;
        }
        t_prev = t;
        f_prev = f;
        if (t >= ub) break;
        t = std::min(t + step, ub);
      }
    } else {
      // Outside the bounds: the sign there is known. On the far side means
      // the crossing lies at the tile boundary already passed.
      const double zm = o.z + 0.5 * (t_cur + t_next) * d.z;
      const bool below = zm < lo;
      if (from_above == below) {
        const double f = F(o, d, t_cur);
        if (target(f)) {
          *t_hit =
              t_cur > t_prev ? Refine(o, d, t_prev, f_prev, t_cur, f) : t_cur;
          return true;
        }
      }
    }
    if (t_next >= te) break;
    if (tnx <= tny) {
      tx += sx;
      tnx = next_x(tx);
    } else {
      ty += sy;
      tny = next_y(ty);
    }
    t_cur = t_next;
  }
  return false;
}

}  // namespace ripple::reference::internal
