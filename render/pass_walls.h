// Walls pass (internal to render/): the glass walls blended over everything
// (dual-source: colour added, transmittance multiplied), far walls first,
// then the walls facing the camera.
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
  };
  bool Create(const Options& options, std::string* error);
  // Draws into the bound output, depth-tested against what is there.
  void Draw(const FrameState& f, const TankWallsMesh& walls);

 private:
  Program programs_[2];  // far walls, front walls
  CommonUniforms common_[2];
  GLint floor_sky_[2] = {-1, -1}, floor_sun_[2] = {-1, -1},
        inv_n2_[2] = {-1, -1}, caustics_on_[2] = {-1, -1};
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_WALLS_H_
