#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <optional>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "render/caustics.h"
#include "render/gl.h"
#include "render/gl_objects.h"
#include "render/shaders.h"

namespace ripple::render {

using internal::Buffer;
using internal::Framebuffer;
using internal::Program;
using internal::Query;
using internal::Renderbuffer;
using internal::Texture;
using internal::VertexArray;

namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Texture units, fixed for every program.
enum Unit : int {
  kUnitHeight = 0,
  kUnitShadow = 1,
  kUnitCaustics = 2,
  kUnitScene = 3,
  kUnitReflection = 4,
  kUnitVideo = 5,
  kUnitReceiver = 7,
  kUnitOverlay = 8,
};

constexpr int kReceiverSize = 128;  // shadow receiver map texels per side

// Water shader variants: llvmpipe executes both sides of every branch, so
// each combination of effects is its own program.
enum WaterVariant : int {
  kWaterShadows = 1,
  kWaterCaustics = 2,
  kWaterReflection = 4,
  kWaterRefraction = 8,
  kWaterFlat = 16,
};

struct SolidVertex {
  glm::vec3 pos, normal;
};
struct WallVertex {
  glm::vec3 pos, normal;
  glm::vec2 wall;
};

void AddQuad(std::vector<SolidVertex>* v, glm::vec3 a, glm::vec3 b, glm::vec3 c,
             glm::vec3 d, glm::vec3 n) {
  for (const glm::vec3& p : {a, b, c, a, c, d}) v->push_back({p, n});
}

// Axis-aligned unit cube [-0.5, 0.5]^3.
std::vector<SolidVertex> UnitBox() {
  std::vector<SolidVertex> v;
  for (int axis = 0; axis < 3; ++axis) {
    for (float s : {-0.5f, 0.5f}) {
      glm::vec3 n(0), u(0), w(0);
      n[axis] = s > 0 ? 1.f : -1.f;
      u[(axis + 1) % 3] = 0.5f;
      w[(axis + 2) % 3] = 0.5f;
      const glm::vec3 c = n * 0.5f;
      AddQuad(&v, c - u - w, c + u - w, c + u + w, c - u + w, n);
    }
  }
  return v;
}

// Cylinder of radius 1 from z = 0 to z = 1, with caps.
std::vector<SolidVertex> UnitCylinder(int segments) {
  std::vector<SolidVertex> v;
  const float step = 2.0f * 3.14159265f / segments;
  for (int i = 0; i < segments; ++i) {
    const float a0 = i * step, a1 = (i + 1) * step;
    const glm::vec3 p0(std::cos(a0), std::sin(a0), 0),
        p1(std::cos(a1), std::sin(a1), 0);
    const glm::vec3 up(0, 0, 1);
    const glm::vec3 n = glm::normalize(p0 + p1);
    AddQuad(&v, p0, p1, p1 + up, p0 + up, n);
    v.push_back({glm::vec3(0, 0, 1), up});
    v.push_back({p0 + up, up});
    v.push_back({p1 + up, up});
    v.push_back({glm::vec3(0), -up});
    v.push_back({p1, -up});
    v.push_back({p0, -up});
  }
  return v;
}

struct Mesh {
  VertexArray vao;
  Buffer vbo;
  int count = 0;
};

void UploadSolid(Mesh* mesh, const std::vector<SolidVertex>& v) {
  mesh->vao.Create();
  mesh->vbo.Create();
  glBindVertexArray(mesh->vao.id());
  glBindBuffer(GL_ARRAY_BUFFER, mesh->vbo.id());
  glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(SolidVertex), v.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex),
                        reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex),
                        reinterpret_cast<void*>(sizeof(glm::vec3)));
  mesh->count = static_cast<int>(v.size());
  glBindVertexArray(0);
}

void SetTextureParams(GLenum min_mag, GLenum wrap) {
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min_mag);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, min_mag);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
}

void AllocTexture(Texture* t, GLint internal_format, int w, int h,
                  GLenum format, GLenum type, GLenum filter, GLenum wrap,
                  const void* data = nullptr) {
  t->Create();
  glBindTexture(GL_TEXTURE_2D, t->id());
  SetTextureParams(filter, wrap);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, internal_format, w, h, 0, format, type, data);
}

// BGR8 -> RGBA8 (alpha 255). RGBA is the layout llvmpipe gives a GL_RGBA8
// texture, so the upload is a plain copy.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "BgrToRgbaRow assumes a little-endian machine");
inline std::uint32_t RgbaFromBgr(std::uint32_t bgr) {
  return ((bgr & 0xffu) << 16) | (bgr & 0xff00u) | ((bgr >> 16) & 0xffu) |
         0xff000000u;
}
void BgrToRgbaRowScalar(const std::uint8_t* bgr, int n, std::uint32_t* out) {
  int i = 0;
  // Four pixels from three unaligned 32-bit words.
  for (; i + 4 <= n; i += 4, bgr += 12) {
    std::uint32_t a, b, c;
    std::memcpy(&a, bgr, 4);
    std::memcpy(&b, bgr + 4, 4);
    std::memcpy(&c, bgr + 8, 4);
    out[i] = RgbaFromBgr(a);
    out[i + 1] = RgbaFromBgr((a >> 24) | (b << 8));
    out[i + 2] = RgbaFromBgr((b >> 16) | (c << 16));
    out[i + 3] = RgbaFromBgr(c >> 8);
  }
  for (; i < n; ++i, bgr += 3) {
    out[i] = bgr[2] | (bgr[1] << 8) | (bgr[0] << 16) | 0xff000000u;
  }
}

#if defined(__x86_64__)
// Four pixels per shuffle: 16 loaded bytes hold pixels 0-3 (and part of 4).
__attribute__((target("ssse3"))) void BgrToRgbaRowSsse3(const std::uint8_t* bgr,
                                                        int n,
                                                        std::uint32_t* out) {
  const __m128i shuffle =
      _mm_setr_epi8(2, 1, 0, -1, 5, 4, 3, -1, 8, 7, 6, -1, 11, 10, 9, -1);
  const __m128i alpha = _mm_set1_epi32(static_cast<int>(0xff000000u));
  int i = 0;
  // 16-byte loads: stop while 16 bytes remain readable (16 / 3 > 5 pixels).
  for (; i + 6 <= n; i += 4, bgr += 12) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bgr));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm_or_si128(_mm_shuffle_epi8(v, shuffle), alpha));
  }
  BgrToRgbaRowScalar(bgr, n - i, out + i);
}
#endif

void BgrToRgbaRow(const std::uint8_t* bgr, int n, std::uint32_t* out) {
#if defined(__x86_64__)
  static const bool ssse3 = __builtin_cpu_supports("ssse3");
  if (ssse3) return BgrToRgbaRowSsse3(bgr, n, out);
#endif
  BgrToRgbaRowScalar(bgr, n, out);
}

