// Water pass (internal to render/): the surface mesh lays its depth and
// marks its visible pixels in the stencil, then one full-screen shading per
// marked pixel (refraction, shadow, caustics, reflection, specular) inside
// the water's window rectangle. With a coarse grid (Options::shading_columns,
// coarse_grid.h) the shading runs on the grid's texels, marked by the tank's
// grown outline, and one bilinear lookup per marked output pixel brings it
// back (water_upsample.frag).
//
// llvmpipe executes both sides of every branch, so each combination of
// effects is its own program; all of them are compiled at creation.
//
// Redraw key: none (the output is redrawn every frame). The floor-return
// map: traced when the tank changes; its surroundings' light re-uploaded
// when the board's radiance beyond a wall, read from the video, changes.
#ifndef RIPPLE_RENDER_PASS_WATER_H_
#define RIPPLE_RENDER_PASS_WATER_H_

#include <glm/glm.hpp>
#include <optional>
#include <string>

#include "render/board_light.h"
#include "render/coarse_grid.h"
#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/optics.h"
#include "render/pass_real.h"

namespace ripple::render::internal {

class WaterPass {
 public:
  struct Options {
    int surface_grid = 8;  // quads per side of the surface mesh
    WaterOptics optics;
    // Every variant: the reflection from the environment cube map
    // (pass_envmap.h) rather than the fold; the daylight sky over it.
    bool env_cube = false;
    bool sky = false;
    // The refracted video by Catmull-Rom interpolation, not one bilinear
    // fetch (RefractionFilter).
    bool cubic_refraction = true;
    // Shade the real pen, the clean plate and the mirror only inside their
    // regions (water_regions.h) and the rest of the water without them; the
    // output is the same. false: every water pixel takes every effect.
    bool regions = true;
    // Shade on a grid of at most this many columns (coarse_grid.h) and
    // upsample into the water's output pixels; 0: at the output's pixels;
    // negative: the automatic choice (CoarseGridFor).
    int shading_columns = 0;
  };
  bool Create(const Options& options, std::string* error);
  // (Re)allocates the coarse grid's target for an output of this size.
  bool AllocateOutput(int width, int height);

  // Draws into `target` (bound, depth laid by earlier passes), with the
  // frame's textures bound to their units. `have_video`: the reflection map
  // holds something; `real`: the real pen and the plate (RealObjectsPass).
  void Draw(const FrameState& f, bool have_video, const RealObjectsState& real,
            GLuint target);
  // Whether Draw shades the real pen (the refracted view of its submerged
  // shaft): then PenOutlinePass blends its dry shaft's outline over the
  // water, and ObstaclesPass lays the shaft's phantom inside that outline.
  static bool ShadesRealPen(const FrameState& f, bool have_video,
                            const RealObjectsState& real);
  // The grid the water is shaded on (inactive: the output's pixels).
  const CoarseGrid& grid() const { return grid_; }
  // The floor's return map and light for this frame (FloorReturnLight):
  // before Draw, and before any pass that reads floor_return_light().
  void UpdateFloorLight(const FrameState& f);
  // The floor-return map's tint and means (frame_state.h).
  const FloorReturnLight& floor_return_light() const { return return_light_; }

  // Texels of the floor-return map (optics.h) over the tank floor, and the
  // directions traced per texel; recomputed when the tank changes.
  static constexpr int kReturnNx = 32, kReturnNy = 21, kReturnRays = 2048;
  // Obstacles the refracted rays are traced against (water.frag's arrays,
  // sized by the MAX_OBSTACLES define).
  static constexpr int kMaxTracedObstacles = 1;

