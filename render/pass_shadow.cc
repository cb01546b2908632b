#include "render/pass_shadow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {
namespace {

constexpr int kReceiverSize = 128;  // receiver map texels per side

double RotationAngle(const glm::dmat4& a, const glm::dmat4& b) {
  const glm::dmat3 r = glm::transpose(glm::dmat3(a)) * glm::dmat3(b);
  const double c =
      std::clamp((r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

bool PoseMoved(const glm::dmat4& a, const glm::dmat4& b, double move_m,
               double turn_rad) {
  return glm::length(glm::dvec3(a[3]) - glm::dvec3(b[3])) > move_m ||
         RotationAngle(a, b) > turn_rad;
}

}  // namespace

std::string ShadowFilterDefines(ShadowFilter filter, float sigma_texels) {
  switch (filter) {
    case ShadowFilter::kPcf:
      return "";
    case ShadowFilter::kHard:
      return "#define SHADOW_FILTER_HARD 1\n";
    case ShadowFilter::kGauss: {
      // The weight of a tap one spacing off the centre, relative to the
      // centre's; the diagonal taps get its square (separable Gaussian).
      const double h = GaussTapSpacingTexels(sigma_texels);
      const double w = std::exp(-h * h / (2.0 * sigma_texels * sigma_texels));
      char line[96];
      std::snprintf(line, sizeof(line),
                    "#define SHADOW_FILTER_GAUSS 1\n#define SHADOW_GAUSS_W1 "
                    "%.6f\n",
                    w);
      return line;
    }
  }
  return "";
}

double GaussTapSpacingTexels(float sigma_texels) {
  return std::clamp(static_cast<double>(sigma_texels), 1.0, 2.0);
}

ShadowKey ShadowKey::Of(const SceneInputs& scene) {
  ShadowKey key;
  key.pen_visible = scene.pen_visible;
  key.tank_from_pen = scene.tank_from_pen;
  key.pen = scene.pen;
  key.obstacles = scene.obstacles;
  key.light = glm::normalize(scene.light_in_tank);
  key.tank = scene.tank;
  return key;
}

bool ShadowKey::Differs(const SceneInputs& s, double move, double turn,
                        bool with_pen) const {
  if (!SameTank(tank, s.tank)) return true;
  if (glm::length(light - glm::normalize(s.light_in_tank)) > 1e-9) return true;
  if (with_pen && pen_visible != s.pen_visible) return true;
  if (with_pen && s.pen_visible &&
      (PoseMoved(tank_from_pen, s.tank_from_pen, move, turn) ||
       pen.cube_edge != s.pen.cube_edge ||
       pen.shaft_radius != s.pen.shaft_radius ||
       pen.shaft_length != s.pen.shaft_length)) {
    return true;
  }
  if (obstacles.size() != s.obstacles.size()) return true;
  for (size_t i = 0; i < s.obstacles.size(); ++i) {
    const Obstacle &a = obstacles[i], &b = s.obstacles[i];
    if (a.shape != b.shape || a.size != b.size ||
        PoseMoved(a.tank_from_obstacle, b.tank_from_obstacle, move, turn)) {
      return true;
    }
  }
  return false;
}

ShadowTransform FitShadowFrustum(const TankGeometry& t, const glm::dvec3& l) {
  // Orthographic light frame: w towards the light, u and v across it.
  const glm::dvec3 helper =
      std::abs(l.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, l));
  const glm::dvec3 v = glm::cross(l, u);
  // Fit the receivers (the tank box) across the light; casters may lie up
  // to a metre towards the light.
  const double pad = 0.005;
  glm::dvec3 lo(1e9), hi(-1e9);
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 p((i & 1 ? 0.5 : -0.5) * t.size_x,
                       (i & 2 ? 0.5 : -0.5) * t.size_y,
                       (i & 4 ? t.wall_height : 0.0));
    const glm::dvec3 q(glm::dot(p, u), glm::dot(p, v), glm::dot(p, l));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  lo -= glm::dvec3(pad, pad, 0.01);
  const double c_max = hi.z + 1.0;
  // shadow_from_tank: p -> ((u.p - lo.x) / du, (v.p - lo.y) / dv,
  // (c_max - l.p) / dc), all in [0, 1].
  const glm::dvec3 extent(hi.x + pad - lo.x, hi.y + pad - lo.y, c_max - lo.z);
  glm::dmat4 m(0.0);
  for (int c = 0; c < 3; ++c) {
    m[c][0] = u[c] / extent.x;
    m[c][1] = v[c] / extent.y;
    m[c][2] = -l[c] / extent.z;
  }
  m[3][0] = -lo.x / extent.x;
  m[3][1] = -lo.y / extent.y;
  m[3][2] = c_max / extent.z;
  m[3][3] = 1.0;
  ShadowTransform s;
  s.shadow_from_tank = m;
  s.bias = static_cast<float>(0.0015 / extent.z);
  const double soft = 0.0012;  // metres: PCF tap offset, the penumbra scale
  s.texel = glm::vec2(soft / extent.x, soft / extent.y);
  return s;
}

bool ShadowPass::Create(const Options& options, std::string* error) {
  options_ = options;
  if (!BuildProgram(&depth_, "depth", "solid.vert", "depth.frag", "", error) ||
      !BuildProgram(
          &receiver_, "shadow_receiver", "fullscreen.vert",
          "shadow_receiver.frag",
          ShadowFilterDefines(options.filter, options.gauss_sigma_texels),
          error)) {
    return false;
  }
  depth_model_.Resolve(depth_);
  receiver_common_.Resolve(receiver_);
  empty_vao_.Create();

  // Shadow map: 24-bit depth with hardware comparison (bilinear PCF; the
  // nearest texel for the hard filter).
  const int s = options.map_size;
  AllocTexture(&shadow_tex_, GL_DEPTH_COMPONENT24, s, s, GL_DEPTH_COMPONENT,
               GL_UNSIGNED_INT,
               options.filter == ShadowFilter::kHard ? GL_NEAREST : GL_LINEAR,
               GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE,
                  GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  shadow_fbo_.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                         shadow_tex_.id(), 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    *error = "shadow framebuffer incomplete";
    return false;
  }
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  // RGBA8 although two channels are used: llvmpipe filters four-channel
  // 8-bit textures in inlined code and sends RG8 and R8 through a slower
  // generic sampling function.
  const std::vector<std::uint8_t> lit(kReceiverSize * kReceiverSize * 4, 255);
  AllocTexture(&receiver_tex_, GL_RGBA8, kReceiverSize, kReceiverSize, GL_RGBA,
               GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE, lit.data());
  if (!AttachColor(&receiver_fbo_, receiver_tex_)) {
    *error = "shadow receiver framebuffer incomplete";
    return false;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return true;
}

bool ShadowPass::NeedsRedraw(const SceneInputs& scene) const {
  return !key_ || key_->Differs(scene, options_.move_threshold_m,
                                options_.turn_threshold_rad, options_.pen);
}

void ShadowPass::Draw(const FrameState& f, const SolidMeshes& solids) {
  const SceneInputs& scene = *f.scene;
  transform_ = FitShadowFrustum(scene.tank, f.light);
  if (options_.filter == ShadowFilter::kGauss) {
    // The Gaussian's taps are spaced in map texels, not metres.
    transform_.texel = glm::vec2(
        static_cast<float>(GaussTapSpacingTexels(options_.gauss_sigma_texels) /
                           options_.map_size));
  }
  const glm::dmat4 clip_from_shadow =
      glm::translate(glm::dmat4(1.0), glm::dvec3(-1.0)) *
      glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
  {
    GlStateGuard state;
    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_.id());
    glViewport(0, 0, options_.map_size, options_.map_size);
    state.Enable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClear(GL_DEPTH_BUFFER_BIT);
    state.Enable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.0f);
    glUseProgram(depth_.id());
    solids.Draw(scene, depth_model_,
                clip_from_shadow * transform_.shadow_from_tank, true,
                options_.pen);
  }

  // What the water sees of it: floor and surface shadow over the tank.
  FrameState g = f;
  g.shadow = transform_;
  glBindFramebuffer(GL_FRAMEBUFFER, receiver_fbo_.id());
  glViewport(0, 0, kReceiverSize, kReceiverSize);
  receiver_common_.Set(receiver_, g, glm::dmat4(1.0));
  glActiveTexture(GL_TEXTURE0 + kUnitShadow);
  glBindTexture(GL_TEXTURE_2D, shadow_tex_.id());
  glBindVertexArray(empty_vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  key_ = ShadowKey::Of(scene);
}

}  // namespace ripple::render::internal
