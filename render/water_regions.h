// Water regions (internal to render/): window rectangles outside which an
// effect of the water shader cannot change a pixel, so that the water pass
// shades the rest of the water with a program that leaves the effect out
// (llvmpipe runs every instruction of a program on every pixel, so an effect
// that touches a few per cent of the water would otherwise cost its full
// price on all of it).
//
// Each rectangle bounds the surface points (z within this frame's lowest
// and highest surface, the height texture's decoded range) whose shading
// can involve the effect, for the frame's steepest surface slope (the
// height texture's range) or, where the rectangle is made tile by tile,
// each slope tile's own (HeightFieldInfo::tile_slope):
//  - the real pen: the refracted ray from the surface meets the submerged
//    shaft. The surface point seeing an underwater point P lies within
//    depth(P) * k of the point above P, k the largest horizontal travel per
//    unit depth of a refracted ray (the camera's rays to the tank's corners,
//    normals tilted up to the steepest slope);
//  - the mirror (pass_mirror.h): the lookup at the surface point displaced by
//    2 * kMirrorDepth_m * the normal's xy lands where the mirror holds
//    something, the mirrored objects' screen box; the displacement is
//    bounded tile by tile by the steepest slope around each tile of the
//    field (HeightFieldInfo::tile_slope), so calm water far from the
//    objects takes no mirror;
//  - the clean plate: the refracted lookup point on the board (the floor,
//    the floor in a wall's mirror, or the board beyond the glass) is seen in
//    the occluder mask's window; it lies within (k + k_out) * depth of the
//    surface point, k_out the travel of the ray that left through a wall,
//    plus the shift along a wall inside its glass of a ray the glass
//    totally reflects;
//  - the virtual obstacles: the refracted lookup point lands on the board
//    an obstacle hides from the camera (ObstacleLookupRect), where the scene
//    copy shows the obstacle; tile by tile, so calm water reaches only as
//    far as its rays travel.
// A rectangle is empty ({0, 0, 0, 0}) when the effect touches nothing and
// the whole window when the bound cannot be made (a point behind the
// camera, the camera under the water, rays near the horizontal).
#ifndef RIPPLE_RENDER_WATER_REGIONS_H_
#define RIPPLE_RENDER_WATER_REGIONS_H_

#include <glm/glm.hpp>

#include "render/frame_state.h"

namespace ripple::render::internal {

// The height the water shader's mirror lookup assumes for what it mirrors.
constexpr float kMirrorDepth_m = 0.03f;

// Surface points whose refracted ray may meet the shaft of radius `radius`
// (+ `margin`) from `tip` along the unit `axis` for `length`.
glm::ivec4 PenRefractionRect(const FrameState& f, const glm::dvec3& tip,
                             const glm::dvec3& axis, double length,
                             double radius, double margin);

// Surface points whose mirror lookup may land inside `mirror_window` (the
// mirrored objects' window rectangle).
glm::ivec4 MirrorLookupRect(const FrameState& f,
                            const glm::ivec4& mirror_window);

// Window rectangle of the mirror images (z -> 2 level - z) of the scene's
// obstacles and, when visible, the pen; empty if there are none.
glm::ivec4 MirroredObjectsRect(const FrameState& f);

// Surface points whose refracted lookup on the board (z = 0) may be seen
// in `image_window` (x, y, w, h: image pixels, the occluder mask's window).
glm::ivec4 PlateLookupRect(const FrameState& f, const glm::ivec4& image_window);

// Surface points whose refracted lookup may land where the scene copy shows
// a virtual obstacle: board points the obstacles hide from the camera (their
// bounding boxes carried along the camera's rays to the board), reached by
// a ray straight (the rays' horizontal travel towards each wall), after a
// side wall's mirror (the hidden box's mirror image), or out through a
// wall (as PlateLookupRect).
glm::ivec4 ObstacleLookupRect(const FrameState& f);

// A rectangle inside which no pixel's shading involves a wall (unlike the
// others, it bounds where an effect is absent): every surface point seen
// there has a view ray that reaches it without crossing a wall's glass on
// the camera's side (over the wall's top instead), and a refracted ray that
// meets the floor before any wall, for any normal within this frame's
// steepest slope. Those are the surface points farther than the refracted
// ray's horizontal reach over the deepest water from every wall, and beyond
// the line where a camera-side wall's top hides the surface; the rectangle
// is the largest one aligned with the window inside that box's image on
// both surface planes (checked at its corners, the region being convex),
// shrunk to llvmpipe's 4 x 4 blocks. Empty when none can be made (the
// camera under a wall's top, rays near the horizontal, a box off screen).
glm::ivec4 WallFreeRect(const FrameState& f);

// The overlap of two rectangles (empty if none).
glm::ivec4 IntersectRect(const glm::ivec4& a, const glm::ivec4& b);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_WATER_REGIONS_H_
