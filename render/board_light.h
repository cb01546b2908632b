// The light on the board around the tank (internal to render/): the glass
// tank of water stands on the real board, so the board beside it receives
// the light and sees the sky through glass and water. On the side away from
// the light the water column's shadow falls (light that enters through the
// surface meets the side walls beyond the critical angle and is mirrored
// back onto the tank's floor); everywhere near the walls part of the sky is
// replaced by what the glass shows (the tank's floor through the water, the
// board mirrored in the glass). The renderer multiplies the video's board by
// this map (differential rendering: the real board's light with the tank
// over the light without it).
//
// Frames and units: tank frame (origin at the tank's centre, z up, the board
// at z = 0), metres. Light in the display units of optics.h: a dry board
// point without the tank receives 1 (the sky a, the light 1 - a).
//
// The tank: glass walls `glass_thickness_m` thick outside the inner size,
// wall_height tall, standing on the board, water at rest up to water_level
// inside (a flat surface: the waves' own light outside the tank is left
// out). Paths are followed through every interface (tank_paths.h).
#ifndef RIPPLE_RENDER_BOARD_LIGHT_H_
#define RIPPLE_RENDER_BOARD_LIGHT_H_

#include <glm/glm.hpp>
#include <vector>

#include "render/optics.h"
#include "render/scene.h"

namespace ripple::render::internal {

struct BoardLightOptions {
  // The map's texel, metres: the direct light's (its shadow's edges are
  // sharp: the light's 2 degree disc blurs them by 1.4 mm at the walls'
  // 40 mm). The sky's view changes slowly: it is traced on a grid of
  // `sky_texels` map texels and interpolated.
  double texel_m = 0.00125;
  int sky_texels = 2;
  // Sky directions per view texel (a fixed stratified, cosine-weighted
  // set, rounded down to the square of an even number), and light paths per map
  // texel along x and y (the light's disc taken at its centre).
  int sky_rays = 144;
  int light_paths_per_axis = 2;
};

// Where the light of a board texel comes from, each relative to the dry
// board's light (the terms that do not depend on the light's direction).
struct BoardSkyView {
  // Its grid, centred on the tank (so the tank's symmetry in x and y maps
  // it onto itself): texel centres at origin + (i + 1/2, j + 1/2) texel;
  // points inside the footprint are traced from the nearest point outside
  // it, so that lookups near the walls interpolate the outside only.
  glm::dvec2 origin{0.0};
  double texel = 0;
  int nx = 0, ny = 0;
  // The sky seen, per band (through glass and water, Fresnel and
  // absorption on the way): 1 with nothing in the way.
  std::vector<glm::vec3> sky;
  // Diffuse surfaces seen through the tank (per texel, green band): the
  // board around (through the water and in the glass's mirror) in units of
  // its radiance, the tank's floor in units of its radiance as the air
  // above the water sees it (over n^2), the board under the glass walls in
  // units of its radiance over the dry board's.
  std::vector<float> board, floor, under_glass;
};

// One texel's light over the dry board's, per band, for a board of radiance
// G in display units: light + G (diffuse + floor x F), with `light` the
// sky's share a * sky_tint * sky plus the light's (1 - a) * sun_tint *
// direct, `diffuse` the board and the board under the glass that the tank
// shows in place of the sky, in units of G, and `floor` the tank's floor,
// in units of its radiance as the air above the water sees it (its light
// with the surface's return, over n^2), F that radiance over G. 1 where the
// tank changes nothing.
struct BoardTexel {
  glm::vec3 light{1.0f};
  float diffuse = 0, floor = 0;
  float Factor(int band, float ground, float floor_over_ground) const {
    return light[band] + ground * (diffuse + floor * floor_over_ground);
  }
};

struct BoardLightMap {
  glm::dvec2 origin{0.0};  // tank-frame x, y of the map's (-x, -y) corner
  double texel = 0;        // metres
  int nx = 0, ny = 0;      // texels, row j along y
  // The outer footprint of the tank (glass included): half sizes.
  double outer_x = 0, outer_y = 0;
  BoardSkyView view;
  // The direct light (the disc) reaching each texel, per band, relative to
  // the open board's; 0 inside the outer footprint.
  std::vector<glm::vec3> direct;

  // The board's light over the dry board's at texel (i, j), in its parts
  // (BoardTexel); `under_glass_light` is the board's light under the walls,
  // relative to the dry board. A texel inside the footprint takes its
  // nearest outside texel's value (bilinear lookups at the footprint's edge
  // then see only the outside).
  BoardTexel Texel(int i, int j, const WaterOptics& optics,
                   float under_glass_light) const;
  bool InFootprint(double x, double y) const;
  // The board's light at tank-frame (x, y) over the dry board's, per band,
  // for white paper (radiance `paper`) beside the tank and a tank floor as
  // bright as the paper: the texel's (nearest texel) factor; 1 outside the
  // map.
  glm::vec3 LightAt(double x, double y, const WaterOptics& optics,
                    float paper) const;
};

// The map's rectangle: the outer footprint grown by two wall heights
// (TankShadowReach), where the walls hide about 5% of the sky, and the
// walls' shadow reaches for a light 27 degrees or more above the board (a
// lower light's shadow is cut at the map's edge).
BoardLightMap BoardLightLayout(const TankGeometry& tank,
                               const WaterOptics& optics,
                               const BoardLightOptions& options);

// Fills map->view: for each texel's centre, the stratified sky directions
// traced through the tank. Depends on the tank and the optics only.
void ComputeBoardSkyView(const TankGeometry& tank, const WaterOptics& optics,
                         const BoardLightOptions& options, BoardLightMap* map);

// Fills map->direct: light paths launched towards -light over a lattice of
// light_paths_per_axis^2 points per texel, aimed where each would meet the
// board without the tank, traced through the tank and splatted bilinearly
// (so the open board receives exactly 1).
void ComputeBoardDirectLight(const TankGeometry& tank,
                             const WaterOptics& optics, const glm::dvec3& light,
                             const BoardLightOptions& options,
                             BoardLightMap* map);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_BOARD_LIGHT_H_
