#include "render/reference/reference.h"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "render/reference/tracing.h"

namespace ripple::reference {
namespace {

bool Fail(std::string* error, const std::string& what) {
  if (error != nullptr) *error = what;
  return false;
}

bool Finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

// A rigid transform: finite, orthonormal rotation (to 1e-6), last row
// (0, 0, 0, 1).
bool IsRigid(const glm::dmat4& m) {
  if (!Finite(m)) return false;
  const glm::dmat3 r(m);
  const glm::dmat3 e = glm::transpose(r) * r - glm::dmat3(1.0);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(e[c][k]) > 1e-6) return false;
    }
  }
  if (glm::determinant(r) <= 0) return false;
  return m[0][3] == 0 && m[1][3] == 0 && m[2][3] == 0 && m[3][3] == 1;
}

bool InUnit(const cv::Vec3f& v) {
  for (int k = 0; k < 3; ++k) {
    if (!(v[k] >= 0 && v[k] <= 1)) return false;
  }
  return true;
}

int ThreadCount(int requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

void CopyChart(const internal::IrradianceAtlas& atlas, int chart,
               cv::Mat* out) {
  const internal::Chart& c = atlas.charts[chart];
  *out = cv::Mat(c.nv, c.nu, CV_32FC3);
  std::copy(atlas.texels[chart].begin(), atlas.texels[chart].end(),
            out->ptr<float>(0));
}

double SrgbEncode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double SrgbDecode(double y) {
  return y <= 0.04045 ? y / 12.92 : std::pow((y + 0.055) / 1.055, 2.4);
}

}  // namespace

bool ReferenceOptions::IsValid(std::string* error) const {
  if (samples_per_pixel < 1 || samples_per_pixel > 65536)
    return Fail(error, "samples_per_pixel must be in [1, 65536]");
  if (light_paths_per_texel < 64 || light_paths_per_texel > 1 << 20)
    return Fail(error, "light_paths_per_texel must be in [64, 2^20]");
  if (disc_directions < 2 || disc_directions > 4096 || disc_directions % 2)
    return Fail(error, "disc_directions must be even and in [2, 4096]");
  if (caustic_map_size < 8 || caustic_map_size > 4096)
    return Fail(error, "caustic_map_size must be in [8, 4096]");
  if (max_bounces < 2 || max_bounces > 64)
    return Fail(error, "max_bounces must be in [2, 64]");
  if (max_diffuse_bounces < 0 || max_diffuse_bounces > 16)
    return Fail(error, "max_diffuse_bounces must be in [0, 16]");
  if (ambient_samples < 1 || ambient_samples > 256)
    return Fail(error, "ambient_samples must be in [1, 256]");
  if (threads < 0 || threads > 256)
    return Fail(error, "threads must be in [0, 256] (0: all cores)");
  if (roi.x < 0 || roi.y < 0 || roi.width < 0 || roi.height < 0)
    return Fail(error, "roi must have non-negative position and size");
  return true;
}

