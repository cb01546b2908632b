// Light tracing of the disc light through the tank (reference.h): each disc
// direction shoots a lattice of parallel paths; each path is split at every
// interface into its Fresnel-reflected and -transmitted flux, attenuated in
// the water, and deposited on the first diffuse surface it reaches.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "render/reference/optics.h"
#include "render/reference/tracing.h"

namespace ripple::reference::internal {
namespace {

// Per-band flux tallies of one chunk (summed in chunk order afterwards, so
// the totals do not depend on the thread count).
struct Tally {
  Spectrum launched{0.0}, occluded{0.0}, unscattered{0.0};
  Spectrum surface_incident{0.0}, surface_transmitted{0.0};
  Spectrum walls_into_water{0.0}, out_of_water{0.0}, absorbed{0.0};
  Spectrum floor{0.0}, board{0.0}, solids{0.0}, solids_in_water{0.0};
  Spectrum outside{0.0}, escaped{0.0}, cut{0.0}, cut_in_water{0.0};
  void Add(const Tally& o) {
    launched += o.launched;
    occluded += o.occluded;
    unscattered += o.unscattered;
    surface_incident += o.surface_incident;
    surface_transmitted += o.surface_transmitted;
    walls_into_water += o.walls_into_water;
    out_of_water += o.out_of_water;
    absorbed += o.absorbed;
    floor += o.floor;
    board += o.board;
    solids += o.solids;
    solids_in_water += o.solids_in_water;
    outside += o.outside;
    escaped += o.escaped;
    cut += o.cut;
    cut_in_water += o.cut_in_water;
  }
};

cv::Vec3d ToVec(const Spectrum& s) { return {s.x, s.y, s.z}; }

double MaxBand(const Spectrum& s) { return std::max({s.x, s.y, s.z}); }

// Fixed-point flux per texel and band: integer sums are exact and
// associative, so the maps are the same for any thread count.
class Deposits {
 public:
  Deposits(const std::vector<Chart>& charts, double quantum)
      : charts_(charts), inv_quantum_(1.0 / quantum) {
    planes_.resize(charts.size());
    for (size_t c = 0; c < charts.size(); ++c) {
      planes_[c].assign(static_cast<size_t>(charts[c].nu) * charts[c].nv * 3,
                        0);
    }
  }
  // Tent splat onto the 4 nearest texel centres; false when (u, v) lies
  // outside a chart that does not clamp (the board map).
  bool Splat(int chart, double u, double v, const Spectrum& flux) {
    // A degenerate path (a grazing 0/0) deposits nothing: converting a NaN
    // to a texel index or an integer flux is undefined.
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(flux[0]) ||
        !std::isfinite(flux[1]) || !std::isfinite(flux[2])) {
      return false;
    }
    const Chart& c = charts_[chart];
    const double U = c.nu * c.du, V = c.nv * c.dv;
    if (chart == kBoardChart && !(u >= 0 && u <= U && v >= 0 && v <= V)) {
      return false;
    }
    const double fu = std::clamp(u, 0.0, U) / c.du - 0.5;
    const double fv = std::clamp(v, 0.0, V) / c.dv - 0.5;
    const int i0 = static_cast<int>(std::floor(fu));
    const int j0 = static_cast<int>(std::floor(fv));
    const double s = fu - i0, t = fv - j0;
    const double w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    const int is[4] = {i0, i0 + 1, i0, i0 + 1};
    const int js[4] = {j0, j0, j0 + 1, j0 + 1};
    std::vector<std::int64_t>& plane = planes_[chart];
    for (int k = 0; k < 4; ++k) {
      int i = is[k], j = std::clamp(js[k], 0, c.nv - 1);
      if (c.wrap_u) {
        i = ((i % c.nu) + c.nu) % c.nu;
      } else {
        i = std::clamp(i, 0, c.nu - 1);
      }
      std::int64_t* texel = &plane[(static_cast<size_t>(j) * c.nu + i) * 3];
      for (int b = 0; b < 3; ++b) {
        // Fluxes are >= 0: round half up.
        texel[b] +=
            static_cast<std::int64_t>(flux[b] * w[k] * inv_quantum_ + 0.5);
      }
    }
    return true;
  }
  void AddTo(Deposits* total) const {
    for (size_t c = 0; c < planes_.size(); ++c) {
      for (size_t k = 0; k < planes_[c].size(); ++k) {
        total->planes_[c][k] += planes_[c][k];
      }
    }
  }
  const std::vector<std::int64_t>& plane(int c) const { return planes_[c]; }

