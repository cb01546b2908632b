#include "render/pass_height.h"

#include <algorithm>
#include <cfloat>
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
    c.inv_step = step > 0 && std::isfinite(1.0f / step) ? 1.0f / step : 0.0f;
    return c;
  }
  // v finite (Update maps the rest to 0).
  std::uint32_t Encode(float v) const {
    const float t = (v - lo) * inv_step + 0.5f;
    // Through int32: SSE2 converts floats to signed integers only, so this
    // keeps the packing loop vectorised.
    return static_cast<std::uint32_t>(
        static_cast<std::int32_t>(std::min(std::max(t, 0.0f), 255.0f)));
  }
};

}  // namespace

void HeightTexturePass::AllocateFlat() {
  const std::uint32_t zero = 0;
  AllocTexture(&texture_, GL_RGBA8, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, GL_LINEAR,
               GL_CLAMP_TO_EDGE, &zero);
  decode_scale_ = decode_offset_ = glm::vec3(0.0f);
  tiles_x_ = tiles_y_ = 0;
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
  if (tiles_x_ > 0 && tiles_y_ > 0) {
    i.tile_slope = tile_slope_.data();
    i.tiles_x = tiles_x_;
    i.tiles_y = tiles_y_;
    i.tile_m = tile_m_;
  }
  return i;
}

void HeightTexturePass::UpdateSlopeTiles(int nx, int ny, float cell_m) {
  const size_t n = static_cast<size_t>(nx) * ny;
  const float* px = planes_.data() + n;
  const float* py = px + n;
  const int tx = (nx + kTileCells - 1) / kTileCells;
  const int ty = (ny + kTileCells - 1) / kTileCells;
  tile_max_.assign(static_cast<size_t>(tx) * ty, 0.0f);
  // Column maxima over a tile's rows (contiguous, so the compiler
  // vectorises it), then each tile's maximum over its columns.
  col_max_.resize(nx);
  for (int tj = 0; tj < ty; ++tj) {
    std::fill(col_max_.begin(), col_max_.end(), 0.0f);
    float* c = col_max_.data();
    for (int j = tj * kTileCells; j < std::min(ny, (tj + 1) * kTileCells);
         ++j) {
      const float* ox = px + static_cast<size_t>(j) * nx;
      const float* oy = py + static_cast<size_t>(j) * nx;
      for (int i = 0; i < nx; ++i)
        c[i] = std::max(c[i], ox[i] * ox[i] + oy[i] * oy[i]);
    }
    for (int t = 0; t < tx; ++t) {
      float m = 0.0f;
      for (int i = t * kTileCells; i < std::min(nx, (t + 1) * kTileCells); ++i)
        m = std::max(m, c[i]);
      tile_max_[static_cast<size_t>(tj) * tx + t] = m;
    }
  }
  // Each tile takes its neighbours' steepest slope too: a lookup near the
  // tile's edge filters texels of the next tile.
  tile_slope_.resize(tile_max_.size());
  for (int j = 0; j < ty; ++j) {
    for (int i = 0; i < tx; ++i) {
      float m = 0.0f;
      for (int b = std::max(0, j - 1); b <= std::min(ty - 1, j + 1); ++b)
        for (int a = std::max(0, i - 1); a <= std::min(tx - 1, i + 1); ++a)
          m = std::max(m, tile_max_[static_cast<size_t>(b) * tx + a]);
      tile_slope_[static_cast<size_t>(j) * tx + i] = std::sqrt(m);
    }
  }
  tiles_x_ = tx;
  tiles_y_ = ty;
  tile_m_ = kTileCells * cell_m;
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
  // Height and central-difference slopes per cell (one-sided at the
  // borders), so the fragment shader needs one fetch for its normal. Planes
  // of floats and branch-free inner loops, which the compiler vectorises:
  // at 256 x 256 cells this runs every frame the water moves.
  const int nx = w.nx, ny = w.ny;
  const size_t n = static_cast<size_t>(nx) * ny;
  const float inv = 1.0f / w.cell_size;
  planes_.resize(3 * n);
  float* ph = planes_.data();
  float* px = ph + n;
  float* py = px + n;
  for (int j = 0; j < ny; ++j) {
    const float* row = w.heights + static_cast<size_t>(j) * nx;
    const float* down = w.heights + static_cast<size_t>(j > 0 ? j - 1 : j) * nx;
    const float* up =
        w.heights + static_cast<size_t>(j + 1 < ny ? j + 1 : j) * nx;
    const float sy = inv / std::max((j > 0 ? 1 : 0) + (j + 1 < ny ? 1 : 0), 1);
    float* oh = ph + static_cast<size_t>(j) * nx;
    float* ox = px + static_cast<size_t>(j) * nx;
    float* oy = py + static_cast<size_t>(j) * nx;
    for (int i = 0; i < nx; ++i) {
      oh[i] = row[i];
      oy[i] = (up[i] - down[i]) * sy;
    }
    const float half = 0.5f * inv;
    for (int i = 1; i + 1 < nx; ++i) ox[i] = (row[i + 1] - row[i - 1]) * half;
    ox[0] = nx > 1 ? (row[1] - row[0]) * inv : 0.0f;
    if (nx > 1) ox[nx - 1] = (row[nx - 1] - row[nx - 2]) * inv;
  }
  // Non-finite values code as the rest level's 0; the range always holds 0.
  glm::vec3 lo(0.0f), hi(0.0f);
  for (int c = 0; c < 3; ++c) {
    float* v = ph + c * n;
    constexpr int kLanes = 16;
    float lo_l[kLanes] = {}, hi_l[kLanes] = {};
    size_t k = 0;
    for (; k + kLanes <= n; k += kLanes) {
      for (int l = 0; l < kLanes; ++l) {
        const float a = v[k + l];
        const float x = std::fabs(a) <= FLT_MAX ? a : 0.0f;
        v[k + l] = x;
        lo_l[l] = std::min(lo_l[l], x);
        hi_l[l] = std::max(hi_l[l], x);
      }
    }
    for (; k < n; ++k) {
      const float x = std::fabs(v[k]) <= FLT_MAX ? v[k] : 0.0f;
      v[k] = x;
      lo_l[0] = std::min(lo_l[0], x);
      hi_l[0] = std::max(hi_l[0], x);
    }
    for (int l = 0; l < kLanes; ++l) {
      lo[c] = std::min(lo[c], lo_l[l]);
      hi[c] = std::max(hi[c], hi_l[l]);
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
  packed_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    packed_[k] = code[0].Encode(ph[k]) | code[1].Encode(px[k]) << 8 |
                 code[2].Encode(py[k]) << 16;
  }
  decode_offset_ = lo;
  decode_scale_ = hi - lo;
  UpdateSlopeTiles(nx, ny, w.cell_size);
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
