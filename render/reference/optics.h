// Interface optics of the reference renderer: exact unpolarised Fresnel
// reflectance, mirror reflection and Snell refraction. Directions are unit
// vectors; `n` is the unit normal on the side the ray comes from
// (dot(d, n) < 0).
#ifndef RIPPLE_RENDER_REFERENCE_OPTICS_H_
#define RIPPLE_RENDER_REFERENCE_OPTICS_H_

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace ripple::reference {

// Fresnel reflectance of unpolarised light, the mean of the s and p
// reflectances of the Fresnel equations (Born & Wolf, Principles of Optics,
// 7th ed., §1.5.2, eqs. 21a-21b):
//   r_s = (n_i cos_i - n_t cos_t) / (n_i cos_i + n_t cos_t),
//   r_p = (n_t cos_i - n_i cos_t) / (n_t cos_i + n_i cos_t),
//   R = (r_s^2 + r_p^2) / 2, T = 1 - R (no absorption at the interface).
// `cos_i` is the cosine of the angle of incidence (clamped to [0, 1]); n_i
// and n_t are the refractive indices of the incident and transmitted media.
// Returns 1 under total internal reflection. `cos_t` (may be null) receives
// the cosine of the refraction angle (0 under total internal reflection).
inline double FresnelReflectance(double cos_i, double n_i, double n_t,
                                 double* cos_t = nullptr) {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double eta = n_i / n_t;
  const double sin2_t = eta * eta * (1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) {
    if (cos_t != nullptr) *cos_t = 0.0;
    return 1.0;
  }
  const double ct = std::sqrt(1.0 - sin2_t);
  if (cos_t != nullptr) *cos_t = ct;
  const double rs = (n_i * cos_i - n_t * ct) / (n_i * cos_i + n_t * ct);
  const double rp = (n_t * cos_i - n_i * ct) / (n_t * cos_i + n_i * ct);
  return 0.5 * (rs * rs + rp * rp);
}

// Mirror reflection of `d` about the plane with normal `n`.
inline glm::dvec3 Reflect(const glm::dvec3& d, const glm::dvec3& n) {
  return d - 2.0 * glm::dot(d, n) * n;
}

// Snell refraction (n_i sin_i = n_t sin_t) of `d` through the plane with
// normal `n` (on the incident side), given cos_i = -dot(d, n) and the
// cos_t that FresnelReflectance returned. The result is a unit vector.
inline glm::dvec3 Refract(const glm::dvec3& d, const glm::dvec3& n, double n_i,
                          double n_t, double cos_i, double cos_t) {
  const double eta = n_i / n_t;
  return glm::normalize(eta * d + (eta * cos_i - cos_t) * n);
}

}  // namespace ripple::reference

#endif  // RIPPLE_RENDER_REFERENCE_OPTICS_H_
