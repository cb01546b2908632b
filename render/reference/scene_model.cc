#include "render/reference/scene_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ripple::reference::internal {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Spectrum ToSpectrum(const cv::Vec3f& v) { return {v[0], v[1], v[2]}; }

void SetFrame(const glm::dmat4& tank_from_local, Solid* s) {
  s->rot = glm::dmat3(tank_from_local);
  s->origin = glm::dvec3(tank_from_local[3]);
}

// Slab test of a ray against an axis-aligned box from outside: entry t and
// the entry axis, or false.
bool EnterBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
              const glm::dvec3& hi, double* t_enter, int* axis) {
  double t0 = -kInf, t1 = kInf;
  int ax = -1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) {
      t0 = ta;
      ax = k;
    }
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1) || !(t0 > kRayEpsilon) || ax < 0) return false;
  *t_enter = t0;
  *axis = ax;
  return true;
}

}  // namespace

int SceneModel::AddChart(double u_size, double v_size, double texel,
                         bool wrap_u) {
  Chart c;
  c.nu = std::max(1, static_cast<int>(std::ceil(u_size / texel - 1e-9)));
  c.nv = std::max(1, static_cast<int>(std::ceil(v_size / texel - 1e-9)));
  c.du = u_size / c.nu;
  c.dv = v_size / c.nv;
  c.wrap_u = wrap_u;
  charts_.push_back(c);
  return static_cast<int>(charts_.size()) - 1;
}

void SceneModel::Init(const ReferenceScene& rs, bool dry, double texel) {
  const render::SceneInputs& sc = rs.scene;
  wet_ = !dry;
  a_ = 0.5 * sc.tank.size_x;
  b_ = 0.5 * sc.tank.size_y;
  A_ = a_ + rs.glass_thickness_m;
  B_ = b_ + rs.glass_thickness_m;
  H_ = sc.tank.wall_height;
  ior_[0] = 1.0;
  ior_[1] = rs.water_ior;
  ior_[2] = rs.glass_ior;
  light_ = glm::normalize(sc.light_in_tank);
  alpha_ = rs.light_angular_radius_rad;
  sigma_ = ToSpectrum(rs.absorption_per_m);
  table_ = ToSpectrum(rs.table_albedo);
  room_ = rs.room;
  albedo_ = rs.floor_albedo;
  albedo_rect_ = rs.floor_rect_m;
  surface_.Init(sc.water, sc.tank.water_level, a_, b_);

  solids_.clear();
  charts_.clear();
  if (wet_) {
    // Floor: caustic_map_size texels along x, square-ish texels.
    Chart floor;
    floor.nu = std::max(1, static_cast<int>(std::lround(2 * a_ / texel)));
    floor.du = 2 * a_ / floor.nu;
    floor.nv = std::max(1, static_cast<int>(std::lround(2 * b_ / floor.du)));
    floor.dv = 2 * b_ / floor.nv;
    charts_.push_back(floor);
    // Board: the outer footprint and the shadow of the walls' top along the
    // disc's rim, with a margin of a quarter wall height for light bent by
    // the walls.
    double x0 = -A_, x1 = A_, y0 = -B_, y1 = B_;
    const glm::dvec3 e1 = glm::normalize(
        std::abs(light_.z) < 0.9 ? glm::cross(light_, glm::dvec3(0, 0, 1))
                                 : glm::cross(light_, glm::dvec3(1, 0, 0)));
    const glm::dvec3 e2 = glm::cross(light_, e1);
    for (int k = 0; k <= 16; ++k) {
      const double phi = 2 * M_PI * k / 16;
      const glm::dvec3 w =
          k == 16 ? light_
                  : std::cos(alpha_) * light_ +
                        std::sin(alpha_) *
                            (std::cos(phi) * e1 + std::sin(phi) * e2);
      for (double sx : {-A_, A_}) {
        for (double sy : {-B_, B_}) {
          const double x = sx - w.x * H_ / w.z, y = sy - w.y * H_ / w.z;
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
          y0 = std::min(y0, y);
          y1 = std::max(y1, y);
        }
      }
    }
    const double margin = 0.25 * H_ + 2 * texel;
    x0 -= margin;
    y0 -= margin;
    x1 += margin;
    y1 += margin;
    Chart board;
    board.nu = static_cast<int>(std::ceil((x1 - x0) / texel));
    board.nv = static_cast<int>(std::ceil((y1 - y0) / texel));
    board.du = board.dv = texel;
    charts_.push_back(board);
    board_rect_ = cv::Rect2d(x0, y0, board.nu * texel, board.nv * texel);
  }
  const double solid_texel = 2 * texel;
  auto add_box = [&](const glm::dmat4& frame, const glm::dvec3& half,
                     const Spectrum& albedo) {
    Solid s;
    s.shape = Solid::Shape::kBox;
    SetFrame(frame, &s);
    s.half = half;
    s.bound_centre = s.origin;
    s.bound_radius = glm::length(half);
    s.albedo = albedo;
    s.first_chart = static_cast<int>(charts_.size());
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        AddChart(2 * half[(axis + 1) % 3], 2 * half[(axis + 2) % 3],
                 solid_texel, false);
      }
    }
    solids_.push_back(s);
  };
  auto add_cylinder = [&](const glm::dmat4& frame, double r, double z0,
                          double z1, const Spectrum& albedo) {
    Solid s;
    s.shape = Solid::Shape::kCylinder;
    SetFrame(frame, &s);
    s.radius = r;
    s.z0 = z0;
    s.z1 = z1;
    s.bound_centre = s.origin + s.rot * glm::dvec3(0, 0, 0.5 * (z0 + z1));
    s.bound_radius = std::hypot(r, 0.5 * (z1 - z0));
    s.albedo = albedo;
    s.first_chart = static_cast<int>(charts_.size());
    AddChart(2 * M_PI * r, z1 - z0, solid_texel, true);
    AddChart(2 * r, 2 * r, solid_texel, false);
    AddChart(2 * r, 2 * r, solid_texel, false);
    solids_.push_back(s);
  };
  if (sc.pen_visible) {
    const render::PenGeometry& g = sc.pen;
    const double c = g.cube_edge;
    add_box(sc.tank_from_pen, glm::dvec3(0.5 * c), ToSpectrum(rs.pen_albedo));
    add_cylinder(sc.tank_from_pen, g.shaft_radius, -0.5 * c - g.shaft_length,
                 -0.5 * c, ToSpectrum(rs.pen_albedo));
  }
  if (wet_) {
    for (const render::Obstacle& ob : sc.obstacles) {
      const glm::dvec3 size(ob.size);
      if (ob.shape == render::Obstacle::Shape::kBox) {
        glm::dmat4 frame = ob.tank_from_obstacle;
        frame[3] += frame[2] * (0.5 * size.z);
        add_box(frame, 0.5 * size, ToSpectrum(rs.obstacle_albedo));
      } else {
        add_cylinder(ob.tank_from_obstacle, size.x, 0.0, size.z,
                     ToSpectrum(rs.obstacle_albedo));
      }
    }
  }
}

