#include "render/frame_state.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

namespace ripple::render::internal {

FrameState MakeFrameState(const SceneInputs& scene, const Intrinsics& k,
                          const WaterOptics& optics, Transfer transfer) {
  FrameState f;
  f.scene = &scene;
  f.k = &k;
  f.optics = &optics;
  f.srgb_output = transfer == Transfer::kSrgb;
  f.clip_from_tank = ClipFromCam(k) * scene.cam_from_tank;
  f.tank_from_cam = glm::inverse(scene.cam_from_tank);
  f.cam_in_tank = f.tank_from_cam[3];
  f.light = glm::normalize(scene.light_in_tank);
  glm::dvec3 lr =
      glm::refract(-f.light, glm::dvec3(0, 0, 1), 1.0 / double(optics.ior));
  if (lr.z > -1e-3) lr = glm::dvec3(0, 0, -1);
  f.light_refracted = lr;
  return f;
}

bool VideoRadianceAt(const VideoFrame& v, const Intrinsics& k,
                     const glm::dmat4& cam_from_tank, const glm::dvec2& q,
                     bool srgb, glm::dvec3* rgb) {
  if (v.bgr == nullptr || v.width <= 0 || v.height <= 0) return false;
  const glm::dvec3 c = glm::dvec3(cam_from_tank * glm::dvec4(q, 0.0, 1.0));
  if (!(c.z > 1e-3)) return false;
  const glm::dvec2 px = DistortedPixel(k, c.x / c.z, c.y / c.z);
  const int u = static_cast<int>(std::floor((px.x + 0.5) * v.width / k.width));
  const int r =
      static_cast<int>(std::floor((px.y + 0.5) * v.height / k.height));
  if (u < 0 || r < 0 || u >= v.width || r >= v.height) return false;
  const int stride = v.stride_bytes > 0 ? v.stride_bytes : 3 * v.width;
  const std::uint8_t* bgr = v.bgr + static_cast<size_t>(r) * stride + 3 * u;
  for (int ch = 0; ch < 3; ++ch) {
    const double e = bgr[2 - ch] / 255.0;
    (*rgb)[ch] = srgb ? SrgbToLinear(e) : e;
  }
  return true;
}

GroundRadiance MeasureGroundRadiance(const SceneInputs& scene,
                                     const Intrinsics& k, bool srgb,
                                     const GroundRadiance& fallback) {
  const TankGeometry& t = scene.tank;
  const double hx = 0.5 * t.size_x, hy = 0.5 * t.size_y;
  constexpr int kN = 8;
  auto mean = [&](auto&& point, const glm::vec3& none) {
    glm::dvec3 sum(0.0), rgb;
    int count = 0;
    for (int j = 0; j < kN; ++j) {
      for (int i = 0; i < kN; ++i) {
        if (VideoRadianceAt(scene.video, k, scene.cam_from_tank,
                            point((i + 0.5) / kN, (j + 0.5) / kN), srgb,
                            &rgb)) {
          sum += rgb;
          ++count;
        }
      }
    }
    return count > 0 ? glm::vec3(sum / double(count)) : none;
  };
  GroundRadiance g;
  // The floor: its inner 80%.
  g.floor = mean(
      [&](double u, double v) {
        return glm::dvec2((u - 0.5) * 1.6 * hx, (v - 0.5) * 1.6 * hy);
      },
      fallback.floor);
  // The ring 1-4 cm outside the walls: u runs around it, v across it.
  g.board = mean(
      [&](double u, double v) {
        const double d = 0.01 + 0.03 * v;
        const double ax = hx + d, ay = hy + d;
        const double s = u * 4.0 * (ax + ay);  // along the ring's perimeter
        if (s < 2 * ax) return glm::dvec2(-ax + s, -ay);
        if (s < 2 * ax + 2 * ay) return glm::dvec2(ax, -ay + (s - 2 * ax));
        if (s < 4 * ax + 2 * ay)
          return glm::dvec2(ax - (s - 2 * ax - 2 * ay), ay);
        return glm::dvec2(-ax, ay - (s - 4 * ax - 2 * ay));
      },
      fallback.board);
  return g;
}

void CommonUniforms::Resolve(const Program& p) {
  clip_from_tank_ = p.Uniform("u_clip_from_tank");
  cam_from_tank_ = p.Uniform("u_cam_from_tank");
  tank_from_cam_ = p.Uniform("u_tank_from_cam");
  intr_ = p.Uniform("u_intr");
  image_size_ = p.Uniform("u_image_size");
  cam_in_tank_ = p.Uniform("u_cam_in_tank");
  tank_ = p.Uniform("u_tank");
  hf_extent_ = p.Uniform("u_hf_extent");
  hf_texel_ = p.Uniform("u_hf_texel");
  hf_scale_ = p.Uniform("u_hf_scale");
  hf_offset_ = p.Uniform("u_hf_offset");
  light_ = p.Uniform("u_light");
  light_refracted_ = p.Uniform("u_light_refracted");
  shadow_from_tank_ = p.Uniform("u_shadow_from_tank");
  shadow_on_ = p.Uniform("u_shadow_on");
  shadow_texel_ = p.Uniform("u_shadow_texel");
  shadow_bias_ = p.Uniform("u_shadow_bias");
  srgb_out_ = p.Uniform("u_srgb_out");
  knee_ = p.Uniform("u_knee");
  ambient_ = p.Uniform("u_ambient");
  cube_from_tank_ = p.Uniform("u_cube_from_tank");
  dist0_ = p.Uniform("u_dist0");
  dist1_ = p.Uniform("u_dist1");
  glUseProgram(p.id());
  const struct {
    const char* name;
    int unit;
  } samplers[] = {{"u_height", kUnitHeight},
                  {"u_shadow", kUnitShadow},
                  {"u_caustics", kUnitCaustics},
                  {"u_scene", kUnitScene},
                  {"u_reflection", kUnitReflection},
                  {"u_receiver", kUnitReceiver},
                  {"u_env", kUnitEnvCube},
                  {"u_sky", kUnitSky},
                  {"u_video", kUnitVideo}};
  for (const auto& s : samplers) glUniform1i(p.Uniform(s.name), s.unit);
}

void CommonUniforms::Set(const Program& p, const FrameState& f,
                         const glm::dmat4& clip_from_tank) const {
  const SceneInputs& scene = *f.scene;
  const Intrinsics& k = *f.k;
  glUseProgram(p.id());
  SetUniform(clip_from_tank_, clip_from_tank);
  SetUniform(cam_from_tank_, scene.cam_from_tank);
  SetUniform(tank_from_cam_, f.tank_from_cam);
  glUniform4f(intr_, k.fx, k.fy, k.cx, k.cy);
  glUniform2f(image_size_, k.width, k.height);
  SetUniform(cam_in_tank_, f.cam_in_tank);
  const TankGeometry& t = scene.tank;
  glUniform4f(tank_, t.size_x, t.size_y, t.wall_height, t.water_level);
  glUniform2f(hf_extent_, f.height.extent.x, f.height.extent.y);
  glUniform2f(hf_texel_, f.height.texel.x, f.height.texel.y);
  SetUniform(hf_scale_, f.height.decode_scale);
  SetUniform(hf_offset_, f.height.decode_offset);
  SetUniform(light_, f.light);
  SetUniform(light_refracted_, f.light_refracted);
  SetUniform(shadow_from_tank_, f.shadow.shadow_from_tank);
  glUniform1f(shadow_on_, scene.effects.shadows ? 1.f : 0.f);
  glUniform2f(shadow_texel_, f.shadow.texel.x, f.shadow.texel.y);
  glUniform1f(shadow_bias_, f.shadow.bias);
  glUniform1f(srgb_out_, f.srgb_output ? 1.f : 0.f);
  glUniform1f(knee_, f.optics->highlight_knee);
  glUniform1f(ambient_, f.optics->ambient_share);
  SetUniform(cube_from_tank_, f.cube_from_tank);
  glUniform4f(dist0_, float(k.dist[0]), float(k.dist[1]), float(k.dist[2]),
              float(k.dist[3]));
  glUniform4f(dist1_, float(k.dist[4]), float(k.dist[5]), float(k.dist[6]),
              float(k.dist[7]));
}

void SetUniform(GLint location, const glm::dmat4& m) {
  const glm::mat4 f(m);
  glUniformMatrix4fv(location, 1, GL_FALSE, glm::value_ptr(f));
}
void SetUniform(GLint location, const glm::dmat3& m) {
  const glm::mat3 f(m);
  glUniformMatrix3fv(location, 1, GL_FALSE, glm::value_ptr(f));
}
void SetUniform(GLint location, const glm::vec3& v) {
  glUniform3f(location, v.x, v.y, v.z);
}
void SetUniform(GLint location, const glm::dvec3& v) {
  SetUniform(location, glm::vec3(v));
}

glm::ivec4 BoxRect(const glm::dmat4& clip_from_tank, double size_x,
                   double size_y, double z0, double z1, int pad, int width,
                   int height) {
  glm::dvec3 corners[8];
  BoxCorners(size_x, size_y, z0, z1, corners);
  return PointsRect(clip_from_tank, corners, 8, pad, width, height);
}

void BoxCorners(double size_x, double size_y, double z0, double z1,
                glm::dvec3 corners[8]) {
  for (int i = 0; i < 8; ++i) {
    corners[i] = {(i & 1 ? 0.5 : -0.5) * size_x, (i & 2 ? 0.5 : -0.5) * size_y,
                  i & 4 ? z1 : z0};
  }
}

glm::ivec4 PointsRect(const glm::dmat4& clip_from_tank, const glm::dvec3* p,
                      int n, int pad, int width, int height) {
  glm::dvec2 lo(1e9), hi(-1e9);
  for (int i = 0; i < n; ++i) {
    const glm::dvec4 c = clip_from_tank * glm::dvec4(p[i], 1.0);
    if (c.w <= 1e-6) return {0, 0, width, height};
    const glm::dvec2 win = WindowFromClip(c, width, height);
    lo = glm::min(lo, win);
    hi = glm::max(hi, win);
  }
  const int x0 = std::clamp(static_cast<int>(std::floor(lo.x)) - pad, 0, width);
  const int y0 =
      std::clamp(static_cast<int>(std::floor(lo.y)) - pad, 0, height);
  const int x1 = std::clamp(static_cast<int>(std::ceil(hi.x)) + pad, 0, width);
  const int y1 = std::clamp(static_cast<int>(std::ceil(hi.y)) + pad, 0, height);
  return {x0, y0, x1 - x0, y1 - y0};
}

glm::ivec4 UnionRect(const glm::ivec4& a, const glm::ivec4& b) {
  if (a.z <= 0 || a.w <= 0) return b;
  if (b.z <= 0 || b.w <= 0) return a;
  const int x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const int x1 = std::max(a.x + a.z, b.x + b.z);
  const int y1 = std::max(a.y + a.w, b.y + b.w);
  return {x0, y0, x1 - x0, y1 - y0};
}

void ObstacleBoxCorners(const Obstacle& o, glm::dvec3 corners[8]) {
  // The model's bounding box (Obstacle::size), base centre at the origin.
  const bool box = o.shape == Obstacle::Shape::kBox;
  const double hx = box ? 0.5 * o.size.x : o.size.x;
  const double hy = box ? 0.5 * o.size.y : o.size.x;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec4 p(i & 1 ? hx : -hx, i & 2 ? hy : -hy,
                       i & 4 ? double(o.size.z) : 0.0, 1.0);
    corners[i] = glm::dvec3(o.tank_from_obstacle * p);
  }
}

