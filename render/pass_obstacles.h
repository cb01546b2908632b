// Obstacles pass (internal to render/): draws the virtual obstacles over the
// video (lit by the sky, the board around them and the light; under the
// water by the floor around them, lit as the water lights it, and the light
// through the surface), copies video + obstacles under the tank for the
// water's refraction, and lays the real pen's depth (a phantom: no colour):
// at its size before the obstacles, so that the pen hides an obstacle behind
// it, and grown by the scene's margin after the copy, so that it hides the
// water where it is in front of it. Where the water's pen outline is
// blended by its share (pass_pen_outline.h), the shaft is laid a pixel and
// a half inside its size instead (the outline's pixels get the water, to be
// blended), and DrawPenPhantom lays the grown phantom after the blend, for
// the walls.
//
// Redraw key: none (the output is redrawn every frame).
#ifndef RIPPLE_RENDER_PASS_OBSTACLES_H_
#define RIPPLE_RENDER_PASS_OBSTACLES_H_

#include <glm/glm.hpp>
#include <string>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/meshes.h"

namespace ripple::render::internal {

class ObstaclesPass {
 public:
  struct Options {
    glm::vec3 albedo{0.80f, 0.76f, 0.70f};  // linear RGB
    // ShadowFilterDefines of the renderer's filter (pass_shadow.h).
    std::string shadow_defines;
    float ior = 1.333f;  // water: Snell's window under its surface
  };
  bool Create(const Options& options, std::string* error);
  // (Re)allocates the refraction copy at the output's size.
  bool AllocateOutput(int width, int height);

  // Draws into `target` (bound, depth cleared); leaves the refraction copy
  // bound to kUnitScene.
  // `floor_return`: this frame's floor-return means (WaterPass::
  // UpdateFloorLight), for the floor's light under water.
  // `pen_outline_blended`: PenOutlinePass blends the shaft's outline over
  // the water this frame (WaterPass::ShadesRealPen).
  void Draw(const FrameState& f, GLuint target, const SolidMeshes& solids,
            const FloorReturnLight& floor_return, bool pen_outline_blended);
  // The pen's phantom grown by the scene's margin, in depth only (into the
  // bound target), when the scene shows the pen.
  void DrawPenPhantom(const FrameState& f, const SolidMeshes& solids);

  GLuint scene_texture() const { return scene_copy_tex_.id(); }

 private:
  Program solid_[2];  // without, with shadows
  CommonUniforms solid_common_[2];
  ModelUniforms solid_model_[2];
  GLint ground_[2] = {-1, -1}, floor_wet_[2] = {-1, -1},
        floor_sky_[2] = {-1, -1}, floor_sun_[2] = {-1, -1},
        inv_n2_[2] = {-1, -1};
  Program depth_;
  ModelUniforms depth_model_;
  Texture scene_copy_tex_;
  Framebuffer scene_copy_fbo_;
};

// A pixel's width at the pen's shaft end nearest the camera (metres): where
// the shaft is widest on screen.
double PenShaftPixelM(const FrameState& f);

// How far inside its radius the shaft's phantom is laid where the pen's
// outline is blended (PenOutlinePass): a pixel and a half at the shaft's
// end nearest the camera, but at most 70% of the radius (metres).
double PenPhantomInset(const FrameState& f);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_OBSTACLES_H_