Spectrum SceneModel::Albedo(const Event& e) const {
  if (e.solid >= 0) return solids_[e.solid].albedo;
  if (albedo_.empty()) return table_;
  const double fx = (e.p.x - albedo_rect_.x) / albedo_rect_.width;
  const double fy = (e.p.y - albedo_rect_.y) / albedo_rect_.height;
  if (!(fx >= 0 && fx <= 1 && fy >= 0 && fy <= 1)) return table_;
  // Bilinear between texel centres, clamped at the edge.
  const double u = std::clamp(fx * albedo_.cols - 0.5, 0.0, albedo_.cols - 1.0);
  const double v = std::clamp(fy * albedo_.rows - 0.5, 0.0, albedo_.rows - 1.0);
  const int i0 = std::min(static_cast<int>(u), albedo_.cols - 1);
  const int j0 = std::min(static_cast<int>(v), albedo_.rows - 1);
  const int i1 = std::min(i0 + 1, albedo_.cols - 1);
  const int j1 = std::min(j0 + 1, albedo_.rows - 1);
  const double s = u - i0, t = v - j0;
  auto at = [&](int i, int j) {
    const cv::Vec3f& c = albedo_.at<cv::Vec3f>(j, i);
    return Spectrum(c[0], c[1], c[2]);
  };
  return (1 - t) * ((1 - s) * at(i0, j0) + s * at(i1, j0)) +
         t * ((1 - s) * at(i0, j1) + s * at(i1, j1));
}

