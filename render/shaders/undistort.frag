// Resamples the distorted camera frame onto the ideal pinhole image: each
// output pixel evaluates OpenCV's distortion model forwards (no iteration)
// to find its source. Arithmetic rather than a precomputed map: on llvmpipe
// a texture fetch costs more than the polynomial.
out vec4 o_color;
uniform sampler2D u_video;
uniform vec4 u_dist0;  // k1 k2 p1 p2
uniform vec4 u_dist1;  // k3 k4 k5 k6
void main() {
  // OpenCV pixel = window - 0.5 in our top-first FBO.
  vec2 xy = (gl_FragCoord.xy - 0.5 - u_intr.zw) / u_intr.xy;
  float r2 = dot(xy, xy);
  float r4 = r2 * r2, r6 = r4 * r2;
  float radial = (1.0 + u_dist0.x * r2 + u_dist0.y * r4 + u_dist1.x * r6) /
                 (1.0 + u_dist1.y * r2 + u_dist1.z * r4 + u_dist1.w * r6);
  float p1 = u_dist0.z, p2 = u_dist0.w;
  vec2 d = vec2(xy.x * radial + 2.0 * p1 * xy.x * xy.y +
                    p2 * (r2 + 2.0 * xy.x * xy.x),
                xy.y * radial + p1 * (r2 + 2.0 * xy.y * xy.y) +
                    2.0 * p2 * xy.x * xy.y);
  vec2 src = (u_intr.xy * d + u_intr.zw + 0.5) / u_image_size;
  // Explicit LOD 0: no derivatives for llvmpipe to compute (no mipmaps).
  o_color = vec4(textureLod(u_video, src, 0.0).rgb, 1.0);
}
