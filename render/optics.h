// Optics of the water, the glass walls and the display, computed on the CPU:
// Fresnel reflectance, pure water's absorption, the sRGB transfer, the
// highlight shoulder, and the per-frame constants of the water's shading
// model. Shared by the real-time renderer (uniforms) and its tests.
//
// Radiometric convention (also the offline reference's): display values are
// linear radiance in which a dry, unshadowed horizontal board point of albedo
// rho reads exactly rho. The light is a distant disc towards `light` plus a
// uniform sky; with ambient share a and cos_l = light.z the sky's radiance is
// a and the disc's irradiance (normal to it) is (1 - a) pi / cos_l, so the
// camera image of the dry board shows its albedo times its real shadowing.
#ifndef RIPPLE_RENDER_OPTICS_H_
#define RIPPLE_RENDER_OPTICS_H_

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "render/sun.h"

namespace ripple::render {

// Unpolarised reflectance of a smooth interface between media of refractive
// indices n1 (incident side) and n2, for light arriving at cos_incident
// (against the normal, in [0, 1]): the mean of the s and p Fresnel
// equations. 1 under total internal reflection.
double FresnelReflectance(double cos_incident, double n1, double n2);

// Reflectance of a thin glass side wall met from the water at cos_incident:
// water-glass, then glass-air (1 beyond the glass-air critical angle);
// multiple reflections inside the glass are not summed.
double SideWallReflectance(double cos_incident, double n_water, double n_glass);

// Absorption coefficient of pure water (1/m) at a wavelength in
// [380, 720] nm: Pope & Fry (1997), "Absorption spectrum (380-700 nm) of pure
// water. II. Integrating cavity measurements", Appl. Opt. 36(33), Table 3,
// sampled every 10 nm and interpolated linearly (clamped outside the range;
// 710 and 720 nm from the same series).
double PureWaterAbsorptionAt(double wavelength_nm);

// The camera's three bands as box filters: blue 400-500 nm, green
// 500-600 nm, red 600-700 nm. Mean of PureWaterAbsorptionAt over each band
// (trapezoidal over the 10 nm table), RGB order: about (0.36, 0.070, 0.0088).
glm::dvec3 PureWaterAbsorptionRgb();

// The sRGB transfer (IEC 61966-2-1), piecewise, values in [0, 1].
double SrgbToLinear(double encoded);
double LinearToSrgb(double linear);

// Highlight shoulder: the identity up to `knee`, then a rational roll-off
// towards 1 (Reinhard's x / (1 + x) on the part above the knee, scaled to
// the room left), with slope 1 at the knee, so radiance above the display
// range keeps its order and shape instead of clipping flat. knee in (0, 1).
double HighlightShoulder(double linear, double knee);

// Share of uniform (Lambertian) radiance inside a medium of index n that a
// flat interface to air (index 1) reflects back into it: the cosine-weighted
// hemispherical mean of FresnelReflectance, total internal reflection
// included (1 - 1/n^2 of it from beyond the critical angle). About 0.475 for
// water.
double DiffuseInternalReflectance(double n);

// What a plane under a flat surface (index n over air) sees above it: the
// cosine-weighted share of pi that Snell's window (the cone of half-angle
// asin(1 / n) about the vertical) covers, for a plane facing up,
// sin^2(theta_c), and for a vertical one, (theta_c - sin theta_c cos
// theta_c) / pi; the rest of the plane's upper view (1 and 1/2 in all) is the
// surface's total reflection. `reflectance` is the window's own mean Fresnel
// reflectance seen from below (cosine-weighted over the window, so that
// facing_up * reflectance + cos^2(theta_c) = DiffuseInternalReflectance).
struct SnellWindowShares {
  double facing_up = 0;
  double facing_side = 0;
  double reflectance = 0;
};
SnellWindowShares ComputeSnellWindowShares(double n);

// What a plane above a flat surface (index n under air) sees of it below:
// the surface's mean Fresnel reflectance over the plane's lower view,
// cosine-weighted about the plane's normal, for a plane facing down (the
// surface's diffuse reflectance from above, about 0.066 for water) and for
// a vertical one (its lower view lies mostly near the horizon, where the
// surface is a mirror: about 0.21). Such a plane sees the floor through
// the water by 1 - it and the sky mirrored by it.
struct LowerViewReflectance {
  double facing_down = 0;
  double facing_side = 0;
};
LowerViewReflectance ComputeLowerViewReflectance(double n);

// Cosine-weighted hemispherical transmittance of a uniform sky through a flat
// surface of index n into a layer of depth `depth_m` with absorption
// `sigma_per_m`, to its floor: the mean over sky directions of
// (1 - F(theta)) exp(-sigma depth / cos(theta_refracted)).
double SkyTransmittance(double n, double sigma_per_m, double depth_m);

// The direct light's transmittance through a flat surface to a floor
// `depth_m` below: (1 - F(theta_l)) exp(-sigma depth / cos(theta_refracted)),
// for a light at cos_light above the horizon.
double DirectTransmittance(double cos_light, double n, double sigma_per_m,
                           double depth_m);

// The water's optical parameters.
enum class WaterLook {
  kClear,  // pure water: Pope & Fry absorption, no scatter colour
  kPool,   // the stylised pool: strong cyan absorption and a deep-water colour
};
bool ParseWaterLook(const std::string& name, WaterLook* look);
const char* WaterLookName(WaterLook look);

// The video's (and so the output's) encoding: geometry/camera_model.h.
using geometry::Transfer;

struct WaterOptics {
  // Defaults: the clear look.
  WaterLook look = WaterLook::kClear;
  glm::vec3 absorption_per_m = glm::vec3(PureWaterAbsorptionRgb());  // 1/m
  glm::vec3 scatter_color{0.0f};  // linear RGB of deep water; 0 = none
  float ior = 1.333f;             // water, visible light at 20 C
  float glass_ior = 1.5f;         // the tank's walls
  // The walls' glass outside the tank's inner size, metres: a ray the glass
  // totally reflects does so at its outer face (water.frag).
  float glass_thickness_m = 0.003f;
  // Share of the board's light that comes from the sky (see above).
  float ambient_share = 0.3f;
  // Angular radius of the light's disc, radians (glints on the ripples).
  float light_angular_radius_rad = 2.0f * 3.14159265f / 180.0f;
  // Highlight shoulder's knee (linear display value).
  float highlight_knee = 0.8f;
  // The colour of the sky's and of the light's share of the board's light,
  // per band, relative to the board's whole light: a * sky_tint + (1 - a) *
  // sun_tint = 1 in every band, so the dry board keeps the video's colour
  // while the floor's ambient term (in shadow, under the water) takes the
  // sky's. (1, 1, 1) both: a grey room light. SetDaylight sets them.
  glm::vec3 sky_tint{1.0f};
  glm::vec3 sun_tint{1.0f};

