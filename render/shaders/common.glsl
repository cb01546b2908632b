// Shared by every Ripple shader; prepended after the #version line.
// Textures have no mipmaps: lookups use textureLod(..., 0.0), which spares
// llvmpipe the per-quad derivatives and LOD selection of texture().
// Frames: tank frame (metres, z up, floor z = 0); camera frame is OpenCV's.
uniform mat4 u_clip_from_tank;   // FBO stores the image top row first
uniform mat4 u_cam_from_tank;
uniform mat4 u_tank_from_cam;
uniform vec4 u_intr;             // fx, fy, cx, cy (pixels)
uniform vec2 u_image_size;       // pixels
uniform vec3 u_cam_in_tank;      // camera centre
uniform vec4 u_tank;             // inner size x, y; wall height; rest level
uniform vec2 u_hf_extent;        // height-field extent nx*d, ny*d (metres)
uniform vec2 u_hf_texel;         // 1/nx, 1/ny
uniform sampler2D u_height;      // RGBA8: displacement from the rest level,
                                 // dh/dx, dh/dy (per cell, linear filtered),
uniform vec3 u_hf_scale;         // coded: value = offset + scale * texel
uniform vec3 u_hf_offset;
uniform vec3 u_light;            // unit vector towards the light
uniform vec3 u_light_refracted;  // light direction under a flat surface
uniform mat4 u_shadow_from_tank; // -> shadow map [0,1]^3
uniform sampler2DShadow u_shadow;
uniform float u_shadow_on;
uniform vec2 u_shadow_texel;    // PCF tap offset (texture units)
uniform float u_shadow_bias;     // depth bias (texture depth units)
uniform sampler2D u_caustics;    // relative floor irradiance (flat = 1)
// Colour: shaders work in linear light (sRGB textures decode the video on
// fetch) and encode what they write with EncodeOutput.
uniform float u_srgb_out;        // 1: the output is sRGB-encoded, 0: linear
uniform float u_knee;            // highlight shoulder's knee (linear)
uniform float u_ambient;         // the sky's share of the board's light

#ifdef ENV_CUBE
uniform samplerCube u_env;       // environment cube map (pass_envmap.h)
uniform mat3 u_cube_from_tank;   // the camera's rotation at its rebuild
#endif
#ifdef SKY
uniform samplerCube u_sky;       // daylight sky, tank frame, display units
#endif

// The sky the lighting model assumes, towards r.
vec3 Overhead(vec3 r) {
#ifdef SKY
  return textureLod(u_sky, r, 0.0).rgb;
#else
  return vec3(u_ambient);
#endif
}

// The environment towards the tank-frame direction r: the cube map, or
// `fallback` (the caller's fold or uniform sky), where the video shows the
// surroundings; rays climbing above that see what no camera looking at a
// table sees, the overhead: the sky the lighting model assumes (outdoors
// the daylight sky, indoors the uniform sky of radiance u_ambient that the
// ambient term integrates), blended in between 20 and 60 degrees of
// elevation (sin = 0.342, 0.866).
float OverheadShare(vec3 r) { return smoothstep(0.342, 0.866, r.z); }

vec3 Environment(vec3 r, vec3 fallback) {
#ifdef ENV_CUBE
  vec3 env = textureLod(u_env, u_cube_from_tank * r, 0.0).rgb;
#else
  vec3 env = fallback;
#endif
  return mix(env, Overhead(r), OverheadShare(r));
}

// The video's encoded value -> linear light (u_srgb_out: the video's
// transfer, which the output shares). The video's textures (the scene copy,
// the reflection map, the clean plate) are plain RGBA8, filtered as stored
// and decoded here, once per lookup: llvmpipe's sRGB textures decode each
// of the four texels before filtering, which cost 8% of the main pass. The power segment of
// IEC 61966-2-1 by a quartic fit, within 0.05 of an 8-bit level through a
// decode and EncodeOutput; filtering before the decode differs from
// filtering linear light only between texels of different values (an edge
// between them moves by a fraction of a pixel).
vec3 DecodeVideo(vec3 e) {
  vec3 power =
      (((-0.116823349 * e + 0.526568333) * e + 0.560340083) * e +
       0.028410428) * e + 0.001045935;
  vec3 lin = mix(e * (1.0 / 12.92), power, step(0.04045, e));
  return mix(e, lin, u_srgb_out);
}

