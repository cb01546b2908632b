// The camera pass (reference.h): per pixel, stratified rays through the
// lens model, traced through the scene's interfaces (Fresnel splitting near
// the camera, Fresnel-weighted choice further on), shaded at diffuse points
// by the straight disc light (shadow rays), the light-traced irradiance maps
// and hemisphere rays for the sky and interreflections.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <thread>

#include "render/reference/optics.h"
#include "render/reference/tracing.h"

namespace ripple::reference::internal {
namespace {

// A branch is split (both Fresnel branches traced) while the smaller one
// still carries this much of the pixel; below, one branch is chosen with
// the Fresnel probabilities.
constexpr double kSplitWeight = 1e-3;

// Stratified 2D points of the first diffuse point a camera sample reaches.
struct FirstHitSamples {
  double disc[2];
  const double* ambient;  // ambient_samples pairs
};

class CameraTracer {
 public:
  CameraTracer(const ReferenceOptions& options, const SceneModel& model,
               const IrradianceAtlas* atlas, const LightRadiometry& rad)
      : options_(options),
        model_(model),
        atlas_(atlas),
        rad_(rad),
        cos_alpha_(std::cos(model.alpha())) {}

  // Radiance arriving at o from direction d (the ray o + t d), in medium m.
  // `weight` is the share of the pixel this ray carries (splitting);
  // `events` the interface events on the path so far.
  Spectrum Radiance(glm::dvec3 o, glm::dvec3 d, Medium m, bool include_disc,
                    bool split, int diffuse_depth, double weight, int events,
                    const FirstHitSamples* first, Rng* rng) const {
    Spectrum result(0.0), throughput(1.0);
    while (true) {
      const Event e = model_.Next(o, d, m);
      if (m == Medium::kAir) {
        double t_wall = 0;
        Spectrum wall(0.0);
        if (model_.RoomWall(o, d, &t_wall, &wall) &&
            (e.kind == Event::Kind::kEscape || t_wall < e.t)) {
          return result + throughput * wall;
        }
      }
      if (m == Medium::kWater && e.kind != Event::Kind::kEscape) {
        throughput *= glm::exp(-model_.sigma() * e.t);
      }
      if (e.kind == Event::Kind::kEscape) {
        if (m != Medium::kAir) return result;
        double sky = rad_.sky_radiance;
        if (include_disc && glm::dot(d, model_.light()) >= cos_alpha_) {
          sky += rad_.disc_radiance;
        }
        return result + throughput * sky;
      }
      if (e.kind == Event::Kind::kDiffuse) {
        return result + throughput * Shade(e, m, diffuse_depth, first, rng);
      }
      if (events >= options_.max_bounces) return result;
      ++events;
      const double n_i = model_.Ior(m), n_t = model_.Ior(e.next);
      const double cos_i = -glm::dot(d, e.n);
      double cos_t = 0;
      const double r = FresnelReflectance(cos_i, n_i, n_t, &cos_t);
      const glm::dvec3 refl = Reflect(d, e.n);
      o = e.p;
      if (r >= 1.0) {
        d = refl;
        continue;
      }
      // L / n^2 is invariant along the refracted ray.
      const double radiance_scale = (n_i / n_t) * (n_i / n_t);
      const glm::dvec3 trans = Refract(d, e.n, n_i, n_t, cos_i, cos_t);
      const double w =
          weight * std::max({throughput.x, throughput.y, throughput.z});
      if (split && w * std::min(r, 1.0 - r) >= kSplitWeight) {
        result += throughput * r *
                  Radiance(o, refl, m, include_disc, split, diffuse_depth,
                           w * r, events, first, rng);
        throughput *= (1.0 - r) * radiance_scale;
        d = trans;
        m = e.next;
      } else if (rng->Uniform() < r) {
        d = refl;
      } else {
        throughput *= radiance_scale;
        d = trans;
        m = e.next;
      }
    }
  }

