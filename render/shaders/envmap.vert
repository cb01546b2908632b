// Environment cube map faces (pass_envmap.h): a face's quad in NDC and its
// homogeneous image coordinate (x q, y q, q).
layout(location = 0) in vec2 a_pos;
layout(location = 1) in vec3 a_image;
out vec3 v_image;
void main() {
  v_image = a_image;
  gl_Position = vec4(a_pos, 0.0, 1.0);
}
