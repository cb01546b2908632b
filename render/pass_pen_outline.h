// Pen outline pass (internal to render/): the real pen's dry shaft in front
// of the water, along its outline. The video shows the pen there; the water
// pass has drawn the water up to the shaft's phantom, which ObstaclesPass
// laid a pixel and a half inside the tracked outline. Each water pixel
// (stencil 1) near the outline, out to the margin and two pixels, is
// blended here: it holds the pen and the water behind it by the share c of
// the pixel the pen covers. The video shows V = c P + (1 - c) B (P the pen,
// B the dry board behind it), so the pixel becomes V + (1 - c) water, with
// the pen's part V - (1 - c) B: the fixed-function blend ONE,
// ONE_MINUS_SRC_ALPHA on the output's sRGB view (linear light), with c as
// alpha (pen_outline.frag gives c and how it is read from the video).
//
// Drawn only where the water pass shades the real pen
// (WaterPass::ShadesRealPen), over a band along each side of the outline
// (pen_outline.vert: from inside the phantom to the margin and two pixels
// out) and the shaft's whole width where it meets the surface, each pixel
// once: the stencil's water mark is raised as a pixel is blended.
//
// Redraw key: none (drawn every frame with the water).
#ifndef RIPPLE_RENDER_PASS_PEN_OUTLINE_H_
#define RIPPLE_RENDER_PASS_PEN_OUTLINE_H_

#include <string>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/pass_real.h"

namespace ripple::render::internal {

class PenOutlinePass {
 public:
  bool Create(std::string* error);
  // Blends the outline into `target` (its stencil holding the water pass's
  // marks) through `srgb_target`, its sRGB view, with the scene copy bound
  // to kUnitScene; the pen as `real` gives it, its phantom laid
  // `phantom_inset_m` inside its radius, `px_m` a pixel's width at its
  // shaft's end nearest the camera (PenPhantomInset, PenShaftPixelM).
  void Draw(const FrameState& f, const RealObjectsState& real,
            double phantom_inset_m, double px_m, GLuint target,
            GLuint srgb_target) const;

 private:
  Program program_;
  CommonUniforms common_;
  VertexArray vao_;
  Buffer vertices_;
  GLint pen_tip_ = -1, pen_axis_ = -1, pen_length_ = -1, pen_radius_ = -1,
        pen_margin_ = -1, pen_px_ = -1, band_ = -1, along_ = -1;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_PEN_OUTLINE_H_