 private:
  // Radiance leaving a Lambertian point towards any direction: rho / pi
  // times the irradiance from the disc (straight and light-traced) and the
  // hemisphere.
  Spectrum Shade(const Event& e, Medium m, int diffuse_depth,
                 const FirstHitSamples* first, Rng* rng) const {
    const Spectrum rho = model_.Albedo(e);
    if (rho == Spectrum(0.0)) return Spectrum(0.0);
    Spectrum irradiance(0.0);
    if (m == Medium::kAir) {
      double u1, u2;
      if (first != nullptr) {
        u1 = first->disc[0];
        u2 = first->disc[1];
      } else {
        u1 = rng->Uniform();
        u2 = rng->Uniform();
      }
      const glm::dvec3 w = SampleCap(model_.light(), cos_alpha_, u1, u2);
      const double c = glm::dot(e.n, w);
      if (c > 0 &&
          model_.Next(e.p, w, Medium::kAir).kind == Event::Kind::kEscape) {
        irradiance += rad_.disc_radiance * rad_.disc_solid_angle * c;
      }
    }
    if (atlas_ != nullptr && e.chart >= 0) {
      irradiance += atlas_->Lookup(e.chart, e.u, e.v);
    }
    if (diffuse_depth < options_.max_diffuse_bounces) {
      const int n = first != nullptr ? options_.ambient_samples : 1;
      Spectrum sum(0.0);
      for (int k = 0; k < n; ++k) {
        double u1, u2;
        if (first != nullptr) {
          u1 = first->ambient[2 * k];
          u2 = first->ambient[2 * k + 1];
        } else {
          u1 = rng->Uniform();
          u2 = rng->Uniform();
        }
        const glm::dvec3 w = SampleCosine(e.n, u1, u2);
        sum += Radiance(e.p, w, m, false, false, diffuse_depth + 1, 1.0, 0,
                        nullptr, rng);
      }
      irradiance += M_PI / n * sum;
    }
    return rho * irradiance / M_PI;
  }

  const ReferenceOptions& options_;
  const SceneModel& model_;
  const IrradianceAtlas* atlas_;
  LightRadiometry rad_;
  double cos_alpha_;
};

// A per-pixel random permutation of 0..n-1 (Fisher-Yates).
void Shuffle(std::vector<int>* v, Rng* rng) {
  std::iota(v->begin(), v->end(), 0);
  for (int i = static_cast<int>(v->size()) - 1; i > 0; --i) {
    const int j = static_cast<int>(rng->Uniform() * (i + 1));
    std::swap((*v)[i], (*v)[std::min(j, i)]);
  }
}

}  // namespace

// The first occluder (reference.h) the ray eye + t d meets, or null.
const ReferenceScene::Occluder* HitOccluder(const ReferenceScene& scene,
                                            const glm::dvec3& eye,
                                            const glm::dvec3& d) {
  for (const ReferenceScene::Occluder& o : scene.occluders) {
    const std::vector<glm::dvec3>& poly = o.polygon_in_tank;
    if (poly.size() < 3) continue;
    const glm::dvec3 n =
        glm::normalize(glm::cross(poly[1] - poly[0], poly[2] - poly[0]));
    const double dn = glm::dot(d, n);
    if (std::abs(dn) < 1e-12) continue;
    const double t = glm::dot(poly[0] - eye, n) / dn;
    if (!(t > 0)) continue;
    const glm::dvec3 p = eye + t * d;
    // Even-odd rule in the plane's own 2D basis.
    const glm::dvec3 u = glm::normalize(poly[1] - poly[0]);
    const glm::dvec3 v = glm::cross(n, u);
    const glm::dvec2 q(glm::dot(p - poly[0], u), glm::dot(p - poly[0], v));
    bool inside = false;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      const glm::dvec2 a(glm::dot(poly[i] - poly[0], u),
                         glm::dot(poly[i] - poly[0], v));
      const glm::dvec2 b(glm::dot(poly[j] - poly[0], u),
                         glm::dot(poly[j] - poly[0], v));
      if ((a.y > q.y) != (b.y > q.y) &&
          q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x)
        inside = !inside;
    }
    if (inside) return &o;
  }
  return nullptr;
}

