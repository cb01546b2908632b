#include "render/pass_height.h"

#include <algorithm>

namespace ripple::render::internal {

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
  if (resized) {
    AllocTexture(&texture_, GL_RGBA16F, nx, ny, GL_RGBA, GL_FLOAT, GL_LINEAR,
                 GL_CLAMP_TO_EDGE, slopes_.data());
    nx_ = nx;
    ny_ = ny;
  } else {
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, nx, ny, GL_RGBA, GL_FLOAT,
                    slopes_.data());
  }
  counter_ = w.change_counter;
  return true;
}

}  // namespace ripple::render::internal
