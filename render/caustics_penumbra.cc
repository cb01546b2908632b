// The light's disc blurs the caustics: PenumbraKernel and ApplyPenumbra
// (caustics_kernels.h).
#include <algorithm>
#include <cmath>

#include "render/caustics_kernels.h"

namespace ripple::render::caustics_internal {

std::vector<float> PenumbraKernel(const TankGeometry& tank, const glm::dvec3& l,
                                  double ior, double alpha, double tx,
                                  double ty, int max_r, int* r) {
  *r = 0;
  if (!(alpha > 0) || max_r < 1) return {1.0f};
  const glm::dvec3 up(0, 0, 1);
  // Floor point of the refracted ray from the surface point above the
  // origin, for light arriving along -w.
  auto shift = [&](const glm::dvec3& w) {
    const glm::dvec3 t = glm::refract(-w, up, 1.0 / ior);
    return glm::dvec2(t.x, t.y) * (tank.water_level / -t.z);
  };
  const glm::dvec2 centre = shift(l);
  // An orthonormal frame around l; directions over the disc by a uniform
  // n x n grid of the disc's tangent plane (its angle to l is small: the
  // solid angle's density stays uniform to second order in alpha).
  const glm::dvec3 e1 = glm::normalize(glm::cross(
      l, std::abs(l.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 e2 = glm::cross(l, e1);
  const double ta = std::tan(alpha);
  constexpr int kN = 48;
  std::vector<glm::ivec2> offsets;
  offsets.reserve(kN * kN);
  int reach = 0;
  for (int j = 0; j < kN; ++j) {
    for (int i = 0; i < kN; ++i) {
      const double u = (i + 0.5) / kN * 2 - 1, v = (j + 0.5) / kN * 2 - 1;
      if (u * u + v * v > 1) continue;
      const glm::dvec3 w = glm::normalize(l + ta * (u * e1 + v * e2));
      if (!(w.z > 1e-3)) continue;
      const glm::dvec2 s = shift(w) - centre;
      const glm::ivec2 o(static_cast<int>(std::lround(s.x / tx)),
                         static_cast<int>(std::lround(s.y / ty)));
      reach = std::max({reach, std::abs(o.x), std::abs(o.y)});
      offsets.push_back(o);
    }
  }
  if (offsets.empty()) return {1.0f};
  *r = std::min(reach, max_r);
  const int side = 2 * *r + 1;
  std::vector<float> kernel(static_cast<size_t>(side) * side, 0.0f);
  for (const glm::ivec2& o : offsets) {
    const int i = std::clamp(o.x, -*r, *r) + *r;
    const int j = std::clamp(o.y, -*r, *r) + *r;
    kernel[static_cast<size_t>(j) * side + i] += 1.0f;
  }
  const float norm = 1.0f / static_cast<float>(offsets.size());
  for (float& k : kernel) k *= norm;
  return kernel;
}

void ApplyPenumbra(const std::vector<float>& kernel, int r, int mx, int my,
                   const float* map, float* out) {
  const int side = 2 * r + 1;
  // Rows padded by r clamped texels on each side, so the inner loop over a
  // row has no edge tests (and vectorises).
  std::vector<float> padded(static_cast<size_t>(mx + 2 * r));
  std::fill(out, out + static_cast<size_t>(mx) * my, 0.0f);
  for (int dj = -r; dj <= r; ++dj) {
    for (int b = 0; b < my; ++b) {
      // Light arriving from the kernel's offset (i, j) lands (i, j) texels
      // away: out(a, b) += k(i, j) map(a - i, b - j).
      const int src_b = std::clamp(b - dj, 0, my - 1);
      const float* src = map + static_cast<size_t>(src_b) * mx;
      std::copy(src, src + mx, padded.begin() + r);
      std::fill(padded.begin(), padded.begin() + r, src[0]);
      std::fill(padded.end() - r, padded.end(), src[mx - 1]);
      float* dst = out + static_cast<size_t>(b) * mx;
      for (int di = -r; di <= r; ++di) {
        const float k = kernel[static_cast<size_t>(dj + r) * side + di + r];
        if (k == 0.0f) continue;
        const float* p = padded.data() + r - di;
        for (int a = 0; a < mx; ++a) dst[a] += k * p[a];
      }
    }
  }
}

}  // namespace ripple::render::caustics_internal
