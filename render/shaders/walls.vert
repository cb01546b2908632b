// Glass walls: one quad per wall, from the floor to the wall height.
layout(location = 0) in vec3 a_pos;     // tank frame
layout(location = 1) in vec3 a_normal;  // outward
layout(location = 2) in vec2 a_wall;    // along-wall metres, wall length
// The part of each wall between these heights (metres) is drawn: the
// front walls' part under the water takes the heavier program.
uniform vec2 u_z_range;
out vec3 v_p;
out vec3 v_n;
out vec2 v_wall;
#ifdef BOARD_MIRROR
// Where the glass mirrors the camera's ray onto the board z = 0: the ray
// from the camera's mirror image c' (across the wall's plane) through the
// wall point p meets the board at B = (c'.z p - p.z c') / (c'.z - p.z).
// That is linear in p as the homogeneous point (c'.z p - p.z c', c'.z -
// p.z), and so is its projection into the video, (u q, v q, q) in pixels:
// interpolated across the wall (perspective-correct, as every varying),
// one division per fragment gives the board's pixel. w = c'.z - p.z > 0:
// the mirrored ray descends.
out vec4 v_board;
#endif
void main() {
  vec3 p = vec3(a_pos.xy, clamp(a_pos.z, u_z_range.x, u_z_range.y));
  v_p = p;
  v_n = a_normal;
  v_wall = a_wall;
#ifdef BOARD_MIRROR
  vec3 c = u_cam_in_tank - 2.0 * dot(u_cam_in_tank - p, a_normal) * a_normal;
  float w = c.z - p.z;
  vec3 b = (u_cam_from_tank * vec4(c.z * p - p.z * c, w)).xyz;
  v_board = vec4(u_intr.xy * b.xy + u_intr.zw * b.z, b.z, w);
#endif
  gl_Position = u_clip_from_tank * vec4(p, 1.0);
}
