// Virtual obstacles: diffuse, lit by the tank's light and its shadow map.
in vec3 v_p;
in vec3 v_n;
out vec4 o_color;
uniform vec3 u_albedo;
void main() {
  vec3 n = normalize(v_n);
  float diffuse = max(dot(n, u_light), 0.0) * Shadow(v_p + n * 5e-4);
  o_color = vec4(u_albedo * (0.45 + 0.65 * diffuse), 1.0);
}
