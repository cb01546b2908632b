#include "render/pass_obstacles.h"

#include <algorithm>
#include <limits>

#include "render/gl_state.h"
#include "render/shaders.h"

namespace ripple::render::internal {

bool ObstaclesPass::Create(const Options& options, std::string* error) {
  if (!BuildProgram(&solid_[0], "solid", "solid.vert", "solid.frag", "",
                    error) ||
      !BuildProgram(&solid_[1], "shadowed solid", "solid.vert", "solid.frag",
                    "#define SHADOWS 1\n" + options.shadow_defines, error) ||
      !BuildProgram(&depth_, "depth", "solid.vert", "depth.frag", "", error)) {
    return false;
  }
  // The surface's view factors depend on its index only: computed once for
  // both variants.
  const SnellWindowShares w = ComputeSnellWindowShares(options.ior);
  const LowerViewReflectance lower = ComputeLowerViewReflectance(options.ior);
  for (int i = 0; i < 2; ++i) {
    solid_common_[i].Resolve(solid_[i]);  // leaves solid_[i] bound
    solid_model_[i].Resolve(solid_[i]);
    SetUniform(solid_[i].Uniform("u_albedo"), options.albedo);
    ground_[i] = solid_[i].Uniform("u_ground");
    floor_wet_[i] = solid_[i].Uniform("u_floor_wet");
    floor_sky_[i] = solid_[i].Uniform("u_floor_sky");
    floor_sun_[i] = solid_[i].Uniform("u_floor_sun");
    inv_n2_[i] = solid_[i].Uniform("u_inv_n2");
    SetUniform(solid_[i].Uniform("u_window"),
               glm::vec3(w.facing_up, w.facing_side, w.reflectance));
    glUniform2f(solid_[i].Uniform("u_lower_reflectance"),
                static_cast<float>(lower.facing_side),
                static_cast<float>(lower.facing_down));
  }
  depth_model_.Resolve(depth_);
  return true;
}

bool ObstaclesPass::AllocateOutput(int width, int height) {
  // Blits into it copy the encoded values (GL_FRAMEBUFFER_SRGB stays off);
  // the shaders decode them after filtering (DecodeVideo, common.glsl).
  AllocTexture(&scene_copy_tex_, GL_RGBA8, width, height, GL_RGBA,
               GL_UNSIGNED_BYTE, GL_LINEAR, GL_CLAMP_TO_EDGE);
  return AttachColor(&scene_copy_fbo_, scene_copy_tex_);
}

double PenShaftPixelM(const FrameState& f) {
  const SceneInputs& scene = *f.scene;
  const PenGeometry& g = scene.pen;
  const glm::dmat4& m = scene.tank_from_pen;
  double nearest = std::numeric_limits<double>::infinity();
  for (const double z :
       {-0.5 * g.cube_edge, -0.5 * g.cube_edge - g.shaft_length}) {
    const glm::dvec3 end(m * glm::dvec4(0, 0, z, 1));
    nearest = std::min(nearest, glm::distance(end, f.cam_in_tank));
  }
  return nearest / f.k->fx;
}

double PenPhantomInset(const FrameState& f) {
  return std::min(1.5 * PenShaftPixelM(f), 0.7 * f.scene->pen.shaft_radius);
}

void ObstaclesPass::DrawPenPhantom(const FrameState& f,
                                   const SolidMeshes& solids) {
  const SceneInputs& scene = *f.scene;
  if (!scene.pen_visible || !scene.effects.pen_occludes) return;
  GlStateGuard state;
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  state.ColorMask(false);
  glUseProgram(depth_.id());
  const double grow = scene.pen_margin_m;
  solids.Draw(scene, depth_model_, f.clip_from_tank, false, true, {grow, grow});
}

void ObstaclesPass::Draw(const FrameState& f, GLuint target,
                         const SolidMeshes& solids,
                         const FloorReturnLight& floor_return,
                         bool pen_outline_blended) {
  const SceneInputs& scene = *f.scene;
  GlStateGuard state;
  state.Enable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const bool pen_phantom = scene.pen_visible && scene.effects.pen_occludes;
  // The pen's cube and shaft in depth only.
  auto draw_phantom = [&](const PenGrow& grow) {
    state.ColorMask(false);
    glUseProgram(depth_.id());
    solids.Draw(scene, depth_model_, f.clip_from_tank, false, true, grow);
  };
  if (!scene.obstacles.empty()) {
    // The real pen hides the obstacles behind it: its phantom, at its
    // tracked size, lays depth first, and the video (which shows the pen)
    // stays where an obstacle lies behind it. Only over the obstacles'
    // rectangle, where it can hide something.
    if (pen_phantom) {
      const glm::ivec4 rect = ObstaclesRect(f, 1);
      if (rect.z > 0 && rect.w > 0) {
        state.Enable(GL_SCISSOR_TEST);
        glScissor(rect.x, rect.y, rect.z, rect.w);
        draw_phantom({});
        state.ColorMask(true);
        glDisable(GL_SCISSOR_TEST);
      }
    }
    const int i = scene.effects.shadows ? 1 : 0;
    solid_common_[i].Set(solid_[i], f, f.clip_from_tank);
    // The floor's radiance in the water: the dry floor the video shows, lit
    // as the water lights it at its mean (water.frag's floor): the flat
    // surface's sky and light, the surroundings through the walls, and the
    // light the surface returns to it from the floor around.
    const glm::vec3 wet =
        f.ground.floor *
        (FloorMeanLight(f.shading, floor_return) +
         floor_return.mean_return * FloorAroundLight(f.shading, floor_return));
    SetUniform(ground_[i], f.ground.board);
    SetUniform(floor_wet_[i], wet);
    SetUniform(floor_sky_[i], f.shading.floor_sky);
    SetUniform(floor_sun_[i], f.shading.floor_sun);
    glUniform1f(inv_n2_[i], f.shading.inv_n2);
    solids.Draw(scene, solid_model_[i], f.clip_from_tank, true, false);
  }
  // The water looks up points inside the tank, and on the board beyond the
  // walls where its rays leave through them; the walls' top faces look up
  // the board under the glass, past the corners too. So the copy is the
  // window rectangle of the tank's outer box (floor to the wall tops, or to
  // the rest level + 1 cm if higher) grown on the board by the water's
  // depth, which holds the rays that leave a wall up to 45 degrees from the
  // vertical, padded for linear filtering. Texels outside it hold whatever
  // an earlier frame left there.
  const TankGeometry& t = scene.tank;
  const double grow = 2.0 * (f.optics->glass_thickness_m + t.water_level);
  const glm::ivec4 r =
      BoxRect(f.clip_from_tank, t.size_x + grow, t.size_y + grow, 0.0,
              std::max<double>(t.wall_height, t.water_level + 0.01), 2,
              f.k->width, f.k->height);
  if (r.z > 0 && r.w > 0) {
    const int x1 = r.x + r.z, y1 = r.y + r.w;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, scene_copy_fbo_.id());
    glBlitFramebuffer(r.x, r.y, x1, y1, r.x, r.y, x1, y1, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
  }
  glActiveTexture(GL_TEXTURE0 + kUnitScene);
  glBindTexture(GL_TEXTURE_2D, scene_copy_tex_.id());

  if (pen_phantom) {
    // The cube keeps its margin: the clean plate leaves the pen's grown
    // silhouette out of its occluder mask, so the margin is what keeps a
    // hand's edge beside the cube in front of the water.
    const double grow = scene.pen_margin_m;
    draw_phantom({grow, pen_outline_blended ? -PenPhantomInset(f) : grow});
  }
}

}  // namespace ripple::render::internal
