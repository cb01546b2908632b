// Virtual obstacles: diffuse, lit by the tank's light and (SHADOWS) its
// shadow map. A variant rather than a branch: llvmpipe would run the PCF
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
  o_color = vec4(u_albedo * (0.45 + 0.65 * diffuse), 1.0);
}
