// Internal pieces shared by the light tracer and the camera tracer: the
// deterministic random numbers, the irradiance atlas, sampling helpers and
// the two passes.
#ifndef RIPPLE_RENDER_REFERENCE_TRACING_H_
#define RIPPLE_RENDER_REFERENCE_TRACING_H_

#include <cmath>
#include <cstdint>
#include <vector>

#include "render/reference/reference.h"
#include "render/reference/scene_model.h"

namespace ripple::reference::internal {

// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number
// generators", OOPSLA 2014): the finaliser as a hash, the sequence as the
// per-pixel and per-chunk generator.
inline std::uint64_t Mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}
inline std::uint64_t Hash(std::uint64_t a, std::uint64_t b) {
  return Mix64(a ^ Mix64(b + 0x632be59bd9b4e019ull));
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

// Van der Corput radical inverse in base 2, in [0, 1).
inline double RadicalInverse2(std::uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return static_cast<double>(i) * 0x1.0p-32;
}

// An orthonormal frame (e1, e2) perpendicular to the unit vector n.
inline void Perpendiculars(const glm::dvec3& n, glm::dvec3* e1,
                           glm::dvec3* e2) {
  const glm::dvec3 t =
      std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  *e1 = glm::normalize(glm::cross(t, n));
  *e2 = glm::cross(n, *e1);
}

// Direction uniform in solid angle on the cap of half-angle alpha around l.
inline glm::dvec3 SampleCap(const glm::dvec3& l, double cos_alpha, double u1,
                            double u2) {
  glm::dvec3 e1, e2;
  Perpendiculars(l, &e1, &e2);
  const double c = 1.0 - u1 * (1.0 - cos_alpha);
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  const double phi = 2.0 * M_PI * u2;
  return c * l + s * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

// Cosine-weighted direction on the hemisphere around n (pdf cos / pi).
inline glm::dvec3 SampleCosine(const glm::dvec3& n, double u1, double u2) {
  glm::dvec3 e1, e2;
  Perpendiculars(n, &e1, &e2);
  const double r = std::sqrt(u1), phi = 2.0 * M_PI * u2;
  return r * std::cos(phi) * e1 + r * std::sin(phi) * e2 +
         std::sqrt(std::max(0.0, 1.0 - u1)) * n;
}

// Irradiance per chart texel (B, G, R), read bilinearly between texel
// centres (clamped at chart edges; wrapped along a cylinder's u).
struct IrradianceAtlas {
  std::vector<Chart> charts;
  std::vector<std::vector<float>> texels;  // nu * nv * 3 per chart
  // Outside the board chart's rectangle: 0.
  Spectrum Lookup(int chart, double u, double v) const;
};

// The light quantities of the scene (reference.h).
LightRadiometry Radiometry(const SceneModel& model, double ambient_share);

// Light tracing into `atlas` (charts of `model`); fills `summary`.
void TraceLight(const ReferenceOptions& options, const SceneModel& model,
                const LightRadiometry& rad, int threads, IrradianceAtlas* atlas,
                LightTraceSummary* summary);

// Camera pass over options.roi (or the whole image) into `image`
// (CV_32FC3, already allocated at the camera size and zeroed).
void TraceCamera(const ReferenceOptions& options, const ReferenceScene& scene,
                 const SceneModel& model, const IrradianceAtlas* atlas,
                 const LightRadiometry& rad, int threads, const cv::Rect& roi,
                 cv::Mat* image);

}  // namespace ripple::reference::internal

#endif  // RIPPLE_RENDER_REFERENCE_TRACING_H_
