// Virtual obstacles: diffuse, lit by the sky and the tank's light and
// (SHADOWS) its shadow map, in linear light, encoded on output. A variant rather than a branch: llvmpipe would run the PCF
// taps even with shadows off.
in vec3 v_p;
in vec3 v_n;
out vec4 o_color;
uniform vec3 u_albedo;
void main() {
  vec3 n = normalize(v_n);
  float diffuse = max(dot(n, u_light), 0.0);
#ifdef SHADOWS
  diffuse *= Shadow(v_p + n * 5e-4);
#endif
  // The board's normalisation (optics.h): a horizontal, unshadowed surface
  // reads its albedo; the direct share scales with n.l / cos(light).
  float direct = (1.0 - u_ambient) * diffuse / max(u_light.z, 1e-3);
  // Alpha 0 marks the obstacles' pixels for the water, which must not
  // light them as the floor behind them (video and water write 1).
  o_color = vec4(EncodeOutput(u_albedo * (u_ambient + direct)), 0.0);
}
