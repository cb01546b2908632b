// Glass walls: one quad per wall, from the floor to the wall height.
layout(location = 0) in vec3 a_pos;     // tank frame
layout(location = 1) in vec3 a_normal;  // outward
layout(location = 2) in vec2 a_wall;    // along-wall metres, wall length
out vec3 v_p;
out vec3 v_n;
out vec2 v_wall;
void main() {
  v_p = a_pos;
  v_n = a_normal;
  v_wall = a_wall;
  gl_Position = u_clip_from_tank * vec4(a_pos, 1.0);
}