 private:
  const std::vector<Chart>& charts_;
  double inv_quantum_;
  std::vector<std::vector<std::int64_t>> planes_;
};

class PathTracer {
 public:
  PathTracer(const SceneModel& model, int max_bounces, Deposits* deposits)
      : model_(model), max_bounces_(max_bounces), deposits_(deposits) {}

  // Follows one light path (and its Fresnel branches) from o along d.
  void Trace(glm::dvec3 o, glm::dvec3 d, Medium m, Spectrum flux,
             bool scattered, int depth, double cutoff, Tally* tally) {
    while (true) {
      const Event e = model_.Next(o, d, m);
      if (m == Medium::kWater && e.kind != Event::Kind::kEscape) {
        const Spectrum att = glm::exp(-model_.sigma() * e.t);
        tally->absorbed += flux * (1.0 - att);
        flux *= att;
      }
      if (e.kind == Event::Kind::kEscape) {
        if (m != Medium::kAir) {
          tally->cut += flux;  // lost numerically inside a medium
          if (m == Medium::kWater) tally->cut_in_water += flux;
        } else if (scattered) {
          tally->escaped += flux;
        } else {
          tally->unscattered += flux;
        }
        return;
      }
      if (e.kind == Event::Kind::kDiffuse) {
        if (!scattered) {
          // Straight light: the camera pass's shadow rays count it.
          (e.solid >= 0 ? tally->occluded : tally->unscattered) += flux;
          return;
        }
        if (e.solid >= 0) {
          deposits_->Splat(e.chart, e.u, e.v, flux);
          tally->solids += flux;
          if (m == Medium::kWater) tally->solids_in_water += flux;
        } else if (e.chart == kFloorChart) {
          deposits_->Splat(e.chart, e.u, e.v, flux);
          tally->floor += flux;
        } else if (deposits_->Splat(e.chart, e.u, e.v, flux)) {
          tally->board += flux;
        } else {
          tally->outside += flux;
        }
        return;
      }
      // A dielectric interface.
      if (depth >= max_bounces_) {
        tally->cut += flux;
        if (m == Medium::kWater) tally->cut_in_water += flux;
        return;
      }
      ++depth;
      scattered = true;
      const double n_i = model_.Ior(m), n_t = model_.Ior(e.next);
      const double cos_i = -glm::dot(d, e.n);
      double cos_t = 0;
      const double r = FresnelReflectance(cos_i, n_i, n_t, &cos_t);
      const Spectrum transmitted = flux * (1.0 - r);
      if (m == Medium::kAir && e.next == Medium::kWater) {
        tally->surface_incident += flux;
        tally->surface_transmitted += transmitted;
      } else if (m == Medium::kGlass && e.next == Medium::kWater) {
        tally->walls_into_water += transmitted;
      } else if (m == Medium::kWater && e.next != Medium::kWater) {
        tally->out_of_water += transmitted;
      }
      const glm::dvec3 refl = Reflect(d, e.n);
      const Spectrum reflected = flux * r;
      bool keep_t = r < 1.0;
      if (keep_t && MaxBand(transmitted) < cutoff) {
        tally->cut += transmitted;
        if (e.next == Medium::kWater) tally->cut_in_water += transmitted;
        keep_t = false;
      }
      bool keep_r = r > 0.0;
      if (keep_r && MaxBand(reflected) < cutoff) {
        tally->cut += reflected;
        if (m == Medium::kWater) tally->cut_in_water += reflected;
        keep_r = false;
      }
      if (keep_r && keep_t) {
        Trace(e.p, refl, m, reflected, true, depth, cutoff, tally);
      }
      if (keep_t) {
        d = Refract(d, e.n, n_i, n_t, cos_i, cos_t);
        m = e.next;
        flux = transmitted;
      } else if (keep_r) {
        d = refl;
        flux = reflected;
      } else {
        return;
      }
      o = e.p;
    }
  }

 private:
  const SceneModel& model_;
  int max_bounces_;
  Deposits* deposits_;
};

}  // namespace

