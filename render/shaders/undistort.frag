// Resamples the distorted camera frame onto the ideal pinhole image: each
// output pixel evaluates OpenCV's distortion model forwards (no iteration,
// DistortedPixel in common.glsl) to find its source. Arithmetic rather than
// a precomputed map: on llvmpipe a texture fetch costs more than the
// polynomial.
out vec4 o_color;
uniform sampler2D u_video;
void main() {
  // OpenCV pixel = window - 0.5 in our top-first FBO.
  vec2 src = (DistortedPixel(gl_FragCoord.xy - 0.5) + 0.5) / u_image_size;
  // Explicit LOD 0: no derivatives for llvmpipe to compute (no mipmaps).
  o_color = vec4(textureLod(u_video, src, 0.0).rgb, 1.0);
}
