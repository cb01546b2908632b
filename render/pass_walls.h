// Walls pass (internal to render/): the glass walls blended over everything
// (dual-source: colour added, transmittance multiplied), far walls first,
// then the walls facing the camera; then the walls' top faces, opaque.
//
// Redraw key: none for the draw; the wall mesh is rebuilt only when the tank
// geometry changes (TankWallsMesh).
#ifndef RIPPLE_RENDER_PASS_WALLS_H_
#define RIPPLE_RENDER_PASS_WALLS_H_

#include <glm/glm.hpp>
#include <string>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/meshes.h"
#include "render/optics.h"

namespace ripple::render::internal {

class WallsPass {
 public:
  struct Options {
    WaterOptics optics;
    // The glass reflects the environment cube map (pass_envmap.h) rather
    // than the uniform sky; the daylight sky over it.
    bool env_cube = false;
    bool sky = false;
  };
  bool Create(const Options& options, std::string* error);
  // Draws into `target` (bound on entry and on return), depth-tested
  // against what is there; with an sRGB-encoded output through
  // `srgb_target` instead, the same texels seen as sRGB
  // (FrameTarget::srgb_fbo), so that the glass blends in linear light.
  // `floor_return`: the water pass's floor-return tint and means (its map
  // is bound on kUnitFloorReturn). `board_mirror`: the reflection map (on
  // kUnitReflection) holds this frame's video, so the glass facing the
  // camera mirrors the board in front of it from there; otherwise it
  // reflects the sky or the environment alone.
  void Draw(const FrameState& f, const TankWallsMesh& walls,
            const FloorReturnLight& floor_return, bool board_mirror,
            GLuint target, GLuint srgb_target);

 private:
  // Far walls, then the front walls' variants: + 1 with shadows, + 2 with
  // caustics (the floor seen through the glass reads their maps), + 4
  // under the surface's lowest point; last the front walls over the water
  // (the far walls' program with the board's mirror image: a far wall
  // mirrors rays into the tank, never onto the board around it).
  static constexpr int kPrograms = 10;
  static constexpr int kFrontAbove = 9;
  Program programs_[kPrograms];
  CommonUniforms common_[kPrograms];
  // The walls' top faces (wall_tops.frag), after the walls: opaque but
  // for their edges' pixels, which they cover by share.
  Program tops_;
  CommonUniforms tops_common_;
  GLint tops_under_glass_[4] = {-1, -1, -1, -1}, tops_floor_seen_ = -1,
        tops_grow_ = -1;
  GLint floor_sky_[kPrograms] = {}, floor_sun_[kPrograms] = {},
        inv_n2_[kPrograms] = {}, z_range_[kPrograms] = {},
        return_tint_[kPrograms] = {}, floor_around_[kPrograms] = {},
        board_mirror_[kPrograms] = {}, floor_seen_[kPrograms] = {};
  // The walls' parts are cut this far outside the surface's height range,
  // which the range's 8-bit code and the mesh's filtering stay well inside.
  static constexpr float kSurfaceSlack_m = 0.001f;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_WALLS_H_
