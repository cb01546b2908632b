// Water surface: per-fragment normal from the full-resolution height field,
// refraction of the real floor in the video, lit by the sky and the light
// through the surface (caustics, shadow), the floor<->surface
// inter-reflection and radiance's 1/n^2 on leaving the water, Beer-Lambert
// absorption along the view path, exact Fresnel against a reflection map
// folded from the video (after Ropinski et al.'s virtual reflections: the
// flat fold, or with ENV_CUBE their cube map, pass_envmap.h; with SKY the
// daylight sky above), and
// glints of the light's disc. All in linear light (render/optics.h gives the
// model and its constants); the result is encoded once, at the end.
//
// Deferred: the coarse mesh (water.vert + depth.frag) has already laid
// depth and marked its pixels in the stencil; this shader runs once per
// marked pixel (a scissored full-screen triangle) and finds the surface
// point by casting the pixel's ray against the height field. llvmpipe shades
// whole 4x4 blocks per triangle, so shading the mesh directly would run this
// shader 2-3 times per pixel along the many triangle edges.
//
// Compiled in variants (#define SHADOWS, CAUSTICS, REFLECTION, REFRACTION,
// REFRACTION_CUBIC, REAL_PEN, REAL_PLATE, MIRROR, WALL_FREE, FLAT_WATER):
// llvmpipe runs both sides of a branch (an `if` whose condition is false on
// every pixel still costs its body), so disabled effects must not be in the
// shader at all. The pen, the plate and the mirror are left out outside
// their regions of the screen, the walls inside theirs (water_regions.h).
//
// The real scene inside the water (with REFRACTION): with REAL_PEN, a
// refracted ray that meets the submerged part of the real pen's shaft sees
// the pen, coloured as the video shows the same line of the shaft just
// above the surface (the real pen is dry and straight, so this draws the
// "bent pen" at the waterline); with REAL_PLATE (a clean plate and an
// occluder mask this frame), a floor point whose line of sight from the
// camera passes through the real pen or an occluder (the video shows them,
// not the floor: the occluder mask marks both) takes the board from the
// clean plate.
in vec3 v_ray;  // the pixel's viewing ray (water_deferred.vert)
out vec4 o_color;
uniform sampler2D u_scene;       // undistorted video (+ virtual obstacles)
uniform sampler2D u_reflection;  // small blurred copy of the frame
uniform sampler2D u_receiver;    // shadow on floor (r) and surface (g)
uniform vec3 u_sigma;            // absorption per metre (r, g, b)
uniform vec3 u_scatter;          // colour of deep water (pool look; else 0)
uniform float u_ior;             // water
uniform float u_glass_ior;       // the walls' glass
uniform float u_glass_d;         // its thickness outside the inner size, m
// Constants of the floor's light (optics.h, WaterShading).
uniform vec3 u_floor_sky;        // sky through the flat surface to the floor
uniform vec3 u_floor_sun;        // direct light through the flat surface
// Over the floor (optics.h, ComputeFloorReturn): rgb the surroundings' light
// the walls let in, a the share of the floor's (green) light the water
// returns to it; u_return_tint the other bands' ratio to green.
uniform sampler2D u_floor_return;
uniform vec3 u_return_tint;
// The floor's mean light and the map's mean return share per band (the
// floor around a point, which the surface's return comes from;
// frame_state.h).
uniform vec3 u_floor_around;
uniform float u_inv_n2;
uniform float u_glass_t;         // a glass wall seen from inside the water
uniform vec3 u_under_glass[4];   // the board under a wall, over the dry
                                 // board: basis over the wall's normal
uniform float u_glint_peak;      // disc radiance per unit Fresnel
uniform float u_inv_alpha2;      // 1 / (disc's angular radius)^2
uniform sampler2D u_mirror;      // mirrored obstacles and pen (premultiplied)
uniform float u_mirror_depth;    // typical height of what it mirrors, metres
#ifdef OBSTACLES
// The virtual obstacles (pass_water.h, kMaxTracedObstacles), each in its own
// frame: base centre at the origin, axis +z; shape = (half x, half y,
// height, 0) for a box, (radius, radius, height, 1) for a cylinder.
const int kMaxObstacles = MAX_OBSTACLES;
uniform int u_obstacle_count;
uniform mat4 u_obstacle_from_tank[kMaxObstacles];
uniform vec4 u_obstacle_shape[kMaxObstacles];
uniform sampler2D u_video;  // the camera's own frame: no virtual object in it

