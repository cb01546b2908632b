// Resamples the distorted camera frame onto the ideal pinhole image through
// a precomputed map (distorted texture coordinate per output pixel).
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_video;
uniform sampler2D u_map;
void main() {
  vec2 src = texture(u_map, v_uv).xy;
  o_color = vec4(texture(u_video, src).rgb, 1.0);
}