Spectrum IrradianceAtlas::Lookup(int chart, double u, double v) const {
  const Chart& c = charts[chart];
  const double U = c.nu * c.du, V = c.nv * c.dv;
  if (chart == kBoardChart && !(u >= 0 && u <= U && v >= 0 && v <= V)) {
    return Spectrum(0.0);
  }
  const double fu = std::clamp(u, 0.0, U) / c.du - 0.5;
  const double fv = std::clamp(v, 0.0, V) / c.dv - 0.5;
  int i0 = static_cast<int>(std::floor(fu)),
      j0 = static_cast<int>(std::floor(fv));
  double s = fu - i0, t = fv - j0;
  int i1 = i0 + 1, j1 = j0 + 1;
  if (c.wrap_u) {
    i0 = ((i0 % c.nu) + c.nu) % c.nu;
    i1 = ((i1 % c.nu) + c.nu) % c.nu;
  } else {
    if (i0 < 0) i0 = 0, s = 0;
    if (i1 > c.nu - 1) i1 = c.nu - 1;
    i0 = std::min(i0, c.nu - 1);
  }
  if (j0 < 0) j0 = 0, t = 0;
  if (j1 > c.nv - 1) j1 = c.nv - 1;
  j0 = std::min(j0, c.nv - 1);
  const std::vector<float>& p = texels[chart];
  auto at = [&](int i, int j) {
    const float* q = &p[(static_cast<size_t>(j) * c.nu + i) * 3];
    return Spectrum(q[0], q[1], q[2]);
  };
  return (1 - t) * ((1 - s) * at(i0, j0) + s * at(i1, j0)) +
         t * ((1 - s) * at(i0, j1) + s * at(i1, j1));
}

LightRadiometry Radiometry(const SceneModel& model, double ambient_share) {
  LightRadiometry r;
  const double alpha = model.alpha();
  r.cos_zenith = model.light().z;
  r.sky_radiance = ambient_share;
  r.disc_irradiance = (1.0 - ambient_share) * M_PI / r.cos_zenith;
  r.disc_radiance =
      r.disc_irradiance / (M_PI * std::sin(alpha) * std::sin(alpha));
  r.disc_solid_angle = 2.0 * M_PI * (1.0 - std::cos(alpha));
  return r;
}