void SceneModel::SolidHits(const glm::dvec3& o, const glm::dvec3& d,
                           Event* best) const {
  for (size_t k = 0; k < solids_.size(); ++k) {
    const Solid& s = solids_[k];
    // Bounding sphere first.
    const glm::dvec3 oc = s.bound_centre - o;
    const double tca = glm::dot(oc, d);
    const double r2 = s.bound_radius * s.bound_radius;
    if (glm::dot(oc, oc) - tca * tca > r2 || tca + s.bound_radius < 0 ||
        tca - s.bound_radius >= best->t) {
      continue;
    }
    const glm::dmat3 local_from_tank = glm::transpose(s.rot);
    const glm::dvec3 lo = local_from_tank * (o - s.origin);
    const glm::dvec3 ld = local_from_tank * d;
    double t = kInf;
    glm::dvec3 n(0.0);
    int chart = -1;
    double u = 0, v = 0;
    if (s.shape == Solid::Shape::kBox) {
      double te = 0;
      int axis = 0;
      if (!EnterBox(lo, ld, -s.half, s.half, &te, &axis)) continue;
      if (te >= best->t) continue;
      t = te;
      const double sign = ld[axis] > 0 ? -1.0 : 1.0;
      n[axis] = sign;
      const glm::dvec3 p = lo + t * ld;
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      chart = s.first_chart + axis * 2 + (sign > 0 ? 1 : 0);
      u = p[a1] + s.half[a1];
      v = p[a2] + s.half[a2];
    } else {
      const double r = s.radius;
      // Side: |xy(t)| = r, entering.
      const double qa = ld.x * ld.x + ld.y * ld.y;
      if (qa > 0) {
        const double qb = lo.x * ld.x + lo.y * ld.y;
        const double qc = lo.x * lo.x + lo.y * lo.y - r * r;
        const double disc = qb * qb - qa * qc;
        if (disc >= 0) {
          const double ts = (-qb - std::sqrt(disc)) / qa;
          const double z = lo.z + ts * ld.z;
          if (ts > kRayEpsilon && z >= s.z0 && z <= s.z1) {
            t = ts;
            const glm::dvec3 p = lo + t * ld;
            n = glm::dvec3(p.x / r, p.y / r, 0);
            chart = s.first_chart;
            u = r * (std::atan2(p.y, p.x) + M_PI);
            v = z - s.z0;
          }
        }
      }
      // Caps, seen from outside.
      if (ld.z != 0) {
        const double zc = ld.z > 0 ? s.z0 : s.z1;
        const double tc = (zc - lo.z) / ld.z;
        if (tc > kRayEpsilon && tc < t) {
          const double x = lo.x + tc * ld.x, y = lo.y + tc * ld.y;
          if (x * x + y * y <= r * r) {
            t = tc;
            n = glm::dvec3(0, 0, ld.z > 0 ? -1.0 : 1.0);
            chart = s.first_chart + (ld.z > 0 ? 1 : 2);
            u = x + r;
            v = y + r;
          }
        }
      }
      if (!(t < best->t)) continue;
    }
    best->kind = Event::Kind::kDiffuse;
    best->t = t;
    best->p = o + t * d;
    best->n = s.rot * n;
    best->solid = static_cast<int>(k);
    best->chart = chart;
    best->u = u;
    best->v = v;
  }
}

bool SceneModel::InsideSolid(const glm::dvec3& p) const {
  for (const Solid& s : solids_) {
    const glm::dvec3 q = glm::transpose(s.rot) * (p - s.origin);
    if (s.shape == Solid::Shape::kBox) {
      if (std::abs(q.x) <= s.half.x && std::abs(q.y) <= s.half.y &&
          std::abs(q.z) <= s.half.z) {
        return true;
      }
    } else if (q.x * q.x + q.y * q.y <= s.radius * s.radius && q.z >= s.z0 &&
               q.z <= s.z1) {
      return true;
    }
  }
  return false;
}

void SceneModel::BoardHit(const glm::dvec3& o, const glm::dvec3& d, double t,
                          Event* best) const {
  if (!(t > kRayEpsilon && t < best->t)) return;
  best->kind = Event::Kind::kDiffuse;
  best->t = t;
  best->p = o + t * d;
  best->p.z = 0;
  best->n = glm::dvec3(0, 0, 1);
  best->solid = -1;
  if (!wet_) {
    best->chart = -1;
  } else if (std::abs(best->p.x) < a_ && std::abs(best->p.y) < b_) {
    best->chart = kFloorChart;
    best->u = best->p.x + a_;
    best->v = best->p.y + b_;
  } else {
    best->chart = kBoardChart;
    best->u = best->p.x - board_rect_.x;
    best->v = best->p.y - board_rect_.y;
  }
}

