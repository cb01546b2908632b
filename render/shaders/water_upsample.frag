// The water shaded on the coarse grid (pass_water.h, coarse_grid.h) brought
// to the output's pixels the water's stencil marks: one bilinear lookup of
// the grid (colour times coverage a; texels it did not shade are 0),
// divided by the coverage, so only shaded texels contribute. The grid and
// the output cover the same image, so v_uv (fullscreen.vert) is the lookup.
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_coarse_water;
void main() {
  vec4 c = textureLod(u_coarse_water, v_uv, 0.0);
  o_color = vec4(c.rgb / max(c.a, 1e-3), 1.0);
}
