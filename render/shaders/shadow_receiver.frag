// The shadow as the water sees it, over the tank interior, redrawn with the
// shadow map: r = light reaching the floor (through the water), g = light
// reaching the surface at rest. The main pass then needs one bilinear fetch
// per receiver instead of a PCF kernel per pixel.
in vec2 v_uv;
out vec4 o_color;
void main() {
  vec2 xy = (v_uv - 0.5) * u_tank.xy;
  o_color = vec4(FloorShadow(vec3(xy, 0.0)), Shadow(vec3(xy, u_tank.w)), 0.0,
                 1.0);
}