void SceneModel::TankAirEvents(const glm::dvec3& o, const glm::dvec3& d,
                               double t_start, Event* best) const {
  const double tx = d.x > 0   ? (a_ - o.x) / d.x
                    : d.x < 0 ? (-a_ - o.x) / d.x
                              : kInf;
  const double ty = d.y > 0   ? (b_ - o.y) / d.y
                    : d.y < 0 ? (-b_ - o.y) / d.y
                              : kInf;
  const double t_wall = std::min(tx, ty);
  const double t_top = d.z > 0 ? (H_ - o.z) / d.z : kInf;
  const double t_end = std::min({t_wall, t_top, best->t});
  double t = 0;
  if (surface_.Intersect(o, d, std::max(t_start, kRayEpsilon), t_end, true,
                         &t)) {
    best->kind = Event::Kind::kInterface;
    best->t = t;
    best->p = o + t * d;
    best->n = surface_.Normal(best->p.x, best->p.y);
    best->next = Medium::kWater;
    best->solid = -1;
    return;
  }
  if (t_wall < t_top && t_wall < best->t && t_wall > kRayEpsilon) {
    best->kind = Event::Kind::kInterface;
    best->t = t_wall;
    best->p = o + t_wall * d;
    best->n = tx <= ty ? glm::dvec3(d.x > 0 ? -1 : 1, 0, 0)
                       : glm::dvec3(0, d.y > 0 ? -1 : 1, 0);
    best->next = Medium::kGlass;
    best->solid = -1;
  }
}

void SceneModel::AirEvents(const glm::dvec3& o, const glm::dvec3& d,
                           Event* best) const {
  if (d.z < 0) BoardHit(o, d, -o.z / d.z, best);
  if (!wet_) return;
  constexpr double kTol = 1e-9;
  if (std::abs(o.x) < a_ + kTol && std::abs(o.y) < b_ + kTol &&
      o.z < H_ + kTol) {
    TankAirEvents(o, d, kRayEpsilon, best);
    return;
  }
  double te = 0;
  int axis = 0;
  if (!EnterBox(o, d, glm::dvec3(-A_, -B_, 0), glm::dvec3(A_, B_, H_), &te,
                &axis) ||
      te >= best->t) {
    return;
  }
  const glm::dvec3 p = o + te * d;
  if (axis == 2 && std::abs(p.x) < a_ && std::abs(p.y) < b_) {
    TankAirEvents(o, d, te, best);  // down into the open tank
    return;
  }
  best->kind = Event::Kind::kInterface;
  best->t = te;
  best->p = p;
  best->n = glm::dvec3(0.0);
  best->n[axis] = d[axis] > 0 ? -1.0 : 1.0;
  best->next = Medium::kGlass;
  best->solid = -1;
}

void SceneModel::WaterEvents(const glm::dvec3& o, const glm::dvec3& d,
                             Event* best) const {
  const double tx = d.x > 0   ? (a_ - o.x) / d.x
                    : d.x < 0 ? (-a_ - o.x) / d.x
                              : kInf;
  const double ty = d.y > 0   ? (b_ - o.y) / d.y
                    : d.y < 0 ? (-b_ - o.y) / d.y
                              : kInf;
  const double t_wall = std::min(tx, ty);
  const double t_floor = d.z < 0 ? -o.z / d.z : kInf;
  const double t_end = std::min({t_wall, t_floor, best->t});
  double t = 0;
  if (surface_.Intersect(o, d, kRayEpsilon, t_end, false, &t)) {
    best->kind = Event::Kind::kInterface;
    best->t = t;
    best->p = o + t * d;
    best->n = -surface_.Normal(best->p.x, best->p.y);
    best->next = Medium::kAir;
    best->solid = -1;
    return;
  }
  if (t_floor <= t_wall) {
    BoardHit(o, d, t_floor, best);
    return;
  }
  if (t_wall < best->t && t_wall > kRayEpsilon) {
    best->kind = Event::Kind::kInterface;
    best->t = t_wall;
    best->p = o + t_wall * d;
    best->n = tx <= ty ? glm::dvec3(d.x > 0 ? -1 : 1, 0, 0)
                       : glm::dvec3(0, d.y > 0 ? -1 : 1, 0);
    best->next = Medium::kGlass;
    best->solid = -1;
  }
}

