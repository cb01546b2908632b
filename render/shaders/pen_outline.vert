// The band along the real pen's dry shaft's outline, on both sides
// (pass_pen_outline.h): each side is the strip between the silhouettes of
// two coaxial cylinders of radii u_band.x and u_band.y (with both radii
// the outer one, the shaft's whole width). A silhouette of a
// cylinder is the generator where the camera's ray touches it, straight on
// screen; its point at axis position u, for radius rho, lies along the unit
// n = (rho / d) w + side sqrt(1 - (rho / d)^2) b from the axis, w the unit
// direction from the axis to the camera (across the axis, at distance d),
// b = axis x w.
layout(location = 0) in vec3 a_pos;  // along, side -+1, 0 in / 1 out
uniform vec3 u_pen_tip;
uniform vec3 u_pen_axis;
uniform vec2 u_along;  // axis positions (metres from the tip) at along 0, 1
uniform vec2 u_band;   // the radii in and out, metres
out vec3 v_p;
void main() {
  vec3 on_axis =
      u_pen_tip + mix(u_along.x, u_along.y, a_pos.x) * u_pen_axis;
  vec3 to_cam = u_cam_in_tank - on_axis;
  vec3 across = to_cam - dot(to_cam, u_pen_axis) * u_pen_axis;
  float d = max(length(across), 1e-6);
  vec3 w = across / d;
  vec3 b = cross(u_pen_axis, w);
  float rho = mix(u_band.x, u_band.y, a_pos.z);
  float k = min(rho / d, 1.0);
  v_p = on_axis + rho * (k * w + a_pos.y * sqrt(1.0 - k * k) * b);
  gl_Position = u_clip_from_tank * vec4(v_p, 1.0);
}