  // The look's absorption and scatter colour, other fields at defaults.
  static WaterOptics ForLook(WaterLook look);
  bool IsValid(std::string* error) const;
};

// Outdoors: the daylight's ambient share and the sky's and the sun's colour
// (render/sun.h, Daylight) into `optics` (ambient_share, sky_tint,
// sun_tint). Below the horizon the ambient share is 1: no direct light.
void SetDaylight(const Daylight& daylight, WaterOptics* optics);

// The daylight sky's radiance towards `view` (ENU) in display units (see
// above): a * L(view) / mean_cos(L) relative to the board's light per band,
// so that the sky's cosine-weighted mean is a * sky_tint.
glm::vec3 DaylightSkyRadiance(const Daylight& daylight,
                              const EnuDirection& view);

// Per-frame constants of the water's shading model (linear RGB where
// vectors), for a tank of rest depth `depth_m` under a light towards
// `light_in_tank` (z > 0, normalised inside). The shader combines, for a
// floor point of video colour V seen through the surface:
//   V * (E + R * V_mean * E_mean / (1 - R_mean * V_mean)) / n^2,
//   E = floor_sky + floor_sun * caustics * shadow (+ the surroundings),
// i.e. the sky and the direct light reaching the floor through the flat
// surface (relative to the dry board), the floor<->surface inter-reflection
// (total internal reflection sends light back onto the floor, from two
// depths times the critical angle's tangent away or more, so from the floor
// around, of the floor's mean albedo V_mean and lit as the floor's mean
// E_mean: render/frame_state.h, FloorAroundLight; on a uniform, uniformly
// lit floor this is V E / (1 - R V)) and
// radiance's 1/n^2 on leaving the water; then Beer-Lambert along the view
// path and Fresnel against the reflection.
struct WaterShading {
  glm::vec3 floor_sky{0.0f};  // a * sky_tint * SkyTransmittance per band
  glm::vec3 floor_sun{0.0f};  // (1 - a) * sun_tint * DirectTransmittance
  float inv_n2 = 1;           // 1 / n^2
  // A floor point seen through a glass wall from inside the water: what the
  // video shows beyond it, times the glass's two interfaces at normal
  // incidence.
  float glass_transmittance = 1;
  // The board under each glass wall (+x, -x, +y, -y), seen from inside the
  // water through the wall's inner face (a ray the outer face reflects
  // totally reaches it) or from above through the top face, relative to the
  // dry board the video shows, per band. Radiance over n^2 is kept across
  // the interfaces, so each direction of the point's hemisphere in the glass
  // brings n_g^2 times the radiance over n^2 of where it ends, and the way
  // out divides by n_g^2 again: with an UnderGlassView the light is the
  // traced shares of the sky, the board around the tank (lit as the dry
  // board), the floor (lit as the floor's mean under water, its radiance
  // over n_w^2) and the board under the glass itself (so the sum is divided
  // by 1 - share x albedo); without one, the sky fills the hemisphere. The
  // direct light is collimated, so it gains no n_g^2 and leaves divided by
  // it (UnderGlassDirectLight). Times the glass-water interface at normal
  // incidence on the way out.
  glm::vec3 under_glass[4] = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f),
                              glm::vec3(1.0f)};
  // Glint radiance per unit Fresnel at the centre of the light's disc:
  // (1 - a) / (cos_l alpha^2), the disc's radiance with its energy spread
  // as exp(-theta^2 / alpha^2) / (pi alpha^2) around the light.
  float glint_peak = 0;
  float inv_alpha2 = 0;  // 1 / alpha^2
};