// Distance along o + s d (0 < s < s_max, d unit) to the nearest virtual
// obstacle; s_max when it meets none. A constant trip count: unrolled, the
// uniforms' indices are constants (llvmpipe runs every iteration anyway).
float ObstaclesHit(vec3 o, vec3 d, float s_max) {
  float nearest = s_max;
  for (int i = 0; i < kMaxObstacles; ++i) {
    vec3 lo = (u_obstacle_from_tank[i] * vec4(o, 1.0)).xyz;
    vec3 ld = mat3(u_obstacle_from_tank[i]) * d;
    vec4 shape = u_obstacle_shape[i];
    // The slab 0 <= z <= height, then the side: the box's x and y slabs or
    // the cylinder's quadric; the ray is inside all of them over [in, out].
    vec3 inv = 1.0 / (abs(ld) + 1e-9) * sign(ld + 1e-12);
    vec2 z = (vec2(0.0, shape.z) - lo.z) * inv.z;
    float in_s = max(min(z.x, z.y), 0.0), out_s = max(z.x, z.y);
    if (shape.w > 0.5) {
      float a = max(dot(ld.xy, ld.xy), 1e-12);
      float b = dot(lo.xy, ld.xy);
      float disc = b * b - a * (dot(lo.xy, lo.xy) - shape.x * shape.x);
      float root = sqrt(max(disc, 0.0));
      in_s = max(in_s, (-b - root) / a);
      out_s = disc > 0.0 ? min(out_s, (-b + root) / a) : -1.0;
    } else {
      vec2 x0 = (-shape.xy - lo.xy) * inv.xy, x1 = (shape.xy - lo.xy) * inv.xy;
      vec2 near = min(x0, x1), far = max(x0, x1);
      in_s = max(in_s, max(near.x, near.y));
      out_s = min(out_s, min(far.x, far.y));
    }
    bool hit = i < u_obstacle_count && in_s < out_s && in_s < nearest;
    nearest = hit ? in_s : nearest;
  }
  return nearest;
}
#endif

#ifdef REAL_PEN
uniform vec3 u_pen_tip;      // shaft axis: tip ...
uniform vec3 u_pen_axis;     // ... towards the cube (unit)
uniform float u_pen_length;  // tip to the cube's face
uniform float u_pen_radius;  // shaft
uniform float u_pen_margin;  // the video's pen may lie this far outside
#endif
#ifdef REAL_PLATE
uniform sampler2D u_occluders;  // 1: an occluder, 0.5: the pen (pass_real.h)
uniform sampler2D u_plate;      // the board alone, tank frame
uniform vec4 u_plate_map;       // uv = xy * map.xy + map.zw
uniform float u_plate_gain;     // this frame's light over the plate's
#endif
#ifdef REAL_PEN

// Distance along o + s d (0 < s < s_max, d unit) to the shaft's side, of
// `radius`; s_max when it misses.
float ShaftHit(vec3 o, vec3 d, float s_max, float radius) {
  vec3 m = o - u_pen_tip;
  vec3 dp = d - dot(d, u_pen_axis) * u_pen_axis;
  vec3 mp = m - dot(m, u_pen_axis) * u_pen_axis;
  float a = max(dot(dp, dp), 1e-12);
  float b = dot(mp, dp);
  float disc = b * b - a * (dot(mp, mp) - radius * radius);
  float s = (-b - sqrt(max(disc, 0.0))) / a;
  float u = dot(m + s * d, u_pen_axis);
  bool hit = disc > 0.0 && s > 0.0 && s < s_max &&
             u > -u_pen_margin && u < u_pen_length;
  return hit ? s : s_max;
}

#endif

// A ray that reaches the surface through a wall facing the camera, above
// the water, crosses the glass slab (u_glass_d thick, outside the inner
// size): it leaves parallel to itself, shifted sideways. The shift of its
// origin, summed over the x and the y wall on the camera's side (zero for a
// ray that passes over a wall's top or meets its inner face under the
// water, where walls.frag draws the glass).
vec3 GlassWallShift(vec3 c, vec3 v) {
  vec3 shift = vec3(0.0);
  for (int axis = 0; axis < 2; ++axis) {
    float half_in = 0.5 * u_tank[axis];
    float side = sign(c[axis]);
    float toward = max(-side * v[axis], 1e-6);  // the ray's speed inwards
    float t_out = (side * c[axis] - half_in - u_glass_d) / toward;
    float t_in = (side * c[axis] - half_in) / toward;
    bool crosses = side * c[axis] > half_in + u_glass_d &&
                   c.z + t_out * v.z < u_tank.z &&
                   c.z + t_in * v.z > u_tank.w;
    vec3 n = vec3(0.0);
    n[axis] = side;  // the wall's outward normal
    vec3 g = refract(v, n, 1.0 / u_glass_ior);
    vec3 d = g * (u_glass_d / max(-dot(g, n), 1e-3)) - v * (u_glass_d / toward);
    shift += crosses ? d : vec3(0.0);
  }
  return shift;
}