bool IsValidScene(const ReferenceScene& s, std::string* error) {
  std::string why;
  if (!s.camera.IsValid(&why)) return Fail(error, "camera: " + why);
  const render::SceneInputs& sc = s.scene;
  if (!IsRigid(sc.cam_from_tank))
    return Fail(error, "scene.cam_from_tank must be a rigid transform");
  const render::TankGeometry& t = sc.tank;
  if (!(t.size_x > 0 && t.size_y > 0 && t.wall_height > 0 &&
        std::isfinite(t.size_x) && std::isfinite(t.size_y) &&
        std::isfinite(t.wall_height)))
    return Fail(error, "scene.tank: sizes and wall_height must be positive");
  if (!(t.water_level > 0 && t.water_level < t.wall_height))
    return Fail(error, "scene.tank.water_level must be in (0, wall_height)");
  if (!(s.glass_thickness_m > 0 && s.glass_thickness_m < 0.1))
    return Fail(error, "glass_thickness_m must be in (0, 0.1) m");
  if (!(s.water_ior >= 1 && s.water_ior < 4 && s.glass_ior >= 1 &&
        s.glass_ior < 4))
    return Fail(error, "water_ior and glass_ior must be in [1, 4)");
  for (int k = 0; k < 3; ++k) {
    if (!(s.absorption_per_m[k] >= 0 && std::isfinite(s.absorption_per_m[k])))
      return Fail(error, "absorption_per_m must be finite and >= 0");
  }
  if (!InUnit(s.table_albedo) || !InUnit(s.pen_albedo) ||
      !InUnit(s.obstacle_albedo))
    return Fail(error,
                "table_albedo, pen_albedo, obstacle_albedo must be in [0, 1]");
  if (!s.floor_albedo.empty()) {
    if (s.floor_albedo.type() != CV_32FC3)
      return Fail(error, "floor_albedo must be CV_32FC3");
    if (!(s.floor_rect_m.width > 0 && s.floor_rect_m.height > 0 &&
          std::isfinite(s.floor_rect_m.x) && std::isfinite(s.floor_rect_m.y)))
      return Fail(error, "floor_rect_m must have a positive size");
    double lo = 0, hi = 0;
    cv::minMaxLoc(s.floor_albedo.reshape(1), &lo, &hi);
    if (!(lo >= 0 && hi <= 1))
      return Fail(error, "floor_albedo values must be in [0, 1]");
  }
  const double alpha = s.light_angular_radius_rad;
  if (!(alpha > 0 && alpha <= 0.5))
    return Fail(error, "light_angular_radius_rad must be in (0, 0.5]");
  if (!(s.ambient_share >= 0 && s.ambient_share <= 1))
    return Fail(error, "ambient_share must be in [0, 1]");
  const glm::dvec3 l = sc.light_in_tank;
  if (!(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z)) ||
      glm::length(l) == 0)
    return Fail(error, "scene.light_in_tank must be a finite non-zero vector");
  if (!(glm::normalize(l).z > std::sin(alpha)))
    return Fail(error,
                "scene.light_in_tank: the whole light disc must be above the "
                "horizon");
  if (sc.water.heights != nullptr) {
    const render::HeightFieldView& w = sc.water;
    if (w.nx <= 0 || w.ny <= 0 || !(w.cell_size > 0) ||
        !std::isfinite(w.cell_size))
      return Fail(error, "scene.water: nx, ny and cell_size must be positive");
    for (size_t k = 0; k < static_cast<size_t>(w.nx) * w.ny; ++k) {
      if (!std::isfinite(w.heights[k]))
        return Fail(error, "scene.water: heights must be finite");
    }
    internal::WaterSurface surface;
    surface.Init(w, t.water_level, 0.5 * t.size_x, 0.5 * t.size_y);
    if (!(surface.z_min() > 0 && surface.z_max() < t.wall_height))
      return Fail(error,
                  "scene.water: the surface must stay inside (0, "
                  "wall_height) (with the interpolant's overshoot)");
  }
  if (sc.pen_visible) {
    const render::PenGeometry& g = sc.pen;
    if (!(g.cube_edge > 0 && g.shaft_radius > 0 && g.shaft_length >= 0))
      return Fail(error, "scene.pen: sizes must be positive");
    if (!IsRigid(sc.tank_from_pen))
      return Fail(error, "scene.tank_from_pen must be a rigid transform");
  }
  for (const render::Obstacle& o : sc.obstacles) {
    if (!(o.size.x > 0 && o.size.z > 0 &&
          (o.shape == render::Obstacle::Shape::kCylinder || o.size.y > 0)))
      return Fail(error, "scene.obstacles: sizes must be positive");
    if (!IsRigid(o.tank_from_obstacle))
      return Fail(error,
                  "scene.obstacles: tank_from_obstacle must be a rigid "
                  "transform");
  }
  return true;
}

LightRadiometry ComputeLightRadiometry(const ReferenceScene& scene) {
  internal::SceneModel model;
  model.Init(scene, true, 1.0);
  return internal::Radiometry(model, scene.ambient_share);
}

bool ComputeLightMaps(const ReferenceOptions& options,
                      const ReferenceScene& scene, LightMaps* maps,
                      LightTraceSummary* summary, std::string* error) {
  if (!options.IsValid(error) || !IsValidScene(scene, error)) return false;
  internal::SceneModel model;
  model.Init(scene, false, scene.scene.tank.size_x / options.caustic_map_size);
  const LightRadiometry rad = internal::Radiometry(model, scene.ambient_share);
  internal::IrradianceAtlas atlas;
  LightTraceSummary local;
  internal::TraceLight(options, model, rad, ThreadCount(options.threads),
                       &atlas, &local);
  if (maps != nullptr) {
    CopyChart(atlas, internal::kFloorChart, &maps->floor_irradiance);
    CopyChart(atlas, internal::kBoardChart, &maps->board_irradiance);
    maps->floor_rect_m = cv::Rect2d(-model.half_x(), -model.half_y(),
                                    2 * model.half_x(), 2 * model.half_y());
    maps->board_rect_m = model.board_rect();
  }
  if (summary != nullptr) *summary = local;
  return true;
}

