// Scoped GL state for the passes (internal to render/).
//
// Every pass starts from, and returns to, one resting state: GL's defaults
// for the capabilities and write masks a pass may change (depth, stencil,
// scissor tests, blending and polygon offset off; colour, depth and stencil
// writes on). A pass changes them only through a GlStateGuard, whose
// destructor puts back exactly what it changed, so no pass depends on what an
// earlier one left behind. Functions and values that only matter while a
// capability is on (glDepthFunc, glBlendFunc, glStencilFunc, ...) are set by
// each pass before it enables the capability and are not restored.
#ifndef RIPPLE_RENDER_GL_STATE_H_
#define RIPPLE_RENDER_GL_STATE_H_

#include "render/gl.h"

namespace ripple::render::internal {

class GlStateGuard {
 public:
  GlStateGuard() = default;
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

  // `cap`: GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_BLEND,
  // GL_POLYGON_OFFSET_FILL or GL_FRAMEBUFFER_SRGB (all off at rest).
  void Enable(GLenum cap);
  // Switches off a capability this guard switched on.
  void Disable(GLenum cap);
  void ColorMask(bool write);     // all four channels; on at rest
  void DepthMask(bool write);     // on at rest
  void StencilMask(GLuint mask);  // all bits at rest

 private:
  static int Bit(GLenum cap);
  int enabled_ = 0;  // Bit()s of capabilities this guard switched on
  bool color_mask_ = false, depth_mask_ = false, stencil_mask_ = false;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_GL_STATE_H_