// A frame of the output's size (the scene copy of video and obstacles, or
// the camera's own frame) at uv, where a refracted ray lands.
// With REFRACTION_CUBIC by Catmull-Rom interpolation (the floor seen through
// the water is magnified, so the lookups fall between the frame's pixels,
// where one bilinear fetch blurs a fine pattern): the weights of the
// frame's 4 x 4 texels around uv are separable, w0..w3 per axis; the middle
// pair's weights (both positive) are taken by one bilinear fetch between
// them, and the four corner taps (w0 w0, w0 w3, ...: each under 0.6% of the
// total) are left out and the other five renormalised. Beside a hard edge
// the negative lobes overshoot by up to 7% of the step for a pixel (a
// halo that clamping to the fetches' range would take away with most of
// the sharpness: the grating's response falls to 0.82); clamped to [0, 1].
vec4 FrameAt(sampler2D frame, vec2 uv) {
#ifdef REFRACTION_CUBIC
  vec2 q = uv * u_image_size;
  vec2 c1 = floor(q - 0.5) + 0.5;  // the texel centre left of / below q
  vec2 f = q - c1;
  vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
  vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
  vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
  vec2 w3 = f * f * (-0.5 + 0.5 * f);
  vec2 w12 = w1 + w2;
  vec2 p0 = (c1 - 1.0) / u_image_size;
  vec2 p3 = (c1 + 2.0) / u_image_size;
  vec2 p12 = (c1 + w2 / w12) / u_image_size;
  vec4 sum = textureLod(frame, p12, 0.0) * (w12.x * w12.y) +
             textureLod(frame, vec2(p12.x, p0.y), 0.0) * (w12.x * w0.y) +
             textureLod(frame, vec2(p12.x, p3.y), 0.0) * (w12.x * w3.y) +
             textureLod(frame, vec2(p0.x, p12.y), 0.0) * (w0.x * w12.y) +
             textureLod(frame, vec2(p3.x, p12.y), 0.0) * (w3.x * w12.y);
  float weight = w12.x * (w0.y + w12.y + w3.y) + w12.y * (w0.x + w3.x);
  return clamp(sum / weight, 0.0, 1.0);
#else
  return textureLod(frame, uv, 0.0);
#endif
}

// The reflected environment towards r: the fold (r's vanishing point in
// the blurred frame: the surroundings as seen from far away) or, with
// ENV_CUBE, the cube map by direction (common.glsl's Environment). A ray
// reflected upwards never comes down to the table's plane, so what it meets
// lies above that plane; read at its vanishing point the frame shows what
// lies along r far away, above the plane's horizon, and never the table
// near the tank, which a point at a finite distance reads wherever the view
// is grazing. The frame shows the direction only if it lies in front of the
// camera and inside the image; elsewhere the ray sees what no frame shows,
// the sky overhead, faded in over the image's outer FOLD_FADE (a share of
// its width / height).
#define FOLD_FADE 0.08
vec3 EnvLookup(vec3 r) {
#ifdef ENV_CUBE
  return Environment(r, vec3(0.0));
#else
  vec3 c = mat3(u_cam_from_tank) * r;
  vec2 uv = (u_intr.xy * c.xy / max(c.z, 0.02) + u_intr.zw + 0.5) /
            u_image_size;
  vec2 inside = min(uv, 1.0 - uv);
  float seen = step(0.02, c.z) *
               smoothstep(0.0, FOLD_FADE, min(inside.x, inside.y));
  vec3 video = DecodeVideo(textureLod(u_reflection, uv, 0.0).rgb);
  vec3 sky = Overhead(r);  // one lookup of the daylight sky, not two
  return mix(mix(sky, video, seen), sky, OverheadShare(r));
#endif
}

