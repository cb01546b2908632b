#include "render/pass_walls.h"

#include <algorithm>
#include <string>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool WallsPass::Create(const Options& options, std::string* error) {
  std::string defines;
  if (options.env_cube) defines += "#define ENV_CUBE 1\n";
  if (options.sky) defines += "#define SKY 1\n";
  if (!BuildProgram(&programs_[0], "walls", "walls.vert", "walls.frag", defines,
                    error) ||
      !BuildProgram(&programs_[kFrontAbove], "front walls over the water",
                    "walls.vert", "walls.frag",
                    defines + "#define BOARD_MIRROR 1\n", error)) {
    return false;
  }
  for (int v = 0; v < 8; ++v) {
    std::string front =
        defines + "#define FRONT_WALL 1\n#define BOARD_MIRROR 1\n";
    if (v & 1) front += "#define SHADOWS 1\n";
    if (v & 2) front += "#define CAUSTICS 1\n";
    if (v & 4) front += "#define UNDER_SURFACE 1\n";
    if (!BuildProgram(&programs_[1 + v], "front walls", "walls.vert",
                      "walls.frag", front, error)) {
      return false;
    }
  }
  if (!BuildProgram(&tops_, "walls' top faces", "wall_tops.vert",
                    "wall_tops.frag", defines, error))
    return false;
  tops_common_.Resolve(tops_);  // leaves it bound
  glUniform1f(tops_.Uniform("u_glass_ior"), options.optics.glass_ior);
  glUniform1f(tops_.Uniform("u_ior"), options.optics.ior);
  glUniform1f(tops_.Uniform("u_glass_thickness"),
              options.optics.glass_thickness_m);
  for (int w = 0; w < 4; ++w) {
    const std::string name = "u_under_glass[" + std::to_string(w) + "]";
    tops_under_glass_[w] = tops_.Uniform(name.c_str());
  }
  tops_floor_seen_ = tops_.Uniform("u_floor_seen");
  tops_grow_ = tops_.Uniform("u_top_grow");
  for (int i = 0; i < kPrograms; ++i) {
    common_[i].Resolve(programs_[i]);  // leaves it bound
    SetUniform(programs_[i].Uniform("u_sigma"),
               options.optics.absorption_per_m);
    SetUniform(programs_[i].Uniform("u_scatter"), options.optics.scatter_color);
    glUniform1f(programs_[i].Uniform("u_glass_ior"), options.optics.glass_ior);
    glUniform1f(programs_[i].Uniform("u_ior"), options.optics.ior);
    glUniform1i(programs_[i].Uniform("u_floor_return"), kUnitFloorReturn);
    floor_sky_[i] = programs_[i].Uniform("u_floor_sky");
    floor_sun_[i] = programs_[i].Uniform("u_floor_sun");
    inv_n2_[i] = programs_[i].Uniform("u_inv_n2");
    z_range_[i] = programs_[i].Uniform("u_z_range");
    return_tint_[i] = programs_[i].Uniform("u_return_tint");
    floor_around_[i] = programs_[i].Uniform("u_floor_around");
    board_mirror_[i] = programs_[i].Uniform("u_board_mirror");
    floor_seen_[i] = programs_[i].Uniform("u_floor_seen");
  }
  return true;
}

