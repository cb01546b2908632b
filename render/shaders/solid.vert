// Rigid meshes (obstacles, the pen phantom, shadow casters).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_tank_from_model;
uniform mat4 u_clip_from_model;
out vec3 v_p;
out vec3 v_n;
void main() {
  v_p = (u_tank_from_model * vec4(a_pos, 1.0)).xyz;
  v_n = mat3(u_tank_from_model) * a_normal;
  gl_Position = u_clip_from_model * vec4(a_pos, 1.0);
}