// Quarter-size RGBA8 image (w / 4 x h / 4; w, h multiples of 4) as
// glBlitFramebuffer with GL_LINEAR makes it: each output pixel's centre
// falls between source pixels 4i+1 and 4i+2 in x and y, i.e. the mean of
// that 2x2 block (rounded; the GPU's 8-bit lerps may differ by 1).
void QuarterRgba(const std::uint32_t* src, int w, int h, std::uint32_t* out) {
  const int rw = w / 4, rh = h / 4;
  for (int j = 0; j < rh; ++j) {
    const auto* r0 = reinterpret_cast<const std::uint8_t*>(
        src + static_cast<size_t>(4 * j + 1) * w);
    const std::uint8_t* r1 = r0 + static_cast<size_t>(w) * 4;
    auto* o =
        reinterpret_cast<std::uint8_t*>(out + static_cast<size_t>(j) * rw);
    for (int i = 0; i < rw; ++i) {
      const int x = 4 * (4 * i + 1);
      for (int c = 0; c < 4; ++c) {
        o[4 * i + c] = static_cast<std::uint8_t>(
            (r0[x + c] + r0[x + 4 + c] + r1[x + c] + r1[x + 4 + c] + 2) >> 2);
      }
    }
  }
}

bool AttachColor(Framebuffer* fbo, const Texture& t) {
  fbo->Create();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo->id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                         t.id(), 0);
  return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

void SetMat4(const Program& p, const char* name, const glm::dmat4& m) {
  const glm::mat4 f(m);
  glUniformMatrix4fv(p.Uniform(name), 1, GL_FALSE, glm::value_ptr(f));
}
void SetVec3(const Program& p, const char* name, const glm::vec3& v) {
  glUniform3f(p.Uniform(name), v.x, v.y, v.z);
}
void SetFloat(const Program& p, const char* name, float f) {
  glUniform1f(p.Uniform(name), f);
}
void SetInt(const Program& p, const char* name, int i) {
  glUniform1i(p.Uniform(name), i);
}

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

// What the shadow map was last drawn from.
struct ShadowKey {
  bool pen_visible = false;
  glm::dmat4 tank_from_pen{1.0};
  PenGeometry pen;
  std::vector<Obstacle> obstacles;
  glm::dvec3 light{0.0};
  TankGeometry tank;
};

bool SameTank(const TankGeometry& a, const TankGeometry& b) {
  return a.size_x == b.size_x && a.size_y == b.size_y &&
         a.wall_height == b.wall_height && a.water_level == b.water_level;
}

}  // namespace

bool RendererOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (surface_grid < 2 || surface_grid > 512)
    return fail("surface_grid must be in [2, 512]");
  if (shadow_map_size < 16 || shadow_map_size > 8192)
    return fail("shadow_map_size must be in [16, 8192]");
  if (caustics_map_size < 8 || caustics_map_size > 4096)
    return fail("caustics_map_size must be in [8, 4096]");
  if (caustics_threads < 1) return fail("caustics_threads must be >= 1");
  if (shadow_move_threshold_m < 0 || shadow_turn_threshold_rad < 0)
    return fail("shadow thresholds must be >= 0");
  return true;
}

struct Renderer::Impl {
  Context* context = nullptr;
  Intrinsics k;
  RendererOptions options;
  PassTimings timings;

  std::map<int, Program> water_programs;  // by WaterVariant bits
  Program solid_programs[2],              // without, with shadows
      depth_program, water_depth_program, walls_programs[2], undistort_program,
      receiver_program, overlay_program;
  VertexArray empty_vao;
  Mesh box, cylinder;
  VertexArray grid_vao;
  Buffer grid_vbo, grid_ibo;
  int grid_index_count = 0;
  VertexArray walls_vao;
  Buffer walls_vbo;
  std::optional<TankGeometry> walls_tank;

  // Output: colour + depth renderbuffers.
  Framebuffer main_fbo;
  Renderbuffer color_rb, depth_rb;
  // Video: raw upload (RGBA8, converted on the CPU: Mesa's BGR8 upload is a
  // slow per-pixel conversion on the calling thread), the undistortion map, the
  // copy of the background (video + obstacles) under the water for
  // refraction, and the small reflection map.
  Texture video_tex, scene_copy_tex, reflection_tex;
  Framebuffer video_fbo, scene_copy_fbo, reflection_fbo;
  int video_w = 0, video_h = 0;
  bool have_video = false;
  // The reflection map was made on the CPU from the last video frame (no
  // distortion, video of the output's size, a multiple of 4): the main pass
  // then needs no downsampling blit, a separate llvmpipe scene.
  bool reflection_from_cpu = false;
  std::vector<std::uint32_t> video_rgba;       // upload buffer
  std::vector<std::uint32_t> reflection_rgba;  // upload buffer
  Buffer pbo;
  // HUD overlay (BGRA8 -> RGBA8 texture), drawn by Present().
  Texture overlay_tex;
  int overlay_w = 0, overlay_h = 0;

  // Height field.
  Texture height_tex;
  int height_nx = 0, height_ny = 0;
  std::optional<std::uint64_t> height_counter;
  glm::vec2 hf_extent{1.0f};
  std::vector<glm::vec4> height_slopes;  // upload buffer: h, dh/dx, dh/dy

  // Shadow map.
  Texture shadow_tex, receiver_tex;
  Framebuffer shadow_fbo, receiver_fbo;
  std::optional<ShadowKey> shadow_key;
  glm::dmat4 shadow_from_tank{1.0};
  float shadow_bias = 0;
  glm::vec2 shadow_texel{0};

  // Caustics.
  Texture caustics_tex;
  std::vector<float> caustics_map;
  CausticsWorkspace caustics_workspace;
  std::optional<std::uint64_t> caustics_counter;
  glm::dvec3 caustics_light{0.0};
  std::optional<TankGeometry> caustics_tank;

  Query queries[2];

  bool Init(std::string* error);
  bool BuildProgram(Program* p, const char* name, const char* vs,
                    const char* fs, const std::string& defines,
                    std::string* error);
  const Program* WaterProgram(int variant);
  bool AllocateOutput(std::string* error);
  void UploadVideo(const VideoFrame& frame);
  void UpdateHeights(const SceneInputs& scene);
  void UpdateWalls(const TankGeometry& tank);
  bool ShadowNeedsRedraw(const SceneInputs& scene) const;
  void DrawShadow(const SceneInputs& scene);
  void UpdateCaustics(const SceneInputs& scene);
  void DrawVideoBackground(bool reflection);
  void DrawMain(const SceneInputs& scene);
  glm::ivec4 TankRect(const SceneInputs& scene,
                      const glm::dmat4& clip_from_tank) const;
  glm::ivec4 WaterRect(const SceneInputs& scene,
                       const glm::dmat4& clip_from_tank) const;
  void DrawSolids(const SceneInputs& scene, const Program& p,
                  const glm::dmat4& clip_from_tank, bool obstacles, bool pen,
                  bool walls);
  void SetCommon(const Program& p, const SceneInputs& scene,
                 const glm::dmat4& clip_from_tank);
  void BeginPass(int query);
  double EndPass(int query, Clock::time_point t0);
};

