#include "render/frame_target.h"

#include <cstring>

#include "render/gl_loader.h"

namespace ripple::render::internal {

void FrameTarget::Create() { pbo_.Create(); }

bool FrameTarget::Allocate(int w, int h, std::string* error) {
  width_ = w;
  height_ = h;
  // Immutable storage, so that it can be viewed as sRGB too.
  color_.Create();
  glBindTexture(GL_TEXTURE_2D, color_.id());
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
  color_srgb_.Create();
  glTextureView(color_srgb_.id(), GL_TEXTURE_2D, color_.id(), GL_SRGB8_ALPHA8,
                0, 1, 0, 1);
  glBindTexture(GL_TEXTURE_2D, 0);
  depth_rb_.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
  for (Framebuffer* fb : {&srgb_fbo_, &fbo_}) {
    fb->Create();
    glBindFramebuffer(GL_FRAMEBUFFER, fb->id());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                           (fb == &fbo_ ? color_ : color_srgb_).id(), 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT,
                              GL_RENDERBUFFER, depth_rb_.id());
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      *error = "main framebuffer incomplete";
      return false;
    }
  }
  glClearColor(0.f, 0.f, 0.f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pbo_.id());
  glBufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(w) * h * 4,
               nullptr, GL_STREAM_READ);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  return true;
}

void FrameTarget::BeginFrame(bool keep_color, const glm::ivec4& window) {
  window_ = window;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, width_, height_);
  if (window.z <= 0 || window.w <= 0) return;
  glClearDepth(1.0);
  glClearStencil(0);
  const bool whole = window == glm::ivec4(0, 0, width_, height_);
  if (!whole) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(window.x, window.y, window.z, window.w);
  }
  if (keep_color) {
    glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  } else {
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  }
  if (!whole) glDisable(GL_SCISSOR_TEST);
}

bool FrameTarget::ReadBgr(const Context& context, const VideoFrame& background,
                          std::uint8_t* bgr, int stride_bytes) {
  const int w = width_, h = height_;
  if (stride_bytes <= 0) stride_bytes = w * 3;
  const glm::ivec4 r = window_;
  // Outside the window: the background as it came.
  const bool have_background = background.bgr != nullptr &&
                               background.width == w && background.height == h;
  const int bg_stride =
      background.stride_bytes > 0 ? background.stride_bytes : w * 3;
  auto outside = [&](int y, int x0, int x1) {
    if (x1 <= x0) return;
    std::uint8_t* d = bgr + static_cast<size_t>(y) * stride_bytes + 3 * x0;
    if (have_background) {
      std::memcpy(d,
                  background.bgr + static_cast<size_t>(y) * bg_stride + 3 * x0,
                  3 * static_cast<size_t>(x1 - x0));
    } else {
      std::memset(d, 0, 3 * static_cast<size_t>(x1 - x0));
    }
  };
  const bool empty = r.z <= 0 || r.w <= 0;
  for (int y = 0; y < h; ++y) {
    if (empty || y < r.y || y >= r.y + r.w) {
      outside(y, 0, w);
    } else {
      outside(y, 0, r.x);
      outside(y, r.x + r.z, w);
    }
  }
  if (empty) return true;
  // `src` holds the window's rows (or the whole image's, `full`).
  auto convert = [&](const std::uint8_t* src, int src_stride, bool rgba,
                     bool full) {
    for (int y = r.y; y < r.y + r.w; ++y) {
      const std::uint8_t* s =
          src + static_cast<size_t>(full ? y : y - r.y) * src_stride +
          (full ? 4 * r.x : 0);
      std::uint8_t* d = bgr + static_cast<size_t>(y) * stride_bytes + 3 * r.x;
      for (int x = 0; x < r.z; ++x, s += 4, d += 3) {
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
    const int x1 = r.x + r.z, y1 = r.y + r.w;
    glBlitFramebuffer(r.x, r.y, x1, y1, r.x, r.y, x1, y1, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glFinish();
    convert(cpu, w * 4, true, true);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return CheckGlError("Renderer::ReadBgr (OSMesa)");
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_.id());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glReadPixels(r.x, r.y, r.z, r.w, GL_BGRA, GL_UNSIGNED_BYTE, nullptr);
  const auto* data = static_cast<const std::uint8_t*>(glMapBufferRange(
      GL_PIXEL_PACK_BUFFER, 0, static_cast<GLsizeiptr>(r.z) * r.w * 4,
      GL_MAP_READ_BIT));
  const bool ok = data != nullptr;
  if (ok) convert(data, r.z * 4, false, false);
  glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return CheckGlError("Renderer::ReadBgr") && ok;
}

}  // namespace ripple::render::internal
