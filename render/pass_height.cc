#include "render/pass_height.h"

#include <algorithm>
#include <cmath>

namespace ripple::render::internal {
namespace {

// One channel's affine 8-bit code over [lo, hi]: texel = (v - lo) / step.
struct ChannelCode {
  float lo = 0, inv_step = 0;
  static ChannelCode Over(float lo, float hi) {
    ChannelCode c;
    c.lo = lo;
    const float step = (hi - lo) / 255.0f;
    c.inv_step = step > 0 ? 1.0f / step : 0.0f;
    return c;
  }
  // Non-finite values code as the rest level's 0 (the test is written so
  // that NaN fails it).
  std::uint32_t Encode(float v) const {
    const float t = ((std::isfinite(v) ? v : 0.0f) - lo) * inv_step + 0.5f;
    return t >= 0.0f ? static_cast<std::uint32_t>(std::min(t, 255.0f)) : 0u;
  }
};

}  // namespace

void HeightTexturePass::AllocateFlat() {
  const std::uint32_t zero = 0;
  AllocTexture(&texture_, GL_RGBA8, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, GL_LINEAR,
               GL_CLAMP_TO_EDGE, &zero);
  decode_scale_ = decode_offset_ = glm::vec3(0.0f);
  nx_ = ny_ = 1;
  counter_.reset();
}

void HeightTexturePass::Create() { AllocateFlat(); }

HeightFieldInfo HeightTexturePass::info() const {
  HeightFieldInfo i;
  i.extent = extent_;
  i.texel = {1.0f / nx_, 1.0f / ny_};
  i.decode_scale = decode_scale_;
  i.decode_offset = decode_offset_;
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
  // needs one fetch for its normal.
  const int nx = w.nx, ny = w.ny;
  const float inv = 1.0f / w.cell_size;
  slopes_.resize(static_cast<size_t>(nx) * ny);
  glm::vec3 lo(0.0f), hi(0.0f);
  for (int j = 0; j < ny; ++j) {
    const float* row = w.heights + static_cast<size_t>(j) * nx;
    const float* down = w.heights + static_cast<size_t>(j > 0 ? j - 1 : j) * nx;
    const float* up =
        w.heights + static_cast<size_t>(j + 1 < ny ? j + 1 : j) * nx;
    const float sy = inv / std::max((j > 0 ? 1 : 0) + (j + 1 < ny ? 1 : 0), 1);
    for (int i = 0; i < nx; ++i) {
      const int il = i > 0 ? i - 1 : i, ir = i + 1 < nx ? i + 1 : i;
      const glm::vec3 v(row[i],
                        (row[ir] - row[il]) * inv / std::max(ir - il, 1),
                        (up[i] - down[i]) * sy);
      slopes_[static_cast<size_t>(j) * nx + i] = v;
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(v[c])) continue;
        lo[c] = std::min(lo[c], v[c]);
        hi[c] = std::max(hi[c], v[c]);
      }
    }
  }
  // Stored as RGBA8, each channel over this frame's range (0 included, so a
  // field at rest decodes to exactly 0): llvmpipe filters four-channel 8-bit
  // textures in inlined code, half floats in a generic sampling function
  // that cost twice as many instructions per lookup. Filtering is linear,
  // so decoding after it is exact; the code's step is 1/255 of the range
  // (8 um of height and 0.006 of slope for +-1 mm and +-0.75).
  const ChannelCode code[3] = {ChannelCode::Over(lo.x, hi.x),
                               ChannelCode::Over(lo.y, hi.y),
                               ChannelCode::Over(lo.z, hi.z)};
  packed_.resize(slopes_.size());
  for (size_t k = 0; k < slopes_.size(); ++k) {
    const glm::vec3& v = slopes_[k];
    packed_[k] = code[0].Encode(v.x) | code[1].Encode(v.y) << 8 |
                 code[2].Encode(v.z) << 16;
  }
  decode_offset_ = lo;
  decode_scale_ = hi - lo;
  if (resized) {
    AllocTexture(&texture_, GL_RGBA8, nx, ny, GL_RGBA, GL_UNSIGNED_BYTE,
                 GL_LINEAR, GL_CLAMP_TO_EDGE, packed_.data());
    nx_ = nx;
    ny_ = ny;
  } else {
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, nx, ny, GL_RGBA, GL_UNSIGNED_BYTE,
                    packed_.data());
  }
  counter_ = w.change_counter;
  return true;
}

}  // namespace ripple::render::internal
