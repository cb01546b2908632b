// The renderer's output (internal to render/): an FBO of colour (RGBA8) and
// depth-stencil renderbuffers at the intrinsics' size, holding the image top
// row first (GL row 0 = image row 0), and its read-back to BGR8.
#ifndef RIPPLE_RENDER_FRAME_TARGET_H_
#define RIPPLE_RENDER_FRAME_TARGET_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <string>

#include "render/context.h"
#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

class FrameTarget {
 public:
  void Create();
  // (Re)allocates at `width` x `height` pixels and clears to black.
  bool Allocate(int width, int height, std::string* error);
  // Binds the FBO with its viewport and clears depth and stencil, and the
  // colour (to black) too unless `keep_color`, inside `window` (x, y, w, h,
  // pixels, top row first): the frame's pixels outside it are not drawn.
  void BeginFrame(bool keep_color, const glm::ivec4& window);
  // Copies the image as BGR8, top row first, rows of `stride_bytes` (0 =
  // width * 3): the window as drawn, and `background` (a frame of the
  // output's size) outside it, or black without one. Uses OSMesa's own
  // buffer when `context` has one of the output's size, a pixel-pack buffer
  // otherwise. Blocks until done.
  bool ReadBgr(const Context& context, const VideoFrame& background,
               std::uint8_t* bgr, int stride_bytes);

  const glm::ivec4& window() const { return window_; }

  GLuint fbo() const { return fbo_.id(); }
  // The same colour and depth, the colour seen as sRGB (a view of the same
  // texels): with GL_FRAMEBUFFER_SRGB on, blending into it decodes what is
  // stored, blends in linear light and encodes the result. Every other pass
  // draws into fbo(), whose RGBA8 view llvmpipe writes, blits and reads on
  // its fast paths (an sRGB target for all of them cost the main pass 12%
  // more instructions).
  GLuint srgb_fbo() const { return srgb_fbo_.id(); }

 private:
  int width_ = 0, height_ = 0;
  glm::ivec4 window_{0};
  Framebuffer fbo_, srgb_fbo_;
  Texture color_, color_srgb_;  // RGBA8 storage, its sRGB view
  Renderbuffer depth_rb_;
  Buffer pbo_;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_FRAME_TARGET_H_