 private:
  // Variant bits: one program per combination of these effects.
  enum Variant : int {
    kShadows = 1,
    kCaustics = 2,
    kReflection = 4,
    kRefraction = 8,
    // Only with kRefraction (RealObjectsState): the submerged real pen, and
    // the clean plate behind this frame's occluder mask.
    kRealPen = 16,
    kRealPlate = 32,
    // Only with kReflection: the mirrored obstacles and pen (pass_mirror.h).
    kMirror = 64,
    // Only with kRefraction: no wall in the view ray's or the refracted
    // ray's way (WallFreeRect in water_regions.h), so neither the glass's
    // shift nor the walls' paths are in the program.
    kWallFree = 128,
    // Only with kRefraction: refracted rays traced against the virtual
    // obstacles where their lookups may land on one (ObstacleLookupRect).
    kObstacles = 256,
    kVariants = 512,
  };
  struct Shading {
    Program program;
    CommonUniforms common;
    // Per-frame optics (FrameState::shading).
    GLint floor_sky = -1, floor_sun = -1, inv_n2 = -1, glass_t = -1,
          glint_peak = -1, inv_alpha2 = -1, return_tint = -1, floor_around = -1;
    GLint under_glass[4] = {-1, -1, -1, -1};  // per wall
    // kRealPen, kRealPlate.
    GLint pen_tip = -1, pen_axis = -1, pen_length = -1, pen_radius = -1,
          pen_margin = -1, plate_map = -1, plate_gain = -1;
    // The virtual obstacles the refracted rays are traced against.
    GLint obstacle_count = -1, obstacle_from_tank = -1, obstacle_shape = -1;
  };
  static bool BuildShading(Shading* s, const std::string& defines,
                           const Options& options, std::string* error);
  // The #defines of variant `v` under this pass's options.
  std::string VariantDefines(int v) const;
  // Variant `v`, a kObstacles one built on first use (without kObstacles
  // if that build fails, reported once).
  const Shading& Variant(int v) const;
  // Binds `s` and sets the frame's uniforms.
  void Prepare(const Shading& s, const FrameState& f,
               const RealObjectsState& real) const;
  // Shades the stencil-marked pixels of the bound target inside `rect`
  // (its pixels), cut into cells by the regions (`region[i]` used where
  // `use[i]`: the real pen, the plate, the mirror, the wall-free rectangle
  // and the obstacles' lookups) each shaded by the variant `base` plus the
  // variant bits of the regions holding it.
  static constexpr int kRegions = 5;
  void ShadeCells(const FrameState& f, const RealObjectsState& real, int base,
                  const glm::ivec4& rect, const glm::ivec4 region[kRegions],
                  const bool use[kRegions]) const;
  // The coarse grid's stencil: the tank's box over this frame's surface
  // heights on screen, grown so that every coarse texel an output water
  // pixel interpolates from is shaded.
  void MarkCoarseWater(const FrameState& f);

  // The floor-return map for the frame's tank (traced on the CPU, once per
  // tank) and its surroundings' light for the board's radiance beyond each
  // wall as this frame's video shows it (re-uploaded when that changes).
  void UpdateFloorReturn(const FrameState& f);
  // The board's light where the floor-return map's board points lie, with
  // the tank standing on it over the dry board's (board_light.h: the sky it
  // hides, the water column's shadow), per point: the video shows the dry
  // board, the water's floor sees the board beside the tank. Traced on the
  // CPU once per tank (the sky) and per light (the direct light).
  void UpdateWetBoard(const FrameState& f, bool new_tank);
  // Changes of the board's radiance below this leave the map as it is.
  static constexpr float kBoardChange = 0.002f;
  // FloorReturnLight::floor_seen for this frame's video (the last frame's
  // stands when there is none).
  void UpdateFloorSeen(const FrameState& f);

  Options options_;
  FloorReturnMap floor_return_;
  Texture floor_return_tex_;  // RGBA: surroundings' light, green return
  FloorReturnLight return_light_;
  std::optional<TankGeometry> floor_return_tank_;
  BoardLightMap wet_board_;
  std::optional<glm::dvec3> wet_board_light_;
  std::vector<glm::vec3> wet_board_factor_[4];  // per board point
  glm::vec3 board_radiance_[4] = {glm::vec3(0.0f), glm::vec3(0.0f),
                                  glm::vec3(0.0f), glm::vec3(0.0f)};
  bool uploaded_ = false;
  // The floor near the walls as the last video showed it, with its return
  // factor 1 / (1 - R rho) (UpdateFloorSeen).
  glm::dvec3 floor_albedo_{0.0};
  bool have_floor_albedo_ = false;
  // Mutable: the kObstacles variants are built when first drawn.
  mutable Shading variants_[kVariants];
  mutable bool obstacles_failed_ = false;
  Shading flat_;  // Effects::flat_water: one colour, whatever the effects
  Program depth_;
  CommonUniforms depth_common_;
  VertexArray grid_vao_, empty_vao_;
  Buffer grid_vbo_, grid_ibo_;
  int grid_index_count_ = 0;

  // The coarse grid: colour (RGBA8: the shaded colour times coverage a,
  // texels not shaded are 0) and stencil; the upsampling and the stencil's
  // polygon (a triangle fan, coarse NDC).
  int out_width_ = 0, out_height_ = 0;
  CoarseGrid grid_;
  Texture coarse_color_;
  Renderbuffer coarse_stencil_;
  Framebuffer coarse_fbo_;
  Program upsample_, hull_;
  VertexArray hull_vao_;
  Buffer hull_vbo_;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_WATER_H_
