// The glass walls' top faces seen from above, in linear light (the sRGB
// view encodes), opaque but for their edges' pixels: a window into the
// slab. The exact dielectric Fresnel reflectance of the
// face mixes in the sky or the environment by the mirrored ray; the rest
// of the camera's ray refracts into the glass and runs down the slab. Its
// vertical faces reflect it totally while they border air, and below the
// water while n_g sin(a) > n_w (a its angle from their normal), so the ray
// ends on the board under the glass: that board as the video shows it where
// the ray's drift along the wall over the wall's height takes it, lit
// through the glass (optics.h, under_glass). Otherwise it leaves the slab
// into the water at the inner face and sees the floor near the wall, at
// its mean (FloorReturnLight::floor_seen).
// The face covers each pixel by its share: the faces are drawn widened
// (wall_tops.vert) and blended over what lies behind them by that share,
// the pixel's footprint across the wall against the face's 0..1 (in
// thicknesses); the face is shaded at the footprint's point nearest it.
in vec3 v_p;
flat in vec2 v_inward;
out vec4 o_color;
uniform sampler2D u_scene;
uniform float u_glass_ior;
uniform float u_ior;
uniform float u_glass_thickness;  // metres
uniform vec3 u_under_glass[4];    // as in water.frag
uniform vec3 u_floor_seen;

void main() {
  vec2 half_size = 0.5 * u_tank.xy;
  vec2 inward = v_inward;
  vec2 along = abs(inward.yx);
  float inner = dot(half_size, abs(inward));
  float across_face = (dot(v_p.xy, -inward) - inner) / u_glass_thickness;
  float step_across = max(fwidth(across_face), 1e-6);
  float cover = clamp((min(across_face + 0.5 * step_across, 1.0) -
                       max(across_face - 0.5 * step_across, 0.0)) /
                          step_across,
                      0.0, 1.0);
  vec3 p_face = vec3(v_p.xy * along -
                         inward * (inner + clamp(across_face, 0.0, 1.0) *
                                               u_glass_thickness),
                     v_p.z);
  vec3 v = normalize(p_face - u_cam_in_tank);
  const vec3 up = vec3(0.0, 0.0, 1.0);
  float r = FresnelExact(-v.z, u_glass_ior);
  vec3 g = refract(v, up, 1.0 / u_glass_ior);
  float c = abs(dot(g.xy, inward));
  bool trapped = u_glass_ior * sqrt(max(1.0 - c * c, 0.0)) > u_ior;
  // The board point under the slab's middle that the ray reaches.
  float drift = dot(g.xy, along) * u_tank.z / max(-g.z, 1e-3);
  vec2 foot = p_face.xy + along * drift;
  float mid = inner + 0.5 * u_glass_thickness;
  foot = foot * along - inward * mid;
  vec3 video =
      DecodeVideo(textureLod(u_scene, VideoUv(vec3(foot, 0.0)), 0.0).rgb);
  vec3 board_under = u_under_glass[0] + inward.x * u_under_glass[1] +
                     inward.y * u_under_glass[2] +
                     abs(inward.x) * u_under_glass[3];
  vec3 below = trapped ? video * board_under : u_floor_seen;
  vec3 sky = Environment(reflect(v, up), vec3(u_ambient));
  o_color = vec4(Shoulder(mix(below, sky, r)), cover);
}
