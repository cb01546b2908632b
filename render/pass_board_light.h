// Board-light pass (internal to render/): the tank's shadow and the sky it
// hides, on the real board around it. Multiplies the video's board outside
// the tank's footprint by the board's light with the tank over its light
// without it (board_light.h), after the video and the occluders' depth
// (real things in front keep their pixels) and before the scene copy that
// the water refracts, so the board seen through the walls carries it too.
//
// Redraw key: the map's sky view when the tank or the glass and water
// optics change, its direct light when the light changes as well, its
// texture when either did, or the ambient share and tints, or the board's
// or the tank floor's radiance moved by more than 3%; drawn every frame it
// is on.
#ifndef RIPPLE_RENDER_PASS_BOARD_LIGHT_H_
#define RIPPLE_RENDER_PASS_BOARD_LIGHT_H_

#include <string>
#include <vector>

#include "render/board_light.h"
#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/pass_real.h"

namespace ripple::render::internal {

class BoardLightPass {
 public:
  bool Create(const BoardLightOptions& options, std::string* error);
  // Brings the map up to date with the scene's tank and light and the
  // frame's optics (a CPU trace when they changed), for the tank floor
  // seen from the air as `floor_seen` (FloorReturnLight, this frame's).
  void Update(const FrameState& f, const glm::vec3& floor_seen);
  // Multiplies the bound output's board around the tank by the map (made
  // for a board of radiance f.ground.board); depth-tested against what is
  // there.
  void Draw(const FrameState& f, const RealObjectsState& real);
  // The board it changes by more than two grey levels (tank frame x0, y0,
  // x1, y1, metres).
  const glm::dvec4& rect() const { return rect_; }

 private:
  BoardLightOptions options_;
  // Without and with the occluder mask's test.
  Program program_[2];
  CommonUniforms common_[2];
  GLint u_map_[2] = {-1, -1};
  Texture texture_;
  Buffer vertices_;
  VertexArray vao_;
  BoardLightMap map_;
  // What the map was made for.
  TankGeometry tank_;
  float ior_ = 0, glass_ior_ = 0, glass_thickness_ = 0;
  glm::vec3 absorption_{-1.0f};
  glm::dvec3 light_{0.0};
  float ambient_ = -1;
  glm::vec3 sky_tint_{-1.0f}, sun_tint_{-1.0f};
  float floor_radiance_ = -1, under_glass_light_ = -1;
  glm::vec3 ground_{-1.0f};
  bool have_map_ = false;
  glm::dvec4 rect_{0.0};
  // Per texel, made when the light or the optics change (the board's and
  // the floor's radiance enter when the texture is made).
  std::vector<BoardTexel> parts_;
  std::vector<float> encode_;  // the sRGB curve, 4096 steps
  glm::ivec2 texture_size_{0};
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_BOARD_LIGHT_H_
