// The board's light with the tank over its light without it
// (render/board_light.h, pass_board_light.cc): the map holds, per band, the
// factor g on the output's encoded board less 0.5. Blended as
// dst * src + dst * src.a = dst * g, with src.a the part of g above 1 in
// the brightest band (0 where g <= 1) and src.rgb the rest.
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_board_light;
#ifdef OCCLUDERS
// The occluder mask (pass_real.h): the real pen's silhouette (0.5) is not in
// the depth buffer yet (its phantom comes with the obstacles), so the pen
// and the occluders keep their pixels here.
uniform sampler2D u_occluders;
#endif
void main() {
#ifdef OCCLUDERS
  if (texelFetch(u_occluders, ivec2(gl_FragCoord.xy), 0).r > 0.25) discard;
#endif
  vec3 g = textureLod(u_board_light, v_uv, 0.0).rgb + 0.5;
  float above = max(max(g.r, max(g.g, g.b)) - 1.0, 0.0);
  o_color = vec4(max(g - above, 0.0), above);
}
