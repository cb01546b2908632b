#include "render/pass_height.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#include <immintrin.h>
#endif

namespace ripple::render::internal {
namespace {

// IEEE half from float, round to nearest even (the portable path).
std::uint16_t HalfOf(float f) {
  std::uint32_t x;
  std::memcpy(&x, &f, 4);
  const std::uint32_t sign = (x >> 16) & 0x8000u;
  const std::uint32_t abs = x & 0x7fffffffu;
  if (abs >= 0x7f800000u) return sign | (abs > 0x7f800000u ? 0x7e00u : 0x7c00u);
  if (abs >= 0x477ff000u) return sign | 0x7c00u;     // overflows to infinity
  if (abs < 0x38800000u) {                           // subnormal or zero
    const float scaled = std::abs(f) * 16777216.0f;  // 2^24: units of 2^-24
    return sign | static_cast<std::uint16_t>(std::nearbyint(scaled));
  }
  const std::uint32_t m = abs + 0xc8000fffu + ((abs >> 13) & 1u);
  return sign | static_cast<std::uint16_t>(m >> 13);
}

void HalvesPortable(const float* in, std::uint16_t* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = HalfOf(in[i]);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx,f16c"))) void HalvesF16c(const float* in,
                                                    std::uint16_t* out,
                                                    std::size_t n) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm_storeu_si128(
        reinterpret_cast<__m128i*>(out + i),
        _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_TO_NEAREST_INT));
  HalvesPortable(in + i, out + i, n - i);
}
#endif

// Half floats are what the RGBA16F texture holds, so the driver copies
// instead of converting every texel (a third of the upload on llvmpipe).
void ToHalves(const float* in, std::uint16_t* out, std::size_t n) {
#if defined(__x86_64__) && defined(__GNUC__)
  // CPUID leaf 1, ECX bit 29 (clang 14's __builtin_cpu_supports has no
  // "f16c").
  static const bool f16c = [] {
    unsigned a = 0, b = 0, c = 0, d = 0;
    return __get_cpuid(1, &a, &b, &c, &d) != 0 && (c & bit_F16C) != 0;
  }();
  if (f16c) return HalvesF16c(in, out, n);
#endif
  HalvesPortable(in, out, n);
}

}  // namespace

void HeightTexturePass::AllocateFlat() {
  const glm::vec4 zero(0.0f);
  AllocTexture(&texture_, GL_RGBA16F, 1, 1, GL_RGBA, GL_FLOAT, GL_LINEAR,
               GL_CLAMP_TO_EDGE, &zero);
  nx_ = ny_ = 1;
  counter_.reset();
}

void HeightTexturePass::Create() { AllocateFlat(); }

HeightFieldInfo HeightTexturePass::info() const {
  HeightFieldInfo i;
  i.extent = extent_;
  i.texel = {1.0f / nx_, 1.0f / ny_};
  return i;
}

bool HeightTexturePass::Update(const SceneInputs& scene) {
  const HeightFieldView& w = scene.water;
  if (w.heights == nullptr || w.nx <= 0 || w.ny <= 0 || w.cell_size <= 0) {
    extent_ = {scene.tank.size_x, scene.tank.size_y};
    if (nx_ == 1 && !counter_.has_value()) return false;
    AllocateFlat();
    return true;
  }
  extent_ = {w.nx * w.cell_size, w.ny * w.cell_size};
  const bool resized = w.nx != nx_ || w.ny != ny_;
  if (!resized && counter_ == w.change_counter) return false;
  // Height and central-difference slopes per cell, so the fragment shader
  // needs one fetch for its normal. Stored as half floats: llvmpipe fetches
  // and filters 8 bytes per texel instead of 16, and displacements of
  // millimetres keep 11 significant bits.
  const int nx = w.nx, ny = w.ny;
  const float inv = 1.0f / w.cell_size;
  slopes_.resize(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    const float* row = w.heights + static_cast<size_t>(j) * nx;
    const float* down = w.heights + static_cast<size_t>(j > 0 ? j - 1 : j) * nx;
    const float* up =
        w.heights + static_cast<size_t>(j + 1 < ny ? j + 1 : j) * nx;
    const float sy = inv / std::max((j > 0 ? 1 : 0) + (j + 1 < ny ? 1 : 0), 1);
    for (int i = 0; i < nx; ++i) {
      const int il = i > 0 ? i - 1 : i, ir = i + 1 < nx ? i + 1 : i;
      slopes_[static_cast<size_t>(j) * nx + i] =
          glm::vec4(row[i], (row[ir] - row[il]) * inv / std::max(ir - il, 1),
                    (up[i] - down[i]) * sy, 0.0f);
    }
  }
  halves_.resize(slopes_.size() * 4);
  ToHalves(&slopes_[0].x, halves_.data(), halves_.size());
  if (resized) {
    AllocTexture(&texture_, GL_RGBA16F, nx, ny, GL_RGBA, GL_HALF_FLOAT,
                 GL_LINEAR, GL_CLAMP_TO_EDGE, halves_.data());
    nx_ = nx;
    ny_ = ny;
  } else {
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, nx, ny, GL_RGBA, GL_HALF_FLOAT,
                    halves_.data());
  }
  counter_ = w.change_counter;
  return true;
}

}  // namespace ripple::render::internal
