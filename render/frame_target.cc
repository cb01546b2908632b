#include "render/frame_target.h"

#include "render/gl_loader.h"

namespace ripple::render::internal {

void FrameTarget::Create() { pbo_.Create(); }

bool FrameTarget::Allocate(int w, int h, std::string* error) {
  width_ = w;
  height_ = h;
  color_rb_.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, color_rb_.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  depth_rb_.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
  fbo_.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                            GL_RENDERBUFFER, color_rb_.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT,
                            GL_RENDERBUFFER, depth_rb_.id());
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    *error = "main framebuffer incomplete";
    return false;
  }
  glClearColor(0.f, 0.f, 0.f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pbo_.id());
  glBufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(w) * h * 4,
               nullptr, GL_STREAM_READ);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  return true;
}

void FrameTarget::BeginFrame(bool keep_color) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, width_, height_);
  glClearDepth(1.0);
  glClearStencil(0);
  if (keep_color) {
    glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  } else {
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  }
}

bool FrameTarget::ReadBgr(const Context& context, std::uint8_t* bgr,
                          int stride_bytes) {
  const int w = width_, h = height_;
  if (stride_bytes <= 0) stride_bytes = w * 3;
  auto convert = [&](const std::uint8_t* src, int src_stride, bool rgba) {
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* s = src + static_cast<size_t>(y) * src_stride;
      std::uint8_t* d = bgr + static_cast<size_t>(y) * stride_bytes;
      for (int x = 0; x < w; ++x, s += 4, d += 3) {
        d[0] = rgba ? s[2] : s[0];
        d[1] = s[1];
        d[2] = rgba ? s[0] : s[2];
      }
    }
  };
  const std::uint8_t* cpu = context.CpuFramebuffer();
  if (cpu != nullptr && context.width() == w && context.height() == h) {
    // OSMesa: its buffer is the default framebuffer, bottom row (GL row 0)
    // first, and our FBO holds the image top row at GL row 0.
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glFinish();
    convert(cpu, w * 4, true);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return CheckGlError("Renderer::ReadBgr (OSMesa)");
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.id());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, w, h, GL_BGRA, GL_UNSIGNED_BYTE, nullptr);
  const auto* data = static_cast<const std::uint8_t*>(
      glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0,
                       static_cast<GLsizeiptr>(w) * h * 4, GL_MAP_READ_BIT));
  const bool ok = data != nullptr;
  if (ok) convert(data, w * 4, false);
  glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return CheckGlError("Renderer::ReadBgr") && ok;
}

}  // namespace ripple::render::internal