bool Renderer::Impl::Init(std::string* error) {
  auto build = [&](Program* p, const char* name, const char* vs,
                   const char* fs) {
    return BuildProgram(p, name, vs, fs, "", error);
  };
  if (!build(&solid_programs[0], "solid", "solid.vert", "solid.frag") ||
      !BuildProgram(&solid_programs[1], "shadowed solid", "solid.vert",
                    "solid.frag", "#define SHADOWS 1\n", error) ||
      !build(&depth_program, "depth", "solid.vert", "depth.frag") ||
      !build(&water_depth_program, "water_depth", "water.vert", "depth.frag") ||
      !build(&walls_programs[0], "walls", "walls.vert", "walls.frag") ||
      !BuildProgram(&walls_programs[1], "front walls", "walls.vert",
                    "walls.frag", "#define FRONT_WALL 1\n", error) ||
      !build(&undistort_program, "undistort", "fullscreen.vert",
             "undistort.frag") ||
      !build(&receiver_program, "shadow_receiver", "fullscreen.vert",
             "shadow_receiver.frag") ||
      !build(&overlay_program, "overlay", "overlay.vert", "overlay.frag")) {
    return false;
  }
  // The default variant, so that shader errors surface here.
  if (WaterProgram(kWaterShadows | kWaterCaustics | kWaterReflection |
                   kWaterRefraction) == nullptr) {
    *error = "water shader failed to build";
    return false;
  }
  empty_vao.Create();
  UploadSolid(&box, UnitBox());
  UploadSolid(&cylinder, UnitCylinder(24));

  // Water grid.
  const int g = options.surface_grid;
  std::vector<glm::vec2> grid;
  grid.reserve((g + 1) * (g + 1));
  for (int j = 0; j <= g; ++j) {
    for (int i = 0; i <= g; ++i) grid.emplace_back(float(i) / g, float(j) / g);
  }
  // One triangle strip, row after row of quads joined by degenerate
  // triangles (4 per row, zero area, dropped by the rasteriser's setup): a
  // third of the indices of a triangle list, so llvmpipe's draw module
  // shades each vertex about twice instead of up to six times. Each quad is
  // split along its (i, j)-(i+1, j+1) diagonal, as a list would.
  std::vector<std::uint32_t> indices;
  indices.reserve(g * (2 * g + 4));
  for (int j = 0; j < g; ++j) {
    if (j > 0) {
      indices.push_back(indices.back());
      indices.push_back(j * (g + 1) + g + 1);
    }
    for (int i = 0; i <= g; ++i) {
      const std::uint32_t a = j * (g + 1) + i;
      indices.push_back(a + g + 1);
      indices.push_back(a);
    }
  }
  grid_index_count = static_cast<int>(indices.size());
  grid_vao.Create();
  grid_vbo.Create();
  grid_ibo.Create();
  glBindVertexArray(grid_vao.id());
  glBindBuffer(GL_ARRAY_BUFFER, grid_vbo.id());
  glBufferData(GL_ARRAY_BUFFER, grid.size() * sizeof(glm::vec2), grid.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, grid_ibo.id());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(std::uint32_t),
               indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);

  walls_vao.Create();
  walls_vbo.Create();
  glBindVertexArray(walls_vao.id());
  glBindBuffer(GL_ARRAY_BUFFER, walls_vbo.id());
  glBufferData(GL_ARRAY_BUFFER, 24 * sizeof(WallVertex), nullptr,
               GL_DYNAMIC_DRAW);
  for (int a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(0));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(sizeof(glm::vec3)));
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(2 * sizeof(glm::vec3)));
  glBindVertexArray(0);

  // Flat water until a height field arrives.
  const glm::vec4 zero(0.0f);
  AllocTexture(&height_tex, GL_RGBA16F, 1, 1, GL_RGBA, GL_FLOAT, GL_LINEAR,
               GL_CLAMP_TO_EDGE, &zero);
  height_nx = height_ny = 1;

  // Shadow map: 24-bit depth with hardware comparison (bilinear PCF).
  const int s = options.shadow_map_size;
  AllocTexture(&shadow_tex, GL_DEPTH_COMPONENT24, s, s, GL_DEPTH_COMPONENT,
               GL_UNSIGNED_INT, GL_LINEAR, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE,
                  GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  shadow_fbo.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                         shadow_tex.id(), 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    *error = "shadow framebuffer incomplete";
    return false;
  }
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  const std::vector<std::uint8_t> lit(kReceiverSize * kReceiverSize * 2, 255);
  AllocTexture(&receiver_tex, GL_RG8, kReceiverSize, kReceiverSize, GL_RG,
               GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE, lit.data());
  if (!AttachColor(&receiver_fbo, receiver_tex)) {
    *error = "shadow receiver framebuffer incomplete";
    return false;
  }

  const int c = options.caustics_map_size;
  caustics_map.assign(static_cast<size_t>(c) * c, 1.0f);
  AllocTexture(&caustics_tex, GL_R32F, c, c, GL_RED, GL_FLOAT, GL_LINEAR,
               GL_CLAMP_TO_EDGE, caustics_map.data());

  for (Query& q : queries) q.Create();
  pbo.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!AllocateOutput(error)) return false;
  if (!CheckGlError("Renderer::Init")) {
    *error = "GL error during initialisation";
    return false;
  }
  return true;
}

bool Renderer::Impl::BuildProgram(Program* p, const char* name, const char* vs,
                                  const char* fs, const std::string& defines,
                                  std::string* error) {
  const char* common = internal::ShaderSource("common.glsl");
  const char* v = internal::ShaderSource(vs);
  const char* f = internal::ShaderSource(fs);
  if (!common || !v || !f) {
    *error = std::string("missing embedded shader for ") + name;
    return false;
  }
  const std::string header =
      std::string("#version 330 core\n") + defines + common;
  return p->Build(name, header + v, header + f, error);
}

const Program* Renderer::Impl::WaterProgram(int variant) {
  auto it = water_programs.find(variant);
  if (it != water_programs.end()) return &it->second;
  std::string defines;
  if (variant & kWaterShadows) defines += "#define SHADOWS 1\n";
  if (variant & kWaterCaustics) defines += "#define CAUSTICS 1\n";
  if (variant & kWaterReflection) defines += "#define REFLECTION 1\n";
  if (variant & kWaterRefraction) defines += "#define REFRACTION 1\n";
  if (variant & kWaterFlat) defines += "#define FLAT_WATER 1\n";
  Program p;
  std::string error;
  if (!BuildProgram(&p, "water", "water_deferred.vert", "water.frag", defines,
                    &error)) {
    std::fprintf(stderr, "ripple render: %s\n", error.c_str());
    return nullptr;
  }
  return &water_programs.emplace(variant, std::move(p)).first->second;
}

