// Glass walls with dual-source blending, dst' = src0 + dst * src1.
//
// FRONT_WALL (walls facing the camera), below the water: what the glass
// shows is computed here in linear light and replaces dst (src1 = 0): the
// ray refracts into the water at the glass (a thin slab refracts as air to
// water), crosses the volume (Beer-Lambert) and ends on the floor (lit like
// the floor under the surface: sky and light through it, caustics, shadow,
// the water's return and the surroundings through the walls, and radiance's
// 1/n^2 on the way out), on the underside of the surface (its mirror image of
// the floor, or the sky through it) or on the far wall (what lies beyond).
//
// With UNDER_SURFACE too, the part of a front wall under the surface's
// lowest point, where the surface test is not needed.
//
// Elsewhere (above the water, walls facing away) the glass's exact Fresnel
// reflection of the sky is blended in linear light, dst * T + C: the pass
// draws into an sRGB view of the output (FrameTarget::srgb_fbo) with
// GL_FRAMEBUFFER_SRGB on, so the blend decodes dst, blends and encodes the
// result. So every output of this shader is linear (after the highlight
// shoulder): src0 = C and src1 = T, and in the front walls' part under the
// water the radiance itself. The corners' rims are mixed towards white in
// linear light. The waterline gets no line of its own: the surface meets
// the glass flat, as in the reference renderer (no meniscus).
in vec3 v_p;
in vec3 v_n;
in vec2 v_wall;
#ifdef BOARD_MIRROR
in vec4 v_board;  // walls.vert
#endif
layout(location = 0, index = 0) out vec4 o_color;
layout(location = 0, index = 1) out vec4 o_transmit;
uniform vec3 u_sigma;
uniform vec3 u_scatter;
uniform float u_glass_ior;
uniform float u_ior;
uniform sampler2D u_scene;
uniform sampler2D u_receiver;
uniform sampler2D u_floor_return;  // as in water.frag
uniform vec3 u_return_tint;
uniform vec3 u_floor_around;  // as in water.frag
uniform vec3 u_floor_sky;
uniform vec3 u_floor_sun;
uniform float u_inv_n2;
uniform sampler2D u_reflection;  // quarter-size video (pass_video.h)
uniform float u_board_mirror;
#ifndef BOARD_MIRROR
// The floor near the walls under flat water as the air sees it
// (frame_state.h, FloorReturnLight::floor_seen).
uniform vec3 u_floor_seen;
#endif

// The floor at `f` under water, of video colour `video`, seen from the
// water: as in water.frag.
vec3 FloorUnderWater(vec3 f, vec3 video) {
  vec2 uv = f.xy / u_tank.xy + 0.5;
  // Compile-time, as in water.frag (llvmpipe would fetch either way).
  float lit = 1.0;
#ifdef SHADOWS
  lit *= textureLod(u_receiver, uv, 0.0).r;
#endif
#ifdef CAUSTICS
  lit *= textureLod(u_caustics, uv, 0.0).r;
#endif
  vec4 back = textureLod(u_floor_return, uv, 0.0);
  vec3 light = u_floor_sky + u_floor_sun * lit + back.rgb;
  vec3 returned = back.a * u_return_tint;
  return video * (light + returned * u_floor_around);
}

// Distance along `d` from `p` (inside the tank) to the floor, the rest
// surface and the side walls.
vec4 Exits(vec3 p, vec3 d) {
  vec2 half_size = 0.5 * u_tank.xy;
  float tf = d.z < -1e-5 ? -p.z / d.z : 1e3;
  float ts = d.z > 1e-5 ? (u_tank.w - p.z) / d.z : 1e3;
  float tx = abs(d.x) > 1e-6 ? (sign(d.x) * half_size.x - p.x) / d.x : 1e3;
  float ty = abs(d.y) > 1e-6 ? (sign(d.y) * half_size.y - p.y) / d.y : 1e3;
  return vec4(tf, ts, max(min(tx, ty), 0.0), 0.0);
}

