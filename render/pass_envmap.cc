#include "render/pass_envmap.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "render/frame_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

SquareToQuad SquareToQuad::FromCorners(const std::array<glm::dvec2, 4>& q) {
  SquareToQuad m;
  const double sx = q[0].x - q[1].x + q[2].x - q[3].x;
  const double sy = q[0].y - q[1].y + q[2].y - q[3].y;
  if (std::abs(sx) < 1e-12 && std::abs(sy) < 1e-12) {
    // A parallelogram: affine.
    m.a = q[1].x - q[0].x;
    m.b = q[2].x - q[1].x;
    m.c = q[0].x;
    m.d = q[1].y - q[0].y;
    m.e = q[2].y - q[1].y;
    m.f = q[0].y;
    m.g = m.h = 0;
    return m;
  }
  const double dx1 = q[1].x - q[2].x, dx2 = q[3].x - q[2].x;
  const double dy1 = q[1].y - q[2].y, dy2 = q[3].y - q[2].y;
  const double den = dx1 * dy2 - dx2 * dy1;
  m.g = (sx * dy2 - dx2 * sy) / den;
  m.h = (dx1 * sy - sx * dy1) / den;
  m.a = q[1].x - q[0].x + m.g * q[1].x;
  m.b = q[3].x - q[0].x + m.h * q[3].x;
  m.c = q[0].x;
  m.d = q[1].y - q[0].y + m.g * q[1].y;
  m.e = q[3].y - q[0].y + m.h * q[3].y;
  m.f = q[0].y;
  return m;
}

glm::dvec2 SquareToQuad::Map(double u, double v) const {
  const double w = Weight(u, v);
  return {(a * u + b * v + c) / w, (d * u + e * v + f) / w};
}

std::array<glm::dvec2, 4> EnvMapFaceQuad(int face, const glm::dvec4& box) {
  const double x0 = box.x, y0 = box.y, x1 = box.z, y1 = box.w;
  switch (face) {
    case kPosX:  // right: box's right edge -> image's right border
      return {{{x1, y1}, {1, 1}, {1, 0}, {x1, y0}}};
    case kNegX:  // left
      return {{{0, 1}, {x0, y1}, {x0, y0}, {0, 0}}};
    case kPosY:  // down (OpenCV +y): box's bottom edge -> image's bottom
      return {{{0, 1}, {1, 1}, {x1, y1}, {x0, y1}}};
    case kNegY:  // up: box's top edge -> image's top
      return {{{x0, y0}, {x1, y0}, {1, 0}, {0, 0}}};
    case kPosZ:  // behind the tank: the box
      return {{{x0, y1}, {x1, y1}, {x1, y0}, {x0, y0}}};
    default:  // kNegZ, behind the camera: the frame, mirrored
      return {{{1, 1}, {0, 1}, {0, 0}, {1, 0}}};
  }
}

glm::dvec4 EnvMapBox(const Intrinsics& k, const glm::dmat4& cam_from_tank,
                     const TankGeometry& tank, double scale, double margin) {
  glm::dvec2 lo(1e9), hi(-1e9);
  bool behind = false;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec4 p((i & 1 ? 0.5 : -0.5) * tank.size_x,
                       (i & 2 ? 0.5 : -0.5) * tank.size_y,
                       i & 4 ? double(tank.wall_height) : 0.0, 1.0);
    const glm::dvec3 c(cam_from_tank * p);
    if (c.z <= 1e-6) {
      behind = true;
      break;
    }
    // Pixel-edge coordinates (OpenCV centres + 0.5), normalised.
    const glm::dvec2 n((k.fx * c.x / c.z + k.cx + 0.5) / k.width,
                       (k.fy * c.y / c.z + k.cy + 0.5) / k.height);
    lo = glm::min(lo, n);
    hi = glm::max(hi, n);
  }
  if (behind) {
    lo = glm::dvec2(0.0);
    hi = glm::dvec2(1.0);
  }
  const glm::dvec2 centre = 0.5 * (lo + hi);
  const glm::dvec2 half = 0.5 * scale * (hi - lo);
  glm::dvec2 a = glm::clamp(centre - half, margin, 1.0 - 3.0 * margin);
  glm::dvec2 b = glm::clamp(centre + half, 3.0 * margin, 1.0 - margin);
  b = glm::max(b, a + 2.0 * margin);
  return {a.x, a.y, b.x, b.y};
}