bool Renderer::Impl::AllocateOutput(std::string* error) {
  const int w = k.width, h = k.height;
  color_rb.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, color_rb.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  depth_rb.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
  main_fbo.Create();
  glBindFramebuffer(GL_FRAMEBUFFER, main_fbo.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                            GL_RENDERBUFFER, color_rb.id());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT,
                            GL_RENDERBUFFER, depth_rb.id());
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    *error = "main framebuffer incomplete";
    return false;
  }
  glClearColor(0.f, 0.f, 0.f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  AllocTexture(&scene_copy_tex, GL_RGBA8, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
               GL_LINEAR, GL_CLAMP_TO_EDGE);
  bool ok = AttachColor(&scene_copy_fbo, scene_copy_tex);
  const int rw = std::max(1, w / 4), rh = std::max(1, h / 4);
  AllocTexture(&reflection_tex, GL_RGBA8, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE,
               GL_LINEAR, GL_MIRRORED_REPEAT);
  ok = ok && AttachColor(&reflection_fbo, reflection_tex);
  reflection_from_cpu = false;  // until the next video upload
  glBindBuffer(GL_PIXEL_PACK_BUFFER, pbo.id());
  glBufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(w) * h * 4,
               nullptr, GL_STREAM_READ);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!ok) *error = "video framebuffers incomplete";
  return ok;
}

void Renderer::Impl::UploadVideo(const VideoFrame& f) {
  if (f.bgr == nullptr || f.width <= 0 || f.height <= 0) return;
  if (f.width != video_w || f.height != video_h) {
    AllocTexture(&video_tex, GL_RGBA8, f.width, f.height, GL_RGBA,
                 GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
    AttachColor(&video_fbo, video_tex);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    video_w = f.width;
    video_h = f.height;
  }
  const int stride = f.stride_bytes > 0 ? f.stride_bytes : f.width * 3;
  video_rgba.resize(static_cast<size_t>(f.width) * f.height);
  for (int y = 0; y < f.height; ++y) {
    BgrToRgbaRow(f.bgr + static_cast<size_t>(y) * stride, f.width,
                 video_rgba.data() + static_cast<size_t>(y) * f.width);
  }
  glBindTexture(GL_TEXTURE_2D, video_tex.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f.width, f.height, GL_RGBA,
                  GL_UNSIGNED_BYTE, video_rgba.data());
  have_video = true;
  // With lens distortion the map is made from the distorted frame: a few
  // pixels of shift in a blurred quarter-size map that only feeds the
  // reflection's fake environment.
  reflection_from_cpu = f.width == k.width && f.height == k.height &&
                        f.width % 4 == 0 && f.height % 4 == 0;
  if (reflection_from_cpu) {
    const int rw = f.width / 4, rh = f.height / 4;
    reflection_rgba.resize(static_cast<size_t>(rw) * rh);
    QuarterRgba(video_rgba.data(), f.width, f.height, reflection_rgba.data());
    glBindTexture(GL_TEXTURE_2D, reflection_tex.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, rw, rh, GL_RGBA, GL_UNSIGNED_BYTE,
                    reflection_rgba.data());
  }
}

void Renderer::Impl::UpdateHeights(const SceneInputs& scene) {
  const HeightFieldView& w = scene.water;
  if (w.heights == nullptr || w.nx <= 0 || w.ny <= 0 || w.cell_size <= 0) {
    if (height_nx != 1 || height_counter.has_value()) {
      const glm::vec4 zero(0.0f);
      AllocTexture(&height_tex, GL_RGBA16F, 1, 1, GL_RGBA, GL_FLOAT, GL_LINEAR,
                   GL_CLAMP_TO_EDGE, &zero);
      height_nx = height_ny = 1;
      height_counter.reset();
      timings.surface_uploaded = true;
    }
    hf_extent = {scene.tank.size_x, scene.tank.size_y};
    return;
  }
  hf_extent = {w.nx * w.cell_size, w.ny * w.cell_size};
  const bool resized = w.nx != height_nx || w.ny != height_ny;
  if (!resized && height_counter == w.change_counter) return;
  // Height and central-difference slopes per cell, so the fragment shader
  // needs one fetch for its normal. Stored as half floats: llvmpipe fetches
  // and filters 8 bytes per texel instead of 16, and displacements of
  // millimetres keep 11 significant bits.
  const int nx = w.nx, ny = w.ny;
  const float inv = 1.0f / w.cell_size;
  height_slopes.resize(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    const float* row = w.heights + static_cast<size_t>(j) * nx;
    const float* down = w.heights + static_cast<size_t>(j > 0 ? j - 1 : j) * nx;
    const float* up =
        w.heights + static_cast<size_t>(j + 1 < ny ? j + 1 : j) * nx;
    const float sy = inv / std::max((j > 0 ? 1 : 0) + (j + 1 < ny ? 1 : 0), 1);
    for (int i = 0; i < nx; ++i) {
      const int il = i > 0 ? i - 1 : i, ir = i + 1 < nx ? i + 1 : i;
      height_slopes[static_cast<size_t>(j) * nx + i] =
          glm::vec4(row[i], (row[ir] - row[il]) * inv / std::max(ir - il, 1),
                    (up[i] - down[i]) * sy, 0.0f);
    }
  }
  if (resized) {
    AllocTexture(&height_tex, GL_RGBA16F, nx, ny, GL_RGBA, GL_FLOAT, GL_LINEAR,
                 GL_CLAMP_TO_EDGE, height_slopes.data());
    height_nx = nx;
    height_ny = ny;
  } else {
    glBindTexture(GL_TEXTURE_2D, height_tex.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, nx, ny, GL_RGBA, GL_FLOAT,
                    height_slopes.data());
  }
  height_counter = w.change_counter;
  timings.surface_uploaded = true;
}

void Renderer::Impl::UpdateWalls(const TankGeometry& t) {
  if (walls_tank && SameTank(*walls_tank, t)) return;
  walls_tank = t;
  const float hx = 0.5f * t.size_x, hy = 0.5f * t.size_y, z = t.wall_height;
  std::vector<WallVertex> v;
  // Corners counter-clockwise seen from above; wall i runs from c[i] to
  // c[i + 1] with outward normal n[i].
  const glm::vec3 c[5] = {
      {-hx, -hy, 0}, {hx, -hy, 0}, {hx, hy, 0}, {-hx, hy, 0}, {-hx, -hy, 0}};
  const glm::vec3 n[4] = {{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (int i = 0; i < 4; ++i) {
    const float len = glm::length(c[i + 1] - c[i]);
    const glm::vec3 up(0, 0, z);
    const WallVertex a{c[i], n[i], {0, len}}, b{c[i + 1], n[i], {len, len}},
        cc{c[i + 1] + up, n[i], {len, len}}, d{c[i] + up, n[i], {0, len}};
    for (const WallVertex& x : {a, b, cc, a, cc, d}) v.push_back(x);
  }
  glBindBuffer(GL_ARRAY_BUFFER, walls_vbo.id());
  glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(WallVertex), v.data());
}

bool Renderer::Impl::ShadowNeedsRedraw(const SceneInputs& s) const {
  if (!shadow_key) return true;
  const ShadowKey& k = *shadow_key;
  const double move = options.shadow_move_threshold_m;
  const double turn = options.shadow_turn_threshold_rad;
  if (!SameTank(k.tank, s.tank)) return true;
  if (glm::length(k.light - glm::normalize(s.light_in_tank)) > 1e-9)
    return true;
  if (k.pen_visible != s.pen_visible) return true;
  if (s.pen_visible &&
      (PoseMoved(k.tank_from_pen, s.tank_from_pen, move, turn) ||
       k.pen.cube_edge != s.pen.cube_edge ||
       k.pen.shaft_radius != s.pen.shaft_radius ||
       k.pen.shaft_length != s.pen.shaft_length)) {
    return true;
  }
  if (k.obstacles.size() != s.obstacles.size()) return true;
  for (size_t i = 0; i < s.obstacles.size(); ++i) {
    const Obstacle &a = k.obstacles[i], &b = s.obstacles[i];
    if (a.shape != b.shape || a.size != b.size ||
        PoseMoved(a.tank_from_obstacle, b.tank_from_obstacle, move, turn)) {
      return true;
    }
  }
  return false;
}

void Renderer::Impl::DrawSolids(const SceneInputs& scene, const Program& p,
                                const glm::dmat4& clip_from_tank,
                                bool obstacles, bool pen, bool walls) {
  auto draw = [&](const Mesh& mesh, const glm::dmat4& tank_from_model) {
    SetMat4(p, "u_tank_from_model", tank_from_model);
    SetMat4(p, "u_clip_from_model", clip_from_tank * tank_from_model);
    glBindVertexArray(mesh.vao.id());
    glDrawArrays(GL_TRIANGLES, 0, mesh.count);
  };
  if (obstacles) {
    for (const Obstacle& o : scene.obstacles) {
      const glm::dvec3 size(o.size);
      if (o.shape == Obstacle::Shape::kBox) {
        draw(box, glm::scale(glm::translate(o.tank_from_obstacle,
                                            {0.0, 0.0, 0.5 * size.z}),
                             size));
      } else {
        draw(cylinder,
             glm::scale(o.tank_from_obstacle, {size.x, size.x, size.z}));
      }
    }
  }
  if (pen && scene.pen_visible) {
    const PenGeometry& g = scene.pen;
    draw(box, glm::scale(scene.tank_from_pen, glm::dvec3(g.cube_edge)));
    const glm::dmat4 shaft = glm::translate(
        scene.tank_from_pen,
        {0.0, 0.0, -0.5 * double(g.cube_edge) - double(g.shaft_length)});
    draw(cylinder,
         glm::scale(shaft, {double(g.shaft_radius), double(g.shaft_radius),
                            double(g.shaft_length)}));
  }
  if (walls) {
    SetMat4(p, "u_tank_from_model", glm::dmat4(1.0));
    SetMat4(p, "u_clip_from_model", clip_from_tank);
    glBindVertexArray(walls_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 24);
  }
  glBindVertexArray(0);
}

void Renderer::Impl::DrawShadow(const SceneInputs& scene) {
  const glm::dvec3 l = glm::normalize(scene.light_in_tank);
  // Orthographic light frame: w towards the light, u and v across it.
  const glm::dvec3 helper =
      std::abs(l.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, l));
  const glm::dvec3 v = glm::cross(l, u);
  // Fit the receivers (the tank box) across the light; casters may lie up
  // to a metre towards the light.
  const TankGeometry& t = scene.tank;
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
  shadow_from_tank = m;
  shadow_bias = static_cast<float>(0.0015 / extent.z);
  const double soft = 0.0012;  // metres: PCF tap offset, the penumbra scale
  shadow_texel = glm::vec2(soft / extent.x, soft / extent.y);
  const glm::dmat4 clip_from_shadow =
      glm::translate(glm::dmat4(1.0), glm::dvec3(-1.0)) *
      glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));

  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.id());
  glViewport(0, 0, options.shadow_map_size, options.shadow_map_size);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  glUseProgram(depth_program.id());
  DrawSolids(scene, depth_program, clip_from_shadow * shadow_from_tank, true,
             true, scene.effects.walls);
  glDisable(GL_POLYGON_OFFSET_FILL);

  // What the water sees of it: floor and surface shadow over the tank.
  glBindFramebuffer(GL_FRAMEBUFFER, receiver_fbo.id());
  glViewport(0, 0, kReceiverSize, kReceiverSize);
  glDisable(GL_DEPTH_TEST);
  SetCommon(receiver_program, scene, glm::dmat4(1.0));
  glActiveTexture(GL_TEXTURE0 + kUnitShadow);
  glBindTexture(GL_TEXTURE_2D, shadow_tex.id());
  glBindVertexArray(empty_vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);

  ShadowKey key;
  key.pen_visible = scene.pen_visible;
  key.tank_from_pen = scene.tank_from_pen;
  key.pen = scene.pen;
  key.obstacles = scene.obstacles;
  key.light = l;
  key.tank = scene.tank;
  shadow_key = std::move(key);
}

