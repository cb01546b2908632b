// A quad covering the viewport (a 4-vertex triangle strip); v_uv in [0,1]^2
// with v = 0 at the viewport's top edge, so an image uploaded top row first
// appears upright in the window.
out vec2 v_uv;
void main() {
  vec2 p = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);
  v_uv = vec2(p.x, 1.0 - p.y);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
