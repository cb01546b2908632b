// Height texture pass (internal to render/): the simulated surface as an
// RGBA8 texture of (h, dh/dx, dh/dy) per cell, each channel coded over the
// frame's range (HeightFieldInfo's decode), which the water shaders sample
// for heights and normals.
//
// Redraw key: the field's size and change counter; null heights key "flat"
// (a 1 x 1 texture of zero over the tank).
#ifndef RIPPLE_RENDER_PASS_HEIGHT_H_
#define RIPPLE_RENDER_PASS_HEIGHT_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

class HeightTexturePass {
 public:
  void Create();
  // Uploads the field if its key changed; true if it did.
  bool Update(const SceneInputs& scene);
  // The texture's mapping for the frame Update() last saw.
  HeightFieldInfo info() const;
  GLuint texture() const { return texture_.id(); }

 private:
  void AllocateFlat();

  Texture texture_;
  int nx_ = 0, ny_ = 0;                   // texels
  std::optional<std::uint64_t> counter_;  // nullopt: flat
  glm::vec2 extent_{1.0f};                // metres
  glm::vec3 decode_scale_{0.0f}, decode_offset_{0.0f};
  // Cells per side of a slope tile (HeightFieldInfo::tile_slope).
  static constexpr int kTileCells = 8;
  void UpdateSlopeTiles(int nx, int ny, float cell_m);

  std::vector<float> planes_;    // h, then dh/dx, then dh/dy planes
  std::vector<float> col_max_;   // scratch: one tile row's column maxima
  std::vector<float> tile_max_;  // per tile, then dilated: tile_slope_
  std::vector<float> tile_slope_;
  int tiles_x_ = 0, tiles_y_ = 0;
  float tile_m_ = 0.0f;
  std::vector<std::uint32_t> packed_;  // the same coded, RGBA8 (upload)
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_HEIGHT_H_
