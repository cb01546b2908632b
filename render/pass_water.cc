#include "render/pass_water.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <glm/gtc/type_ptr.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/gl_state.h"
#include "render/meshes.h"
#include "render/shaders.h"
#include "render/water_regions.h"

namespace ripple::render::internal {

bool WaterPass::BuildShading(Shading* s, const std::string& defines,
                             const Options& options, std::string* error) {
  if (!BuildProgram(&s->program, "water", "water_deferred.vert", "water.frag",
                    defines, error)) {
    return false;
  }
  const Program& p = s->program;
  s->common.Resolve(p);  // leaves p bound
  glUniform1i(p.Uniform("u_floor_return"), kUnitFloorReturn);

  glUniform1f(p.Uniform("u_ior"), options.optics.ior);
  glUniform1f(p.Uniform("u_glass_ior"), options.optics.glass_ior);
  glUniform1f(p.Uniform("u_glass_d"), options.optics.glass_thickness_m);
  SetUniform(p.Uniform("u_sigma"), options.optics.absorption_per_m);
  SetUniform(p.Uniform("u_scatter"), options.optics.scatter_color);
  s->floor_sky = p.Uniform("u_floor_sky");
  s->floor_sun = p.Uniform("u_floor_sun");
  s->inv_n2 = p.Uniform("u_inv_n2");
  s->glass_t = p.Uniform("u_glass_t");
  for (int w = 0; w < 4; ++w) {
    const std::string name = "u_under_glass[" + std::to_string(w) + "]";
    s->under_glass[w] = p.Uniform(name.c_str());
  }
  s->glint_peak = p.Uniform("u_glint_peak");
  s->return_tint = p.Uniform("u_return_tint");
  s->floor_around = p.Uniform("u_floor_around");
  s->inv_alpha2 = p.Uniform("u_inv_alpha2");
  glUniform1i(p.Uniform("u_occluders"), kUnitOccluders);
  glUniform1i(p.Uniform("u_plate"), kUnitPlate);
  glUniform1i(p.Uniform("u_mirror"), kUnitMirror);
  glUniform1f(p.Uniform("u_mirror_depth"), kMirrorDepth_m);
  s->pen_tip = p.Uniform("u_pen_tip");
  s->pen_axis = p.Uniform("u_pen_axis");
  s->pen_length = p.Uniform("u_pen_length");
  s->pen_radius = p.Uniform("u_pen_radius");
  s->pen_margin = p.Uniform("u_pen_margin");
  s->plate_map = p.Uniform("u_plate_map");
  s->plate_gain = p.Uniform("u_plate_gain");
  s->obstacle_count = p.Uniform("u_obstacle_count");
  s->obstacle_from_tank = p.Uniform("u_obstacle_from_tank");
  s->obstacle_shape = p.Uniform("u_obstacle_shape");
  return true;
}

namespace {

// ComputeFloorReturn for the water pass's map: about 0.4 s, so renderers
// made one after another for the same tank and optics (the benchmark's
// scenes, the tests) share the last one.
FloorReturnMap FloorReturnFor(const WaterOptics& o, const TankGeometry& t) {
  static std::mutex mutex;
  static std::vector<double> last_key;
  static std::shared_ptr<const FloorReturnMap> last;
  const std::vector<double> key = {t.size_x,
                                   t.size_y,
                                   t.water_level,
                                   t.wall_height,
                                   o.ior,
                                   o.glass_ior,
                                   o.glass_thickness_m,
                                   o.ambient_share,
                                   o.absorption_per_m.r,
                                   o.absorption_per_m.g,
                                   o.absorption_per_m.b};
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (last && key == last_key) return *last;
  }
  auto map = std::make_shared<const FloorReturnMap>(ComputeFloorReturn(
      o, t.size_x, t.size_y, t.water_level, t.wall_height, WaterPass::kReturnNx,
      WaterPass::kReturnNy, WaterPass::kReturnRays));
  std::lock_guard<std::mutex> lock(mutex);
  last_key = key;
  last = map;
  return *map;
}

}  // namespace