void main() {
#ifdef FLAT_WATER
  o_color = vec4(1.0);
#else
  // The pixel's ray (OpenCV pixel = window - 0.5 in our top-first FBO) and
  // two fixed-point steps onto the surface z = level + h(x, y). Height and
  // slope are precomputed per cell: (h, dh/dx, dh/dy).
  vec3 v = normalize(v_ray);
#ifdef WALL_FREE
  // No wall's glass between the camera and the surface here, and no wall
  // in the refracted ray's way (water_regions.h, WallFreeRect).
  vec3 c = u_cam_in_tank;
#else
  vec3 c = u_cam_in_tank + GlassWallShift(u_cam_in_tank, v);
#endif
  float dz = min(v.z, -1e-4);
  float s = (u_tank.w - c.z) / dz;
  vec3 hs = HeightAt(c.xy + s * v.xy);
  s = (u_tank.w + hs.x - c.z) / dz;
  hs = HeightAt(c.xy + s * v.xy);
  s = (u_tank.w + hs.x - c.z) / dz;
  vec3 p = c + s * v;
  p.xy = clamp(p.xy, -0.5 * u_tank.xy, 0.5 * u_tank.xy);
  vec3 n = normalize(vec3(-hs.y, -hs.z, 1.0));
  vec2 tank_uv = p.xy / u_tank.xy + 0.5;

  // Refraction (Snell, air to water) to the floor or a wall.
#ifdef REFRACTION
  vec3 t = refract(v, n, 1.0 / u_ior);
#else
  vec3 t = v;
#endif
#ifdef WALL_FREE
  float th = t.z < -1e-5 ? -p.z / t.z : 1e3;
  vec3 f = p + t * th;
  vec3 lookup = f;
  bool floor_seen = true;
  // The ray's legs in the water: from the surface, and none after it.
  float leg1 = th, leg2 = 0.0;
  vec3 leg2_from = f, leg2_dir = t;
#else
  vec2 half_size = 0.5 * u_tank.xy;
  float tf = t.z < -1e-5 ? -p.z / t.z : 1e3;
  float tx = abs(t.x) > 1e-6 ? (sign(t.x) * half_size.x - p.x) / t.x : 1e3;
  float ty = abs(t.y) > 1e-6 ? (sign(t.y) * half_size.y - p.y) / t.y : 1e3;
  float tw = max(min(tx, ty), 0.0);
  float th = min(tf, tw);
  vec3 f = p + t * th;
  // At a side wall (a glass slab refracts as water to air): beyond the
  // critical angle the slab's outer face mirrors the ray back; otherwise it
  // leaves the tank and meets the board behind it (or the sky: the ambient
  // radiance) and the video is read there. Mirrored, the ray crosses the
  // glass twice (direction tg out, its mirror image back), coming down by
  // 2 d |tg.z| / |tg.n| and along the wall by 2 d |tg_t| / |tg.n| before it
  // re-enters the water towards the floor; a ray that reaches z = 0 inside
  // the glass sees the board under it.
  bool on_floor = tf <= tw;
  vec3 wall_n = tx < ty ? vec3(-sign(t.x), 0.0, 0.0) : vec3(0.0, -sign(t.y), 0.0);
  vec3 out_dir = refract(t, wall_n, u_ior);
  bool mirrored = !on_floor && dot(out_dir, out_dir) < 0.5;
  vec3 t2 = reflect(t, wall_n);
  vec3 tg = refract(t, wall_n, u_ior / u_glass_ior);
  vec3 tg_back = reflect(tg, wall_n);
  float glass_path = 2.0 * u_glass_d / max(-dot(tg, wall_n), 1e-3);
  float to_board = f.z / max(-tg.z, 1e-5);
  bool under_glass = mirrored && to_board < glass_path;
  vec3 in_glass = f + tg * min(to_board, 0.5 * glass_path) +
                  tg_back * max(to_board - 0.5 * glass_path, 0.0);
  // Out through the slab: a parallel slab keeps the ray's direction but
  // moves the point where it leaves, to the outer face d / cos(theta_g)
  // along the ray in the glass (half the mirrored path); a ray that comes
  // down to z = 0 inside the glass sees the board under it.
  vec3 exit = f + tg * (0.5 * glass_path);
  vec3 f2 = exit + tg_back * (0.5 * glass_path);
  float tf2 = t2.z < -1e-5 ? -f2.z / t2.z : 0.0;
  float leave = out_dir.z < -1e-5 ? -exit.z / out_dir.z : 0.0;
  vec3 beyond = exit.z > 0.0 ? exit + out_dir * leave : in_glass;
  vec3 lookup = on_floor ? f
                         : (mirrored ? (under_glass ? in_glass : f2 + t2 * tf2)
                                     : beyond);
  bool floor_seen = on_floor || (mirrored && !under_glass);
  // The ray's legs in the water: from the surface to the floor or a wall,
  // and from a wall's mirror to the floor.
  float leg1 = th, leg2 = floor_seen && mirrored ? tf2 : 0.0;
  vec3 leg2_from = f2, leg2_dir = t2;
  th += floor_seen && mirrored ? tf2 : 0.0;
  f = floor_seen ? lookup : f;
#endif
#ifdef REAL_PEN
  // The submerged shaft in the way: seen as the video shows the same line
  // of the cylinder 4 mm above the surface (one fetch for either: the
  // lookup point is chosen, not the colour), lit like an obstacle.
  float s_pen = ShaftHit(p, t, th, u_pen_radius);
  bool pen_hit = s_pen < th;
  vec3 h = p + s_pen * t;
  vec3 above =
      h + u_pen_axis * ((u_tank.w + 0.004 - h.z) / max(u_pen_axis.z, 0.2));
  lookup = pen_hit ? above : lookup;
#else
  const bool pen_hit = false;
#endif
  vec2 lookup_uv = VideoUv(lookup);
  vec4 seen = FrameAt(u_scene, lookup_uv);
#ifdef OBSTACLES
  // A virtual obstacle in the copy where the ray lands may only hide that
  // point from the camera, not stand in the ray's way (the copy is the
  // camera's view, the ray runs from the surface). Traced against the
  // obstacles: a ray that meets one keeps the copy's obstacle; one that
  // passes reads the point in the camera's own frame, which holds no
  // virtual object (one bilinear fetch: llvmpipe runs this on every pixel
  // of the variant).
  bool passes = ObstaclesHit(p, t, leg1) >= leg1 &&
                ObstaclesHit(leg2_from, leg2_dir, leg2) >= leg2;
  if (seen.a < 0.5 && !pen_hit && passes) {
    vec2 frame_px = DistortedPixel(lookup_uv * u_image_size - 0.5);
    seen = vec4(
        textureLod(u_video, (frame_px + 0.5) / u_image_size, 0.0).rgb, 1.0);
  }
#endif
  seen.rgb = DecodeVideo(seen.rgb);
#ifdef REAL_PLATE
  // A board point (z = 0) the video does not show (the occluder mask: 1 an
  // occluder, 0.5 the pen's silhouette): the clean plate's board there
  // (unknown texels keep the video).
  if (!pen_hit && seen.a > 0.5 && lookup.z < 1e-3 &&
      textureLod(u_occluders, lookup_uv, 0.0).r > 0.25) {
    vec4 board =
        textureLod(u_plate, lookup.xy * u_plate_map.xy + u_plate_map.zw, 0.0);
    seen.rgb =
        mix(seen.rgb, DecodeVideo(board.rgb) * u_plate_gain, board.a);
  }
#endif
  // A virtual obstacle in the way (alpha 0, solid.frag) holds its radiance
  // in the water: the floor's light does not apply to it.
  float obstacle = 1.0 - seen.a;
  // The real pen's shaft, as the video shows it in the air: lit through the
  // surface like the floor, without the floor's shadow and caustics.
  float shaft = 0.0;
#ifdef REAL_PEN
  if (pen_hit) {
    obstacle = 0.0;
    shaft = 1.0;
    th = s_pen;
    f = h;
    floor_seen = true;
  }
#endif
  vec3 video = seen.rgb;  // linear
  float lit = 1.0;
  vec2 floor_uv = f.xy / u_tank.xy + 0.5;
#ifdef SHADOWS
  lit *= textureLod(u_receiver, floor_uv, 0.0).r;
#endif
#ifdef CAUSTICS
  lit *= textureLod(u_caustics, floor_uv, 0.0).r;
#endif
  // The floor under water, relative to the dry floor the video shows: the
  // sky and the light through the surface, the surroundings through the
  // walls, the water's return and 1/n^2; a ray out through a wall sees the
  // board (the video) or the sky beyond the glass.
  vec3 floor_light = u_floor_sky + u_floor_sun * mix(lit, 1.0, shaft);
  vec4 back = textureLod(u_floor_return, floor_uv, 0.0);
  vec3 returned = back.a * u_return_tint;
  floor_light += back.rgb;
  // An obstacle's pixel holds its radiance in the water (solid.frag): only
  // the way out, 1/n^2, applies to it.
  // The surface's return comes from the floor around, of the floor's mean
  // albedo and lit as the floor's mean: L = V (E + R u_floor_around), with
  // u_floor_around = V_mean E_mean / (1 - R_mean V_mean); V E / (1 - R V) on
  // a uniform, uniformly lit floor.
  vec3 under =
      mix(video * (floor_light + returned * u_floor_around), video, obstacle) *
      u_inv_n2;
#ifdef WALL_FREE
  vec3 below = under;
#else
  // Out through a wall: the board beyond it (the video) or the sky, through
  // the glass; the board under the glass, lit through it (optics.h,
  // under_glass: per wall, from the basis that pass_water.cc makes of it).
  vec3 board_under = u_under_glass[0] + wall_n.x * u_under_glass[1] +
                     wall_n.y * u_under_glass[2] +
                     abs(wall_n.x) * u_under_glass[3];
  vec3 seen_out = out_dir.z < -1e-5 || under_glass ? video : vec3(u_ambient);
  vec3 below =
      floor_seen ? under
                 : seen_out * (under_glass ? board_under : vec3(u_glass_t));
  // The board under the glass is a band a few pixels tall between the floor
  // at the wall's foot and the floor in the wall's mirror: its pixels on
  // either edge hold both, by the share of the pixel each covers. The ray
  // meets the wall's plane at height z_wall (below 0 where the floor comes
  // first) and sees the board under the glass for 0 < z_wall < the descent
  // of its way out and back through the slab; either side the floor's
  // paper, lit as the floor is (`under`, from the same fetch: the paper
  // under the glass and beside it are one sheet).
  float z_wall = p.z + t.z * tw;
  float band_top = glass_path * max(-tg.z, 0.0);
  // The step between neighbouring pixels, capped at a centimetre: where
  // the rays of neighbouring pixels meet the wall's plane farther apart
  // than that (a steep ripple; a ray nearly vertical whose wall lies metres
  // away along it; the nearest wall switching between x and y), the pixel
  // does not straddle the band's edge, and fwidth's huge step would spread
  // the band over the open floor (a quarter of the board under the glass
  // mixed into pixels far from any wall). A wall seen through the water
  // climbs a few millimetres a pixel.
  float z_step = clamp(fwidth(z_wall), 1e-7, 0.01);
  float band = clamp(0.5 + z_wall / z_step, 0.0, 1.0) *
               clamp(0.5 + (band_top - z_wall) / z_step, 0.0, 1.0);
  band *= float(dot(out_dir, out_dir) < 0.5 && !pen_hit) * (1.0 - obstacle);
  below = band > 0.0 ? mix(under, video * board_under, band) : below;
#endif
  vec3 transmit = exp(-u_sigma * th);
  vec3 color = below * transmit + u_scatter * (1.0 - transmit);

  vec3 r = reflect(v, n);
  float fresnel = FresnelExact(dot(-v, n), u_ior);
#ifdef REFLECTION
  // The environment, and over it the mirrored obstacles and pen
  // (pass_mirror.h, premultiplied), displaced by the surface's slope: a tilt
  // of the normal turns the reflected ray by twice as much.
  vec3 env = EnvLookup(r);
#ifdef MIRROR
  vec4 mirror = textureLod(
      u_mirror, VideoUv(p + vec3(2.0 * u_mirror_depth * n.xy, 0.0)), 0.0);
  env = env * (1.0 - mirror.a) + mirror.rgb;
#endif
  color = mix(color, env, fresnel);
#else
  color *= 1.0 - fresnel;
#endif
#ifdef SHADOWS
  float sun = textureLod(u_receiver, tank_uv, 0.0).g;
#else
  float sun = 1.0;
#endif
  // Glints: the disc's radiance, spread as exp(-theta^2 / alpha^2) around
  // the light with the disc's energy, theta^2 ~ 2 (1 - cos theta).
  float x = max(dot(r, u_light), 0.0);
  color += (u_glint_peak * fresnel * sun) *
           exp(-2.0 * u_inv_alpha2 * (1.0 - x));
  o_color = vec4(EncodeOutput(color), 1.0);
#endif
}