void main() {
  vec3 v = normalize(v_p - u_cam_in_tank);
  vec2 half_size = 0.5 * u_tank.xy;
#if defined(FRONT_WALL) && !defined(UNDER_SURFACE)
  float surface = SurfaceZ(clamp(v_p.xy, -half_size, half_size));
#endif
  vec3 color = vec3(0.0);
  // Bright rims at the corners, where two slabs meet (the top edge is the
  // top face's, wall_tops.frag).
  float edge = min(v_wall.x, v_wall.y - v_wall.x);
  float rim = 0.45 * (1.0 - smoothstep(0.0006, 0.0016, edge));
  const vec3 kRimColor = vec3(0.787, 0.933, 1.0);  // linear
  vec3 nrm = normalize(v_n);
  float cos_v = abs(dot(v, nrm));
  float r_glass = 2.0 * FresnelExact(cos_v, u_glass_ior);
  // What the glass reflects: the uniform sky, or the environment (cube map,
  // daylight sky) by the mirrored ray; the water in the tank where that ray
  // goes down into it (below). A wall facing the camera
  // (BOARD_MIRROR) mirrors the ray downwards onto the board in front of it,
  // which the video shows: that board point (walls.vert), looked up in the
  // quarter-size reflection map while it lies in the frame (the glass shows
  // the tags and the paper around the tank mirrored, as real glass does; it
  // reflects a few per cent, so the map's blur hardly shows).
  vec3 sky_seen = Environment(reflect(v, nrm), vec3(u_ambient));
#ifdef BOARD_MIRROR
  vec2 board_uv = (v_board.xy / v_board.z + 0.5) / u_image_size;
  bool board_seen = u_board_mirror > 0.5 && v_board.w > 0.0 &&
                    v_board.z > 0.0 && all(greaterThan(board_uv, vec2(0.0))) &&
                    all(lessThan(board_uv, vec2(1.0)));
  if (board_seen)
    sky_seen = DecodeVideo(textureLod(u_reflection, board_uv, 0.0).rgb);
#else
  // A wall seen from inside the tank (the back and side walls) mirrors the
  // ray downwards into the tank: above the water the mirrored ray meets the
  // surface a few millimetres from the wall and sees the sky's image in it
  // (Fresnel) and, refracted, the floor under the water near the walls,
  // taken at its mean (u_floor_seen): the glass reflects it at grazing
  // angles, where the floor's pattern, caustics and shadows blur into it.
  sky_seen = mix(u_floor_seen, sky_seen,
                 FresnelExact(-reflect(v, nrm).z, u_ior));
#endif
#ifdef FRONT_WALL
#ifdef UNDER_SURFACE
  {
#else
  if (v_p.z < surface) {
#endif
    // The slab's two interfaces: air-glass outside, glass-water inside (the
    // ray's cosine in the glass by Snell); both reflect the sky's mirror
    // direction, and the rest enters the water.
    float cos_g = sqrt(1.0 - (1.0 - cos_v * cos_v) /
                                 (u_glass_ior * u_glass_ior));
    r_glass = FresnelExact(cos_v, u_glass_ior) +
              FresnelExact(cos_g, u_ior / u_glass_ior);
    // Into the water through the glass (n_glass cancels for a thin slab).
    vec3 d = refract(v, nrm, 1.0 / u_ior);
    vec3 p = v_p - nrm * 1e-5;
    vec4 e = Exits(p, d);
    // One lookup: the floor straight ahead, the floor in the surface's
    // mirror (seen from below), or what lies beyond the far wall.
    bool to_floor = e.x <= e.y && e.x <= e.z;
    bool to_surface = !to_floor && e.y <= e.z;
    vec3 q = p + d * e.y;
    vec3 d2 = vec3(d.xy, -d.z);
    vec4 e2 = Exits(q, d2);
    float t2 = min(e2.x, e2.z);
    float r_s = to_surface ? FresnelExact(d.z, 1.0 / u_ior) : 1.0;
    vec3 at = to_floor ? p + d * e.x : (to_surface ? q + d2 * t2 : p + d * e.z);
    float len = to_floor ? e.x : (to_surface ? e.y + t2 : e.z);
    vec3 video = DecodeVideo(textureLod(u_scene, VideoUv(at), 0.0).rgb);
    vec3 floor_seen = FloorUnderWater(at, video) * u_inv_n2;
    vec3 seen = to_floor || to_surface
                    ? r_s * floor_seen + (1.0 - r_s) * vec3(u_ambient)
                    : video;
    vec3 transmit_w = exp(-u_sigma * len);
    vec3 lin = (seen * transmit_w + u_scatter * (1.0 - transmit_w)) *
                   (1.0 - r_glass) +
               sky_seen * r_glass;
    o_color = vec4(mix(Shoulder(lin), kRimColor, rim), 1.0);
    o_transmit = vec4(0.0);
    return;
  }
#endif
#ifndef UNDER_SURFACE
  // Glass: two faces reflecting the sky (radiance u_ambient) or the
  // environment by Fresnel; the glass is grey, one transmittance for the
  // three bands.
  color = color * (1.0 - r_glass) + sky_seen * r_glass;
  float transmit = 1.0 - r_glass;
  color = color * (1.0 - rim) + kRimColor * rim;
  transmit *= 1.0 - rim;
  o_color = vec4(color, 1.0);
  o_transmit = vec4(vec3(transmit), 1.0);
#endif
}