// The hemisphere of the board under each glass wall (+x, -x, +y, -y), seen
// from inside the slab: the cosine-weighted shares of it whose paths end at
// the sky (per band), on the board around the tank, on the tank's floor and
// on the board under the glass, each times the Fresnel factors and the
// water's absorption on the way (render/under_glass.h traces them).
struct UnderGlassView {
  bool traced = false;  // false: the sky fills the hemisphere
  glm::vec3 sky[4] = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f),
                      glm::vec3(0.0f)};
  float board[4] = {0, 0, 0, 0};
  float floor[4] = {0, 0, 0, 0};
  float under[4] = {0, 0, 0, 0};
  // The board's and the floor's albedo (linear), for the light they send.
  float albedo = 0.85f;
};

WaterShading ComputeWaterShading(const WaterOptics& optics, double depth_m,
                                 const glm::dvec3& light_in_tank,
                                 const UnderGlassView& view = {});

// The direct light on the board under a glass side wall (`outward` its
// outward unit normal, horizontal), per unit of the light's irradiance on
// the open board, for a tank filled `depth_m` deep and the light towards
// `light` (unit, z > 0). Three ways in, each spread over the slab's
// thickness: through the wall's top face (Fresnel at the light's incidence;
// total internal reflection guides it down); from the water, the refracted
// beam that meets the inner face low enough to reach the board inside the
// slab, directly or after the outer face's reflection (total beyond the
// critical angle); and from outside, the beam that meets the outer face low
// enough. Beer-Lambert and the floor's caustics are left out.
double UnderGlassDirectLight(const WaterOptics& optics, const glm::dvec3& light,
                             const glm::dvec3& outward, double depth_m);

// The share of a floor point's (Lambertian) light that the water sends back
// onto the floor, per band, in the tank's box: rays leave the floor
// cosine-distributed and are followed through specular events only, the
// surface at rest reflecting by Fresnel (totally beyond the critical angle)
// and the side walls as glass slabs `glass_thickness_m` thick and
// `wall_height_m` tall: Fresnel at the water-glass and glass-air faces
// (totally beyond their critical angles), the slab guiding what its outer
// face reflects totally, and its top face turning what reaches it back down
// (part of the floor's light that leaves a thin wall upwards comes back to
// the floor this way), with Beer-Lambert along the way. In an unbounded
// layer this is DiffuseInternalReflectance less the absorption; near walls
// and in a small tank part of the light leaves through the glass. By
// reciprocity the same directions bring the surroundings' light in: what
// leaves through a wall going down lands on the board around the tank
// (radiance `surround_radiance`; the board under the glass counts as the
// board at the wall's foot), going up it sees the sky (radiance a), and
// that radiance L comes in as n^2 T L (T the way's transmittance). The sky
// seen through the surface is the shading's uniform term (floor_sky),
// which takes every upward direction to the surface at once; near the walls
// some of them meet a wall first, so the map counts the sky wherever each
// ray actually leaves (the surface, directly or after the walls'
// reflections, or a wall) and takes the uniform term's share off:
// `surround` is what the uniform term misses (negative where the walls
// show less than the sky they hide). In a world of uniform radiance over a
// white floor without absorption the floor's light is then n^2 times it at
// every texel (Clausius' law). A stratified set of `rays` directions per
// texel, shifted by the texel's own fixed offset (deterministic).
struct FloorReturnMap {
  int nx = 0, ny = 0;  // texels over the tank floor, row j along y
  // nx * ny, RGB: the share of the floor's light returned to it, and the
  // irradiance from the surroundings that the sky term leaves out (relative
  // to the dry board's, pi; see above).
  std::vector<glm::vec3> returned, surround;
  // The surroundings by where their light comes from, for a board whose
  // radiance is read each frame: `sky` the sky's part of `surround` and,
  // per side wall (+x, -x, +y, -y), `board[w]` the irradiance a board of
  // radiance 1 beyond it gives, so that
  //   surround = sky + surround_radiance * (board[0] + ... + board[3]).
  std::vector<glm::vec3> sky;
  std::vector<glm::vec3> board[4];
  // Per wall, kBoardPoints points (tank frame x, y on the board, z = 0)
  // where the light leaving through it going down lands, each standing for
  // an equal share of it over the whole floor: the board's mean radiance
  // over them is the radiance to weigh board[w] with.
  static constexpr int kBoardPoints = 64;
  std::vector<glm::dvec2> board_points[4];
};
FloorReturnMap ComputeFloorReturn(const WaterOptics& optics, double size_x_m,
                                  double size_y_m, double depth_m,
                                  double wall_height_m, int nx, int ny,
                                  int rays, double surround_radiance = 0.85);

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_OPTICS_H_