glm::ivec4 ObstaclesRect(const FrameState& f, int pad) {
  glm::ivec4 r(0);
  for (const Obstacle& o : f.scene->obstacles) {
    glm::dvec3 corners[8];
    ObstacleBoxCorners(o, corners);
    r = UnionRect(r, PointsRect(f.clip_from_tank, corners, 8, pad, f.k->width,
                                f.k->height));
  }
  return r;
}

glm::ivec4 OutputWindow(const FrameState& f, int pad) {
  const SceneInputs& scene = *f.scene;
  const TankGeometry& t = scene.tank;
  const int w = f.k->width, h = f.k->height;
  // The walls' top faces reach the glass's outer faces.
  const double glass = f.optics ? 2.0 * f.optics->glass_thickness_m : 0.0;
  glm::ivec4 r =
      BoxRect(f.clip_from_tank, t.size_x + glass, t.size_y + glass, 0.0,
              std::max<double>(t.wall_height, t.water_level + 0.01), pad, w, h);
  r = UnionRect(r, ObstaclesRect(f, pad));
  const glm::dvec4& b = f.board_light_rect;
  if (b.x < b.z && b.y < b.w) {
    const glm::dvec3 corners[4] = {
        {b.x, b.y, 0.0}, {b.z, b.y, 0.0}, {b.x, b.w, 0.0}, {b.z, b.w, 0.0}};
    r = UnionRect(r, PointsRect(f.clip_from_tank, corners, 4, pad, w, h));
  }
  return r;
}

}  // namespace ripple::render::internal
