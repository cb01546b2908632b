// Caustics on the tank floor after Nishita & Nakamae, "Method of displaying
// optical effects within water using accumulation buffer" (SIGGRAPH 1994):
// every triangle of the water surface carries the light it intercepts down
// its refracted rays onto the floor, and deposits it over its projected
// triangle, so intensity ~ surface area / projected area.
//
// Deposition is exact and conservative: every projected triangle spreads its
// flux uniformly over its projected area, and each map texel receives the
// flux of exactly the part of the triangle that overlaps it (analytic area
// coverage, accumulated once per mesh edge and prefix-summed as in font-rs'
// accumulation rasteriser, along x or along y for flat edges, with exact
// corner terms; AVX2 where the CPU has it). The flux deposited equals the flux
// entering the surface (minus what lands outside the map, which the summary
// counts), and flat water gives a uniform map. A triangle focused to less
// than a tenth of a texel is splatted bilinearly at its centroid, so
// focusing cannot create infinite intensity.
#ifndef RIPPLE_RENDER_CAUSTICS_H_
#define RIPPLE_RENDER_CAUSTICS_H_

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "render/scene.h"

namespace ripple::render {

struct CausticsOptions {
  // Map texels over the tank floor: texel (a, b) covers
  // x in size_x * [a / map_nx - 1/2, (a + 1) / map_nx - 1/2], same in y.
  int map_nx = 256, map_ny = 256;
  double ior = 1.333;  // water
  // Attenuation of light along the refracted path (1/m). The map is
  // normalised by the flat-water path so that flat water reads 1.
  double attenuation_per_m = 0.0;
  int threads = 1;  // CPU threads; each adds a private accumulation map
  // The glass walls: light_through_walls adds the light that enters the
  // water through them (the strip along the walls facing an oblique light,
  // which the surface's refracted light misses, is lit through them;
  // analytically per texel for the rest level); glass_near_walls applies
  // what the glass does to the surface's light (the glass above the water
  // transmits it, reflects it onto the surface near the wall facing away,
  // and its top face turns part of it away; below the water the wall facing
  // away mirrors back what the surface sent beyond it), light-traced through
  // slabs `glass_thickness_m` thick with `glass_paths_per_axis`^2 paths per
  // texel (caustics_kernels.h, NearWallGlassMaps). Both are computed once
  // per tank, light and map.
  bool light_through_walls = true;
  bool glass_near_walls = true;
  double glass_ior = 1.5;
  double glass_thickness_m = 0.003;
  int glass_paths_per_axis = 2;
  // Angular radius of the light's disc (radians): every direction within it
  // lights the floor with the same pattern, moved by the shift of its
  // refracted ray over the rest depth, so the map is convolved with that
  // disc's footprint on the floor (0.65 mm for 2 degrees under 25 mm of
  // water: a texel of the default map; caustics_kernels.h PenumbraKernel).
  // 0: a point light. The fluxes in CausticsSummary are before it (the
  // kernel sums to 1; only the map's edges, clamped, move any flux).
  double light_angular_radius_rad = 0.0;
  // AVX2 kernels where the CPU has them; false forces the baseline-ISA
  // build of the same kernels (identical results; for tests).
  bool simd = true;

  bool IsValid(std::string* error) const;
};

struct CausticsSummary {
  int triangles = 0;
  // Fluxes in m^2 times the irradiance of the light on a plane facing it
  // (i.e. with unit irradiance): entering the surface, deposited in the
  // map, and landing outside it. With zero attenuation
  // flux_deposited + flux_outside == flux_in.
  double flux_in = 0;
  double flux_deposited = 0;
  double flux_outside = 0;
  // Deposited in the map by the light through the walls (not in the three
  // above), in the same units, relative to flat water's transmittance.
  double flux_walls = 0;
  // What the glass near the walls (glass_near_walls) added to the
  // surface's light in the map (negative where it dims more than it adds),
  // in the same units.
  double flux_near_walls = 0;
};

// Scratch memory of ComputeCaustics, kept between calls so that a frame
// does not page-fault fresh buffers in. Not thread-safe; one per caller.
struct CausticsWorkspace {
  struct Buffers;
  CausticsWorkspace();
  ~CausticsWorkspace();
  std::unique_ptr<Buffers> buffers;
};

// Fills `map` (map_nx * map_ny floats, row-major, row b along tank y) with
// the floor irradiance relative to that under flat water: 1 = unchanged,
// > 1 focused light, 0 where no refracted light lands (the strip along the
// walls facing an oblique light, lit only through the walls). `light_in_tank`
// points towards the light (normalised inside, must have z > 0). The surface is
// the height field's cell-corner mesh (corner heights averaged from the
// adjacent cells) covering the whole field. Null or empty heights (or a
// non-positive cell size) mean flat water: the tank's surface, its light
// shifted by the refraction, exact per texel (1 inside, no triangles in the
// summary). Returns false on invalid options or a light at or below the horizon
// (map of 0).
bool ComputeCaustics(const CausticsOptions& options,
                     const HeightFieldView& water, const TankGeometry& tank,
                     const glm::dvec3& light_in_tank, std::vector<float>* map,
                     CausticsSummary* summary,
                     CausticsWorkspace* workspace = nullptr);

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_CAUSTICS_H_
