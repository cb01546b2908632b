#include "render/pass_board_light.h"

#include <algorithm>
#include <cmath>

#include "render/gl_state.h"
#include "render/meshes.h"
#include "render/shaders.h"

namespace ripple::render::internal {
namespace {

// The change of the board that the pass draws: more than two grey levels
// (a webcam's own noise is 2-3). Drawing every change over one level
// (the sky the walls hide reaches two wall heights out) cost twice as
// much: 5.2 M instructions a frame against 2.7 M.
constexpr float kLevels = 2.0f;

}  // namespace

bool BoardLightPass::Create(const BoardLightOptions& options,
                            std::string* error) {
  options_ = options;
  for (int v = 0; v < 2; ++v) {
    if (!BuildProgram(&program_[v], "board_light", "board_light.vert",
                      "board_light.frag", v ? "#define OCCLUDERS\n" : "",
                      error)) {
      return false;
    }
    common_[v].Resolve(program_[v]);  // leaves it bound
    glUniform1i(program_[v].Uniform("u_board_light"), kUnitBoardLight);
    if (v) glUniform1i(program_[v].Uniform("u_occluders"), kUnitOccluders);
    u_map_[v] = program_[v].Uniform("u_map");
  }
  texture_.Create();
  vertices_.Create();
  vao_.Create();
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.id());
  glBufferData(GL_ARRAY_BUFFER, 24 * sizeof(glm::vec2), nullptr,
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  return true;
}

void BoardLightPass::Update(const FrameState& f, const glm::vec3& floor_seen) {
  const SceneInputs& scene = *f.scene;
  const WaterOptics& o = *f.optics;
  const bool view_valid = have_map_ && SameTank(tank_, scene.tank) &&
                          ior_ == o.ior && glass_ior_ == o.glass_ior &&
                          glass_thickness_ == o.glass_thickness_m &&
                          absorption_ == o.absorption_per_m;
  const bool direct_valid = view_valid && light_ == f.light;
  // The board under the walls as lit through them (the mean of the four).
  float under_glass = 0;
  for (const glm::vec3& u : f.shading.under_glass) under_glass += 0.25f * u.g;
  const bool parts_valid = direct_valid && ambient_ == o.ambient_share &&
                           sky_tint_ == o.sky_tint && sun_tint_ == o.sun_tint &&
                           under_glass_light_ == under_glass;
  // The board's radiance G per band (kept off 0), and the tank's floor as
  // the air sees it over G (green). A change of these by under 3% moves
  // the board by under a grey level's fraction (the diffuse surfaces the
  // tank shows are a quarter of a texel's light at most): the texture is
  // remade beyond that. They follow the video, which hands and the pen
  // move from frame to frame.
  const glm::vec3 ground = glm::max(f.ground.board, glm::vec3(0.02f));
  const float floor_radiance = floor_seen.g / ground.g;
  auto near = [](float a, float b) {
    return std::abs(a - b) <= 0.03f * std::abs(b);
  };
  if (parts_valid && near(floor_radiance, floor_radiance_) &&
      near(ground.r, ground_.r) && near(ground.g, ground_.g) &&
      near(ground.b, ground_.b)) {
    return;
  }
  if (!view_valid) {
    map_ = BoardLightLayout(scene.tank, o, options_);
    ComputeBoardSkyView(scene.tank, o, options_, &map_);
    tank_ = scene.tank;
    ior_ = o.ior;
    glass_ior_ = o.glass_ior;
    glass_thickness_ = o.glass_thickness_m;
    absorption_ = o.absorption_per_m;
    have_map_ = true;
  }
  if (!direct_valid) {
    ComputeBoardDirectLight(scene.tank, o, f.light, options_, &map_);
    light_ = f.light;
  }
  if (!parts_valid) {
    parts_.resize(static_cast<size_t>(map_.nx) * map_.ny);
    for (int j = 0; j < map_.ny; ++j) {
      for (int i = 0; i < map_.nx; ++i) {
        parts_[static_cast<size_t>(j) * map_.nx + i] =
            map_.Texel(i, j, o, under_glass);
      }
    }
    ambient_ = o.ambient_share;
    sky_tint_ = o.sky_tint;
    sun_tint_ = o.sun_tint;
    under_glass_light_ = under_glass;
  }
  floor_radiance_ = floor_radiance;
  ground_ = ground;

  // Per texel and band, what the output's encoded board is multiplied by:
  // a board of radiance G shows G + S(G f) - S(G) with f the map's factor,
  // the change passed through the output's highlight shoulder S like every
  // rendered light (exactly G where f = 1: the video as it came), so the
  // factor is that value's encoding over G's. Exact for pixels of the
  // board's radiance; others take the same factor. RGBA8 over [0.5, 1.5)
  // (a step of 1/255 is under half a grey level on white paper).
  const float knee = o.highlight_knee;
  if (encode_.empty()) {
    // The sRGB curve on 4096 steps (linear between them: within 0.01 of
    // a level).
    encode_.resize(4097);
    for (int k = 0; k <= 4096; ++k) {
      encode_[k] = static_cast<float>(LinearToSrgb(k / 4096.0));
    }
  }
  auto encode = [&](float linear) {
    const float v = std::clamp(linear, 0.0f, 1.0f);
    if (!f.srgb_output) return v;
    const float x = v * 4096.0f;
    const int k = std::min(static_cast<int>(x), 4095);
    return encode_[k] + (x - k) * (encode_[k + 1] - encode_[k]);
  };
  auto shoulder = [&](float x) {
    return static_cast<float>(HighlightShoulder(x, knee));
  };
  glm::vec3 ground_encoded(1.0f), ground_shoulder(0.0f);
  for (int c = 0; c < 3; ++c) {
    ground_encoded[c] = std::max(encode(ground[c]), 1e-6f);
    ground_shoulder[c] = shoulder(ground[c]);
  }
  std::vector<std::uint8_t> texels(static_cast<size_t>(map_.nx) * map_.ny * 4);
  // The board that changes by more than kLevels grey levels.
  glm::dvec4 r(-map_.outer_x, -map_.outer_y, map_.outer_x, map_.outer_y);
  for (int j = 0; j < map_.ny; ++j) {
    for (int i = 0; i < map_.nx; ++i) {
      const size_t k = static_cast<size_t>(j) * map_.nx + i;
      const BoardTexel& t = parts_[k];
      std::uint8_t* p = &texels[k * 4];
      bool changes = false;
      for (int c = 0; c < 3; ++c) {
        const float g = ground[c];
        const float shown = g + shoulder(g * t.Factor(c, g, floor_radiance)) -
                            ground_shoulder[c];
        const float e = encode(shown);
        changes = changes || std::abs(e - ground_encoded[c]) * 255.0f > kLevels;
        p[c] = static_cast<std::uint8_t>(std::lround(
            std::clamp(e / ground_encoded[c] - 0.5f, 0.0f, 1.0f) * 255.0f));
      }
      p[3] = 255;
      if (!changes) continue;
      const double x = map_.origin.x + (i + 0.5) * map_.texel;
      const double y = map_.origin.y + (j + 0.5) * map_.texel;
      r.x = std::min(r.x, x - 1.5 * map_.texel);
      r.y = std::min(r.y, y - 1.5 * map_.texel);
      r.z = std::max(r.z, x + 1.5 * map_.texel);
      r.w = std::max(r.w, y + 1.5 * map_.texel);
    }
  }
  glActiveTexture(GL_TEXTURE0 + kUnitBoardLight);
  if (texture_size_ != glm::ivec2(map_.nx, map_.ny)) {
    AllocTexture(&texture_, GL_RGBA8, map_.nx, map_.ny, GL_RGBA,
                 GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
    texture_size_ = glm::ivec2(map_.nx, map_.ny);
  }
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, map_.nx, map_.ny, GL_RGBA,
                  GL_UNSIGNED_BYTE, texels.data());

  // The frame between the changed board's edge and the footprint: four
  // quads.
  rect_ = glm::dvec4(std::max(r.x, map_.origin.x), std::max(r.y, map_.origin.y),
                     std::min(r.z, map_.origin.x + map_.nx * map_.texel),
                     std::min(r.w, map_.origin.y + map_.ny * map_.texel));
  const float x0 = static_cast<float>(rect_.x);
  const float y0 = static_cast<float>(rect_.y);
  const float x1 = static_cast<float>(rect_.z);
  const float y1 = static_cast<float>(rect_.w);
  const float fx = static_cast<float>(map_.outer_x);
  const float fy = static_cast<float>(map_.outer_y);
  const glm::vec2 quads[4][2] = {{{x0, y0}, {x1, -fy}},
                                 {{x0, fy}, {x1, y1}},
                                 {{x0, -fy}, {-fx, fy}},
                                 {{fx, -fy}, {x1, fy}}};
  std::vector<glm::vec2> v;
  for (const auto& q : quads) {
    const glm::vec2 a = q[0], b = q[1];
    for (const glm::vec2 c :
         {a, glm::vec2(b.x, a.y), b, a, b, glm::vec2(a.x, b.y)}) {
      v.push_back(c);
    }
  }
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.id());
  glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(glm::vec2), v.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void BoardLightPass::Draw(const FrameState& f, const RealObjectsState& real) {
  if (!have_map_) return;
  GlStateGuard state;
  // With an occluder mask, only where it was looked for: an occluder
  // beyond its window is not known.
  const int v = real.mask ? 1 : 0;
  if (real.mask) {
    state.Enable(GL_SCISSOR_TEST);
    const glm::ivec4 w = real.mask_window;
    glScissor(w.x, w.y, w.z, w.w);
  }
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  state.DepthMask(false);
  state.Enable(GL_BLEND);
  glBlendFunc(GL_DST_COLOR, GL_SRC_ALPHA);
  common_[v].Set(program_[v], f, f.clip_from_tank);
  const double w = map_.nx * map_.texel, h = map_.ny * map_.texel;
  glUniform4f(u_map_[v], static_cast<float>(1.0 / w),
              static_cast<float>(1.0 / h),
              static_cast<float>(-map_.origin.x / w),
              static_cast<float>(-map_.origin.y / h));
  glActiveTexture(GL_TEXTURE0 + kUnitBoardLight);
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glBindVertexArray(vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 24);
  glBindVertexArray(0);
}

}  // namespace ripple::render::internal