void Renderer::Impl::UpdateCaustics(const SceneInputs& scene) {
  const glm::dvec3 l = glm::normalize(scene.light_in_tank);
  const HeightFieldView& w = scene.water;
  const std::optional<std::uint64_t> counter =
      w.heights ? std::optional<std::uint64_t>(w.change_counter) : std::nullopt;
  if (caustics_tank && SameTank(*caustics_tank, scene.tank) &&
      caustics_counter == counter && glm::length(caustics_light - l) < 1e-9) {
    return;
  }
  const auto t0 = Clock::now();
  CausticsOptions co;
  co.map_nx = co.map_ny = options.caustics_map_size;
  co.threads = options.caustics_threads;
  // Light loses the water's mean absorption on its way down (Nishita's
  // attenuation along the refracted path); the map is relative to flat water.
  co.attenuation_per_m =
      (options.absorption_per_m.x + options.absorption_per_m.y +
       options.absorption_per_m.z) /
      3.0;
  ComputeCaustics(co, w, scene.tank, l, &caustics_map, nullptr,
                  &caustics_workspace);
  glBindTexture(GL_TEXTURE_2D, caustics_tex.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, co.map_nx, co.map_ny, GL_RED,
                  GL_FLOAT, caustics_map.data());
  caustics_counter = counter;
  caustics_light = l;
  caustics_tank = scene.tank;
  timings.caustics_recomputed = true;
  timings.caustics_ms = MsSince(t0);
}

