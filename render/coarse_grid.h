// The water's coarse shading grid (internal to render/). The water's
// per-pixel shading is most of a frame's work on llvmpipe and grows with the
// water's pixels: at 1280x720 the same view has three times the pixels of
// 640x480. The water pass can shade on a coarser grid over the same image
// (the output's aspect, at most RendererOptions::water_shading_columns
// columns) and
// upsample it into the water's own output pixels: the edges of the water
// against walls, obstacles and the video stay the output's, only the
// water's interior is interpolated.
//
// Both grids cover the same image: coarse texel centre (i + 0.5, j + 0.5)
// is output position ((i + 0.5) / scale.x, (j + 0.5) / scale.y), window
// coordinates of Ripple's top-row-first FBOs (y = image row).
#ifndef RIPPLE_RENDER_COARSE_GRID_H_
#define RIPPLE_RENDER_COARSE_GRID_H_

#include <glm/glm.hpp>
#include <vector>

namespace ripple::render::internal {

struct CoarseGrid {
  int width = 0, height = 0;  // texels; 0: shading at the output's pixels
  glm::dvec2 scale{1.0};      // texels per output pixel in x and y

  bool active() const { return width > 0; }
  // The coarse texels that can touch output rectangle `r` (x, y, w, h):
  // scaled outwards, grown by `pad` texels, clamped to the grid.
  glm::ivec4 RectOut(const glm::ivec4& r, int pad) const;
};

// The automatic choice (RendererOptions::water_shading_columns < 0): the
// output's own columns up to 640, a grid of 640 columns above.
constexpr int kAutoMaxColumns = 640;

// The grid for an output of `width` x `height` pixels shaded on at most
// `max_columns` columns (0: no limit; negative: the automatic choice);
// inactive when the output has no more columns than that.
CoarseGrid CoarseGridFor(int width, int height, int max_columns);

// The convex polygon, counter-clockwise in window coordinates of an image
// of `width` x `height`, covering the projection of the tank interior's box
// [-size/2, size/2]^2 x [z0, z1] by `clip_from_tank`, grown by `grow` in x
// and y (its Minkowski sum with the square [-grow, grow]^2). Empty when a
// corner lies behind the camera (no bound: cover the whole image).
std::vector<glm::dvec2> GrownBoxHull(const glm::dmat4& clip_from_tank,
                                     double size_x, double size_y, double z0,
                                     double z1, int width, int height,
                                     double grow);

// The convex hull of `points`, counter-clockwise (Andrew's monotone chain;
// collinear points dropped).
std::vector<glm::dvec2> ConvexHull(std::vector<glm::dvec2> points);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_COARSE_GRID_H_
