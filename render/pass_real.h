// Real objects pass (internal to render/): what the video shows in front of
// or inside the virtual tank. Uploads the occluder mask (SceneInputs::
// occluders) and lays it into depth at the near plane, so that no later
// pass draws over a hand; uploads the clean plate of the board
// (SceneInputs::plate) that the water's refraction reads where the video
// shows a real object instead of the board; and gives the water the real
// pen's geometry (its submerged shaft in the refracted view).
//
// Redraw keys: the mask's window is uploaded every frame it is given (with
// the last window, to clear it); the plate when its change counter moves.
#ifndef RIPPLE_RENDER_PASS_REAL_H_
#define RIPPLE_RENDER_PASS_REAL_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/frame_state.h"
#include "render/gl_objects.h"

namespace ripple::render::internal {

// The real pen and the plate as the water shader takes them (tank frame).
struct RealObjectsState {
  bool pen = false;         // a pen to test refracted rays and lookups against
  glm::vec3 pen_tip{0.0f};  // shaft axis from the tip ...
  glm::vec3 pen_axis{0.0f, 0.0f, 1.0f};  // ... towards the cube, unit
  float pen_length = 0;                  // tip to the cube's face, metres
  float pen_radius = 0;                  // shaft radius, metres
  float pen_margin = 0;                  // SceneInputs::pen_margin_m
  bool mask = false;                     // an occluder mask this frame
  glm::ivec4 mask_window{0};             // where it is non-zero (pixels)
  bool plate = false;                    // a plate is uploaded
  glm::vec4 plate_map{0.0f};             // uv = xy * map.xy + map.zw
  float plate_gain = 1.0f;               // linear-light gain of the plate
};

class RealObjectsPass {
 public:
  // `srgb`: the video (and so the plate) is sRGB-encoded.
  bool Create(bool srgb, std::string* error);
  bool AllocateOutput(int width, int height);

  // Uploads what changed; fills `state` for the water pass.
  void Upload(const SceneInputs& scene, RealObjectsState* state);
  // Lays the mask's pixels into depth at the near plane (the bound output,
  // depth cleared), and binds the mask and plate to their units.
  void Draw(const FrameState& f, const RealObjectsState& state);

 private:
  Program depth_;
  VertexArray empty_vao_;
  Texture mask_tex_, plate_tex_;
  int width_ = 0, height_ = 0;
  glm::ivec4 last_window_{0};
  std::optional<std::uint64_t> plate_counter_;
  int plate_w_ = 0, plate_h_ = 0;
  bool srgb_ = true;
  std::vector<std::uint8_t> zeros_;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_REAL_H_