void WaterPass::UpdateWetBoard(const FrameState& f, bool new_tank) {
  const TankGeometry& tank = f.scene->tank;
  BoardLightOptions o;
  o.texel_m = 0.0025;  // the points stand for the board beyond a whole wall
  if (new_tank) {
    wet_board_ = BoardLightLayout(tank, options_.optics, o);
    ComputeBoardSkyView(tank, options_.optics, o, &wet_board_);
  }
  ComputeBoardDirectLight(tank, options_.optics, f.light, o, &wet_board_);
  wet_board_light_ = f.light;
  for (int w = 0; w < 4; ++w) {
    const std::vector<glm::dvec2>& points = floor_return_.board_points[w];
    wet_board_factor_[w].resize(points.size());
    for (size_t p = 0; p < points.size(); ++p) {
      wet_board_factor_[w][p] = wet_board_.LightAt(
          points[p].x, points[p].y, options_.optics, kPaperRadiance);
    }
  }
}

void WaterPass::UpdateFloorReturn(const FrameState& f) {
  const TankGeometry& tank = f.scene->tank;
  const bool new_tank =
      !floor_return_tank_ || !SameTank(*floor_return_tank_, tank);
  if (new_tank) {
    floor_return_ = FloorReturnFor(options_.optics, tank);
    // The other bands' return is green's times the map's mean ratio (their
    // extra absorption on the way, nearly uniform over the floor).
    glm::dvec3 mean(0.0);
    for (const glm::vec3& r : floor_return_.returned) mean += glm::dvec3(r);
    return_light_.tint = glm::vec3(mean / std::max(mean.g, 1e-12));
    return_light_.mean_return = glm::vec3(
        mean / double(std::max<size_t>(floor_return_.returned.size(), 1)));
    floor_return_tank_ = tank;
  }
  const bool new_light = !wet_board_light_ || *wet_board_light_ != f.light;
  if (new_tank || new_light) UpdateWetBoard(f, new_tank);
  // The board's radiance beyond each wall, as the video shows it where the
  // light leaving through that wall lands (the board is real: the video
  // shows it around the virtual tank), lit as the board beside the tank is.
  const VideoFrame& v = f.scene->video;
  // No frame this time: the last one's board stands.
  if (v.bgr == nullptr && uploaded_ && !new_tank && !new_light) return;
  glm::vec3 radiance[4];
  int seen = 0;
  glm::vec3 seen_sum(0.0f);
  bool have[4] = {false, false, false, false};
  const Intrinsics& k = *f.k;
  for (int w = 0; w < 4; ++w) {
    glm::dvec3 sum(0.0);
    int count = 0;
    const std::vector<glm::dvec2>& points = floor_return_.board_points[w];
    for (size_t p = 0; p < points.size(); ++p) {
      glm::dvec3 rgb;
      if (!VideoRadianceAt(v, k, f.scene->cam_from_tank, points[p],
                           f.srgb_output, &rgb))
        continue;
      sum += rgb * glm::dvec3(wet_board_factor_[w][p]);
      ++count;
    }
    if (count > 0) {
      radiance[w] = glm::vec3(sum / double(count));
      have[w] = true;
      seen_sum += radiance[w];
      ++seen;
    }
  }
  // A wall whose board the frame does not show takes the others' mean; no
  // board in view (or no video) leaves white paper's.
  for (int w = 0; w < 4; ++w) {
    if (!have[w])
      radiance[w] =
          seen > 0 ? seen_sum / float(seen) : glm::vec3(kPaperRadiance);
  }
  bool changed = new_tank || !uploaded_;
  for (int w = 0; w < 4; ++w) {
    const glm::vec3 d = glm::abs(radiance[w] - board_radiance_[w]);
    changed = changed || std::max(d.r, std::max(d.g, d.b)) > kBoardChange;
  }
  if (!changed) return;
  // One fetch: rgb = the surroundings' light, a = the green band's return.
  const FloorReturnMap& map = floor_return_;
  std::vector<glm::vec4> packed(map.returned.size());
  glm::dvec3 surround_sum(0.0);
  for (size_t i = 0; i < packed.size(); ++i) {
    glm::vec3 surround = map.sky[i];
    for (int w = 0; w < 4; ++w) surround += map.board[w][i] * radiance[w];
    packed[i] = glm::vec4(surround, map.returned[i].g);
    // The texture clamps what it stores at 0; so does its mean.
    surround_sum += glm::dvec3(glm::max(surround, glm::vec3(0.0f)));
  }
  return_light_.mean_surround =
      glm::vec3(surround_sum / double(std::max<size_t>(packed.size(), 1)));
  // On its own unit: AllocTexture binds to the active one. 8 bits: the
  // light comes to at most about half the dry board's, in steps of 0.4 %
  // of it; a surroundings' term under 0 (walls showing less than the sky
  // they hide: none for a board of albedo 0.05 to 0.85 under 0.3 to all of
  // the light from the sky, ComputeFloorReturn) reads 0.
  glActiveTexture(GL_TEXTURE0 + kUnitFloorReturn);
  if (new_tank || !uploaded_) {
    AllocTexture(&floor_return_tex_, GL_RGBA8, map.nx, map.ny, GL_RGBA,
                 GL_FLOAT, GL_LINEAR, GL_CLAMP_TO_EDGE, packed.data());
  } else {
    glBindTexture(GL_TEXTURE_2D, floor_return_tex_.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, map.nx, map.ny, GL_RGBA, GL_FLOAT,
                    packed.data());
  }
  for (int w = 0; w < 4; ++w) board_radiance_[w] = radiance[w];
  uploaded_ = true;
}