void TraceLight(const ReferenceOptions& options, const SceneModel& model,
                const LightRadiometry& rad, int threads, IrradianceAtlas* atlas,
                LightTraceSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  const glm::dvec3 l = model.light();
  const double cos_alpha = std::cos(model.alpha());
  const int K = options.disc_directions;
  const int m = std::max(
      1, static_cast<int>(std::ceil(
             std::sqrt(double(options.light_paths_per_texel) / K) - 1e-9)));
  const Chart& floor = model.charts()[kFloorChart];
  const double texel = floor.du;
  const double h = texel / m;

  // The disc quadrature: K / 2 rings of equal solid angle, one direction
  // per ring at a golden-angle azimuth and its antipode about l, so the
  // mean direction is the disc's, l (1 + cos alpha) / 2.
  std::vector<glm::dvec3> dirs;
  glm::dvec3 e1, e2;
  Perpendiculars(l, &e1, &e2);
  const double phi0 =
      2.0 * M_PI * (Mix64(options.seed ^ 0x5eedull) >> 11) * 0x1.0p-53;
  for (int j = 0; j < K / 2; ++j) {
    const double c = 1.0 - (j + 0.5) / (K / 2) * (1.0 - cos_alpha);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = phi0 + j * M_PI * (3.0 - std::sqrt(5.0));
    const glm::dvec3 q = std::cos(phi) * e1 + std::sin(phi) * e2;
    dirs.push_back(c * l + s * q);
    dirs.push_back(c * l - s * q);
  }

  // Launch plane above everything that refracts; the launch rectangle holds
  // every point from which a disc direction reaches the tank's box.
  const double z_top =
      std::max(model.wall_height(), model.surface().z_max()) + 1e-3;
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  const double A = model.outer_half_x(), B = model.outer_half_y();
  for (const glm::dvec3& w : dirs) {
    for (double sx : {-A, A}) {
      for (double sy : {-B, B}) {
        for (double sz : {0.0, model.wall_height()}) {
          const double k = (z_top - sz) / w.z;
          x0 = std::min(x0, sx + k * w.x);
          x1 = std::max(x1, sx + k * w.x);
          y0 = std::min(y0, sy + k * w.y);
          y1 = std::max(y1, sy + k * w.y);
        }
      }
    }
  }
  x0 -= texel;
  y0 -= texel;
  const int nx = static_cast<int>(std::ceil((x1 + texel - x0) / h));
  const int ny = static_cast<int>(std::ceil((y1 + texel - y0) / h));

  // Flux of one path of direction w: the disc's radiance over its share of
  // the disc's solid angle, times w.z h^2 (the lattice cell seen along w).
  // Summed over the quadrature this is Ed l.z h^2.
  std::vector<double> path_flux(K);
  double max_flux = 0;
  for (int k = 0; k < K; ++k) {
    path_flux[k] =
        rad.disc_radiance * rad.disc_solid_angle / K * dirs[k].z * h * h;
    max_flux = std::max(max_flux, path_flux[k]);
  }
  std::vector<glm::dvec2> offsets(K);
  for (int k = 0; k < K; ++k) {
    const std::uint64_t hk = Hash(options.seed, 0x1000 + k);
    offsets[k] = {(hk >> 11) * 0x1.0p-53, (Mix64(hk) >> 11) * 0x1.0p-53};
  }

  // A fixed-point quantum far below one path's flux. Without disc light
  // (all ambient) every path carries zero flux and deposits zero; a zero
  // quantum would make each deposit 0 * inf (NaN, converted to an integer:
  // undefined), so any positive quantum serves.
  const double quantum = max_flux > 0 ? max_flux * 0x1.0p-32 : 1.0;
  const int chunks = K * ny;
  std::vector<Tally> tallies(chunks);
  std::vector<Deposits> per_thread;
  per_thread.reserve(threads);
  for (int t = 0; t < threads; ++t) {
    per_thread.emplace_back(model.charts(), quantum);
  }
  std::atomic<int> next{0};
  auto worker = [&](int thread) {
    PathTracer tracer(model, options.max_bounces, &per_thread[thread]);
    for (int c = next++; c < chunks; c = next++) {
      const int k = c / ny, j = c % ny;
      const glm::dvec3& w = dirs[k];
      const Spectrum flux(path_flux[k]);
      const double cutoff = 1e-6 * path_flux[k];
      Tally& tally = tallies[c];
      const double y = y0 + (j + offsets[k].y) * h;
      for (int i = 0; i < nx; ++i) {
        const glm::dvec3 p(x0 + (i + offsets[k].x) * h, y, z_top);
        tally.launched += flux;
        // Anything opaque above the launch plane (the pen held high), or
        // through it (a tall obstacle, the pen's shaft): the light to a
        // launch point inside a solid crossed the solid.
        if (model.InsideSolid(p) ||
            model.Next(p, w, Medium::kAir).kind == Event::Kind::kDiffuse) {
          tally.occluded += flux;
          continue;
        }
        tracer.Trace(p, -w, Medium::kAir, flux, false, 0, cutoff, &tally);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& t : pool) t.join();

  Deposits total(model.charts(), quantum);
  for (const Deposits& d : per_thread) d.AddTo(&total);
  atlas->charts = model.charts();
  atlas->texels.resize(atlas->charts.size());
  for (size_t c = 0; c < atlas->charts.size(); ++c) {
    const Chart& ch = atlas->charts[c];
    const double scale = quantum / (ch.du * ch.dv);
    const std::vector<std::int64_t>& plane = total.plane(static_cast<int>(c));
    atlas->texels[c].resize(plane.size());
    for (size_t k = 0; k < plane.size(); ++k) {
      atlas->texels[c][k] = static_cast<float>(plane[k] * scale);
    }
  }

  Tally sum;
  for (const Tally& t : tallies) sum.Add(t);
  LightTraceSummary& s = *summary;
  s.paths = static_cast<std::int64_t>(K) * nx * ny;
  s.paths_per_texel = K * m * m;
  s.disc_directions = K;
  s.texel_m = texel;
  s.launch_spacing_m = h;
  s.launch_rect_m = cv::Rect2d(x0, y0, nx * h, ny * h);
  s.launch_z_m = z_top;
  s.launched = ToVec(sum.launched);
  s.occluded = ToVec(sum.occluded);
  s.unscattered = ToVec(sum.unscattered);
  s.surface_incident = ToVec(sum.surface_incident);
  s.surface_transmitted = ToVec(sum.surface_transmitted);
  s.walls_into_water = ToVec(sum.walls_into_water);
  s.out_of_water = ToVec(sum.out_of_water);
  s.absorbed_in_water = ToVec(sum.absorbed);
  s.deposited_floor = ToVec(sum.floor);
  s.deposited_board = ToVec(sum.board);
  s.deposited_solids = ToVec(sum.solids);
  s.deposited_solids_in_water = ToVec(sum.solids_in_water);
  s.outside_map = ToVec(sum.outside);
  s.escaped = ToVec(sum.escaped);
  s.cut = ToVec(sum.cut);
  s.cut_in_water = ToVec(sum.cut_in_water);
  s.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
}

}  // namespace ripple::reference::internal
