#include "render/gl_state.h"

#include <string>

#include "geometry/check.h"

namespace ripple::render::internal {
namespace {

constexpr GLenum kCaps[] = {GL_DEPTH_TEST,          GL_STENCIL_TEST,
                            GL_SCISSOR_TEST,        GL_BLEND,
                            GL_POLYGON_OFFSET_FILL, GL_FRAMEBUFFER_SRGB};

}  // namespace

int GlStateGuard::Bit(GLenum cap) {
  for (int i = 0; i < static_cast<int>(sizeof(kCaps) / sizeof(kCaps[0])); ++i) {
    if (kCaps[i] == cap) return 1 << i;
  }
  RIPPLE_CHECK(false,
               "GlStateGuard: unsupported capability " + std::to_string(cap));
  return 0;
}

GlStateGuard::~GlStateGuard() {
  for (int i = 0; i < static_cast<int>(sizeof(kCaps) / sizeof(kCaps[0])); ++i) {
    if (enabled_ & (1 << i)) glDisable(kCaps[i]);
  }
  if (color_mask_) glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (depth_mask_) glDepthMask(GL_TRUE);
  if (stencil_mask_) glStencilMask(~0u);
}

void GlStateGuard::Enable(GLenum cap) {
  glEnable(cap);
  enabled_ |= Bit(cap);
}

void GlStateGuard::Disable(GLenum cap) {
  glDisable(cap);
  enabled_ &= ~Bit(cap);
}

void GlStateGuard::ColorMask(bool write) {
  const GLboolean w = write ? GL_TRUE : GL_FALSE;
  glColorMask(w, w, w, w);
  color_mask_ = true;
}

void GlStateGuard::DepthMask(bool write) {
  glDepthMask(write ? GL_TRUE : GL_FALSE);
  depth_mask_ = true;
}

void GlStateGuard::StencilMask(GLuint mask) {
  glStencilMask(mask);
  stencil_mask_ = true;
}

}  // namespace ripple::render::internal
