// Mirror pass (internal to render/): the planar reflection of what stands
// over the water, after Nelson & Kolsch's reflections of virtual objects on
// live water (AR-VAST): the virtual obstacles (lit as the obstacles pass lights
// them) and the real pen (its phantom, coloured from the video where the
// camera sees the pen) mirrored in the rest plane of the water, into a
// quarter-size (each way) premultiplied RGBA texture that the water reads in
// place of the environment where it holds something. Alpha falls off with
// height above the water (exp(-h / fade)); the water distorts the lookup by the
// surface normal. Parts under the water are not mirrored.
//
// Redraw key: none while it holds something (drawn every frame there are
// obstacles or a pen); cleared once when they go.
#ifndef RIPPLE_RENDER_PASS_MIRROR_H_
#define RIPPLE_RENDER_PASS_MIRROR_H_

#include <string>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/meshes.h"

namespace ripple::render::internal {

class MirrorPass {
 public:
  struct Options {
    glm::vec3 obstacle_albedo{0.8f};  // linear RGB
    float fade_m = 0.1f;              // alpha e-folding height, metres
  };
  bool Create(const Options& options, std::string* error);
  bool AllocateOutput(int width, int height);

  // Draws the mirrored obstacles and pen, the pen coloured from
  // `scene_copy` (the last frame's video: the pass runs before the main
  // pass, which a target switch in its middle would flush), then restores
  // `target` and the viewport, and binds the result on kUnitMirror.
  void Draw(const FrameState& f, GLuint target, GLuint scene_copy,
            const SolidMeshes& solids);

 private:
  Options options_;
  Program program_;
  CommonUniforms common_;
  ModelUniforms model_;
  GLint u_is_pen_ = -1;
  Texture color_;
  Renderbuffer depth_;
  Framebuffer fbo_;
  // The mirror's size: a quarter of the output's each way (the reflection
  // is a few per cent of the colour, blurred by the waves).
  int width_ = 0, height_ = 0;
  int out_width_ = 0, out_height_ = 0;
  bool dirty_ = true;  // holds something (or was never cleared)
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_MIRROR_H_