void WaterPass::UpdateFloorLight(const FrameState& f) {
  return_light_.direct_mean = f.caustics_mean;
  UpdateFloorReturn(f);
  UpdateFloorSeen(f);
}

void WaterPass::UpdateFloorSeen(const FrameState& f) {
  // No frame this time: the last one's floor stands; the light may move.
  const VideoFrame& v = f.scene->video;
  if (v.bgr != nullptr || !have_floor_albedo_) {
    const TankGeometry& t = f.scene->tank;
    // 16 points along each wall, 15 mm in (or the middle of a smaller
    // tank).
    const double hx = 0.5 * t.size_x, hy = 0.5 * t.size_y;
    const double in_x = std::min(0.015, hx), in_y = std::min(0.015, hy);
    const glm::dvec3 r(return_light_.mean_return);
    // The floor's light with the return it gets back from the surface, as
    // in water.frag: E / (1 - R rho) for a uniformly lit floor.
    auto with_return = [&](const glm::dvec3& rho) {
      return rho / (1.0 - r * glm::min(rho, glm::dvec3(0.95)));
    };
    glm::dvec3 sum(0.0);
    int count = 0;
    constexpr int kPerWall = 16;
    for (int i = 0; i < kPerWall; ++i) {
      const double s = (i + 0.5) / kPerWall;
      const double x = -hx + in_x + s * 2.0 * (hx - in_x);
      const double y = -hy + in_y + s * 2.0 * (hy - in_y);
      const glm::dvec2 points[4] = {
          {hx - in_x, y}, {-hx + in_x, y}, {x, hy - in_y}, {x, -hy + in_y}};
      for (const glm::dvec2& q : points) {
        glm::dvec3 rho;
        if (VideoRadianceAt(v, *f.k, f.scene->cam_from_tank, q, f.srgb_output,
                            &rho)) {
          sum += with_return(rho);
          ++count;
        }
      }
    }
    floor_albedo_ = count > 0 ? sum / double(count)
                              : with_return(glm::dvec3(kPaperRadiance));
    have_floor_albedo_ = count > 0;
    // The whole floor's mean albedo (what the surface's return carries):
    // the video's floor at the centres of a 12 x 8 grid over the tank.
    constexpr int kGridX = 12, kGridY = 8;
    glm::dvec3 floor_sum(0.0);
    int floor_count = 0;
    for (int j = 0; j < kGridY; ++j) {
      for (int i = 0; i < kGridX; ++i) {
        const glm::dvec2 q(-hx + (i + 0.5) * 2.0 * hx / kGridX,
                           -hy + (j + 0.5) * 2.0 * hy / kGridY);
        glm::dvec3 rho;
        if (VideoRadianceAt(v, *f.k, f.scene->cam_from_tank, q, f.srgb_output,
                            &rho)) {
          floor_sum += glm::min(rho, glm::dvec3(0.95));
          ++floor_count;
        }
      }
    }
    if (floor_count > 0) {
      return_light_.floor_albedo = glm::vec3(floor_sum / double(floor_count));
    }
  }
  const glm::dvec3 light(FloorMeanLight(f.shading, return_light_));
  return_light_.floor_seen =
      glm::vec3(floor_albedo_ * light * double(f.shading.inv_n2));
}

