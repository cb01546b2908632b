// The board around the tank (pass_board_light.h): tank-frame points on the
// board plane z = 0, and their coordinates in the board-light map.
layout(location = 0) in vec2 a_xy;  // tank frame, metres
uniform vec4 u_map;                 // uv = xy * map.xy + map.zw
out vec2 v_uv;
void main() {
  v_uv = a_xy * u_map.xy + u_map.zw;
  gl_Position = u_clip_from_tank * vec4(a_xy, 0.0, 1.0);
}
