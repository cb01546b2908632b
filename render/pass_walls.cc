#include "render/pass_walls.h"

#include <algorithm>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool WallsPass::Create(const Options& options, std::string* error) {
  std::string defines;
  if (options.env_cube) defines += "#define ENV_CUBE 1\n";
  if (options.sky) defines += "#define SKY 1\n";
  if (!BuildProgram(&programs_[0], "walls", "walls.vert", "walls.frag", defines,
                    error)) {
    return false;
  }
  for (int v = 0; v < 4; ++v) {
    std::string front = defines + "#define FRONT_WALL 1\n";
    if (v & 1) front += "#define SHADOWS 1\n";
    if (v & 2) front += "#define CAUSTICS 1\n";
    if (!BuildProgram(&programs_[1 + v], "front walls", "walls.vert",
                      "walls.frag", front, error)) {
      return false;
    }
  }
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
  }
  return true;
}

void WallsPass::Draw(const FrameState& f, const TankWallsMesh& walls,
                     const glm::vec3& return_tint) {
  GlStateGuard state;
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  state.Enable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_SRC1_COLOR);
  state.DepthMask(false);
  glBindVertexArray(walls.vao());
  // Which side of each wall's plane the camera is on (wall i as in
  // TankWallsMesh): outside means the wall faces the camera.
  const glm::dvec3& cam = f.cam_in_tank;
  const TankGeometry& t = f.scene->tank;
  const glm::dvec3 hs(0.5 * t.size_x, 0.5 * t.size_y, 0);
  const double outside[4] = {-hs.y - cam.y, cam.x - hs.x, cam.y - hs.y,
                             -hs.x - cam.x};
  // Front walls: under the water (and a margin for the waves) with the
  // FRONT_WALL program, above it with the plain one, which is the same
  // there.
  const float split =
      std::min(t.wall_height, t.water_level + kFrontWallMargin_m);
  const Effects& fx = f.scene->effects;
  const int front_program = 1 + (fx.shadows ? 1 : 0) + (fx.caustics ? 2 : 0);
  for (int pass = 0; pass < 2; ++pass) {
    const int p = pass == 0 ? 0 : front_program;
    common_[p].Set(programs_[p], f, f.clip_from_tank);
    SetUniform(floor_sky_[p], f.shading.floor_sky);
    SetUniform(floor_sun_[p], f.shading.floor_sun);
    glUniform1f(inv_n2_[p], f.shading.inv_n2);
    SetUniform(return_tint_[p], return_tint);
    for (int i = 0; i < 4; ++i) {
      const bool front = outside[i] > 0;
      if (pass == 1 && !front) continue;
      if (pass == 0 && front) {
        glUniform2f(z_range_[p], split, t.wall_height);
      } else if (pass == 1) {
        glUniform2f(z_range_[p], 0.0f, split);
      } else {
        glUniform2f(z_range_[p], 0.0f, t.wall_height);
      }
      glDrawArrays(GL_TRIANGLES, 6 * i, 6);
    }
  }
  glBindVertexArray(0);
}

}  // namespace ripple::render::internal
