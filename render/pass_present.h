// Present pass (internal to render/): shows the output in a window's
// default framebuffer, letterboxed (LetterboxRect), with the HUD overlay
// alpha-blended at the window's top-left corner, then swaps buffers.
//
// Redraw key: none (every Present() call); the overlay texture changes only
// in SetOverlay().
#ifndef RIPPLE_RENDER_PASS_PRESENT_H_
#define RIPPLE_RENDER_PASS_PRESENT_H_

#include <cstdint>
#include <string>

#include "render/context.h"
#include "render/gl_objects.h"

namespace ripple::render::internal {

class PresentPass {
 public:
  bool Create(std::string* error);
  // BGRA8, straight alpha, top row first; nullptr or an empty size clears.
  void SetOverlay(const std::uint8_t* bgra, int width, int height,
                  int stride_bytes);
  // Shows the `image_width` x `image_height` image of FBO `source` in
  // `context`'s window; no-op on headless backends.
  void Present(Context* context, GLuint source, int image_width,
               int image_height);

 private:
  Program overlay_;
  VertexArray empty_vao_;
  Texture overlay_tex_;
  int overlay_w_ = 0, overlay_h_ = 0;  // pixels; 0: no overlay
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_PRESENT_H_
