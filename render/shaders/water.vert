// The coarse surface mesh: a regular grid over the tank interior displaced by
// the (linearly filtered) height texture. Detail comes from the fragment
// shader's per-pixel normals.
layout(location = 0) in vec2 a_grid;  // [0,1]^2 over the tank interior
out vec3 v_p;
void main() {
  vec2 xy = (a_grid - 0.5) * u_tank.xy;
  v_p = vec3(xy, SurfaceZ(xy));
  gl_Position = u_clip_from_tank * vec4(v_p, 1.0);
}
