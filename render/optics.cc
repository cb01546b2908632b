#include "render/optics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ripple::render {
namespace {

// Pope & Fry (1997) Table 3, 1/m, every 10 nm from 380 nm.
constexpr double kPopeFry[] = {
    0.01137, 0.00851, 0.00663, 0.00473, 0.00454, 0.00495, 0.00635,
    0.00922, 0.00979, 0.01060, 0.01270, 0.01500, 0.02040, 0.03250,
    0.04090, 0.04340, 0.04740, 0.05650, 0.06190, 0.06950, 0.08960,
    0.13510, 0.22240, 0.26440, 0.27550, 0.29160, 0.31080, 0.34000,
    0.41000, 0.43900, 0.46500, 0.51600, 0.62400, 0.82700, 1.23100};
constexpr double kPopeFryFirstNm = 380.0;
constexpr int kPopeFryCount = sizeof(kPopeFry) / sizeof(kPopeFry[0]);

double BandMean(double lo_nm, double hi_nm) {
  // Trapezoids on the table's own 10 nm grid (band edges are on it).
  double sum = 0;
  int n = 0;
  for (double w = lo_nm; w < hi_nm - 1e-9; w += 10.0, ++n) {
    sum += 0.5 * (PureWaterAbsorptionAt(w) + PureWaterAbsorptionAt(w + 10.0));
  }
  return n > 0 ? sum / n : PureWaterAbsorptionAt(lo_nm);
}

// Cosine-weighted hemispherical mean of f(cos_theta): the integral of
// f(mu) 2 mu dmu over [0, 1], by Simpson's rule in mu (f is smooth in mu
// except at the critical angle, where the fine grid keeps the error small).
template <typename F>
double HemisphereMean(F f) {
  constexpr int kSteps = 4096;  // even
  const double h = 1.0 / kSteps;
  double sum = 0;
  for (int i = 0; i <= kSteps; ++i) {
    const double mu = i * h;
    const double w = (i == 0 || i == kSteps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * f(mu) * 2.0 * mu;
  }
  return sum * h / 3.0;
}

// Cosine of the refracted angle for light from n1 into n2 at cos_i; 0
// under total internal reflection.
double CosRefracted(double cos_i, double n1, double n2) {
  const double sin2_t = (n1 / n2) * (n1 / n2) * (1.0 - cos_i * cos_i);
  return sin2_t >= 1.0 ? 0.0 : std::sqrt(1.0 - sin2_t);
}

}  // namespace

double FresnelReflectance(double cos_incident, double n1, double n2) {
  const double ci = std::clamp(cos_incident, 0.0, 1.0);
  const double ct = CosRefracted(ci, n1, n2);
  if (ct <= 0.0) return 1.0;
  const double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
  const double rp = (n1 * ct - n2 * ci) / (n1 * ct + n2 * ci);
  return 0.5 * (rs * rs + rp * rp);
}

double PureWaterAbsorptionAt(double wavelength_nm) {
  const double x = (wavelength_nm - kPopeFryFirstNm) / 10.0;
  if (x <= 0) return kPopeFry[0];
  if (x >= kPopeFryCount - 1) return kPopeFry[kPopeFryCount - 1];
  const int i = static_cast<int>(x);
  const double t = x - i;
  return kPopeFry[i] * (1.0 - t) + kPopeFry[i + 1] * t;
}

glm::dvec3 PureWaterAbsorptionRgb() {
  return {BandMean(600, 700), BandMean(500, 600), BandMean(400, 500)};
}

double SrgbToLinear(double e) {
  return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

double LinearToSrgb(double l) {
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

double HighlightShoulder(double x, double knee) {
  if (x <= knee) return x;
  const double room = 1.0 - knee, over = x - knee;
  return knee + room * over / (over + room);
}

double DiffuseInternalReflectance(double n) {
  return HemisphereMean(
      [n](double mu) { return FresnelReflectance(mu, n, 1.0); });
}

SnellWindowShares ComputeSnellWindowShares(double n) {
  const double theta_c = std::asin(1.0 / n);
  const double s = std::sin(theta_c), c = std::cos(theta_c);
  SnellWindowShares w;
  w.facing_up = s * s;
  w.facing_side = (theta_c - s * c) / M_PI;
  w.reflectance = (DiffuseInternalReflectance(n) - c * c) / w.facing_up;
  return w;
}

LowerViewReflectance ComputeLowerViewReflectance(double n) {
  LowerViewReflectance r;
  r.facing_down =
      HemisphereMean([n](double mu) { return FresnelReflectance(mu, 1.0, n); });
  // A vertical plane of normal +x: its lower view, directions d with
  // d.x > 0 and d.z < 0, weighted by d.x; the surface met at cos = -d.z.
  // Midpoint rule in (angle from the normal, azimuth about it).
  constexpr int kSteps = 256;
  double sum = 0, weight = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double theta = (i + 0.5) / kSteps * 0.5 * M_PI;
    for (int j = 0; j < kSteps; ++j) {
      const double phi = M_PI + (j + 0.5) / kSteps * M_PI;  // d.z < 0
      const double dz = std::sin(theta) * std::sin(phi);
      const double w = std::cos(theta) * std::sin(theta);
      sum += w * FresnelReflectance(-dz, 1.0, n);
      weight += w;
    }
  }
  r.facing_side = sum / weight;
  return r;
}

double SkyTransmittance(double n, double sigma_per_m, double depth_m) {
  return HemisphereMean([&](double mu) {
    const double ct = CosRefracted(mu, 1.0, n);
    return (1.0 - FresnelReflectance(mu, 1.0, n)) *
           std::exp(-sigma_per_m * depth_m / std::max(ct, 1e-9));
  });
}

double SideWallReflectance(double cos_incident, double n_water,
                           double n_glass) {
  const double r1 = FresnelReflectance(cos_incident, n_water, n_glass);
  const double sin2_g = (n_water / n_glass) * (n_water / n_glass) *
                        (1.0 - cos_incident * cos_incident);
  if (sin2_g >= 1.0) return 1.0;
  const double r2 = FresnelReflectance(std::sqrt(1.0 - sin2_g), n_glass, 1.0);
  return 1.0 - (1.0 - r1) * (1.0 - r2);
}

double DirectTransmittance(double cos_light, double n, double sigma_per_m,
                           double depth_m) {
  const double ct = CosRefracted(cos_light, 1.0, n);
  return (1.0 - FresnelReflectance(cos_light, 1.0, n)) *
         std::exp(-sigma_per_m * depth_m / std::max(ct, 1e-9));
}

bool ParseWaterLook(const std::string& name, WaterLook* look) {
  if (name == "clear") {
    *look = WaterLook::kClear;
  } else if (name == "pool") {
    *look = WaterLook::kPool;
  } else {
    return false;
  }
  return true;
}

const char* WaterLookName(WaterLook look) {
  return look == WaterLook::kClear ? "clear" : "pool";
}

WaterOptics WaterOptics::ForLook(WaterLook look) {
  WaterOptics o;
  o.look = look;
  if (look == WaterLook::kClear) {
    o.absorption_per_m = glm::vec3(PureWaterAbsorptionRgb());
    o.scatter_color = glm::vec3(0.0f);
  } else {
    // A stylised swimming-pool tint: tank-scale paths look metres deep.
    o.absorption_per_m = {28.0f, 9.0f, 6.0f};
    o.scatter_color = {0.08f, 0.30f, 0.38f};
  }
  return o;
}

bool WaterOptics::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  for (int c = 0; c < 3; ++c) {
    if (!(absorption_per_m[c] >= 0.0f && absorption_per_m[c] <= 1e4f))
      return fail("water absorption must be in [0, 1e4] per metre");
    if (!(scatter_color[c] >= 0.0f && scatter_color[c] <= 1.0f))
      return fail("water scatter colour must be in [0, 1]");
  }
  if (!(ior >= 1.0f && ior <= 3.0f)) return fail("water ior must be in [1, 3]");
  if (!(glass_ior >= 1.0f && glass_ior <= 3.0f))
    return fail("glass ior must be in [1, 3]");
  if (!(glass_thickness_m >= 0.0f && glass_thickness_m <= 0.05f))
    return fail("glass thickness must be in [0, 0.05] m");
  if (!(ambient_share >= 0.0f && ambient_share <= 1.0f))
    return fail("ambient share must be in [0, 1]");
  if (!(light_angular_radius_rad >= 1e-4f && light_angular_radius_rad <= 0.5f))
    return fail("light angular radius must be in [1e-4, 0.5] rad");
  if (!(highlight_knee > 0.0f && highlight_knee < 1.0f))
    return fail("highlight knee must be in (0, 1)");
  return true;
}

double UnderGlassDirectLight(const WaterOptics& o, const glm::dvec3& light,
                             const glm::dvec3& outward, double depth_m) {
  const double nw = o.ior, ng = o.glass_ior, g = o.glass_thickness_m;
  const double cos_l = std::max(light.z, 1e-3);
  double e = 1.0 - FresnelReflectance(cos_l, 1.0, ng);  // the top face
  if (!(g > 0.0)) return e;
  // A beam travelling along `d` (unit, downwards) enters the slab through a
  // face whose normal towards the glass is `into` (index n1 to ng): its
  // direction in the glass keeps the tangential part times n1 / ng. The
  // height it descends while it crosses the slab's thickness once.
  auto descent = [&](const glm::dvec3& d, const glm::dvec3& into, double n1,
                     double* sin_g) {
    const glm::dvec3 tangent = (d - glm::dot(d, into) * into) * (n1 / ng);
    *sin_g = glm::length(tangent);
    const double cos_g = std::sqrt(std::max(1.0 - *sin_g * *sin_g, 1e-12));
    return g * std::abs(tangent.z) / cos_g;
  };
  // From the water: the beam refracted at the flat surface.
  const glm::dvec3 t_air = -light;
  const glm::dvec3 tangent_w = glm::dvec3(t_air.x, t_air.y, 0.0) / nw;
  const glm::dvec3 dw(
      tangent_w.x, tangent_w.y,
      -std::sqrt(std::max(1.0 - glm::dot(tangent_w, tangent_w), 0.0)));
  const double c_in = glm::dot(dw, outward);  // > 0: towards this wall
  if (c_in > 0.0 && depth_m > 0.0) {
    double sin_g = 0;
    const double reach = descent(dw, outward, nw, &sin_g);
    // At the outer face: totally reflected beyond the critical angle.
    const double cos_g = std::sqrt(std::max(1.0 - sin_g * sin_g, 0.0));
    const double r_out = FresnelReflectance(cos_g, ng, 1.0);
    const double height =
        std::min(depth_m, reach) +
        r_out * std::max(0.0, std::min(depth_m, 2.0 * reach) - reach);
    const double per_wall_area = (1.0 - FresnelReflectance(cos_l, 1.0, nw)) *
                                 c_in / std::max(-dw.z, 1e-3) *
                                 (1.0 - FresnelReflectance(c_in, nw, ng));
    e += per_wall_area * height / g;
  }
  // From outside: the light falling on the outer face.
  const double c_out = glm::dot(light, outward);
  if (c_out > 0.0) {
    double sin_g = 0;
    const double reach = descent(t_air, -outward, 1.0, &sin_g);
    e += c_out / cos_l * (1.0 - FresnelReflectance(c_out, 1.0, ng)) * reach / g;
  }
  return e;
}

WaterShading ComputeWaterShading(const WaterOptics& o, double depth_m,
                                 const glm::dvec3& light_in_tank,
                                 const UnderGlassView& view) {
  WaterShading s;
  const double len = glm::length(light_in_tank);
  const double cos_l = len > 0 ? std::max(light_in_tank.z / len, 1e-3) : 1.0;
  const double a = o.ambient_share;
  const double d = std::max(depth_m, 0.0);
  for (int c = 0; c < 3; ++c) {
    const double sigma = o.absorption_per_m[c];
    s.floor_sky[c] = static_cast<float>(a * o.sky_tint[c] *
                                        SkyTransmittance(o.ior, sigma, d));
    s.floor_sun[c] =
        static_cast<float>((1.0 - a) * o.sun_tint[c] *
                           DirectTransmittance(cos_l, o.ior, sigma, d));
  }
  s.inv_n2 = static_cast<float>(1.0 / (double(o.ior) * o.ior));
  s.glass_transmittance =
      static_cast<float>((1.0 - FresnelReflectance(1.0, 1.0, o.glass_ior)) *
                         (1.0 - FresnelReflectance(1.0, o.glass_ior, o.ior)));
  const double inner_t = 1.0 - FresnelReflectance(1.0, o.glass_ior, o.ior);
  const double ng2 = double(o.glass_ior) * o.glass_ior;
  const glm::dvec3 l = len > 0 ? light_in_tank / len : glm::dvec3(0, 0, 1);
  const glm::dvec3 outward[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const double nw2 = double(o.ior) * o.ior;
  const double v = view.albedo;
  for (int w = 0; w < 4; ++w) {
    const double direct = UnderGlassDirectLight(o, l, outward[w], d);
    for (int c = 0; c < 3; ++c) {
      const double sun = (1.0 - a) * o.sun_tint[c] * direct / ng2;
      double light = a * o.sky_tint[c] + sun;
      if (view.traced) {
        const double floor_light = s.floor_sky[c] + s.floor_sun[c];
        light = (a * o.sky_tint[c] * view.sky[w][c] + view.board[w] * v +
                 view.floor[w] * v * floor_light / nw2 + sun) /
                std::max(1.0 - view.under[w] * v, 1e-3);
      }
      s.under_glass[w][c] = static_cast<float>(light * inner_t);
    }
  }
  const double alpha = o.light_angular_radius_rad;
  s.inv_alpha2 = static_cast<float>(1.0 / (alpha * alpha));
  s.glint_peak = static_cast<float>((1.0 - a) / (cos_l * alpha * alpha));
  return s;
}

namespace {

// The board's light per band in units of its luminance: a sky + (1 - a) sun.
glm::dvec3 BoardLight(const Daylight& d) {
  const double a = d.ambient_share;
  return {a * d.sky_rgb.r + (1 - a) * d.sun_rgb.r,
          a * d.sky_rgb.g + (1 - a) * d.sun_rgb.g,
          a * d.sky_rgb.b + (1 - a) * d.sun_rgb.b};
}

}  // namespace

void SetDaylight(const Daylight& d, WaterOptics* o) {
  const glm::dvec3 w = BoardLight(d);
  o->ambient_share = static_cast<float>(d.ambient_share);
  o->sky_tint =
      glm::vec3(glm::dvec3(d.sky_rgb.r, d.sky_rgb.g, d.sky_rgb.b) / w);
  o->sun_tint =
      glm::vec3(glm::dvec3(d.sun_rgb.r, d.sun_rgb.g, d.sun_rgb.b) / w);
}

glm::vec3 DaylightSkyRadiance(const Daylight& d, const EnuDirection& view) {
  const double mean_y = d.sky_mean_relative;
  const LinearRgb l = SkyRgbRelativeToZenith(d.sky, view);
  const glm::dvec3 w = BoardLight(d);
  const double k = d.ambient_share / std::max(mean_y, 1e-12);
  return glm::vec3(k * glm::dvec3(l.r, l.g, l.b) / w);
}

namespace {

// A ray of the water meeting a side wall of glass, followed through the
// slab: the glass-water and glass-air faces by Fresnel (total beyond their
// critical angles), the slab's top face (at the wall's height) by Fresnel
// from inside, and its bottom on the board. The slab guides light that its
// outer face reflects totally: each return to the inner face lets part of
// it back into the tank, and what reaches the top face turns downwards
// there. Light back in above the water `level` going up leaves for the sky;
// going down it meets the surface from above and is counted as entering the
// water there (the surface's own reflection of it left out). Shares of the
// ray's weight (before the wall), by where they go.
struct WallPassage {
  double back_same = 0;    // into the water, mirrored, same vertical sense
  double back_turned = 0;  // into the water going down after the top face
  double turned_z = 0;     // mean height (m) at which back_turned leaves
  double top = 0;          // out through the top face, or back in above
                           // the water going up: the sky
  double under = 0;        // onto the board under the glass
  // Out through the outer face: the share and the height of each exit, and
  // whether it goes down (the board beyond) or up (the sky).
  struct Exit {
    double share, z;
    bool down;
  };
  std::vector<Exit> out;
};

WallPassage ThroughSideWall(double cos_n, double dz, double z, double level,
                            double height, double thickness, double n,
                            double ng) {
  WallPassage w;
  const double r1 = FresnelReflectance(cos_n, n, ng);
  w.back_same = r1;
  const double sin2_g = (n / ng) * (n / ng) * (1.0 - cos_n * cos_n);
  if (sin2_g >= 1.0) {
    w.back_same = 1.0;
    return w;
  }
  const double cg = std::sqrt(1.0 - sin2_g);
  const double r2 = FresnelReflectance(cg, ng, 1.0);
  const double gz = std::abs(dz) * n / ng;  // |vertical| in the glass
  const double rise = thickness * gz / std::max(cg, 1e-9);  // per crossing
  const double r_top = FresnelReflectance(gz, ng, 1.0);
  double a = 1.0 - r1;
  double sense = dz >= 0 ? 1.0 : -1.0;
  double at = z;
  bool turned = false;
  double turned_sum = 0;
  // One crossing of the slab; false when the light has left it on the way.
  auto cross = [&]() {
    at += sense * rise;
    if (sense < 0 && at <= 0.0) {
      w.under += a;
      a = 0;
      return false;
    }
    if (sense > 0 && at >= height) {
      w.top += a * (1.0 - r_top);
      a *= r_top;
      sense = -1.0;
      turned = true;
      at = 2.0 * height - at;
    }
    return a > 1e-7;
  };
  for (int k = 0; k < 400 && a > 1e-7; ++k) {
    if (!cross()) break;
    w.out.push_back({a * (1.0 - r2), at, sense < 0});
    a *= r2;
    if (!cross()) break;
    // The inner face borders the water below the level and the tank's air
    // above it (the same as the outer face there: total reflection guides
    // the light on).
    const double r_in = at > level ? r2 : r1;
    const double back = a * (1.0 - r_in);
    if (turned) {
      w.back_turned += back;
      turned_sum += back * std::min(at, level);
    } else if (at > level) {
      w.top += back;
    } else {
      w.back_same += back;
    }
    a *= r_in;
  }
  w.turned_z = w.back_turned > 0 ? turned_sum / w.back_turned : z;
  return w;
}

}  // namespace

FloorReturnMap ComputeFloorReturn(const WaterOptics& o, double size_x,
                                  double size_y, double depth,
                                  double wall_height, int nx, int ny, int rays,
                                  double surround_radiance) {
  FloorReturnMap map;
  map.nx = nx;
  map.ny = ny;
  map.returned.assign(static_cast<size_t>(nx) * ny, glm::vec3(0.0f));
  map.surround.assign(map.returned.size(), glm::vec3(0.0f));
  map.sky.assign(map.returned.size(), glm::vec3(0.0f));
  for (std::vector<glm::vec3>& b : map.board)
    b.assign(map.returned.size(), glm::vec3(0.0f));
  // Every down-going exit's landing point and weight (green), per wall,
  // for the board points.
  std::vector<std::pair<glm::dvec2, double>> landings[4];
  const double n = o.ior, ng = o.glass_ior;
  const double thickness = o.glass_thickness_m;
  const double height = std::max(wall_height, depth);
  const double hx = 0.5 * size_x, hy = 0.5 * size_y;
  const glm::dvec3 sigma(o.absorption_per_m);
  // Stratified cosine-weighted directions (Hammersley in the unit disc,
  // lifted to the hemisphere), shifted per texel by a fixed pseudo-random
  // offset (Cranley-Patterson rotation): the walls' thin features (the band
  // of heights from which the glass sends light under itself) alias on one
  // fixed set, the same way at every texel; shifted, the error is noise that
  // neighbouring texels average.
  std::vector<glm::dvec2> unit(rays);
  for (int k = 0; k < rays; ++k) {
    unsigned b = static_cast<unsigned>(k);
    b = (b << 16) | (b >> 16);
    b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
    b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
    b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
    b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
    unit[k] = {(k + 0.5) / rays, b * (1.0 / 4294967296.0)};
  }
  std::vector<glm::dvec3> dirs(rays);
  auto texel_directions = [&](int i, int j) {
    uint32_t h = static_cast<uint32_t>(i) * 0x9E3779B1u ^
                 static_cast<uint32_t>(j) * 0x85EBCA77u;
    auto next = [&h]() {
      h ^= h >> 16;
      h *= 0x7FEB352Du;
      h ^= h >> 15;
      h *= 0x846CA68Bu;
      h ^= h >> 16;
      return h * (1.0 / 4294967296.0);
    };
    const double su = next(), sv = next();
    for (int k = 0; k < rays; ++k) {
      double u = unit[k].x + su, v = unit[k].y + sv;
      u -= std::floor(u);
      v -= std::floor(v);
      const double r = std::sqrt(u), phi = 2.0 * 3.14159265358979 * v;
      dirs[k] = {r * std::cos(phi), r * std::sin(phi), std::sqrt(1.0 - u)};
    }
  };
  struct Ray {
    glm::dvec3 p, d;
    double weight, length;
    int events;
  };
  std::vector<Ray> stack;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const glm::dvec3 start(-hx + (i + 0.5) * size_x / nx,
                             -hy + (j + 0.5) * size_y / ny, 0.0);
      texel_directions(i, j);
      glm::dvec3 sum(0.0), outside(0.0), board[4] = {};
      const double sky = o.ambient_share;
      for (const glm::dvec3& d0 : dirs) {
        // The shader's sky term (WaterShading::floor_sky) takes every
        // upward direction to the surface at once; the sky's light along
        // this one is counted below wherever the ray actually leaves (the
        // surface, directly or after the walls' reflections, or a wall), so
        // the uniform term's share of it comes off here.
        outside -= (1.0 - FresnelReflectance(d0.z, n, 1.0)) * n * n * sky *
                   glm::exp(-sigma * (depth / d0.z));
        stack.assign(1, Ray{start, d0, 1.0, 0.0, 0});
        while (!stack.empty()) {
          Ray ray = stack.back();
          stack.pop_back();
          glm::dvec3& p = ray.p;
          glm::dvec3& d = ray.d;
          if (ray.weight < 1e-4 || ray.events >= 64) continue;
          ++ray.events;
          const double tz =
              d.z > 0 ? (depth - p.z) / d.z : (d.z < 0 ? -p.z / d.z : 1e30);
          const double tx =
              d.x > 0 ? (hx - p.x) / d.x : (d.x < 0 ? (-hx - p.x) / d.x : 1e30);
          const double ty =
              d.y > 0 ? (hy - p.y) / d.y : (d.y < 0 ? (-hy - p.y) / d.y : 1e30);
          const double t = std::max(std::min(tz, std::min(tx, ty)), 0.0);
          p += t * d;
          ray.length += t;
          const glm::dvec3 absorbed = glm::exp(-sigma * ray.length);
          if (t == tz && d.z < 0) {
            sum += ray.weight * absorbed;  // back on the floor
            continue;
          }
          if (t == tz) {
            const double r = FresnelReflectance(d.z, n, 1.0);
            outside += ray.weight * (1.0 - r) * n * n * sky * absorbed;
            ray.weight *= r;
            d.z = -d.z;
            stack.push_back(ray);
            continue;
          }
          const bool x_wall = t == tx;
          const double cos_n = std::abs(x_wall ? d.x : d.y);
          const WallPassage pass =
              ThroughSideWall(cos_n, d.z, p.z, depth, height, thickness, n, ng);
          // Out of the glass: the board around the tank below, the sky
          // above. Radiance over n^2 is what an interface keeps, so the
          // outside's radiance L arrives in the water as n^2 T L (its rays'
          // solid angle narrows by n^2 on the way in).
          const glm::dvec3 share = ray.weight * n * n * absorbed;
          const int w = x_wall ? (d.x > 0 ? 0 : 1) : (d.y > 0 ? 2 : 3);
          const glm::dvec3 wall_n =
              x_wall ? glm::dvec3(d.x > 0 ? -1.0 : 1.0, 0.0, 0.0)
                     : glm::dvec3(0.0, d.y > 0 ? -1.0 : 1.0, 0.0);
          const glm::dvec3 out = glm::refract(d, wall_n, n);
          const glm::dvec3 out_down(out.x, out.y, -std::abs(out.z));
          for (const WallPassage::Exit& e : pass.out) {
            if (!e.down) {
              outside += share * e.share * sky;
              continue;
            }
            // Down to the board beyond the glass, from the exit's height.
            board[w] += share * e.share;
            const double s_land = e.z / std::max(-out_down.z, 1e-9);
            const glm::dvec2 at(p.x - wall_n.x * thickness,
                                p.y - wall_n.y * thickness);
            landings[w].emplace_back(
                at + s_land * glm::dvec2(out_down.x, out_down.y),
                share.g * e.share);
          }
          // The board under the glass counts as the board at the wall's
          // foot (its own light is not modelled apart).
          if (pass.under > 0) {
            board[w] += share * pass.under;
            landings[w].emplace_back(glm::dvec2(p.x - wall_n.x * thickness,
                                                p.y - wall_n.y * thickness),
                                     share.g * pass.under);
          }
          outside += share * pass.top * sky;
          glm::dvec3 mirrored = d;
          if (x_wall) {
            mirrored.x = -mirrored.x;
          } else {
            mirrored.y = -mirrored.y;
          }
          if (pass.back_same > 0) {
            stack.push_back(Ray{p, mirrored, ray.weight * pass.back_same,
                                ray.length, ray.events});
          }
          if (pass.back_turned > 0) {
            stack.push_back(Ray{glm::dvec3(p.x, p.y, pass.turned_z),
                                glm::dvec3(mirrored.x, mirrored.y, -mirrored.z),
                                ray.weight * pass.back_turned, ray.length,
                                ray.events});
          }
        }
      }
      const size_t at = static_cast<size_t>(j) * nx + i;
      map.returned[at] = glm::vec3(sum / double(rays));
      map.sky[at] = glm::vec3(outside / double(rays));
      glm::dvec3 all_board(0.0);
      for (int w = 0; w < 4; ++w) {
        map.board[w][at] = glm::vec3(board[w] / double(rays));
        all_board += board[w];
      }
      map.surround[at] =
          glm::vec3((outside + surround_radiance * all_board) / double(rays));
    }
  }
  // Systematic sampling by weight: each point stands for an equal share of
  // the wall's landing light.
  for (int w = 0; w < 4; ++w) {
    double total = 0;
    for (const auto& l : landings[w]) total += l.second;
    if (!(total > 0)) continue;
    const double step = total / FloorReturnMap::kBoardPoints;
    double next = 0.5 * step, acc = 0;
    for (const auto& l : landings[w]) {
      acc += l.second;
      while (acc > next && static_cast<int>(map.board_points[w].size()) <
                               FloorReturnMap::kBoardPoints) {
        map.board_points[w].push_back(l.first);
        next += step;
      }
    }
  }
  return map;
}

}  // namespace ripple::render
