// The glass walls' top faces seen from above, in linear light, opaque: a
// window into the slab. The exact dielectric Fresnel reflectance of the
// face mixes in the sky or the environment by the mirrored ray; the rest
// of the camera's ray refracts into the glass and runs down the slab. Its
// vertical faces reflect it totally while they border air, and below the
// water while n_g sin(a) > n_w (a its angle from their normal), so the ray
// ends on the board under the glass: that board as the video shows it where
// the ray's drift along the wall over the wall's height takes it, lit
// through the glass (optics.h, under_glass). Otherwise it leaves the slab
// into the water at the inner face and sees the floor near the wall, at
// its mean (FloorReturnLight::floor_seen).
in vec3 v_p;
out vec4 o_color;
uniform sampler2D u_scene;
uniform float u_glass_ior;
uniform float u_ior;
uniform float u_glass_thickness;  // metres
uniform vec3 u_under_glass[4];    // as in water.frag
uniform vec3 u_floor_seen;

void main() {
  vec3 v = normalize(v_p - u_cam_in_tank);
  vec2 half_size = 0.5 * u_tank.xy;
  // The y walls' faces take the corners.
  bool y_wall = abs(v_p.y) > half_size.y;
  vec2 inward = y_wall ? vec2(0.0, -sign(v_p.y)) : vec2(-sign(v_p.x), 0.0);
  vec2 along = abs(inward.yx);
  const vec3 up = vec3(0.0, 0.0, 1.0);
  float r = FresnelExact(-v.z, u_glass_ior);
  vec3 g = refract(v, up, 1.0 / u_glass_ior);
  float c = abs(dot(g.xy, inward));
  bool trapped = u_glass_ior * sqrt(max(1.0 - c * c, 0.0)) > u_ior;
  // The board point under the slab's middle that the ray reaches.
  float drift = dot(g.xy, along) * u_tank.z / max(-g.z, 1e-3);
  vec2 foot = v_p.xy + along * drift;
  float mid = dot(half_size, abs(inward)) + 0.5 * u_glass_thickness;
  foot = foot * along - inward * mid;
  vec3 video =
      DecodeVideo(textureLod(u_scene, VideoUv(vec3(foot, 0.0)), 0.0).rgb);
  vec3 board_under = u_under_glass[0] + inward.x * u_under_glass[1] +
                     inward.y * u_under_glass[2] +
                     abs(inward.x) * u_under_glass[3];
  vec3 below = trapped ? video * board_under : u_floor_seen;
  vec3 sky = Environment(reflect(v, up), vec3(u_ambient));
  o_color = vec4(EncodeOutput(mix(below, sky, r)), 1.0);
}