vec2 HeightUv(vec2 xy) { return xy / u_hf_extent + 0.5; }

// (h, dh/dx, dh/dy) at tank point xy, filtered and decoded.
vec3 HeightAt(vec2 xy) {
  return u_hf_offset + u_hf_scale * textureLod(u_height, HeightUv(xy), 0.0).rgb;
}

float SurfaceZ(vec2 xy) {
  return u_tank.w + u_hf_offset.x +
         u_hf_scale.x * textureLod(u_height, HeightUv(xy), 0.0).r;
}

// Texture coordinate of a tank point in the (undistorted) video.
vec2 VideoUv(vec3 p_tank) {
  vec3 c = (u_cam_from_tank * vec4(p_tank, 1.0)).xyz;
  vec2 px = u_intr.xy * c.xy / max(c.z, 1e-4) + u_intr.zw;
  return (px + 0.5) / u_image_size;
}

// OpenCV's distortion model (u_dist0: k1 k2 p1 p2, u_dist1: k3 k4 k5 k6)
// forwards: an ideal pinhole image's pixel -> the camera frame's, both with
// OpenCV's centres (pixel (0, 0) at the first texel's centre).
uniform vec4 u_dist0;
uniform vec4 u_dist1;
vec2 DistortedPixel(vec2 px) {
  vec2 xy = (px - u_intr.zw) / u_intr.xy;
  float r2 = dot(xy, xy);
  float r4 = r2 * r2, r6 = r4 * r2;
  float radial = (1.0 + u_dist0.x * r2 + u_dist0.y * r4 + u_dist1.x * r6) /
                 (1.0 + u_dist1.y * r2 + u_dist1.z * r4 + u_dist1.w * r6);
  float p1 = u_dist0.z, p2 = u_dist0.w;
  vec2 d = vec2(xy.x * radial + 2.0 * p1 * xy.x * xy.y +
                    p2 * (r2 + 2.0 * xy.x * xy.x),
                xy.y * radial + p1 * (r2 + 2.0 * xy.y * xy.y) +
                    2.0 * p2 * xy.x * xy.y);
  return u_intr.xy * d + u_intr.zw;
}

// The shadow map's filter, a compile-time variant (RendererOptions::
// shadow_filter; llvmpipe would run every branch). 1 = lit.
//   default: percentage-closer filtering, 4 bilinear hardware-compared taps
//     u_shadow_texel apart (1.2 mm on the tank's scale);
//   SHADOW_FILTER_GAUSS: Gaussian-weighted PCF (after Kolivand & Sunar's
//     Z-GaF): 3x3 bilinear hardware-compared taps u_shadow_texel apart,
//     weighted 1, SHADOW_GAUSS_W1, SHADOW_GAUSS_W1^2 (centre, side, corner)
//     and normalised;
//   SHADOW_FILTER_HARD: one hardware-compared tap of the nearest texel.
float Shadow(vec3 p_tank) {
  if (u_shadow_on < 0.5) return 1.0;
  vec3 s = (u_shadow_from_tank * vec4(p_tank, 1.0)).xyz;
  s.z -= u_shadow_bias;
  if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0))))
    return 1.0;
  vec2 o = u_shadow_texel;
#if defined(SHADOW_FILTER_HARD)
  return textureLod(u_shadow, s, 0.0);
