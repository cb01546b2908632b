#include "render/pass_present.h"

#include "render/frame_state.h"
#include "render/gl_loader.h"
#include "render/gl_state.h"
#include "render/renderer.h"
#include "render/shaders.h"

namespace ripple::render {

glm::ivec4 LetterboxRect(int image_width, int image_height, int window_width,
                         int window_height) {
  if (image_width <= 0 || image_height <= 0 || window_width <= 0 ||
      window_height <= 0) {
    return {0, 0, 0, 0};
  }
  // Fit the width or the height, whichever binds, in integer arithmetic.
  int w = window_width, h = window_height;
  if (static_cast<long long>(window_width) * image_height >
      static_cast<long long>(window_height) * image_width) {
    w = static_cast<int>((static_cast<long long>(window_height) * image_width +
                          image_height / 2) /
                         image_height);
  } else {
    h = static_cast<int>((static_cast<long long>(window_width) * image_height +
                          image_width / 2) /
                         image_width);
  }
  return {(window_width - w) / 2, (window_height - h) / 2, w, h};
}

namespace internal {

bool PresentPass::Create(std::string* error) {
  if (!BuildProgram(&overlay_, "overlay", "overlay.vert", "overlay.frag", "",
                    error)) {
    return false;
  }
  glUseProgram(overlay_.id());
  glUniform1i(overlay_.Uniform("u_overlay"), kUnitOverlay);
  empty_vao_.Create();
  return true;
}

void PresentPass::SetOverlay(const std::uint8_t* bgra, int width, int height,
                             int stride_bytes) {
  if (bgra == nullptr || width <= 0 || height <= 0) {
    overlay_w_ = overlay_h_ = 0;
    return;
  }
  if (stride_bytes <= 0) stride_bytes = width * 4;
  if (width != overlay_w_ || height != overlay_h_ || overlay_tex_.id() == 0) {
    AllocTexture(&overlay_tex_, GL_RGBA8, width, height, GL_BGRA,
                 GL_UNSIGNED_BYTE, GL_NEAREST, GL_CLAMP_TO_EDGE);
    overlay_w_ = width;
    overlay_h_ = height;
  }
  glBindTexture(GL_TEXTURE_2D, overlay_tex_.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (stride_bytes % 4 == 0) {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, stride_bytes / 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_BGRA,
                    GL_UNSIGNED_BYTE, bgra);
  } else {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    for (int y = 0; y < height; ++y) {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y, width, 1, GL_BGRA,
                      GL_UNSIGNED_BYTE,
                      bgra + static_cast<size_t>(y) * stride_bytes);
    }
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  CheckGlError("Renderer::SetOverlay");
}

void PresentPass::Present(Context* context, GLuint source, int image_width,
                          int image_height) {
  const int fb = context->DefaultFramebuffer();
  if (fb < 0) return;
  int fw = 0, fh = 0;
  context->GetFramebufferSize(&fw, &fh);
  if (fw > 0 && fh > 0) {  // 0 x 0 while minimised
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fb));
    glViewport(0, 0, fw, fh);
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    const glm::ivec4 r = LetterboxRect(image_width, image_height, fw, fh);
    // GL rows count from the bottom; the FBO holds the image top row first,
    // so the blit flips it.
    const int y_bottom = fh - r.y - r.w;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(fb));
    glBlitFramebuffer(0, 0, image_width, image_height, r.x, y_bottom + r.w,
                      r.x + r.z, y_bottom, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    if (overlay_w_ > 0 && overlay_h_ > 0) {
      GlStateGuard state;
      glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fb));
      // 1:1 framebuffer pixels at the top-left corner.
      glViewport(0, fh - overlay_h_, overlay_w_, overlay_h_);
      state.Enable(GL_BLEND);
      glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE,
                          GL_ONE_MINUS_SRC_ALPHA);
      glUseProgram(overlay_.id());
      glActiveTexture(GL_TEXTURE0 + kUnitOverlay);
      glBindTexture(GL_TEXTURE_2D, overlay_tex_.id());
      glBindVertexArray(empty_vao_.id());
      glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
      glBindVertexArray(0);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    CheckGlError("Renderer::Present");
  }
  context->SwapBuffers();
}

}  // namespace internal
}  // namespace ripple::render
