// Glass walls with dual-source blending, dst' = src0 + dst * src1, so the
// water behind a front wall tints each colour channel by its own
// transmittance: the user sees the water's volume through the glass.
// FRONT_WALL (defined for walls facing the camera) adds the water volume.
//
// The blend happens on encoded values. The physics (Beer-Lambert through
// the water's volume, the glass's exact Fresnel reflection of the sky) is
// computed in linear light as dst * T + C and carried into the encoded
// output to first order: with sRGB, src1 = T^(1/2.2) (exact for a power-law
// transfer) and src0 = C times the transfer's slope at mid-grey (0.66).
// Rims and the meniscus line are mixed towards white in encoded space.
in vec3 v_p;
in vec3 v_n;
in vec2 v_wall;
layout(location = 0, index = 0) out vec4 o_color;
layout(location = 0, index = 1) out vec4 o_transmit;
uniform vec3 u_sigma;
uniform vec3 u_scatter;
uniform float u_glass_ior;

void main() {
  vec3 v = normalize(v_p - u_cam_in_tank);
  vec2 half_size = 0.5 * u_tank.xy;
  float surface = SurfaceZ(clamp(v_p.xy, -half_size, half_size));
  vec3 color = vec3(0.0);
  vec3 transmit = vec3(1.0);
#ifdef FRONT_WALL
  if (v_p.z < surface) {
    // Path through the water until the floor, the surface or a far wall.
    float tf = v.z < -1e-5 ? -v_p.z / v.z : 1e3;
    float ts = v.z > 1e-5 ? (u_tank.w - v_p.z) / v.z : 1e3;
    float tx = abs(v.x) > 1e-6 ? (sign(v.x) * half_size.x - v_p.x) / v.x : 1e3;
    float ty = abs(v.y) > 1e-6 ? (sign(v.y) * half_size.y - v_p.y) / v.y : 1e3;
    float len = max(min(min(tf, ts), min(tx, ty)), 0.0);
    transmit = exp(-u_sigma * len);
    color = u_scatter * (1.0 - transmit);
  }
#endif
  // Glass: two faces reflecting the sky (radiance u_ambient) by Fresnel.
  float cos_v = abs(dot(v, normalize(v_n)));
  float r_glass = 2.0 * FresnelExact(cos_v, u_glass_ior);
  color = color * (1.0 - r_glass) + vec3(u_ambient * r_glass);
  transmit *= 1.0 - r_glass;
  if (u_srgb_out > 0.5) {
    transmit = pow(transmit, vec3(1.0 / 2.2));
    color *= 0.66;
  }
  // Bright rims at the top edge and the corners, and a bright line where
  // the water meets the glass.
  float edge = min(min(v_wall.x, v_wall.y - v_wall.x), u_tank.z - v_p.z);
  float rim = 1.0 - smoothstep(0.0006, 0.0016, edge);
  float meniscus = 1.0 - smoothstep(0.0002, 0.0007, abs(v_p.z - surface));
  float a = clamp(0.45 * rim + 0.3 * meniscus, 0.0, 1.0);
  color = color * (1.0 - a) + vec3(0.9, 0.97, 1.0) * a;
  transmit *= 1.0 - a;
  o_color = vec4(color, 1.0);
  o_transmit = vec4(transmit, 1.0);
}