#elif defined(SHADOW_FILTER_GAUSS)
  const float w1 = SHADOW_GAUSS_W1;
  float centre = textureLod(u_shadow, s, 0.0);
  float sides = textureLod(u_shadow, vec3(s.xy + vec2(-o.x, 0.0), s.z), 0.0) +
                textureLod(u_shadow, vec3(s.xy + vec2(o.x, 0.0), s.z), 0.0) +
                textureLod(u_shadow, vec3(s.xy + vec2(0.0, -o.y), s.z), 0.0) +
                textureLod(u_shadow, vec3(s.xy + vec2(0.0, o.y), s.z), 0.0);
  float corners =
      textureLod(u_shadow, vec3(s.xy + vec2(-o.x, -o.y), s.z), 0.0) +
      textureLod(u_shadow, vec3(s.xy + vec2(o.x, -o.y), s.z), 0.0) +
      textureLod(u_shadow, vec3(s.xy + vec2(-o.x, o.y), s.z), 0.0) +
      textureLod(u_shadow, vec3(s.xy + vec2(o.x, o.y), s.z), 0.0);
  float norm = (1.0 + 2.0 * w1) * (1.0 + 2.0 * w1);
  return (centre + w1 * sides + w1 * w1 * corners) / norm;
#else
  float sum = textureLod(u_shadow, vec3(s.xy + vec2(-o.x, -o.y), s.z), 0.0) +
              textureLod(u_shadow, vec3(s.xy + vec2(o.x, -o.y), s.z), 0.0) +
              textureLod(u_shadow, vec3(s.xy + vec2(-o.x, o.y), s.z), 0.0) +
              textureLod(u_shadow, vec3(s.xy + vec2(o.x, o.y), s.z), 0.0);
  return 0.25 * sum;
#endif
}

// Light reaching a floor point through the water: shadowed where the
// refracted light path enters the surface (occluders above the water) or
// where it passes through an occluder under the water. Under the surface the
// light travels along the refracted direction, so that part is tested at
// two points of the refracted path (a third and two thirds of the way up):
// an occluder the path crosses contains them or lies towards the light from
// them. (Testing along the unrefracted direction from the floor point made
// submerged occluders' shadows longer than refraction allows.)
float FloorShadow(vec3 f) {
  if (u_shadow_on < 0.5) return 1.0;
  vec3 up = -u_light_refracted * (u_tank.w / -u_light_refracted.z);
  return min(Shadow(f + up), min(Shadow(f + up * (1.0 / 3.0)),
                                 Shadow(f + up * (2.0 / 3.0))));
}


// Linear radiance -> the output's encoding: the highlight shoulder (identity
// up to the knee, then a rational roll-off towards 1 with slope 1 at the
// knee, so bright caustics and glints keep their order and shape; optics.h)
// and the video's transfer (sRGB, IEC 61966-2-1, or linear). Shoulder
// alone for a pass whose target encodes (GL_FRAMEBUFFER_SRGB, walls.frag).
vec3 Shoulder(vec3 c) {
  c = max(c, vec3(0.0));
  float room = 1.0 - u_knee;
  vec3 over = max(c - u_knee, vec3(0.0));
  return min(c, vec3(u_knee)) + room * over / (over + room);
}

vec3 EncodeOutput(vec3 c) {
  vec3 s = Shoulder(c);
  // The power segment by three square roots (llvmpipe's pow is a log2 and
  // an exp2 polynomial per channel): s^(1/2), s^(1/4), s^(1/8) fitted by
  // least squares to the exact curve over encoded values 0.04-1, within
  // 0.24 of an 8-bit level and 0.001 of one on average (Ian Taylor's
  // coefficients 0.585122381, 0.783140355, -0.368262736 were within 0.4 but
  // 0.1 low on average, 0.15-0.2 low over linear 0.3-0.6).
  vec3 s1 = sqrt(s), s2 = sqrt(s1), s3 = sqrt(s2);
  vec3 e = mix(12.92 * s, 0.58995544 * s1 + 0.77383208 * s2 -
                              0.36299813 * s3,
               step(0.0031308, s));
  return mix(s, e, u_srgb_out);
}

// Unpolarised Fresnel reflectance, exact (Fresnel's equations in the form
// of Cook & Torrance 1982): light at cos_i onto an interface of relative
// index eta = n_transmitted / n_incident. 1 under total internal reflection.
float FresnelExact(float cos_i, float eta) {
  float c = clamp(cos_i, 1e-4, 1.0);
  float g2 = eta * eta - 1.0 + c * c;
  float g = sqrt(max(g2, 0.0));
  float a = (g - c) / (g + c);
  float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return mix(1.0, 0.5 * a * a * (1.0 + b * b), step(0.0, g2));
}