void Renderer::Impl::SetCommon(const Program& p, const SceneInputs& scene,
                               const glm::dmat4& clip_from_tank) {
  glUseProgram(p.id());
  SetMat4(p, "u_clip_from_tank", clip_from_tank);
  SetMat4(p, "u_cam_from_tank", scene.cam_from_tank);
  SetMat4(p, "u_tank_from_cam", glm::inverse(scene.cam_from_tank));
  glUniform4f(p.Uniform("u_intr"), k.fx, k.fy, k.cx, k.cy);
  glUniform2f(p.Uniform("u_image_size"), k.width, k.height);
  const glm::dvec3 cam = glm::inverse(scene.cam_from_tank)[3];
  SetVec3(p, "u_cam_in_tank", cam);
  const TankGeometry& t = scene.tank;
  glUniform4f(p.Uniform("u_tank"), t.size_x, t.size_y, t.wall_height,
              t.water_level);
  glUniform2f(p.Uniform("u_hf_extent"), hf_extent.x, hf_extent.y);
  glUniform2f(p.Uniform("u_hf_texel"), 1.0f / height_nx, 1.0f / height_ny);
  const glm::dvec3 l = glm::normalize(scene.light_in_tank);
  SetVec3(p, "u_light", l);
  glm::dvec3 lr = glm::refract(-l, glm::dvec3(0, 0, 1), 1.0 / 1.33);
  if (lr.z > -1e-3) lr = glm::dvec3(0, 0, -1);
  SetVec3(p, "u_light_refracted", lr);
  SetMat4(p, "u_shadow_from_tank", shadow_from_tank);
  SetFloat(p, "u_shadow_on", scene.effects.shadows ? 1.f : 0.f);
  glUniform2f(p.Uniform("u_shadow_texel"), shadow_texel.x, shadow_texel.y);
  SetFloat(p, "u_shadow_bias", shadow_bias);
  SetInt(p, "u_height", kUnitHeight);
  SetInt(p, "u_shadow", kUnitShadow);
  SetInt(p, "u_caustics", kUnitCaustics);
  SetInt(p, "u_scene", kUnitScene);
  SetInt(p, "u_reflection", kUnitReflection);
  SetInt(p, "u_receiver", kUnitReceiver);
  SetVec3(p, "u_sigma", options.absorption_per_m);
  SetVec3(p, "u_scatter", options.deep_water_color);
}

