// What the passes of one frame share (internal to render/): values derived
// once per frame from the scene and the camera, the textures earlier passes
// produced, and the uniforms of common.glsl, whose locations every program
// resolves once at link time.
#ifndef RIPPLE_RENDER_FRAME_STATE_H_
#define RIPPLE_RENDER_FRAME_STATE_H_

#include <glm/glm.hpp>

#include "render/camera.h"
#include "render/gl.h"
#include "render/gl_objects.h"
#include "render/optics.h"
#include "render/scene.h"

namespace ripple::render::internal {

// Texture units, fixed for every program (sampler uniforms are set once,
// when a program is linked).
enum TextureUnit : int {
  kUnitHeight = 0,
  kUnitShadow = 1,
  kUnitCaustics = 2,
  kUnitScene = 3,
  kUnitReflection = 4,
  kUnitVideo = 5,
  kUnitCoarseWater = 6,  // the water on its coarse grid (pass_water.h)
  kUnitReceiver = 7,
  kUnitOverlay = 8,
  kUnitFloorReturn = 9,
  kUnitOccluders = 10,
  kUnitPlate = 11,
  kUnitMirror = 12,
  kUnitEnvCube = 13,     // samplerCube: the environment (pass_envmap.h)
  kUnitSky = 14,         // samplerCube: the daylight sky (pass_envmap.h)
  kUnitBoardLight = 15,  // the board's light around the tank
};

// The height texture's mapping (HeightTexturePass).
struct HeightFieldInfo {
  glm::vec2 extent{1.0f};  // metres covered by the texture in x, y
  glm::vec2 texel{1.0f};   // 1 / texels in x, y
  // (h, dh/dx, dh/dy) = offset + scale * the filtered RGBA8 texel's rgb
  // (metres, slopes).
  glm::vec3 decode_scale{0.0f};
  glm::vec3 decode_offset{0.0f};
  // The steepest slope |grad h| over each tile of the field and its eight
  // neighbours (so over every texel that filtering mixes into the tile's
  // lookups), tiles_x * tiles_y row-major from the field's (-x, -y)
  // corner, each tile_m metres square; null for a flat field.
  const float* tile_slope = nullptr;
  int tiles_x = 0, tiles_y = 0;
  float tile_m = 0.0f;
};

// Tank frame -> shadow map texture coordinates and its sampling constants
// (ShadowPass).
struct ShadowTransform {
  glm::dmat4 shadow_from_tank{1.0};
  float bias = 0;         // depth units of the map
  glm::vec2 texel{0.0f};  // PCF / Gaussian tap offset, texture units
};

// A board's linear radiance where no frame shows it: white paper.
constexpr float kPaperRadiance = 0.85f;

// What the virtual obstacles' diffuse surfaces see around them, from the
// video (display units, linear RGB; RendererOptions' video transfer): the
// board around the tank, a ring 1-4 cm outside the inner walls, and the
// tank's floor, its inner 80%, both dry. Each is the mean over the samples
// the frame shows; `fallback` where it shows none.
struct GroundRadiance {
  glm::vec3 board{kPaperRadiance};
  glm::vec3 floor{kPaperRadiance};
};

// Per-frame values, computed once by the renderer.
// What the floor's light under water needs of the water pass's floor-return
// map (optics.h, FloorReturnMap) beyond its texels: the return's ratio of
// the bands to green, and the map's means over the floor (the
// surroundings' light and the return share, per band).
struct FloorReturnLight {
  glm::vec3 tint{1.0f};
  glm::vec3 mean_surround{0.0f};
  glm::vec3 mean_return{0.0f};
  // The floor near the walls under flat water, as the air above sees it:
  // the video's floor 15 mm in from each wall (mean over points along all
  // four), lit as the floor's mean with the surface's return to it, over n^2
  // (what the back and side walls mirror into the tank, walls.frag).
  glm::vec3 floor_seen{0.0f};
  // The floor's mean albedo as the video shows it (linear, each band at most
  // 0.95): the floor around a point, whose light the surface returns to it.
  glm::vec3 floor_albedo{kPaperRadiance};
  // The direct light's mean factor over the floor: the caustics map's mean
  // where caustics are drawn (the light the walls let in adds to what the
  // surface lets in and moves), else 1. The obstacles' shadows are taken
  // at 1.
  float direct_mean = 1.0f;
};

// The floor's mean light under water, relative to the dry board: the sky,
// the direct light at its mean over the floor (the caustics map's mean:
// the surface moves the light, the walls add theirs) and the
// surroundings' mean. The surface's return to a point comes from the floor
// around it (a totally reflected ray lands two depths times the critical
// angle's tangent away or more), lit as this mean, not as the point
// (water.frag, walls.frag).
inline glm::vec3 FloorMeanLight(const WaterShading& s,
                                const FloorReturnLight& r) {
  return s.floor_sky + s.floor_sun * r.direct_mean + r.mean_surround;
}

// What the surface sends back to a floor point per unit of its return
// share: the radiance of the floor around it, of the floor's mean albedo,
// lit as the floor's mean and by its own return,
// rho_mean E_mean / (1 - R_mean rho_mean). A point's own albedo does not
// enter: on a tiled floor a white tile and the grout beside it get the
// same light back.
inline glm::vec3 FloorAroundLight(const WaterShading& s,
                                  const FloorReturnLight& r) {
  return r.floor_albedo * FloorMeanLight(s, r) /
         (glm::vec3(1.0f) - r.mean_return * r.floor_albedo);
}

// WaterShading::under_glass (walls +x, -x, +y, -y) as the basis the
// shaders take: the board under the wall whose inward normal is n (one of
// +-x, +-y) is b[0] + n.x b[1] + n.y b[2] + |n.x| b[3], three multiply-adds
// instead of a choice among four.
inline void UnderGlassBasis(const WaterShading& s, glm::vec3 b[4]) {
  const glm::vec3* u = s.under_glass;
  b[0] = 0.5f * (u[2] + u[3]);
  b[1] = 0.5f * (u[1] - u[0]);
  b[2] = 0.5f * (u[3] - u[2]);
  b[3] = 0.5f * (u[0] + u[1]) - b[0];
}

struct FrameState {
  const SceneInputs* scene = nullptr;
  const Intrinsics* k = nullptr;
  glm::dmat4 clip_from_tank{1.0};
  glm::dmat4 tank_from_cam{1.0};
  glm::dvec3 cam_in_tank{0.0};
  glm::dvec3 light{0.0, 0.0, 1.0};             // unit, towards the light
  glm::dvec3 light_refracted{0.0, 0.0, -1.0};  // under a flat surface
  HeightFieldInfo height;
  ShadowTransform shadow;
  const WaterOptics* optics = nullptr;
  WaterShading shading;            // for this light and depth
  glm::dmat3 cube_from_tank{1.0};  // the environment cube's frame
  bool srgb_output = true;
  GroundRadiance ground;  // the obstacles' surroundings (MeasureGroundRadiance)
  // The board around the tank that the board-light pass changes (tank frame
  // x0, y0, x1, y1, metres, z = 0); empty (x0 >= x1) when it is off.
  glm::dvec4 board_light_rect{0.0};
  // The caustics map's mean over the floor this frame (CausticsPass::mean);
  // 1 without caustics.
  float caustics_mean = 1.0f;
};

// `optics` must outlive the frame; `shading` is left for the caller, which
// caches it (ComputeWaterShading integrates over the sky).
FrameState MakeFrameState(const SceneInputs& scene, const Intrinsics& k,
                          const WaterOptics& optics, Transfer transfer);

// The uniforms of common.glsl in one program.
class CommonUniforms {
 public:
  // Resolves the locations and sets the sampler units; `p` must be linked.
  // Leaves `p` bound.
  void Resolve(const Program& p);
  // Binds the program and sets the per-frame values; `clip_from_tank` is
  // the program's own projection (the camera's, or the identity for
  // full-screen passes).
  void Set(const Program& p, const FrameState& f,
           const glm::dmat4& clip_from_tank) const;

