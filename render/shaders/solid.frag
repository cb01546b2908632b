// Virtual obstacles: diffuse, lit by the sky and the tank's light and
// (SHADOWS) its shadow map, in linear light, encoded on output. A variant rather than a branch: llvmpipe would run the PCF
// taps even with shadows off.
in vec3 v_p;
in vec3 v_n;
out vec4 o_color;
uniform vec3 u_albedo;
// What surrounds the obstacles (pass_obstacles.cc, from the video; display
// units, linear): the board around the tank (dry) and, under the water,
// the floor's radiance in the water and the light from above the floor
// gets (the sky through the surface).
uniform vec3 u_ground;
uniform vec3 u_floor_wet;
uniform vec3 u_floor_sky;
uniform vec3 u_floor_sun;
// Snell's window from below (optics.h, SnellWindowShares): its share of
// the view of a plane facing up and of a vertical one, and its own mean
// reflectance.
uniform vec3 u_window;
// The surface's mean reflectance over the lower view of a face above it,
// vertical (x) and facing down (y) (optics.h, LowerViewReflectance).
uniform vec2 u_lower_reflectance;
uniform float u_inv_n2;
void main() {
  vec3 n = normalize(v_n);
  vec2 half_size = 0.5 * u_tank.xy;
  bool in_tank = all(lessThan(abs(v_p.xy), half_size));
  // Under the rest level: the waves (a millimetre or so) move the
  // waterline on an obstacle by less than the water's own silhouette
  // there, which decides what is seen through the water.
  bool under = in_tank && v_p.z < u_tank.w;
  // Diffuse light on a face of normal n in units where the dry, unshadowed
  // board reads its albedo (optics.h). A plane sees the upper hemisphere's
  // mean radiance with weight (1 + n.z) / 2 and the lower's with (1 - n.z)
  // / 2 (its view factors).
  //   In air: the sky (radiance u_ambient) above, and below the board
  //   around the tank or, over the tank, the water (the wet floor seen
  //   through the surface, 1/n^2, and the sky it mirrors) and the board
  //   beyond the walls; the light's direct share by n.l / cos(light).
  //   Under water: above, Snell's window (the sky through the surface, of
  //   the radiance that gives the floor what it gets from it, and the floor
  //   in the window's partial reflection) and outside it the floor totally
  //   reflected, by their shares of this face's view (exact facing up,
  //   sideways and down, linear between: a vertical face sees the window
  //   near its horizon, a fifth of its upper view); below, the floor; the
  //   light refracted at the flat surface, by n.t / cos(t).
  float up = 0.5 * (1.0 + n.z), down = 0.5 * (1.0 - n.z);
  vec3 t = -u_light_refracted;  // towards the light, under water
  vec3 light_dir = under ? t : u_light;
  float diffuse = max(dot(n, light_dir), 0.0) / max(light_dir.z, 1e-3);
#ifdef SHADOWS
  // Under the water the shadow map is read where the refracted light
  // crossed the rest surface (as FloorShadow does for the floor).
  vec3 lit_at = under ? v_p + t * ((u_tank.w - v_p.z) / max(t.z, 1e-3)) : v_p;
  diffuse *= Shadow(lit_at + n * 5e-4);
#endif
  // The three terms' radiances, selected (llvmpipe would run both sides of
  // a branch); `upper` is the upper view's light, weighted.
  float window = n.z >= 0.0 ? mix(u_window.y, u_window.x, n.z)
                            : u_window.y * (1.0 + n.z);
  vec3 upper_water = window * (u_floor_sky / u_window.x +
                               u_window.z * u_floor_wet) +
                     (up - window) * u_floor_wet;
  vec3 upper = under ? upper_water : u_ambient * vec3(up);
  // Over the tank the lower view is the water out to the walls and, at
  // depressions under delta = atan(height over the water / distance to the
  // wall along the face's horizontal normal), the board beyond them: a
  // vertical face sees the band between the horizon and delta below it
  // with the share sin(delta) of its lower view ((cos a1 - cos a2) / 2 for
  // a wedge about a line in the face's plane); a tilted face is weighted
  // the same way, the water taking the rest.
  vec2 nh = n.xy / max(length(n.xy), 1e-4);
  vec2 side = mix(vec2(-1.0), vec2(1.0), step(0.0, nh));
  vec2 to_wall = (half_size - side * v_p.xy) / max(abs(nh), vec2(1e-4));
  float reach = max(min(to_wall.x, to_wall.y), 1e-4);
  float height = max(v_p.z - u_tank.w, 0.0);
  float beyond = height * inversesqrt(height * height + reach * reach);
  // The water seen from above: the wet floor through the surface and the
  // sky it mirrors, by the surface's mean reflectance over this face's
  // lower view (a vertical face sees it mostly near the horizon).
  float mirror = mix(u_lower_reflectance.x, u_lower_reflectance.y,
                     max(-n.z, 0.0));
  vec3 water = mix(u_floor_wet * u_inv_n2, vec3(u_ambient), mirror);
  vec3 below = under ? u_floor_wet
                     : (in_tank ? mix(water, u_ground, beyond) : u_ground);
  vec3 direct = under ? u_floor_sun : vec3(1.0 - u_ambient);
  vec3 light = upper + below * down + direct * diffuse;
  // Alpha 0 marks the obstacles' pixels for the water, which must not
  // light them as the floor behind them (video and water write 1); under
  // the water this is the radiance in the water, which the water pass sees
  // through the surface (1/n^2, Fresnel, absorption).
  o_color = vec4(EncodeOutput(u_albedo * light), 0.0);
}