int CubeFaceOf(const glm::dvec3& r, glm::dvec2* st) {
  const glm::dvec3 a = glm::abs(r);
  int face;
  double sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    face = r.x > 0 ? kPosX : kNegX;
    sc = r.x > 0 ? -r.z : r.z;
    tc = -r.y;
    ma = a.x;
  } else if (a.y >= a.z) {
    face = r.y > 0 ? kPosY : kNegY;
    sc = r.x;
    tc = r.y > 0 ? r.z : -r.z;
    ma = a.y;
  } else {
    face = r.z > 0 ? kPosZ : kNegZ;
    sc = r.z > 0 ? r.x : -r.x;
    tc = -r.y;
    ma = a.z;
  }
  if (st) *st = {0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)};
  return face;
}

namespace {

// A cube texture's parameters: linear, clamped, no mipmaps.
void CubeParameters() {
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAX_LEVEL, 0);
}

// The direction of texel (s, t) of `face` (inverting CubeFaceOf).
glm::dvec3 CubeDirection(int face, double s, double t) {
  const double sc = 2 * s - 1, tc = 2 * t - 1;
  switch (face) {
    case kPosX:
      return {1, -tc, -sc};
    case kNegX:
      return {-1, -tc, sc};
    case kPosY:
      return {sc, 1, tc};
    case kNegY:
      return {sc, -1, -tc};
    case kPosZ:
      return {sc, -tc, 1};
    default:
      return {-sc, -tc, -1};
  }
}

}  // namespace

void EnvMapPass::SetSky(
    const std::function<glm::vec3(const glm::dvec3&)>& radiance) {
  const int n = kSkyFaceSize;
  sky_.Create();
  glActiveTexture(GL_TEXTURE0 + kUnitSky);
  glBindTexture(GL_TEXTURE_CUBE_MAP, sky_.id());
  std::vector<glm::vec4> texels(static_cast<size_t>(n) * n);
  for (int f = 0; f < kNumFaces; ++f) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const glm::dvec3 d =
            glm::normalize(CubeDirection(f, (i + 0.5) / n, (j + 0.5) / n));
        texels[static_cast<size_t>(j) * n + i] = glm::vec4(radiance(d), 1.0f);
      }
    }
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, n, n, 0,
                 GL_RGBA, GL_FLOAT, texels.data());
  }
  CubeParameters();
}

bool EnvMapPass::Create(const Options& options, std::string* error) {
  options_ = options;
  if (!BuildProgram(&program_, "envmap", "envmap.vert", "envmap.frag", "",
                    error)) {
    return false;
  }
  glUseProgram(program_.id());
  glUniform1i(program_.Uniform("u_source"), kUnitReflection);
  glUniform1f(program_.Uniform("u_srgb_out"), options.srgb_source ? 1.f : 0.f);
  const int n = options.face_size;
  cube_.Create();
  glActiveTexture(GL_TEXTURE0 + kUnitEnvCube);
  glBindTexture(GL_TEXTURE_CUBE_MAP, cube_.id());
  for (int f = 0; f < kNumFaces; ++f) {
    glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, n, n, 0,
                 GL_RGBA, GL_FLOAT, nullptr);
  }
  CubeParameters();
  // Filtering across the faces' edges (the faces join without seams).
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  fbo_.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                         GL_TEXTURE_CUBE_MAP_POSITIVE_X, cube_.id(), 0);
  const bool ok =
      glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!ok) {
    *error = "environment cube map framebuffer incomplete";
    return false;
  }
  // Per vertex: the face's corner in NDC and the homogeneous image
  // coordinate (x q, y q, q); 4 vertices per face, filled per rebuild.
  vao_.Create();
  vbo_.Create();
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.id());
  glBufferData(GL_ARRAY_BUFFER, sizeof(float) * 5 * 4 * kNumFaces, nullptr,
               GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float),
                        reinterpret_cast<void*>(2 * sizeof(float)));
  glBindVertexArray(0);
  return true;
}

