#include "render/pass_video.h"

#include <algorithm>

#include "render/frame_state.h"
#include "render/pixel_convert.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool VideoBackgroundPass::Create(std::string* error) {
  if (!BuildProgram(&undistort_, "undistort", "fullscreen.vert",
                    "undistort.frag", "", error)) {
    return false;
  }
  u_intr_ = undistort_.Uniform("u_intr");
  u_image_size_ = undistort_.Uniform("u_image_size");
  u_dist0_ = undistort_.Uniform("u_dist0");
  u_dist1_ = undistort_.Uniform("u_dist1");
  glUseProgram(undistort_.id());
  glUniform1i(undistort_.Uniform("u_video"), kUnitVideo);
  empty_vao_.Create();
  return true;
}

bool VideoBackgroundPass::AllocateOutput(int width, int height) {
  const int rw = std::max(1, width / 4), rh = std::max(1, height / 4);
  AllocTexture(&reflection_tex_, GL_RGBA8, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE,
               GL_LINEAR, GL_MIRRORED_REPEAT);
  const bool ok = AttachColor(&reflection_fbo_, reflection_tex_);
  reflection_from_cpu_ = false;  // until the next video upload
  return ok;
}

bool VideoBackgroundPass::DirectWindow(const VideoFrame& f,
                                       const Intrinsics& k) const {
  return f.bgr != nullptr && f.width == k.width && f.height == k.height &&
         f.width % 4 == 0 && f.height % 4 == 0 && !k.HasDistortion();
}

void VideoBackgroundPass::Upload(const VideoFrame& f, const Intrinsics& k,
                                 const glm::ivec4& window) {
  if (f.bgr == nullptr || f.width <= 0 || f.height <= 0) return;
  if (f.width != video_w_ || f.height != video_h_) {
    AllocTexture(&video_tex_, GL_RGBA8, f.width, f.height, GL_RGBA,
                 GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
    AttachColor(&video_fbo_, video_tex_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    video_w_ = f.width;
    video_h_ = f.height;
  }
  const int stride = f.stride_bytes > 0 ? f.stride_bytes : f.width * 3;
  // Only the window's pixels reach the output (the draw copies no more).
  glm::ivec4 r(0, 0, f.width, f.height);
  if (DirectWindow(f, k)) {
    r.x = std::clamp(window.x, 0, f.width);
    r.y = std::clamp(window.y, 0, f.height);
    r.z = std::clamp(window.z, 0, f.width - r.x);
    r.w = std::clamp(window.w, 0, f.height - r.y);
  }
  video_rgba_.resize(static_cast<size_t>(r.z) * r.w);
  for (int y = 0; y < r.w; ++y) {
    BgrToRgbaRow(f.bgr + static_cast<size_t>(r.y + y) * stride + 3 * r.x, r.z,
                 video_rgba_.data() + static_cast<size_t>(y) * r.z);
  }
  if (r.z > 0 && r.w > 0) {
    glBindTexture(GL_TEXTURE_2D, video_tex_.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTexSubImage2D(GL_TEXTURE_2D, 0, r.x, r.y, r.z, r.w, GL_RGBA,
                    GL_UNSIGNED_BYTE, video_rgba_.data());
  }
  have_video_ = true;
  thumbnail_.resize(3 * kThumbW * kThumbH);
  for (int j = 0; j < kThumbH; ++j) {
    for (int i = 0; i < kThumbW; ++i) {
      int sum[3] = {0, 0, 0};
      for (int b = 0; b < 4; ++b) {
        const int y = ((4 * j + b) * 2 + 1) * f.height / (8 * kThumbH);
        // From the whole frame (the upload above may be a window of it).
        const std::uint8_t* row = f.bgr + static_cast<size_t>(y) * stride;
        for (int a = 0; a < 4; ++a) {
          const std::uint8_t* px =
              row + 3 * (((4 * i + a) * 2 + 1) * f.width / (8 * kThumbW));
          // RGB out of BGR.
          for (int c = 0; c < 3; ++c) sum[c] += px[2 - c];
        }
      }
      for (int c = 0; c < 3; ++c)
        thumbnail_[3 * (j * kThumbW + i) + c] =
            static_cast<std::uint8_t>((sum[c] + 8) / 16);
    }
  }
  // With lens distortion the map is made from the distorted frame: a few
  // pixels of shift in a blurred quarter-size map that only feeds the
  // reflection's fake environment.
  reflection_from_cpu_ = f.width == k.width && f.height == k.height &&
                         f.width % 4 == 0 && f.height % 4 == 0;
  if (reflection_from_cpu_) {
    const int rw = f.width / 4, rh = f.height / 4;
    reflection_rgba_.resize(static_cast<size_t>(rw) * rh);
    QuarterRgbaFromBgr(f.bgr, stride, f.width, f.height,
                       reflection_rgba_.data());
    glBindTexture(GL_TEXTURE_2D, reflection_tex_.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE,
                    reflection_rgba_.data());
  }
}

void VideoBackgroundPass::Draw(const Intrinsics& k, GLuint target,
                               bool reflection, const glm::ivec4& window) {
  if (!have_video_) return;
  const int w = k.width, h = k.height;
  if (k.HasDistortion()) {
    // Drawn in the resting state (gl_state.h): no tests, no blending.
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    glViewport(0, 0, w, h);
    glUseProgram(undistort_.id());
    glUniform4f(u_intr_, float(k.fx), float(k.fy), float(k.cx), float(k.cy));
    glUniform2f(u_image_size_, float(w), float(h));
    glUniform4f(u_dist0_, float(k.dist[0]), float(k.dist[1]), float(k.dist[2]),
                float(k.dist[3]));
    glUniform4f(u_dist1_, float(k.dist[4]), float(k.dist[5]), float(k.dist[6]),
                float(k.dist[7]));
    glActiveTexture(GL_TEXTURE0 + kUnitVideo);
    glBindTexture(GL_TEXTURE_2D, video_tex_.id());
    glBindVertexArray(empty_vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  } else {
    // Same size: GL_NEAREST lets Mesa copy the pixels (resource_copy_region)
    // instead of drawing a textured quad (1.5 ms at 640x480 on llvmpipe).
    glBindFramebuffer(GL_READ_FRAMEBUFFER, video_fbo_.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    if (video_w_ == w && video_h_ == h) {
      const int x0 = window.x, y0 = window.y;
      const int x1 = x0 + window.z, y1 = y0 + window.w;
      glBlitFramebuffer(x0, y0, x1, y1, x0, y0, x1, y1, GL_COLOR_BUFFER_BIT,
                        GL_NEAREST);
    } else {
      glBlitFramebuffer(0, 0, video_w_, video_h_, 0, 0, w, h,
                        GL_COLOR_BUFFER_BIT, GL_LINEAR);
    }
  }
  if (reflection && !reflection_from_cpu_) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, reflection_fbo_.id());
    glBlitFramebuffer(0, 0, w, h, 0, 0, std::max(1, w / 4), std::max(1, h / 4),
                      GL_COLOR_BUFFER_BIT, GL_LINEAR);
  }
}

}  // namespace ripple::render::internal
