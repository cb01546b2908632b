// The glass walls' top faces: the ring at the wall height between the inner
// size and the glass's outer faces (TankWallsMesh, vertices 24..47).
layout(location = 0) in vec3 a_pos;  // tank frame
out vec3 v_p;
void main() {
  v_p = a_pos;
  gl_Position = u_clip_from_tank * vec4(a_pos, 1.0);
}
