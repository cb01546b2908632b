// The water's deferred pass: one triangle covering the viewport (as
// fullscreen.vert) that also interpolates each pixel's viewing ray, which is
// affine in the window position, so the fragment shader needs no matrix.
out vec3 v_ray;  // tank frame, unnormalised (camera z component 1)
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  // Window position of the vertex, OpenCV pixels (window - 0.5).
  vec2 px = p * u_image_size - 0.5;
  v_ray = mat3(u_tank_from_cam) * vec3((px - u_intr.zw) / u_intr.xy, 1.0);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