void WallsPass::Draw(const FrameState& f, const TankWallsMesh& walls,
                     const FloorReturnLight& floor_return, bool board_mirror,
                     GLuint target, GLuint srgb_target) {
  GlStateGuard state;
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  state.Enable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_SRC1_COLOR);
  // Blend in linear light: the sRGB view decodes and encodes.
  if (f.srgb_output) {
    glBindFramebuffer(GL_FRAMEBUFFER, srgb_target);
    state.Enable(GL_FRAMEBUFFER_SRGB);
  }
  state.DepthMask(false);
  glBindVertexArray(walls.vao());
  // Which side of each wall's plane the camera is on (wall i as in
  // TankWallsMesh): outside means the wall faces the camera.
  const glm::dvec3& cam = f.cam_in_tank;
  const TankGeometry& t = f.scene->tank;
  const glm::dvec3 hs(0.5 * t.size_x, 0.5 * t.size_y, 0);
  const double outside[4] = {-hs.y - cam.y, cam.x - hs.x, cam.y - hs.y,
                             -hs.x - cam.x};
  // Front walls: between the surface's lowest and highest points (this
  // frame's height range, widened by kSurfaceSlack_m) with the
  // FRONT_WALL program, which tests each pixel against the surface; above
  // with the plain one, which is the same there; under with the variant
  // that skips the test.
  const HeightFieldInfo& h = f.height;
  const float split = std::clamp(
      t.water_level + h.decode_offset.x + h.decode_scale.x + kSurfaceSlack_m,
      0.0f, t.wall_height);
  // Far walls are drawn from the same height: nothing under the surface's
  // lowest point shows. A ray from the camera (above the water) to such a
  // point crosses the surface mesh inside the tank, whose depth hides it,
  // or enters through a front wall under the water, whose program replaces
  // the pixel.
  const float deep = std::clamp(
      t.water_level + h.decode_offset.x - kSurfaceSlack_m, 0.0f, split);
  const Effects& fx = f.scene->effects;
  const int front_program = 1 + (fx.shadows ? 1 : 0) + (fx.caustics ? 2 : 0);
  // (program, z range, which walls), farthest first (the blend is not
  // commutative where a front wall covers a far one at the corners): far
  // walls; the front walls' part over the water, near the surface, under
  // it.
  struct Part {
    int program;
    float z0, z1;
    bool front;
  };
  const Part parts[4] = {{0, deep, t.wall_height, false},
                         {kFrontAbove, split, t.wall_height, true},
                         {front_program, deep, split, true},
                         {front_program + 4, 0.0f, deep, true}};
  for (const Part& part : parts) {
    if (!(part.z1 > part.z0)) continue;
    const int p = part.program;
    common_[p].Set(programs_[p], f, f.clip_from_tank);
    SetUniform(floor_sky_[p], f.shading.floor_sky);
    SetUniform(floor_sun_[p], f.shading.floor_sun);
    glUniform1f(inv_n2_[p], f.shading.inv_n2);
    SetUniform(return_tint_[p], floor_return.tint);
    SetUniform(floor_around_[p], FloorAroundLight(f.shading, floor_return));
    glUniform1f(board_mirror_[p], board_mirror ? 1.0f : 0.0f);
    SetUniform(floor_seen_[p], floor_return.floor_seen);
    glUniform2f(z_range_[p], part.z0, part.z1);
    for (int i = 0; i < 4; ++i) {
      if ((outside[i] > 0) == part.front) glDrawArrays(GL_TRIANGLES, 6 * i, 6);
    }
  }
  // The top faces replace what lies behind them, except in their edges'
  // pixels, which they cover by share: blended in linear light, on the
  // same sRGB view as the walls.
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  tops_common_.Set(tops_, f, f.clip_from_tank);
  // Widened by a pixel and a half at the tank's distance, each way.
  glUniform1f(tops_grow_,
              static_cast<float>(1.5 * glm::length(f.cam_in_tank) / f.k->fx));
  glm::vec3 basis[4];
  UnderGlassBasis(f.shading, basis);
  for (int w = 0; w < 4; ++w) SetUniform(tops_under_glass_[w], basis[w]);
  SetUniform(tops_floor_seen_, floor_return.floor_seen);
  glDrawArrays(GL_TRIANGLES, TankWallsMesh::kTopFirst,
               TankWallsMesh::kTopCount);
  glBindVertexArray(0);
  if (f.srgb_output) glBindFramebuffer(GL_FRAMEBUFFER, target);
}

}  // namespace ripple::render::internal