std::string WaterPass::VariantDefines(int v) const {
  std::string defines;
  if (options_.env_cube) defines += "#define ENV_CUBE 1\n";
  if (options_.sky) defines += "#define SKY 1\n";
  if (options_.cubic_refraction) defines += "#define REFRACTION_CUBIC 1\n";
  if (v & kShadows) defines += "#define SHADOWS 1\n";
  if (v & kCaustics) defines += "#define CAUSTICS 1\n";
  if (v & kReflection) defines += "#define REFLECTION 1\n";
  if (v & kRefraction) defines += "#define REFRACTION 1\n";
  if (v & kRealPen) defines += "#define REAL_PEN 1\n";
  if (v & kRealPlate) defines += "#define REAL_PLATE 1\n";
  if (v & kMirror) defines += "#define MIRROR 1\n";
  if (v & kWallFree) defines += "#define WALL_FREE 1\n";
  if (v & kObstacles) {
    defines += "#define OBSTACLES 1\n#define MAX_OBSTACLES " +
               std::to_string(kMaxTracedObstacles) + "\n";
  }
  return defines;
}

const WaterPass::Shading& WaterPass::Variant(int v) const {
  Shading& s = variants_[v];
  if (s.program.id() != 0 || !(v & kObstacles)) return s;
  // Built on first use: only frames with an obstacle in view need these.
  std::string error;
  if (!obstacles_failed_ &&
      BuildShading(&s, VariantDefines(v), options_, &error))
    return s;
  if (!obstacles_failed_)
    std::fprintf(stderr, "ripple: water shader with obstacles: %s\n",
                 error.c_str());
  obstacles_failed_ = true;
  return variants_[v & ~kObstacles];
}

bool WaterPass::Create(const Options& options, std::string* error) {
  options_ = options;
  for (int v = 0; v < kVariants; ++v) {
    if ((v & (kRealPen | kRealPlate)) && !(v & kRefraction)) continue;
    if ((v & kMirror) && !(v & kReflection)) continue;
    if ((v & kWallFree) && !(v & kRefraction)) continue;
    // The obstacles' variants are built when first drawn (Variant).
    if (v & kObstacles) continue;
    if (!BuildShading(&variants_[v], VariantDefines(v), options, error))
      return false;
  }
  if (!BuildShading(&flat_, "#define FLAT_WATER 1\n", options, error) ||
      !BuildProgram(&depth_, "water_depth", "water.vert", "depth.frag", "",
                    error)) {
    return false;
  }
  depth_common_.Resolve(depth_);
  empty_vao_.Create();
  if (!BuildProgram(&upsample_, "water_upsample", "fullscreen.vert",
                    "water_upsample.frag", "", error) ||
      !BuildProgram(&hull_, "water_coarse_mark", "ndc.vert", "depth.frag", "",
                    error)) {
    return false;
  }
  glUseProgram(upsample_.id());
  glUniform1i(upsample_.Uniform("u_coarse_water"), kUnitCoarseWater);
  glUseProgram(0);
  hull_vao_.Create();
  hull_vbo_.Create();
  glBindVertexArray(hull_vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, hull_vbo_.id());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glBindVertexArray(0);

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
  grid_index_count_ = static_cast<int>(indices.size());
  grid_vao_.Create();
  grid_vbo_.Create();
  grid_ibo_.Create();
  glBindVertexArray(grid_vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, grid_vbo_.id());
  glBufferData(GL_ARRAY_BUFFER, grid.size() * sizeof(glm::vec2), grid.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, grid_ibo_.id());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(std::uint32_t),
               indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  return true;
}

bool WaterPass::AllocateOutput(int width, int height) {
  out_width_ = width;
  out_height_ = height;
  grid_ = CoarseGridFor(width, height, options_.shading_columns);
  if (!grid_.active()) return true;
  glActiveTexture(GL_TEXTURE0 + kUnitCoarseWater);
  AllocTexture(&coarse_color_, GL_RGBA8, grid_.width, grid_.height, GL_RGBA,
               GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
  coarse_stencil_.Create();
  glBindRenderbuffer(GL_RENDERBUFFER, coarse_stencil_.id());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, grid_.width,
                        grid_.height);
  if (!AttachColor(&coarse_fbo_, coarse_color_)) return false;
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT,
                            GL_RENDERBUFFER, coarse_stencil_.id());
  return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