namespace {

// Window rectangle (x, y, w, h) of a centred box in the tank frame (x, y
// sizes, z from z0 to z1), grown by `pad` pixels and clipped to the window;
// the whole window when a corner is behind the camera.
glm::ivec4 BoxRect(const glm::dmat4& clip_from_tank, double size_x,
                   double size_y, double z0, double z1, int pad, int width,
                   int height) {
  glm::dvec2 lo(1e9), hi(-1e9);
  for (int i = 0; i < 8; ++i) {
    const glm::dvec4 p((i & 1 ? 0.5 : -0.5) * size_x,
                       (i & 2 ? 0.5 : -0.5) * size_y, i & 4 ? z1 : z0, 1.0);
    const glm::dvec4 c = clip_from_tank * p;
    if (c.w <= 1e-6) return {0, 0, width, height};
    const glm::dvec2 win = WindowFromClip(c, width, height);
    lo = glm::min(lo, win);
    hi = glm::max(hi, win);
  }
  const int x0 = std::clamp(static_cast<int>(std::floor(lo.x)) - pad, 0, width);
  const int y0 =
      std::clamp(static_cast<int>(std::floor(lo.y)) - pad, 0, height);
  const int x1 = std::clamp(static_cast<int>(std::ceil(hi.x)) + pad, 0, width);
  const int y1 = std::clamp(static_cast<int>(std::ceil(hi.y)) + pad, 0, height);
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

// Window rectangle (x, y, w, h) holding the water whatever its waves: the
// tank interior between 1 cm under and over the rest level.
glm::ivec4 Renderer::Impl::WaterRect(const SceneInputs& scene,
                                     const glm::dmat4& clip_from_tank) const {
  const TankGeometry& t = scene.tank;
  return BoxRect(clip_from_tank, t.size_x, t.size_y, t.water_level - 0.01,
                 t.water_level + 0.01, 1, k.width, k.height);
}

// Window rectangle holding the whole tank box (floor to the wall tops, or
// to the water's rest level + 1 cm if higher), padded for linear filtering:
// everything the water's refraction can look up.
glm::ivec4 Renderer::Impl::TankRect(const SceneInputs& scene,
                                    const glm::dmat4& clip_from_tank) const {
  const TankGeometry& t = scene.tank;
  return BoxRect(clip_from_tank, t.size_x, t.size_y, 0.0,
                 std::max<double>(t.wall_height, t.water_level + 0.01), 2,
                 k.width, k.height);
}

// Background: the (undistorted) video drawn straight into the output FBO,
// and the quarter-size reflection map taken from it when `reflection`
// (unless UploadVideo already made it on the CPU).
// Nothing is drawn before any video has arrived.
void Renderer::Impl::DrawVideoBackground(bool reflection) {
  if (!have_video) return;
  const int w = k.width, h = k.height;
  if (k.HasDistortion()) {
    glBindFramebuffer(GL_FRAMEBUFFER, main_fbo.id());
    glViewport(0, 0, w, h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    const Program& p = undistort_program;
    glUseProgram(p.id());
    SetInt(p, "u_video", kUnitVideo);
    glUniform4f(p.Uniform("u_intr"), float(k.fx), float(k.fy), float(k.cx),
                float(k.cy));
    glUniform2f(p.Uniform("u_image_size"), float(w), float(h));
    glUniform4f(p.Uniform("u_dist0"), float(k.dist[0]), float(k.dist[1]),
                float(k.dist[2]), float(k.dist[3]));
    glUniform4f(p.Uniform("u_dist1"), float(k.dist[4]), float(k.dist[5]),
                float(k.dist[6]), float(k.dist[7]));
    glActiveTexture(GL_TEXTURE0 + kUnitVideo);
    glBindTexture(GL_TEXTURE_2D, video_tex.id());
    glBindVertexArray(empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  } else {
    // Same size: GL_NEAREST lets Mesa copy the pixels (resource_copy_region)
    // instead of drawing a textured quad (1.5 ms at 640x480 on llvmpipe).
    glBindFramebuffer(GL_READ_FRAMEBUFFER, video_fbo.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, main_fbo.id());
    glBlitFramebuffer(0, 0, video_w, video_h, 0, 0, w, h, GL_COLOR_BUFFER_BIT,
                      video_w == w && video_h == h ? GL_NEAREST : GL_LINEAR);
  }
  if (reflection && !reflection_from_cpu) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, main_fbo.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, reflection_fbo.id());
    glBlitFramebuffer(0, 0, w, h, 0, 0, std::max(1, w / 4), std::max(1, h / 4),
                      GL_COLOR_BUFFER_BIT, GL_LINEAR);
  }
}

void Renderer::Impl::DrawMain(const SceneInputs& scene) {
  const int w = k.width, h = k.height;
  const glm::dmat4 clip_from_tank = ClipFromCam(k) * scene.cam_from_tank;

  DrawVideoBackground(scene.effects.reflection);
  glBindFramebuffer(GL_FRAMEBUFFER, main_fbo.id());
  glViewport(0, 0, w, h);
  glClearDepth(1.0);
  glClearStencil(0);
  glStencilMask(0xff);
  if (have_video) {
    glClear(GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  } else {
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);

  glActiveTexture(GL_TEXTURE0 + kUnitHeight);
  glBindTexture(GL_TEXTURE_2D, height_tex.id());
  glActiveTexture(GL_TEXTURE0 + kUnitShadow);
  glBindTexture(GL_TEXTURE_2D, shadow_tex.id());
  glActiveTexture(GL_TEXTURE0 + kUnitCaustics);
  glBindTexture(GL_TEXTURE_2D, caustics_tex.id());
  glActiveTexture(GL_TEXTURE0 + kUnitReflection);
  glBindTexture(GL_TEXTURE_2D, reflection_tex.id());
  glActiveTexture(GL_TEXTURE0 + kUnitReceiver);
  glBindTexture(GL_TEXTURE_2D, receiver_tex.id());

  // Virtual obstacles, then a copy of video + obstacles for refraction. The
  // water only looks up points inside the tank, so only the tank's window
  // rectangle is copied.
  if (!scene.obstacles.empty()) {
    const Program& solid = solid_programs[scene.effects.shadows ? 1 : 0];
    SetCommon(solid, scene, clip_from_tank);
    SetVec3(solid, "u_albedo", options.obstacle_albedo);
    DrawSolids(scene, solid, clip_from_tank, true, false, false);
  }
  const glm::ivec4 tank_rect = TankRect(scene, clip_from_tank);
  if (tank_rect.z > 0 && tank_rect.w > 0) {
    const int x1 = tank_rect.x + tank_rect.z, y1 = tank_rect.y + tank_rect.w;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, main_fbo.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, scene_copy_fbo.id());
    glBlitFramebuffer(tank_rect.x, tank_rect.y, x1, y1, tank_rect.x,
                      tank_rect.y, x1, y1, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, main_fbo.id());
  }
  glActiveTexture(GL_TEXTURE0 + kUnitScene);
  glBindTexture(GL_TEXTURE_2D, scene_copy_tex.id());

  // The real pen hides the water where it is in front of it.
  if (scene.pen_visible && scene.effects.pen_occludes) {
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(depth_program.id());
    DrawSolids(scene, depth_program, clip_from_tank, false, true, false);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  // Water surface.
  const Effects& fx = scene.effects;
  const int variant =
      (fx.shadows ? kWaterShadows : 0) | (fx.caustics ? kWaterCaustics : 0) |
      (fx.reflection && have_video ? kWaterReflection : 0) |
      (fx.refraction ? kWaterRefraction : 0) | (fx.flat_water ? kWaterFlat : 0);
  const Program* water = WaterProgram(variant);
  if (water == nullptr) return;
  // (a) The mesh lays depth and marks its visible pixels in the stencil.
  SetCommon(water_depth_program, scene, clip_from_tank);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glBindVertexArray(grid_vao.id());
  glDrawElements(GL_TRIANGLE_STRIP, grid_index_count, GL_UNSIGNED_INT, nullptr);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  // (b) One shading per marked pixel, in the water's screen rectangle.
  SetCommon(*water, scene, clip_from_tank);
  SetFloat(*water, "u_ambient", options.shadow_ambient);
  SetFloat(*water, "u_env_distance", options.reflection_distance_m);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  glStencilMask(0);
  glDisable(GL_DEPTH_TEST);
  const glm::ivec4 rect = WaterRect(scene, clip_from_tank);
  glEnable(GL_SCISSOR_TEST);
  glScissor(rect.x, rect.y, rect.z, rect.w);
  glBindVertexArray(empty_vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glStencilMask(0xff);
  glEnable(GL_DEPTH_TEST);

  // Glass walls, far ones first, blended over everything.
  if (scene.effects.walls) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_SRC1_COLOR);
    glDepthMask(GL_FALSE);
    glBindVertexArray(walls_vao.id());
    const glm::dvec3 cam = glm::inverse(scene.cam_from_tank)[3];
    const glm::dvec3 hs(0.5 * scene.tank.size_x, 0.5 * scene.tank.size_y, 0);
    const double outside[4] = {-hs.y - cam.y, cam.x - hs.x, cam.y - hs.y,
                               -hs.x - cam.x};
    for (int pass = 0; pass < 2; ++pass) {
      SetCommon(walls_programs[pass], scene, clip_from_tank);
      for (int i = 0; i < 4; ++i) {
        if ((outside[i] > 0) == (pass == 1))
          glDrawArrays(GL_TRIANGLES, 6 * i, 6);
      }
    }
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
}

void Renderer::Impl::BeginPass(int query) {
  if (options.timing == RendererOptions::Timing::kGpuQueries) {
    glBeginQuery(GL_TIME_ELAPSED, queries[query].id());
  } else if (options.timing == RendererOptions::Timing::kCpuFinish) {
    glFinish();
  }
}

double Renderer::Impl::EndPass(int query, Clock::time_point t0) {
  if (options.timing == RendererOptions::Timing::kGpuQueries) {
    glEndQuery(GL_TIME_ELAPSED);
    return -1;  // read after the frame
  }
  if (options.timing == RendererOptions::Timing::kCpuFinish) {
    glFinish();
    return MsSince(t0);
  }
  return 0;
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() {
  if (impl_ && impl_->context) impl_->context->MakeCurrent();
}

std::unique_ptr<Renderer> Renderer::TryCreate(Context* context,
                                              const Intrinsics& intrinsics,
                                              const RendererOptions& options,
                                              std::string* error) {
  std::string local;
  if (error == nullptr) error = &local;
  if (context == nullptr) {
    *error = "renderer: no GL context";
    return nullptr;
  }
  if (!intrinsics.IsValid(error) || !options.IsValid(error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  impl->context = context;
  impl->k = intrinsics;
  impl->options = options;
  if (!impl->Init(error)) return nullptr;
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

void Renderer::SetIntrinsics(const Intrinsics& intrinsics) {
  if (intrinsics == impl_->k) return;
  impl_->k = intrinsics;
  std::string error;
  if (!impl_->AllocateOutput(&error)) {
    std::fprintf(stderr, "ripple render: %s\n", error.c_str());
  }
}

const Intrinsics& Renderer::intrinsics() const { return impl_->k; }
const RendererOptions& Renderer::options() const { return impl_->options; }
const PassTimings& Renderer::timings() const { return impl_->timings; }

glm::dmat4 Renderer::ClipFromTank(const glm::dmat4& cam_from_tank) const {
  return ClipFromCam(impl_->k) * cam_from_tank;
}

bool Renderer::Render(const SceneInputs& scene) {
  Impl& m = *impl_;
  const auto t_start = Clock::now();
  m.timings = PassTimings{};
  m.timings.timing = m.options.timing;

  auto t0 = Clock::now();
  m.UploadVideo(scene.video);
  m.UpdateHeights(scene);
  m.UpdateWalls(scene.tank);
  m.timings.upload_ms = MsSince(t0);

  bool shadow_query = false;
  if (scene.effects.shadows && m.ShadowNeedsRedraw(scene)) {
    t0 = Clock::now();
    m.BeginPass(0);
    m.DrawShadow(scene);
    m.timings.shadow_ms = m.EndPass(0, t0);
    m.timings.shadow_redrawn = true;
    shadow_query = true;
  }
  if (scene.effects.caustics) m.UpdateCaustics(scene);

  t0 = Clock::now();
  m.BeginPass(1);
  m.DrawMain(scene);
  m.timings.main_ms = m.EndPass(1, t0);

  if (m.options.timing == RendererOptions::Timing::kGpuQueries) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(m.queries[1].id(), GL_QUERY_RESULT, &ns);
    m.timings.main_ms = ns * 1e-6;
    if (shadow_query) {
      glGetQueryObjectui64v(m.queries[0].id(), GL_QUERY_RESULT, &ns);
      m.timings.shadow_ms = ns * 1e-6;
    }
  }
  m.timings.total_ms = MsSince(t_start);
  return CheckGlError("Renderer::Render");
}

void Renderer::Finish() { glFinish(); }

bool Renderer::ReadBgr(std::uint8_t* bgr, int stride_bytes) {
  Impl& m = *impl_;
  const int w = m.k.width, h = m.k.height;
  if (stride_bytes <= 0) stride_bytes = w * 3;
  auto convert = [&](const std::uint8_t* src, int src_stride, bool rgba) {
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* s = src + static_cast<size_t>(y) * src_stride;
      std::uint8_t* d = bgr + static_cast<size_t>(y) * stride_bytes;
      for (int x = 0; x < w; ++x, s += 4, d += 3) {
        d[0] = rgba ? s[2] : s[0];
        d[1] = s[1];
        d[2] = rgba ? s[0] : s[2];
      }
    }
  };
  const std::uint8_t* cpu = m.context->CpuFramebuffer();
  if (cpu != nullptr && m.context->width() == w && m.context->height() == h) {
    // OSMesa: its buffer is the default framebuffer, bottom row (GL row 0)
    // first, and our FBO holds the image top row at GL row 0.
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m.main_fbo.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glFinish();
    convert(cpu, w * 4, true);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return CheckGlError("Renderer::ReadBgr (OSMesa)");
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m.main_fbo.id());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, m.pbo.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, w, h, GL_BGRA, GL_UNSIGNED_BYTE, nullptr);
  const auto* data = static_cast<const std::uint8_t*>(
      glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0,
                       static_cast<GLsizeiptr>(w) * h * 4, GL_MAP_READ_BIT));
  bool ok = data != nullptr;
  if (ok) convert(data, w * 4, false);
  glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return CheckGlError("Renderer::ReadBgr") && ok;
}

bool Renderer::RenderVideoOnly(const VideoFrame& video) {
  Impl& m = *impl_;
  const auto t_start = Clock::now();
  m.timings = PassTimings{};
  m.timings.timing = m.options.timing;
  m.UploadVideo(video);
  m.timings.upload_ms = MsSince(t_start);
  const auto t0 = Clock::now();
  m.BeginPass(1);
  m.DrawVideoBackground(false);
  if (!m.have_video) {
    glBindFramebuffer(GL_FRAMEBUFFER, m.main_fbo.id());
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m.timings.main_ms = m.EndPass(1, t0);
  if (m.options.timing == RendererOptions::Timing::kGpuQueries) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(m.queries[1].id(), GL_QUERY_RESULT, &ns);
    m.timings.main_ms = ns * 1e-6;
  }
  m.timings.total_ms = MsSince(t_start);
  return CheckGlError("Renderer::RenderVideoOnly");
}

void Renderer::SetOverlay(const std::uint8_t* bgra, int width, int height,
                          int stride_bytes) {
  Impl& m = *impl_;
  if (bgra == nullptr || width <= 0 || height <= 0) {
    m.overlay_w = m.overlay_h = 0;
    return;
  }
  if (stride_bytes <= 0) stride_bytes = width * 4;
  if (width != m.overlay_w || height != m.overlay_h ||
      m.overlay_tex.id() == 0) {
    AllocTexture(&m.overlay_tex, GL_RGBA8, width, height, GL_BGRA,
                 GL_UNSIGNED_BYTE, GL_NEAREST, GL_CLAMP_TO_EDGE);
    m.overlay_w = width;
    m.overlay_h = height;
  }
  glBindTexture(GL_TEXTURE_2D, m.overlay_tex.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (stride_bytes % 4 == 0) {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, stride_bytes / 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_BGRA,
                    GL_UNSIGNED_BYTE, bgra);
  } else {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    for (int y = 0; y < height; ++y) {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y, width, 1, GL_BGRA,
                      GL_UNSIGNED_BYTE,
                      bgra + static_cast<size_t>(y) * stride_bytes);
    }
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  CheckGlError("Renderer::SetOverlay");
}

glm::ivec4 LetterboxRect(int image_width, int image_height, int window_width,
                         int window_height) {
  if (image_width <= 0 || image_height <= 0 || window_width <= 0 ||
      window_height <= 0) {
    return {0, 0, 0, 0};
  }
  // Fit the width or the height, whichever binds, in integer arithmetic.
  int w = window_width, h = window_height;
  if (static_cast<long long>(window_width) * image_height >
      static_cast<long long>(window_height) * image_width) {
    w = static_cast<int>((static_cast<long long>(window_height) * image_width +
                          image_height / 2) /
                         image_height);
  } else {
    h = static_cast<int>((static_cast<long long>(window_width) * image_height +
                          image_width / 2) /
                         image_width);
  }
  return {(window_width - w) / 2, (window_height - h) / 2, w, h};
}

void Renderer::Present() {
  Impl& m = *impl_;
  const int fb = m.context->DefaultFramebuffer();
  if (fb < 0) return;
  int fw = 0, fh = 0;
  m.context->GetFramebufferSize(&fw, &fh);
  if (fw > 0 && fh > 0) {  // 0 x 0 while minimised
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fb));
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glViewport(0, 0, fw, fh);
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    const glm::ivec4 r = LetterboxRect(m.k.width, m.k.height, fw, fh);
    // GL rows count from the bottom; the FBO holds the image top row first,
    // so the blit flips it.
    const int y_bottom = fh - r.y - r.w;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m.main_fbo.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(fb));
    glBlitFramebuffer(0, 0, m.k.width, m.k.height, r.x, y_bottom + r.w,
                      r.x + r.z, y_bottom, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    if (m.overlay_w > 0 && m.overlay_h > 0) {
      glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(fb));
      // 1:1 framebuffer pixels at the top-left corner.
      glViewport(0, fh - m.overlay_h, m.overlay_w, m.overlay_h);
      glDisable(GL_DEPTH_TEST);
      glDisable(GL_STENCIL_TEST);
      glEnable(GL_BLEND);
      glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE,
                          GL_ONE_MINUS_SRC_ALPHA);
      glUseProgram(m.overlay_program.id());
      SetInt(m.overlay_program, "u_overlay", kUnitOverlay);
      glActiveTexture(GL_TEXTURE0 + kUnitOverlay);
      glBindTexture(GL_TEXTURE_2D, m.overlay_tex.id());
      glBindVertexArray(m.empty_vao.id());
      glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
      glBindVertexArray(0);
      glDisable(GL_BLEND);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    CheckGlError("Renderer::Present");
  }
  m.context->SwapBuffers();
}

}  // namespace ripple::render