void TraceCamera(const ReferenceOptions& options, const ReferenceScene& scene,
                 const SceneModel& model, const IrradianceAtlas* atlas,
                 const LightRadiometry& rad, int threads, const cv::Rect& roi,
                 cv::Mat* image) {
  const geometry::CameraModel& cam = scene.camera;
  const glm::dmat4 tank_from_cam = glm::inverse(scene.scene.cam_from_tank);
  const glm::dmat3 rot(tank_from_cam);
  const glm::dvec3 eye(tank_from_cam[3]);
  const int spp = options.samples_per_pixel;
  const int grid = static_cast<int>(std::lround(std::sqrt(double(spp))));
  const bool jittered_grid = grid * grid == spp;
  const int n_amb = options.ambient_samples;
  const CameraTracer tracer(options, model, atlas, rad);

  std::atomic<int> next_row{0};
  auto worker = [&]() {
    std::vector<int> perm_disc(spp), perm_amb(spp * n_amb);
    std::vector<double> ambient(2 * n_amb);
    for (int r = next_row++; r < roi.height; r = next_row++) {
      const int row = roi.y + r;
      cv::Vec3f* out = image->ptr<cv::Vec3f>(row);
      for (int col = roi.x; col < roi.x + roi.width; ++col) {
        Rng rng(Hash(options.seed,
                     static_cast<std::uint64_t>(row) * cam.width + col));
        // Cranley-Patterson rotations and permutations of the strata.
        const double rot_pix[2] = {rng.Uniform(), rng.Uniform()};
        const double rot_disc[2] = {rng.Uniform(), rng.Uniform()};
        const double rot_amb[2] = {rng.Uniform(), rng.Uniform()};
        Shuffle(&perm_disc, &rng);
        Shuffle(&perm_amb, &rng);
        Spectrum sum(0.0);
        for (int s = 0; s < spp; ++s) {
          double sx, sy;
          if (jittered_grid) {
            sx = (s % grid + rng.Uniform()) / grid;
            sy = (s / grid + rng.Uniform()) / grid;
          } else {
            sx = std::fmod((s + 0.5) / spp + rot_pix[0], 1.0);
            sy = std::fmod(RadicalInverse2(s) + rot_pix[1], 1.0);
          }
          FirstHitSamples first;
          const int pd = perm_disc[s];
          first.disc[0] = std::fmod((pd + 0.5) / spp + rot_disc[0], 1.0);
          first.disc[1] = std::fmod(RadicalInverse2(pd) + rot_disc[1], 1.0);
          for (int k = 0; k < n_amb; ++k) {
            const int pa = perm_amb[s * n_amb + k];
            ambient[2 * k] =
                std::fmod((pa + 0.5) / (spp * n_amb) + rot_amb[0], 1.0);
            ambient[2 * k + 1] =
                std::fmod(RadicalInverse2(pa) + rot_amb[1], 1.0);
          }
          first.ambient = ambient.data();
          // Box filter: the sample's position inside the pixel (centre at
          // the integer coordinate).
          const Eigen::Vector2d pixel(col - 0.5 + sx, row - 0.5 + sy);
          const Eigen::Vector3d ray = PixelRay(cam, pixel, options.distort);
          const glm::dvec3 d =
              glm::normalize(rot * glm::dvec3(ray.x(), ray.y(), ray.z()));
          if (const auto* o = HitOccluder(scene, eye, d)) {
            sum += Spectrum(o->radiance_bgr[0], o->radiance_bgr[1],
                            o->radiance_bgr[2]);
            continue;
          }
          sum += tracer.Radiance(eye, d, Medium::kAir, true, true, 0, 1.0, 0,
                                 &first, &rng);
        }
        sum /= spp;
        out[col] =
            cv::Vec3f(static_cast<float>(sum.x), static_cast<float>(sum.y),
                      static_cast<float>(sum.z));
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

}  // namespace ripple::reference::internal
