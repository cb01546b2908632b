#include "render/pass_real.h"

#include <algorithm>
#include <cmath>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool RealObjectsPass::Create(bool srgb, std::string* error) {
  srgb_ = srgb;
  if (!BuildProgram(&depth_, "occluder_depth", "near.vert",
                    "occluder_depth.frag", "", error)) {
    return false;
  }
  glUseProgram(depth_.id());
  glUniform1i(depth_.Uniform("u_mask"), kUnitOccluders);
  empty_vao_.Create();
  // A 1x1 unknown plate until one arrives (alpha 0: the video stays).
  const std::uint8_t none[4] = {0, 0, 0, 0};
  glActiveTexture(GL_TEXTURE0 + kUnitPlate);
  AllocTexture(&plate_tex_, GL_RGBA8, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE,
               GL_LINEAR, GL_CLAMP_TO_EDGE, none);
  plate_w_ = plate_h_ = 1;
  return true;
}

bool RealObjectsPass::AllocateOutput(int width, int height) {
  width_ = width;
  height_ = height;
  zeros_.assign(static_cast<size_t>(width) * height, 0);
  glActiveTexture(GL_TEXTURE0 + kUnitOccluders);
  AllocTexture(&mask_tex_, GL_R8, width, height, GL_RED, GL_UNSIGNED_BYTE,
               GL_NEAREST, GL_CLAMP_TO_EDGE, zeros_.data());
  last_window_ = glm::ivec4(0);
  return true;
}

namespace {

glm::ivec4 Clip(const glm::ivec4& r, int width, int height) {
  const int x0 = std::clamp(r.x, 0, width), y0 = std::clamp(r.y, 0, height);
  const int x1 = std::clamp(r.x + r.z, 0, width);
  const int y1 = std::clamp(r.y + r.w, 0, height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

}  // namespace

void RealObjectsPass::Upload(const SceneInputs& scene,
                             RealObjectsState* state) {
  *state = RealObjectsState();
  // The pen: its shaft from the tip to the cube's face, the cube's
  // bounding sphere.
  const bool real = scene.effects.real_objects;
  if (real && scene.pen_visible && scene.effects.pen_occludes) {
    const PenGeometry& g = scene.pen;
    const glm::dmat4& m = scene.tank_from_pen;
    const glm::dvec3 face =
        glm::dvec3(m * glm::dvec4(0, 0, -0.5 * g.cube_edge, 1));
    const glm::dvec3 tip = glm::dvec3(
        m * glm::dvec4(0, 0, -0.5 * g.cube_edge - g.shaft_length, 1));
    state->pen = true;
    state->pen_tip = glm::vec3(tip);
    state->pen_axis = glm::vec3(glm::normalize(face - tip));
    state->pen_length = g.shaft_length;
    state->pen_radius = g.shaft_radius;
    state->pen_margin = scene.pen_margin_m;
  }
  // The mask: this frame's window, and the last one to clear it.
  const OccluderMaskView& o = scene.occluders;
  const bool have_mask =
      o.mask != nullptr && o.width == width_ && o.height == height_;
  const glm::ivec4 window =
      have_mask ? Clip(o.window, width_, height_) : glm::ivec4(0);
  glActiveTexture(GL_TEXTURE0 + kUnitOccluders);
  glBindTexture(GL_TEXTURE_2D, mask_tex_.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (last_window_.z > 0 && last_window_.w > 0) {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTexSubImage2D(GL_TEXTURE_2D, 0, last_window_.x, last_window_.y,
                    last_window_.z, last_window_.w, GL_RED, GL_UNSIGNED_BYTE,
                    zeros_.data());
  }
  if (window.z > 0 && window.w > 0) {
    const int stride = o.stride_bytes > 0 ? o.stride_bytes : o.width;
    glPixelStorei(GL_UNPACK_ROW_LENGTH, stride);
    glTexSubImage2D(GL_TEXTURE_2D, 0, window.x, window.y, window.z, window.w,
                    GL_RED, GL_UNSIGNED_BYTE,
                    o.mask + static_cast<size_t>(window.y) * stride + window.x);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    state->mask = true;
    state->mask_window = window;
  }
  last_window_ = window;
  // The plate, when it changed.
  const BoardPlateView& p = scene.plate;
  if (real && p.bgra != nullptr && p.width > 0 && p.height > 0 &&
      p.texel_m > 0) {
    glActiveTexture(GL_TEXTURE0 + kUnitPlate);
    if (p.width != plate_w_ || p.height != plate_h_) {
      AllocTexture(&plate_tex_, GL_RGBA8, p.width, p.height, GL_BGRA,
                   GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
      plate_w_ = p.width;
      plate_h_ = p.height;
      plate_counter_.reset();
    }
    if (plate_counter_ != p.change_counter) {
      glBindTexture(GL_TEXTURE_2D, plate_tex_.id());
      const int stride = p.stride_bytes > 0 ? p.stride_bytes : 4 * p.width;
      glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      glPixelStorei(GL_UNPACK_ROW_LENGTH, stride / 4);
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, p.width, p.height, GL_BGRA,
                      GL_UNSIGNED_BYTE, p.bgra);
      glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
      plate_counter_ = p.change_counter;
    }
    state->plate = true;
    const double sx = 1.0 / (p.texel_m * p.width);
    const double sy = 1.0 / (p.texel_m * p.height);
    state->plate_map =
        glm::vec4(sx, sy, -p.corner_m.x * sx, -p.corner_m.y * sy);
    // The gain is a ratio of encoded values; its linear-light equivalent
    // for sRGB follows the transfer's power segment.
    state->plate_gain = srgb_ ? std::pow(std::max(p.gain, 0.0f), 2.4f) : p.gain;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void RealObjectsPass::Draw(const FrameState& /*f*/,
                           const RealObjectsState& state) {
  glActiveTexture(GL_TEXTURE0 + kUnitOccluders);
  glBindTexture(GL_TEXTURE_2D, mask_tex_.id());
  glActiveTexture(GL_TEXTURE0 + kUnitPlate);
  glBindTexture(GL_TEXTURE_2D, plate_tex_.id());
  if (!state.mask) return;
  GlStateGuard guard;
  guard.ColorMask(false);
  guard.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  guard.Enable(GL_SCISSOR_TEST);
  glScissor(last_window_.x, last_window_.y, last_window_.z, last_window_.w);
  glUseProgram(depth_.id());
  glBindVertexArray(empty_vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthFunc(GL_LESS);
}

}  // namespace ripple::render::internal
