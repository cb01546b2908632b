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
void main() {
  vec3 p = vec3(a_pos.xy, clamp(a_pos.z, u_z_range.x, u_z_range.y));
  v_p = p;
  v_n = a_normal;
  v_wall = a_wall;
  gl_Position = u_clip_from_tank * vec4(p, 1.0);
}