void WaterPass::Prepare(const Shading& s, const FrameState& f,
                        const RealObjectsState& real) const {
  s.common.Set(s.program, f, f.clip_from_tank);
  const WaterShading& w = f.shading;
  SetUniform(s.floor_sky, w.floor_sky);
  SetUniform(s.floor_sun, w.floor_sun);
  glUniform1f(s.inv_n2, w.inv_n2);
  glUniform1f(s.glass_t, w.glass_transmittance);
  glm::vec3 basis[4];
  UnderGlassBasis(w, basis);
  for (int i = 0; i < 4; ++i) SetUniform(s.under_glass[i], basis[i]);
  glUniform1f(s.glint_peak, w.glint_peak);
  glUniform1f(s.inv_alpha2, w.inv_alpha2);
  SetUniform(s.return_tint, return_light_.tint);
  SetUniform(s.floor_around, FloorAroundLight(w, return_light_));
  // Locations are -1 in the variants without the pen or the plate.
  SetUniform(s.pen_tip, real.pen_tip);
  SetUniform(s.pen_axis, real.pen_axis);
  glUniform1f(s.pen_length, real.pen_length);
  glUniform1f(s.pen_radius, real.pen_radius);
  glUniform1f(s.pen_margin, real.pen_margin);
  glUniform4f(s.plate_map, real.plate_map.x, real.plate_map.y, real.plate_map.z,
              real.plate_map.w);
  glUniform1f(s.plate_gain, real.plate_gain);
  // Only the kObstacles variants have them (Draw uses those for up to
  // kMaxTracedObstacles).
  if (s.obstacle_count < 0) return;
  const std::vector<Obstacle>& obstacles = f.scene->obstacles;
  const int n =
      static_cast<int>(std::min(obstacles.size(), size_t{kMaxTracedObstacles}));
  glm::mat4 from_tank[kMaxTracedObstacles];
  glm::vec4 shape[kMaxTracedObstacles];
  for (int i = 0; i < n; ++i) {
    const Obstacle& o = obstacles[i];
    from_tank[i] = glm::mat4(glm::inverse(o.tank_from_obstacle));
    shape[i] = o.shape == Obstacle::Shape::kBox
                   ? glm::vec4(0.5f * o.size.x, 0.5f * o.size.y, o.size.z, 0.f)
                   : glm::vec4(o.size.x, o.size.x, o.size.z, 1.f);
  }
  glUniform1i(s.obstacle_count, n);
  if (n > 0) {
    glUniformMatrix4fv(s.obstacle_from_tank, n, GL_FALSE,
                       glm::value_ptr(from_tank[0]));
    glUniform4fv(s.obstacle_shape, n, glm::value_ptr(shape[0]));
  }
}

void WaterPass::MarkCoarseWater(const FrameState& f) {
  const TankGeometry& t = f.scene->tank;
  // The surface lies within this frame's height range (the height
  // texture's code, which includes 0), plus a millimetre for its filtering.
  // A texel holds an output pixel's interpolation when it is one of the four
  // around it: within one texel of the water in x and y. Half a texel more
  // keeps the texel centres on the polygon's edges inside.
  const HeightFieldInfo& h = f.height;
  const double low = t.water_level + h.decode_offset.x - 0.001;
  const double high =
      t.water_level + h.decode_offset.x + h.decode_scale.x + 0.001;
  std::vector<glm::dvec2> hull =
      GrownBoxHull(f.clip_from_tank, t.size_x, t.size_y, low, high, grid_.width,
                   grid_.height, 1.5);
  std::vector<glm::vec2> fan;
  if (hull.empty()) {  // no bound: the whole grid
    fan = {{-1.f, -1.f}, {1.f, -1.f}, {1.f, 1.f}, {-1.f, 1.f}};
  } else {
    for (const glm::dvec2& w : hull) {
      fan.emplace_back(float(2.0 * w.x / grid_.width - 1.0),
                       float(2.0 * w.y / grid_.height - 1.0));
    }
  }
  glBindVertexArray(hull_vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, hull_vbo_.id());
  glBufferData(GL_ARRAY_BUFFER, fan.size() * sizeof(glm::vec2), fan.data(),
               GL_STREAM_DRAW);
  glUseProgram(hull_.id());
  GlStateGuard mask;
  mask.ColorMask(false);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glDrawArrays(GL_TRIANGLE_FAN, 0, static_cast<GLsizei>(fan.size()));
  glBindVertexArray(0);
}