void SceneModel::GlassEvents(const glm::dvec3& o, const glm::dvec3& d,
                             Event* best) const {
  // Leaving the outer box.
  const double ex = d.x > 0   ? (A_ - o.x) / d.x
                    : d.x < 0 ? (-A_ - o.x) / d.x
                              : kInf;
  const double ey = d.y > 0   ? (B_ - o.y) / d.y
                    : d.y < 0 ? (-B_ - o.y) / d.y
                              : kInf;
  const double ez = d.z > 0 ? (H_ - o.z) / d.z : d.z < 0 ? -o.z / d.z : kInf;
  const double t_exit = std::min({ex, ey, ez});
  // Entering the inner column |x| < a, |y| < b.
  double c0 = -kInf, c1 = kInf;
  int c_axis = -1;
  bool column = true;
  for (int k = 0; k < 2; ++k) {
    const double h = k == 0 ? a_ : b_;
    if (d[k] == 0) {
      if (std::abs(o[k]) >= h) column = false;
      continue;
    }
    double ta = (-h - o[k]) / d[k], tb = (h - o[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    if (ta > c0) {
      c0 = ta;
      c_axis = k;
    }
    c1 = std::min(c1, tb);
  }
  if (column && c_axis >= 0 && c0 < c1 && c0 > kRayEpsilon && c0 < t_exit &&
      c0 < best->t) {
    best->kind = Event::Kind::kInterface;
    best->t = c0;
    best->p = o + c0 * d;
    best->n = glm::dvec3(0.0);
    best->n[c_axis] = d[c_axis] > 0 ? -1.0 : 1.0;
    best->next = best->p.z < surface_.Z(best->p.x, best->p.y) ? Medium::kWater
                                                              : Medium::kAir;
    best->solid = -1;
    return;
  }
  if (!(t_exit < best->t) || !(t_exit > kRayEpsilon)) return;
  if (ez <= ex && ez <= ey && d.z < 0) {
    BoardHit(o, d, t_exit, best);  // the board under the glass
    return;
  }
  best->kind = Event::Kind::kInterface;
  best->t = t_exit;
  best->p = o + t_exit * d;
  best->n = glm::dvec3(0.0);
  const int axis = (ex <= ey && ex <= ez) ? 0 : (ey <= ez ? 1 : 2);
  best->n[axis] = d[axis] > 0 ? -1.0 : 1.0;
  best->next = Medium::kAir;
  best->solid = -1;
}

Event SceneModel::Next(const glm::dvec3& o, const glm::dvec3& d,
                       Medium m) const {
  Event best;
  best.t = kInf;
  SolidHits(o, d, &best);
  switch (m) {
    case Medium::kAir:
      AirEvents(o, d, &best);
      break;
    case Medium::kWater:
      WaterEvents(o, d, &best);
      break;
    case Medium::kGlass:
      GlassEvents(o, d, &best);
      break;
  }
  return best;
}

bool SceneModel::RoomWall(const glm::dvec3& o, const glm::dvec3& d, double* t,
                          Spectrum* radiance) const {
  if (!room_.on) return false;
  const double inf = std::numeric_limits<double>::infinity();
  const double tx = d.x > 0   ? (room_.half_x - o.x) / d.x
                    : d.x < 0 ? (-room_.half_x - o.x) / d.x
                              : inf;
  const double ty = d.y > 0   ? (room_.half_y - o.y) / d.y
                    : d.y < 0 ? (-room_.half_y - o.y) / d.y
                              : inf;
  const double tw = std::min(tx, ty);
  if (!(tw > 0) || tw == inf) return false;
  const glm::dvec3 p = o + tw * d;
  if (p.z < 0 || p.z > room_.height) return false;
  const int wall = tx < ty ? (d.x < 0 ? 0 : 1) : (d.y < 0 ? 2 : 3);
  const double along = tx < ty ? p.y : p.x;
  const bool dark =
      static_cast<long>(std::floor(along / room_.stripe_m)) % 2 != 0;
  *t = tw;
  *radiance = ToSpectrum(room_.wall_bgr[wall]) *
              (dark ? double(room_.stripe_dark) : 1.0);
  return true;
}

}  // namespace ripple::reference::internal
