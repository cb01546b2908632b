#include "render/pass_mirror.h"

#include <algorithm>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool MirrorPass::Create(const Options& options, std::string* error) {
  options_ = options;
  if (!BuildProgram(&program_, "mirror", "solid.vert", "mirror.frag", "",
                    error)) {
    return false;
  }
  common_.Resolve(program_);  // leaves it bound
  model_.Resolve(program_);
  SetUniform(program_.Uniform("u_albedo"), options.obstacle_albedo);
  glUniform1f(program_.Uniform("u_fade_m"), options.fade_m);
  u_is_pen_ = program_.Uniform("u_is_pen");
  return true;
}

bool MirrorPass::AllocateOutput(int width, int height) {
  out_width_ = width;
  out_height_ = height;
  width_ = std::max(1, width / 4);
  height_ = std::max(1, height / 4);
  glActiveTexture(GL_TEXTURE0 + kUnitMirror);
  AllocTexture(&color_, GL_RGBA8, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE,
               GL_LINEAR, GL_CLAMP_TO_EDGE);
  depth_.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, depth_.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width_, height_);
  if (!AttachColor(&fbo_, color_)) return false;
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT,
                            GL_RENDERBUFFER, depth_.id());
  const bool ok =
      glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  dirty_ = true;
  return ok;
}

void MirrorPass::Draw(const FrameState& f, GLuint target, GLuint scene_copy,
                      const SolidMeshes& solids) {
  const SceneInputs& scene = *f.scene;
  const bool obstacles = !scene.obstacles.empty();
  const bool pen = scene.pen_visible;
  const bool draw = scene.effects.reflection && (obstacles || pen);
  if (draw || dirty_) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width_, height_);
    glClearColor(0.f, 0.f, 0.f, 0.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    dirty_ = false;
    if (draw) {
      GlStateGuard state;
      state.Enable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      // The mirror image in the rest plane z = L: z -> 2L - z.
      glm::dmat4 mirror(1.0);
      mirror[2][2] = -1.0;
      mirror[3][2] = 2.0 * scene.tank.water_level;
      const glm::dmat4 clip_from_tank = f.clip_from_tank * mirror;
      common_.Set(program_, f, f.clip_from_tank);
      glActiveTexture(GL_TEXTURE0 + kUnitScene);
      glBindTexture(GL_TEXTURE_2D, scene_copy);
      if (obstacles) {
        glUniform1f(u_is_pen_, 0.0f);
        solids.Draw(scene, model_, clip_from_tank, true, false);
      }
      if (pen) {
        glUniform1f(u_is_pen_, 1.0f);
        solids.Draw(scene, model_, clip_from_tank, false, true);
      }
      dirty_ = true;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    glViewport(0, 0, out_width_, out_height_);
  }
  glActiveTexture(GL_TEXTURE0 + kUnitMirror);
  glBindTexture(GL_TEXTURE_2D, color_.id());
}

}  // namespace ripple::render::internal
