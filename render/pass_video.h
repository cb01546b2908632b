// Video background pass (internal to render/): uploads each camera frame
// and draws it, undistorted, as the background of the output; keeps the
// quarter-size reflection map taken from it.
//
// Redraw key: none for the draw (the output is redrawn every frame); the
// upload runs whenever a frame is given (a null frame keeps the last one).
#ifndef RIPPLE_RENDER_PASS_VIDEO_H_
#define RIPPLE_RENDER_PASS_VIDEO_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

class VideoBackgroundPass {
 public:
  // The video, the background and the reflection map keep the video's
  // encoding; shaders decode what they fetch (DecodeVideo, common.glsl).
  bool Create(std::string* error);
  // (Re)allocates what has the output's size (the reflection map).
  bool AllocateOutput(int width, int height);

  // Converts and uploads `frame` (no-op for a null frame): all of it, or
  // only `window` (x, y, w, h, pixels, top row first) when that is all the
  // output needs (DirectWindow). With a frame of the output's size (a
  // multiple of 4, no distortion) the reflection map is made from the whole
  // frame on the CPU, sparing the main pass a downsampling blit.
  void Upload(const VideoFrame& frame, const Intrinsics& k,
              const glm::ivec4& window);

  // Whether the output can be the video outside a window: the frame has the
  // output's size and no lens to undo, and the reflection map comes from
  // the CPU (a blit would read the whole output).
  bool DirectWindow(const VideoFrame& frame, const Intrinsics& k) const;

  // Draws the video into `target` (k.width x k.height), undistorted with
  // k's lens model, and the reflection map from it when `reflection` (unless
  // Upload already made it); a direct copy only inside `window`. Nothing is
  // drawn before any video arrived.
  void Draw(const Intrinsics& k, GLuint target, bool reflection,
            const glm::ivec4& window);

  bool have_video() const { return have_video_; }
  // A 32 x 24 RGB thumbnail of the last frame (each texel the mean of a
  // 4 x 4 grid of samples over its cell), for change detection; empty
  // before the first frame.
  const std::vector<std::uint8_t>& thumbnail() const { return thumbnail_; }
  static constexpr int kThumbW = 32, kThumbH = 24;
  GLuint reflection_texture() const { return reflection_tex_.id(); }
  // The camera's frame as uploaded (distorted; RGBA8, the video's encoding).
  GLuint video_texture() const { return video_tex_.id(); }

 private:
  Program undistort_;
  GLint u_intr_ = -1, u_image_size_ = -1, u_dist0_ = -1, u_dist1_ = -1;
  VertexArray empty_vao_;
  // Raw upload (RGBA8, converted on the CPU) and its framebuffer for blits.
  Texture video_tex_;
  Framebuffer video_fbo_;
  int video_w_ = 0, video_h_ = 0;
  bool have_video_ = false;
  Texture reflection_tex_;
  Framebuffer reflection_fbo_;
  bool reflection_from_cpu_ = false;
  std::vector<std::uint32_t> video_rgba_;       // upload buffer
  std::vector<std::uint32_t> reflection_rgba_;  // upload buffer
  std::vector<std::uint8_t> thumbnail_;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_VIDEO_H_
