// The mirrored obstacles and pen (pass_mirror.h): solid.vert gives the real
// (unmirrored) surface point and normal; the geometry itself was placed at
// its mirror image. Premultiplied linear colour, alpha fading with height.
in vec3 v_p;
in vec3 v_n;
out vec4 o_color;
uniform sampler2D u_scene;  // undistorted video (+ obstacles)
uniform vec3 u_albedo;
uniform float u_is_pen;   // 1: coloured from the video (the real pen)
uniform float u_fade_m;   // alpha e-folding height above the water
void main() {
  float h = v_p.z - u_tank.w;
  if (h < 0.0) discard;  // under the water: not mirrored
  vec3 n = normalize(v_n);
  float diffuse = max(dot(n, u_light), 0.0);
  float direct = (1.0 - u_ambient) * diffuse / max(u_light.z, 1e-3);
  vec3 lit = u_albedo * (u_ambient + direct);
  vec3 seen = DecodeVideo(textureLod(u_scene, VideoUv(v_p), 0.0).rgb);
  vec3 c = mix(lit, seen, u_is_pen);
  float a = exp(-h / u_fade_m);
  o_color = vec4(c * a, a);
}
