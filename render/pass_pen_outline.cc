#include "render/pass_pen_outline.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool PenOutlinePass::Create(std::string* error) {
  if (!BuildProgram(&program_, "pen outline", "pen_outline.vert",
                    "pen_outline.frag", "", error)) {
    return false;
  }
  common_.Resolve(program_);  // leaves it bound
  glUniform1i(program_.Uniform("u_scene"), kUnitScene);
  pen_tip_ = program_.Uniform("u_pen_tip");
  pen_axis_ = program_.Uniform("u_pen_axis");
  pen_length_ = program_.Uniform("u_pen_length");
  along_ = program_.Uniform("u_along");
  pen_radius_ = program_.Uniform("u_pen_radius");
  pen_margin_ = program_.Uniform("u_pen_margin");
  pen_px_ = program_.Uniform("u_pen_px");
  band_ = program_.Uniform("u_band");
  // Two strips (sides -1, +1), each two triangles between the inner (0)
  // and the outer (1) silhouette, from along = 0 to 1; then one quad across
  // the shaft, from side -1 to side +1.
  std::vector<glm::vec3> v;
  for (const float side : {-1.0f, 1.0f}) {
    const glm::vec3 in0(0, side, 0), in1(1, side, 0), out0(0, side, 1),
        out1(1, side, 1);
    for (const glm::vec3& p : {in0, out0, in1, in1, out0, out1}) v.push_back(p);
  }
  const glm::vec3 a0(0, -1, 1), a1(1, -1, 1), b0(0, 1, 1), b1(1, 1, 1);
  for (const glm::vec3& p : {a0, b0, a1, a1, b0, b1}) v.push_back(p);
  vertices_.Create();
  vao_.Create();
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.id());
  glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(glm::vec3), v.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  return true;
}

void PenOutlinePass::Draw(const FrameState& f, const RealObjectsState& real,
                          double phantom_inset_m, double px_m, GLuint target,
                          GLuint srgb_target) const {
  if (!real.pen) return;
  GlStateGuard state;  // no depth test: the stencil says where the water is
  // Water pixels only, each once: a blended pixel's mark goes to 2.
  state.Enable(GL_STENCIL_TEST);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
  state.Enable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  if (f.srgb_output) {
    glBindFramebuffer(GL_FRAMEBUFFER, srgb_target);
    state.Enable(GL_FRAMEBUFFER_SRGB);
  }
  common_.Set(program_, f, f.clip_from_tank);
  SetUniform(pen_tip_, real.pen_tip);
  SetUniform(pen_axis_, real.pen_axis);
  glUniform1f(pen_length_, real.pen_length);
  glUniform1f(pen_radius_, real.pen_radius);
  glUniform1f(pen_margin_, real.pen_margin);
  glUniform1f(pen_px_, static_cast<float>(1.0 / f.k->fx));
  // From half a pixel inside the phantom to the margin and two pixels out.
  const float out =
      static_cast<float>(real.pen_radius + real.pen_margin + 2 * px_m);
  glUniform2f(along_, 0.0f, real.pen_length);
  glUniform2f(band_,
              static_cast<float>(std::max(
                  real.pen_radius - phantom_inset_m - 0.5 * px_m, 0.0)),
              out);
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 12);
  // And the shaft's whole width where it meets the surface (within the
  // waves' reach, 1 cm, and its radius): there a ray that meets the dry
  // shaft can pass the phantom under the surface, so the water is drawn
  // inside the outline too.
  const double level = f.scene->tank.water_level;
  const double slope = std::max(std::abs(real.pen_axis.z), 0.1f);
  const double u_wet =
      (level - real.pen_tip.z) / slope * (real.pen_axis.z < 0 ? -1.0 : 1.0);
  const double reach = (0.01 + out) / slope;
  const double u0 = std::max(u_wet - reach, 0.0);
  const double u1 = std::min(u_wet + reach, double{real.pen_length});
  if (u1 > u0) {
    glUniform2f(along_, static_cast<float>(u0), static_cast<float>(u1));
    glUniform2f(band_, out, out);
    glDrawArrays(GL_TRIANGLES, 12, 6);
  }
  glBindVertexArray(0);
  if (f.srgb_output) glBindFramebuffer(GL_FRAMEBUFFER, target);
}

}  // namespace ripple::render::internal