namespace {

double TurnRad(const glm::dmat3& a, const glm::dmat3& b) {
  const glm::dmat3 r = glm::transpose(a) * b;
  const double c = 0.5 * (r[0][0] + r[1][1] + r[2][2] - 1.0);
  return std::acos(std::clamp(c, -1.0, 1.0));
}

glm::dvec4 BoxPixels(const glm::dvec4& box, const Intrinsics& k) {
  return {box.x * k.width, box.y * k.height, box.z * k.width, box.w * k.height};
}

}  // namespace

bool EnvMapPass::NeedsRebuild(
    const Intrinsics& k, const glm::dmat4& cam_from_tank,
    const TankGeometry& tank,
    const std::vector<std::uint8_t>& thumbnail) const {
  if (!built_ || thumbnail.size() != thumbnail_.size()) return true;
  if (TurnRad(cube_from_tank_, glm::dmat3(cam_from_tank)) >
      options_.rebuild_turn_rad)
    return true;
  const glm::dvec4 box =
      BoxPixels(EnvMapBox(k, cam_from_tank, tank, options_.box_scale,
                          options_.box_margin),
                k);
  const glm::dvec4 moved = glm::abs(box - box_px_);
  if (std::max({moved.x, moved.y, moved.z, moved.w}) > options_.rebuild_box_px)
    return true;
  long sum = 0;
  for (size_t i = 0; i < thumbnail.size(); ++i)
    sum += std::abs(int(thumbnail[i]) - int(thumbnail_[i]));
  return double(sum) / std::max<size_t>(thumbnail.size(), 1) >
         options_.rebuild_mean_levels;
}

void EnvMapPass::Rebuild(GLuint source, const Intrinsics& k,
                         const glm::dmat4& cam_from_tank,
                         const TankGeometry& tank,
                         const std::vector<std::uint8_t>& thumbnail,
                         GLuint target) {
  const glm::dvec4 box = EnvMapBox(k, cam_from_tank, tank, options_.box_scale,
                                   options_.box_margin);
  float vertices[kNumFaces][4][5];
  const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int f = 0; f < kNumFaces; ++f) {
    const SquareToQuad m = SquareToQuad::FromCorners(EnvMapFaceQuad(f, box));
    for (int i = 0; i < 4; ++i) {
      const double u = corners[i][0], v = corners[i][1];
      const double w = m.Weight(u, v);
      const glm::dvec2 q = m.Map(u, v);
      float* out = vertices[f][i];
      out[0] = float(2 * u - 1);
      out[1] = float(2 * v - 1);
      out[2] = float(q.x * w);
      out[3] = float(q.y * w);
      out[4] = float(w);
    }
  }
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.id());
  glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof(vertices), vertices);
  // Drawn in the resting state (gl_state.h): no tests, no blending.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, options_.face_size, options_.face_size);
  glUseProgram(program_.id());
  glActiveTexture(GL_TEXTURE0 + kUnitReflection);
  glBindTexture(GL_TEXTURE_2D, source);
  glBindVertexArray(vao_.id());
  for (int f = 0; f < kNumFaces; ++f) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                           GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, cube_.id(), 0);
    glDrawArrays(GL_TRIANGLE_FAN, 4 * f, 4);
  }
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, k.width, k.height);
  built_ = true;
  cube_from_tank_ = glm::dmat3(cam_from_tank);
  box_px_ = BoxPixels(box, k);
  thumbnail_ = thumbnail;
  ++rebuilds_;
}

}  // namespace ripple::render::internal
