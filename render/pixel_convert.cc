#include "render/pixel_convert.h"

#include <cstddef>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace ripple::render::internal {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "BgrToRgbaRow assumes a little-endian machine");
inline std::uint32_t RgbaFromBgr(std::uint32_t bgr) {
  return ((bgr & 0xffu) << 16) | (bgr & 0xff00u) | ((bgr >> 16) & 0xffu) |
         0xff000000u;
}

void BgrToRgbaRowScalar(const std::uint8_t* bgr, int n, std::uint32_t* out) {
  int i = 0;
  // Four pixels from three unaligned 32-bit words.
  for (; i + 4 <= n; i += 4, bgr += 12) {
    std::uint32_t a, b, c;
    std::memcpy(&a, bgr, 4);
    std::memcpy(&b, bgr + 4, 4);
    std::memcpy(&c, bgr + 8, 4);
    out[i] = RgbaFromBgr(a);
    out[i + 1] = RgbaFromBgr((a >> 24) | (b << 8));
    out[i + 2] = RgbaFromBgr((b >> 16) | (c << 16));
    out[i + 3] = RgbaFromBgr(c >> 8);
  }
  for (; i < n; ++i, bgr += 3) {
    out[i] = bgr[2] | (bgr[1] << 8) | (bgr[0] << 16) | 0xff000000u;
  }
}

#if defined(__x86_64__)
// Four pixels per shuffle: 16 loaded bytes hold pixels 0-3 (and part of 4).
__attribute__((target("ssse3"))) void BgrToRgbaRowSsse3(const std::uint8_t* bgr,
                                                        int n,
                                                        std::uint32_t* out) {
  const __m128i shuffle =
      _mm_setr_epi8(2, 1, 0, -1, 5, 4, 3, -1, 8, 7, 6, -1, 11, 10, 9, -1);
  const __m128i alpha = _mm_set1_epi32(static_cast<int>(0xff000000u));
  int i = 0;
  // 16-byte loads: stop while 16 bytes remain readable (16 / 3 > 5 pixels).
  for (; i + 6 <= n; i += 4, bgr += 12) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bgr));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm_or_si128(_mm_shuffle_epi8(v, shuffle), alpha));
  }
  BgrToRgbaRowScalar(bgr, n - i, out + i);
}
#endif

}  // namespace

void BgrToRgbaRow(const std::uint8_t* bgr, int n, std::uint32_t* out) {
#if defined(__x86_64__)
  static const bool ssse3 = __builtin_cpu_supports("ssse3");
  if (ssse3) return BgrToRgbaRowSsse3(bgr, n, out);
#endif
  BgrToRgbaRowScalar(bgr, n, out);
}

void QuarterRgba(const std::uint32_t* src, int w, int h, std::uint32_t* out) {
  const int rw = w / 4, rh = h / 4;
  for (int j = 0; j < rh; ++j) {
    const auto* r0 = reinterpret_cast<const std::uint8_t*>(
        src + static_cast<size_t>(4 * j + 1) * w);
    const std::uint8_t* r1 = r0 + static_cast<size_t>(w) * 4;
    auto* o =
        reinterpret_cast<std::uint8_t*>(out + static_cast<size_t>(j) * rw);
    for (int i = 0; i < rw; ++i) {
      const int x = 4 * (4 * i + 1);
      for (int c = 0; c < 4; ++c) {
        o[4 * i + c] = static_cast<std::uint8_t>(
            (r0[x + c] + r0[x + 4 + c] + r1[x + c] + r1[x + 4 + c] + 2) >> 2);
      }
    }
  }
}

void QuarterRgbaFromBgr(const std::uint8_t* bgr, int stride, int w, int h,
                        std::uint32_t* out) {
  const int rw = w / 4, rh = h / 4;
  for (int j = 0; j < rh; ++j) {
    const std::uint8_t* r0 = bgr + static_cast<size_t>(4 * j + 1) * stride;
    const std::uint8_t* r1 = r0 + stride;
    auto* o =
        reinterpret_cast<std::uint8_t*>(out + static_cast<size_t>(j) * rw);
    for (int i = 0; i < rw; ++i) {
      const int x = 3 * (4 * i + 1);
      for (int c = 0; c < 3; ++c) {
        // BGR in, RGBA out.
        o[4 * i + 2 - c] = static_cast<std::uint8_t>(
            (r0[x + c] + r0[x + 3 + c] + r1[x + c] + r1[x + 3 + c] + 2) >> 2);
      }
      o[4 * i + 3] = 255;
    }
  }
}

}  // namespace ripple::render::internal
