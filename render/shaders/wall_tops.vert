// The glass walls' top faces: the ring at the wall height between the inner
// size and the glass's outer faces (TankWallsMesh, vertices 24..47), each
// face widened across its wall by u_top_grow (metres) on both long edges,
// so that the pixels its edges cross are shaded and covered by share
// (wall_tops.frag).
layout(location = 0) in vec3 a_pos;   // tank frame
layout(location = 1) in vec3 a_grow;  // across the wall, away from the face
layout(location = 2) in vec2 a_inward;
uniform float u_top_grow;
out vec3 v_p;
flat out vec2 v_inward;
void main() {
  v_p = a_pos + a_grow * u_top_grow;
  v_inward = a_inward;
  gl_Position = u_clip_from_tank * vec4(v_p, 1.0);
}