bool WaterPass::ShadesRealPen(const FrameState& f, bool have_video,
                              const RealObjectsState& real) {
  const Effects& fx = f.scene->effects;
  return fx.refraction && have_video && !fx.flat_water && real.pen;
}

void WaterPass::Draw(const FrameState& f, bool have_video,
                     const RealObjectsState& real, GLuint target) {
  const Effects& fx = f.scene->effects;
  const SceneInputs& scene = *f.scene;
  // The plate matters only where this frame's mask hides the board.
  const bool real_ok = fx.refraction && have_video && !fx.flat_water;
  const bool with_pen = ShadesRealPen(f, have_video, real);
  const bool with_plate = real_ok && real.mask && real.plate;
  const bool reflection = fx.reflection && have_video;
  // The mirror holds something only with obstacles or the pen in view.
  const bool with_mirror = reflection && !fx.flat_water &&
                           (!scene.obstacles.empty() || scene.pen_visible);
  // Obstacles to trace the refracted rays against: the shader holds a few.
  const bool with_obstacles =
      fx.refraction && have_video && !scene.obstacles.empty() &&
      scene.obstacles.size() <= size_t{kMaxTracedObstacles};
  const int base = (fx.shadows ? kShadows : 0) | (fx.caustics ? kCaustics : 0) |
                   (reflection ? kReflection : 0) |
                   (fx.refraction ? kRefraction : 0);
  GlStateGuard state;
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  state.Enable(GL_STENCIL_TEST);
  {
    // (a) The mesh lays depth and marks its visible pixels in the stencil.
    GlStateGuard mask;
    mask.ColorMask(false);
    depth_common_.Set(depth_, f, f.clip_from_tank);
    glStencilFunc(GL_ALWAYS, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glBindVertexArray(grid_vao_.id());
    glDrawElements(GL_TRIANGLE_STRIP, grid_index_count_, GL_UNSIGNED_INT,
                   nullptr);
  }
  // (b) One shading per marked pixel, in the water's screen rectangle: the
  // tank interior between 1 cm under and over the rest level, whatever the
  // waves.
  glActiveTexture(GL_TEXTURE0 + kUnitFloorReturn);
  glBindTexture(GL_TEXTURE_2D, floor_return_tex_.id());
  state.Disable(GL_DEPTH_TEST);
  const TankGeometry& t = scene.tank;
  const glm::ivec4 rect =
      BoxRect(f.clip_from_tank, t.size_x, t.size_y, t.water_level - 0.01,
              t.water_level + 0.01, 1, f.k->width, f.k->height);
  state.Enable(GL_SCISSOR_TEST);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  if (fx.flat_water) {
    glBindVertexArray(empty_vao_.id());
    Prepare(flat_, f, real);
    glStencilFunc(GL_EQUAL, 1, 0xff);
    state.StencilMask(0);
    glScissor(rect.x, rect.y, rect.z, rect.w);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return;
  }
  // The pen, the plate and the mirror, each only inside its region, and the
  // walls only outside theirs (water_regions.h). The wall-free rectangle is
  // in the output's pixels: not on the coarse grid.
  glm::ivec4 region[kRegions] = {rect, rect, rect, {}, rect};
  bool use[kRegions] = {with_pen, with_plate, with_mirror, false,
                        with_obstacles};
  if (options_.regions) {
    if (fx.refraction && !grid_.active()) {
      region[3] = WallFreeRect(f);
      use[3] = region[3].z > 0 && region[3].w > 0;
    }
    if (with_pen) {
      region[0] =
          PenRefractionRect(f, real.pen_tip, real.pen_axis, real.pen_length,
                            real.pen_radius, real.pen_margin);
    }
    if (with_plate) region[1] = PlateLookupRect(f, real.mask_window);
    if (with_mirror) region[2] = MirrorLookupRect(f, MirroredObjectsRect(f));
    if (with_obstacles) region[4] = ObstacleLookupRect(f);
  }
  if (!grid_.active() || rect.z <= 0 || rect.w <= 0) {
    glStencilFunc(GL_EQUAL, 1, 0xff);
    state.StencilMask(0);
    ShadeCells(f, real, base, rect, region, use);
    return;
  }
  // (c) On the coarse grid: mark the tank's grown outline, shade the marked
  // texels (the same cells, scaled), then (d) bring them to the output's
  // marked pixels. The grid is cleared only around the water: the upsampling
  // reads no texel outside the outline.
  const glm::ivec4 coarse_rect = grid_.RectOut(rect, 2);
  glm::ivec4 coarse_region[kRegions];
  for (int i = 0; i < kRegions; ++i)
    coarse_region[i] = use[i] ? grid_.RectOut(region[i], 1) : region[i];
  glBindFramebuffer(GL_FRAMEBUFFER, coarse_fbo_.id());
  glViewport(0, 0, grid_.width, grid_.height);
  glScissor(coarse_rect.x, coarse_rect.y, coarse_rect.z, coarse_rect.w);
  glClearColor(0.f, 0.f, 0.f, 0.f);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  MarkCoarseWater(f);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  state.StencilMask(0);
  ShadeCells(f, real, base, coarse_rect, coarse_region, use);
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  glViewport(0, 0, out_width_, out_height_);
  glActiveTexture(GL_TEXTURE0 + kUnitCoarseWater);
  glBindTexture(GL_TEXTURE_2D, coarse_color_.id());
  glUseProgram(upsample_.id());
  glScissor(rect.x, rect.y, rect.z, rect.w);
  glBindVertexArray(empty_vao_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

void WaterPass::ShadeCells(const FrameState& f, const RealObjectsState& real,
                           int base, const glm::ivec4& rect,
                           const glm::ivec4 region_in[kRegions],
                           const bool use[kRegions]) const {
  // The rectangle is cut along the regions' edges into cells, and each run
  // of cells along a row that the same regions hold is drawn once,
  // scissored, by the program with just those effects. The cells do not
  // overlap: llvmpipe's stencil test of a block it then rejects costs about
  // a tenth of shading it.
  const int bit[kRegions] = {kRealPen, kRealPlate, kMirror, kWallFree,
                             kObstacles};
  glm::ivec4 region[kRegions];
  std::copy(region_in, region_in + kRegions, region);
  std::vector<int> xs = {rect.x, rect.x + rect.z};
  std::vector<int> ys = {rect.y, rect.y + rect.w};
  for (int i = 0; i < kRegions; ++i) {
    if (!use[i]) continue;
    // Grown out to llvmpipe's 4x4 blocks: a block that a cell's scissor
    // cuts is shaded whole (its pixels outside masked), so an edge inside a
    // block would shade it once per side. A larger region is still right.
    // The wall-free rectangle bounds where an effect is absent: it comes
    // shrunk to whole blocks already.
    if (bit[i] != kWallFree && region[i].z > 0 && region[i].w > 0) {
      const int x0 = region[i].x & ~3, y0 = region[i].y & ~3;
      const int x1 = (region[i].x + region[i].z + 3) & ~3;
      const int y1 = (region[i].y + region[i].w + 3) & ~3;
      region[i] = {x0, y0, x1 - x0, y1 - y0};
    }
    region[i] = IntersectRect(region[i], rect);
    if (region[i].z <= 0 || region[i].w <= 0) continue;
    xs.insert(xs.end(), {region[i].x, region[i].x + region[i].z});
    ys.insert(ys.end(), {region[i].y, region[i].y + region[i].w});
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  auto effects_at = [&](int x, int y) {
    int e = 0;
    for (int i = 0; i < kRegions; ++i) {
      const glm::ivec4& r = region[i];
      if (use[i] && x >= r.x && x < r.x + r.z && y >= r.y && y < r.y + r.w)
        e |= bit[i];
    }
    return e;
  };
  glBindVertexArray(empty_vao_.id());
  for (size_t b = 0; b + 1 < ys.size(); ++b) {
    const int y0 = ys[b], y1 = ys[b + 1];
    size_t a = 0;
    while (a + 1 < xs.size()) {
      const int e = effects_at(xs[a], y0);
      size_t end = a + 1;
      while (end + 1 < xs.size() && effects_at(xs[end], y0) == e) ++end;
      Prepare(Variant(base | e), f, real);
      glScissor(xs[a], y0, xs[end] - xs[a], y1 - y0);
      glDrawArrays(GL_TRIANGLES, 0, 3);
      a = end;
    }
  }
  glBindVertexArray(0);
}

}  // namespace ripple::render::internal