bool RenderReference(const ReferenceOptions& options,
                     const ReferenceScene& scene, cv::Mat* linear_bgr,
                     ReferenceSummary* summary, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.IsValid(error) || !IsValidScene(scene, error)) return false;
  const int w = scene.camera.width, h = scene.camera.height;
  cv::Rect roi = options.roi.area() > 0 ? options.roi : cv::Rect(0, 0, w, h);
  if ((roi & cv::Rect(0, 0, w, h)) != roi)
    return Fail(error, "roi must lie inside the camera image");
  const int threads = ThreadCount(options.threads);
  internal::SceneModel model;
  model.Init(scene, options.dry,
             scene.scene.tank.size_x / options.caustic_map_size);
  const LightRadiometry rad = internal::Radiometry(model, scene.ambient_share);
  ReferenceSummary local;
  internal::IrradianceAtlas atlas;
  if (!options.dry) {
    internal::TraceLight(options, model, rad, threads, &atlas, &local.light);
  }
  const auto light_done = std::chrono::steady_clock::now();
  *linear_bgr = cv::Mat::zeros(h, w, CV_32FC3);
  internal::TraceCamera(options, scene, model, options.dry ? nullptr : &atlas,
                        rad, threads, roi, linear_bgr);
  const auto done = std::chrono::steady_clock::now();
  local.width = w;
  local.height = h;
  local.roi = roi;
  local.camera_samples =
      static_cast<std::int64_t>(roi.area()) * options.samples_per_pixel;
  local.threads = threads;
  local.light_seconds =
      std::chrono::duration<double>(light_done - start).count();
  local.camera_seconds =
      std::chrono::duration<double>(done - light_done).count();
  local.total_seconds = std::chrono::duration<double>(done - start).count();
  if (summary != nullptr) *summary = local;
  return true;
}

std::string ReferenceSummary::BriefReport() const {
  char buf[512];
  const cv::Vec3d& in = light.surface_transmitted;
  std::snprintf(buf, sizeof(buf),
                "reference %dx%d roi %dx%d+%d+%d, %lld camera samples, %d "
                "threads: light %.2f s (%lld paths, %d per texel, texel %.3f "
                "mm, into water G %.4g, floor G %.4g, cut G %.2g), camera "
                "%.2f s, total %.2f s",
                width, height, roi.width, roi.height, roi.x, roi.y,
                static_cast<long long>(camera_samples), threads, light_seconds,
                static_cast<long long>(light.paths), light.paths_per_texel,
                light.texel_m * 1e3, in[1] + light.walls_into_water[1],
                light.deposited_floor[1], light.cut[1], camera_seconds,
                total_seconds);
  return buf;
}

Eigen::Vector3d PixelRay(const geometry::CameraModel& camera,
                         const Eigen::Vector2d& pixel, bool distort) {
  Eigen::Vector2d xy((pixel.x() - camera.cx) / camera.fx,
                     (pixel.y() - camera.cy) / camera.fy);
  if (distort && camera.HasDistortion()) {
    xy = camera.UndistortToNormalized(pixel);
    // Newton polish on the analytic Jacobian (z = 1: d pixel / d (x, y) is
    // the Jacobian's first two columns).
    for (int it = 0; it < 4; ++it) {
      Eigen::Matrix<double, 2, 3> j;
      const Eigen::Vector2d r =
          camera.ProjectWithJacobian(Eigen::Vector3d(xy.x(), xy.y(), 1.0), &j) -
          pixel;
      if (r.norm() < 1e-10) break;
      xy -= j.leftCols<2>().inverse() * r;
    }
  }
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
}

cv::Mat LinearToSrgb8(const cv::Mat& linear_bgr) {
  CV_Assert(linear_bgr.type() == CV_32FC3);
  cv::Mat out(linear_bgr.size(), CV_8UC3);
  for (int r = 0; r < linear_bgr.rows; ++r) {
    const float* in = linear_bgr.ptr<float>(r);
    std::uint8_t* o = out.ptr<std::uint8_t>(r);
    for (int k = 0; k < linear_bgr.cols * 3; ++k) {
      o[k] = static_cast<std::uint8_t>(std::lround(255.0 * SrgbEncode(in[k])));
    }
  }
  return out;
}

cv::Mat Srgb8ToLinear(const cv::Mat& bgr8) {
  CV_Assert(bgr8.type() == CV_8UC3);
  float table[256];
  for (int k = 0; k < 256; ++k) table[k] = float(SrgbDecode(k / 255.0));
  cv::Mat out(bgr8.size(), CV_32FC3);
  for (int r = 0; r < bgr8.rows; ++r) {
    const std::uint8_t* in = bgr8.ptr<std::uint8_t>(r);
    float* o = out.ptr<float>(r);
    for (int k = 0; k < bgr8.cols * 3; ++k) o[k] = table[in[k]];
  }
  return out;
}

}  // namespace ripple::reference