 private:
  GLint clip_from_tank_ = -1, cam_from_tank_ = -1, tank_from_cam_ = -1,
        intr_ = -1, image_size_ = -1, cam_in_tank_ = -1, tank_ = -1,
        hf_extent_ = -1, hf_texel_ = -1, hf_scale_ = -1, hf_offset_ = -1,
        light_ = -1, light_refracted_ = -1, shadow_from_tank_ = -1,
        shadow_on_ = -1, shadow_texel_ = -1, shadow_bias_ = -1, srgb_out_ = -1,
        knee_ = -1, ambient_ = -1, cube_from_tank_ = -1, dist0_ = -1,
        dist1_ = -1;
};

// The video's linear radiance (RGB; decoded when `srgb`) at the board point
// q (tank frame, z = 0), through the lens as the frame shows it; false when
// it lies behind the camera or outside the frame, or there is no frame.
bool VideoRadianceAt(const VideoFrame& v, const Intrinsics& k,
                     const glm::dmat4& cam_from_tank, const glm::dvec2& q,
                     bool srgb, glm::dvec3* rgb);

// GroundRadiance for this frame's video.
GroundRadiance MeasureGroundRadiance(const SceneInputs& scene,
                                     const Intrinsics& k, bool srgb,
                                     const GroundRadiance& fallback);

// glUniform wrappers for glm types (location -1 is ignored, as by GL).
void SetUniform(GLint location, const glm::dmat4& m);
void SetUniform(GLint location, const glm::dmat3& m);
void SetUniform(GLint location, const glm::vec3& v);
void SetUniform(GLint location, const glm::dvec3& v);

// The corners of a centred box in the tank frame (x, y sizes, z from z0 to
// z1): bit 0 of the index picks +x, bit 1 +y, bit 2 z1.
void BoxCorners(double size_x, double size_y, double z0, double z1,
                glm::dvec3 corners[8]);

// Window rectangle (x, y, w, h) of a centred box in the tank frame (x, y
// sizes, z from z0 to z1), grown by `pad` pixels and clipped to the window;
// the whole window when a corner is behind the camera.
glm::ivec4 BoxRect(const glm::dmat4& clip_from_tank, double size_x,
                   double size_y, double z0, double z1, int pad, int width,
                   int height);

// The same for `n` tank-frame points.
glm::ivec4 PointsRect(const glm::dmat4& clip_from_tank, const glm::dvec3* p,
                      int n, int pad, int width, int height);

// The smallest rectangle holding both (an empty one counts as nothing).
glm::ivec4 UnionRect(const glm::ivec4& a, const glm::ivec4& b);

// The tank-frame corners of an obstacle's bounding box.
void ObstacleBoxCorners(const Obstacle& o, glm::dvec3 corners[8]);

// Window rectangle of every obstacle's bounding box, grown by `pad` pixels
// (as PointsRect); empty when there is no obstacle.
glm::ivec4 ObstaclesRect(const FrameState& f, int pad);

// The output's window (x, y, w, h; window pixels, top row first): every
// pixel a pass can change. That is the tank's box out to the glass's outer
// faces, from its floor to the wall tops (or the rest level + 1 cm, if
// higher), and every obstacle's
// bounding box, grown by `pad` pixels. Outside it the output is the video
// as it came; the pen's phantom and the occluders only lay depth.
glm::ivec4 OutputWindow(const FrameState& f, int pad);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_FRAME_STATE_H_
