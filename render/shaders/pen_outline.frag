// The real pen's dry shaft in front of the water, along its outline
// (pass_pen_outline.h): drawn over a band along the outline out to the
// margin and two pixels (pen_outline.vert), on the water's pixels; writes
// (the pen's part, its share c), blended as out = rgb + (1 - a) water in
// linear light.
//
// The pixel's ray c + s v passes the shaft's side (0 < s <= s_max, the rest
// level's distance: along the outline, and where the shaft meets the
// surface; between the tip and the cube) within its radius + margin + a
// pixel. The video shows V = c P + (1 - c) B there (P the pen, B the dry
// board behind it). B is read a pixel beyond the grown outline, P on the
// axis, and c is V's share along B -> P, kept between the shares that
// shafts of the tracked radius -+ the margin cover: so a tracked outline off
// by up to the margin still leaves the pen to the video and the board
// around it to the water, and a board that is not uniform (a tag's edge
// behind the outline) moves c no further than the margin allows. Where the
// pen and the board look alike, or a virtual obstacle (alpha 0 in the
// scene copy) hides V or B, the pixel is the water and P by the share the
// tracked shaft covers. The video's pen is seen straight, not through the
// glass: the camera's own ray.
in vec3 v_p;  // a point of the grown shaft on the pixel's ray (solid.vert)
out vec4 o_color;
uniform sampler2D u_scene;   // undistorted video (+ virtual obstacles)
uniform vec3 u_pen_tip;      // shaft axis: tip ...
uniform vec3 u_pen_axis;     // ... towards the cube (unit)
uniform float u_pen_length;  // tip to the cube's face
uniform float u_pen_radius;  // shaft
uniform float u_pen_margin;  // the video's pen may lie this far outside
uniform float u_pen_px;      // a pixel's width per metre of range

void main() {
  vec3 c = u_cam_in_tank;
  vec3 v = normalize(v_p - c);
  float s_max = (u_tank.w - c.z) / min(v.z, -1e-4);
  // The ray's point nearest the axis, on the ray's dry part (a convex
  // distance: its minimum, else the surface point).
  vec3 w0 = c - u_pen_tip;
  float b = dot(v, u_pen_axis);
  float d = dot(v, w0);
  float e = dot(u_pen_axis, w0);
  float u0 = (e - b * d) / max(1.0 - b * b, 1e-6);
  float s = clamp(dot(u_pen_tip + u0 * u_pen_axis - c, v), 0.0, s_max);
  vec3 x = c + s * v;
  float u = dot(x - u_pen_tip, u_pen_axis);
  vec3 a = u_pen_tip + u * u_pen_axis;
  vec3 off = x - a;
  float dist = length(off);
  float px = s * u_pen_px;
  float reach = u_pen_radius + u_pen_margin + px;
  // Outwards across the outline on screen: perpendicular to the axis and
  // to the ray, on the ray's side.
  vec3 side = normalize(cross(u_pen_axis, v));
  vec3 out_dir = dot(off, side) < 0.0 ? -side : side;
  // Unfiltered reads (the scene copy has the output's pixels): this pixel,
  // and the pixels holding the point beyond the outline and the axis.
  vec4 Vs = texelFetch(u_scene, ivec2(gl_FragCoord.xy), 0);
  vec4 Bs = texelFetch(
      u_scene, ivec2(VideoUv(a + out_dir * (reach + px)) * u_image_size), 0);
  vec3 V = DecodeVideo(Vs.rgb);
  vec3 B = DecodeVideo(Bs.rgb);
  vec3 P = DecodeVideo(
      texelFetch(u_scene, ivec2(VideoUv(a) * u_image_size), 0).rgb);
  vec3 pb = P - B;
  float contrast = dot(pb, pb);
  // The shares a shaft of the tracked radius, and of that radius -+ the
  // margin, covers (a box filter across the outline).
  float cover_shaft = clamp(0.5 + (u_pen_radius - dist) / px, 0.0, 1.0);
  float cover_lo =
      clamp(0.5 + (u_pen_radius - u_pen_margin - dist) / px, 0.0, 1.0);
  float cover_hi =
      clamp(0.5 + (u_pen_radius + u_pen_margin - dist) / px, 0.0, 1.0);
  float cover_video =
      clamp(dot(V - B, pb) / max(contrast, 1e-6), cover_lo, cover_hi);
  bool seen = Vs.a > 0.5 && Bs.a > 0.5 && contrast > 3e-3;
  // V - (1 - c) B is the pen's part, c P: never negative.
  vec4 blend = seen ? vec4(max(V - (1.0 - cover_video) * B, vec3(0.0)),
                           cover_video)
                    : vec4(cover_shaft * P, cover_shaft);
  bool outline = dist < reach && u > 0.0 && u < u_pen_length;
  o_color = outline ? blend : vec4(0.0);
}
