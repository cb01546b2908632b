// The renderer orchestrates its passes; each pass (pass_*.h) owns its GL
// objects, its programs with their uniform locations, its redraw key and
// the GL state it changes (GlStateGuard).
#include "render/renderer.h"

#include <chrono>
#include <cstdio>

#include "render/frame_state.h"
#include "render/frame_target.h"
#include "render/gl.h"
#include "render/meshes.h"
#include "render/pass_board_light.h"
#include "render/pass_caustics.h"
#include "render/pass_envmap.h"
#include "render/pass_height.h"
#include "render/pass_mirror.h"
#include "render/pass_obstacles.h"
#include "render/pass_pen_outline.h"
#include "render/pass_present.h"
#include "render/pass_real.h"
#include "render/pass_shadow.h"
#include "render/pass_timer.h"
#include "render/pass_video.h"
#include "render/pass_walls.h"
#include "render/pass_water.h"
#include "render/under_glass.h"

namespace ripple::render {

using internal::PassTimer;

namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

CausticsOptions CausticsOptionsFor(const RendererOptions& o) {
  CausticsOptions c;
  c.map_nx = c.map_ny = o.caustics_map_size;
  c.threads = o.caustics_threads;
  const glm::vec3& sigma = o.optics.absorption_per_m;
  c.attenuation_per_m = (sigma.x + sigma.y + sigma.z) / 3.0;
  c.ior = o.optics.ior;
  c.glass_ior = o.optics.glass_ior;
  c.glass_thickness_m = o.optics.glass_thickness_m;
  c.light_angular_radius_rad = o.optics.light_angular_radius_rad;
  return c;
}

const char* ShadowFilterName(ShadowFilter filter) {
  switch (filter) {
    case ShadowFilter::kPcf:
      return "pcf";
    case ShadowFilter::kGauss:
      return "gauss";
    case ShadowFilter::kHard:
      return "hard";
  }
  return "?";
}

bool ParseShadowFilter(const std::string& name, ShadowFilter* filter) {
  for (ShadowFilter f :
       {ShadowFilter::kPcf, ShadowFilter::kGauss, ShadowFilter::kHard}) {
    if (name == ShadowFilterName(f)) {
      *filter = f;
      return true;
    }
  }
  return false;
}

const char* RefractionFilterName(RefractionFilter filter) {
  switch (filter) {
    case RefractionFilter::kLinear:
      return "linear";
    case RefractionFilter::kCubic:
      return "cubic";
  }
  return "?";
}

bool ParseRefractionFilter(const std::string& name, RefractionFilter* filter) {
  for (RefractionFilter f :
       {RefractionFilter::kLinear, RefractionFilter::kCubic}) {
    if (name == RefractionFilterName(f)) {
      *filter = f;
      return true;
    }
  }
  return false;
}

const char* ReflectionMapName(ReflectionMap map) {
  switch (map) {
    case ReflectionMap::kFold:
      return "fold";
    case ReflectionMap::kCubeMap:
      return "cubemap";
  }
  return "?";
}

bool ParseReflectionMap(const std::string& name, ReflectionMap* map) {
  for (ReflectionMap m : {ReflectionMap::kFold, ReflectionMap::kCubeMap}) {
    if (name == ReflectionMapName(m)) {
      *map = m;
      return true;
    }
  }
  return false;
}

bool RendererOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (surface_grid < 2 || surface_grid > 512)
    return fail("surface_grid must be in [2, 512]");
  if (shadow_map_size < 16 || shadow_map_size > 8192)
    return fail("shadow_map_size must be in [16, 8192]");
  if (!(shadow_gauss_sigma_texels >= 0.5f && shadow_gauss_sigma_texels <= 4.f))
    return fail("shadow_gauss_sigma_texels must be in [0.5, 4]");
  if (caustics_map_size < 8 || caustics_map_size > 4096)
    return fail("caustics_map_size must be in [8, 4096]");
  if (caustics_threads < 1) return fail("caustics_threads must be >= 1");
  if (water_shading_columns != kWaterColumnsAuto &&
      water_shading_columns != 0 && water_shading_columns < 64)
    return fail("water_shading_columns must be -1 (auto), 0 or >= 64");
  if (!(reflection_fade_m > 0)) return fail("reflection_fade_m must be > 0");
  if (shadow_move_threshold_m < 0 || shadow_turn_threshold_rad < 0)
    return fail("shadow thresholds must be >= 0");
  const EnvMapOptions& e = envmap;
  if (e.face_size < 8 || e.face_size > 1024)
    return fail("envmap.face_size must be in [8, 1024]");
  if (!(e.box_scale >= 1 && e.box_scale <= 2))
    return fail("envmap.box_scale must be in [1, 2]");
  if (!(e.box_margin >= 0 && e.box_margin <= 0.2))
    return fail("envmap.box_margin must be in [0, 0.2]");
  if (!(e.rebuild_turn_rad >= 0 && e.rebuild_box_px >= 0 &&
        e.rebuild_mean_levels >= 0))
    return fail("envmap rebuild thresholds must be >= 0");
  if (!optics.IsValid(error)) return false;
  return true;
}

struct Renderer::Impl {
  Context* context = nullptr;
  Intrinsics k;
  RendererOptions options;
  PassTimings timings;

  internal::FrameTarget target;
  internal::SolidMeshes solids;
  internal::TankWallsMesh walls_mesh;
  // What the obstacles' surfaces see around them, from the last frame
  // with obstacles and video (FrameState::ground).
  internal::GroundRadiance ground;
  internal::VideoBackgroundPass video;
  internal::HeightTexturePass height;
  internal::ShadowPass shadow;
  internal::CausticsPass caustics;
  internal::ObstaclesPass obstacles;
  internal::WaterPass water;
  internal::WallsPass walls;
  internal::PenOutlinePass pen_outline;
  internal::PresentPass present;
  internal::RealObjectsPass real;
  internal::MirrorPass mirror;
  internal::EnvMapPass envmap;
  internal::BoardLightPass board_light;
  internal::RealObjectsState real_state;
  PassTimer timer;
  // The last video frame given (the caller's buffer) and the window it was
  // uploaded for: a null frame keeps both.
  VideoFrame last_video;
  glm::ivec4 last_window{0};

  // The water's optics for the scene's light and tank, recomputed only
  // when they change (ComputeWaterShading integrates over the sky; the view
  // from under the glass walls is traced per tank and water level).
  const WaterShading& Shading(const SceneInputs& scene);
  glm::dvec3 shading_light{0.0};
  TankGeometry shading_tank;
  bool shading_valid = false;
  UnderGlassView under_glass_view;
  WaterShading shading;

  bool Init(std::string* error);
  // This frame's output window (PassTimings::window) for `video`: the
  // whole frame unless the rest can be the video as it came; `f` null: a
  // frame of video only. Remembers the video for ReadBgr.
  glm::ivec4 Window(const VideoFrame& video, const internal::FrameState* f);
  bool AllocateOutput(std::string* error);
  void BindFrameTextures();
  void StartTimings();
};

bool Renderer::Impl::Init(std::string* error) {
  const RendererOptions& o = options;
  internal::ShadowPass::Options shadow_options;
  shadow_options.map_size = o.shadow_map_size;
  shadow_options.move_threshold_m = o.shadow_move_threshold_m;
  shadow_options.turn_threshold_rad = o.shadow_turn_threshold_rad;
  shadow_options.pen = o.pen_casts_shadow;
  shadow_options.filter = o.shadow_filter;
  shadow_options.gauss_sigma_texels = o.shadow_gauss_sigma_texels;
  const bool srgb = o.video_transfer == Transfer::kSrgb;
  const internal::ObstaclesPass::Options obstacles_options{
      o.obstacle_albedo,
      internal::ShadowFilterDefines(o.shadow_filter,
                                    o.shadow_gauss_sigma_texels),
      o.optics.ior};
  const bool cube = o.reflection_map == ReflectionMap::kCubeMap;
  const bool sky = o.daylight.has_value();
  internal::WaterPass::Options water_options;
  water_options.surface_grid = o.surface_grid;
  water_options.optics = o.optics;
  water_options.env_cube = cube;
  water_options.sky = sky;
  water_options.cubic_refraction =
      o.refraction_filter == RefractionFilter::kCubic;
  water_options.regions = o.water_regions;
  water_options.shading_columns = o.water_shading_columns;
  const internal::WallsPass::Options walls_options{o.optics, cube, sky};
  internal::EnvMapPass::Options envmap_options;
  envmap_options.face_size = o.envmap.face_size;
  envmap_options.box_scale = o.envmap.box_scale;
  envmap_options.box_margin = o.envmap.box_margin;
  envmap_options.rebuild_turn_rad = o.envmap.rebuild_turn_rad;
  envmap_options.rebuild_box_px = o.envmap.rebuild_box_px;
  envmap_options.rebuild_mean_levels = o.envmap.rebuild_mean_levels;
  envmap_options.srgb_source = srgb;
  if (!video.Create(error) || !shadow.Create(shadow_options, error) ||
      !obstacles.Create(obstacles_options, error) ||
      !water.Create(water_options, error) ||
      !walls.Create(walls_options, error) || !pen_outline.Create(error) ||
      !present.Create(error) || !real.Create(srgb, error) ||
      !mirror.Create({o.obstacle_albedo, o.reflection_fade_m}, error) ||
      !envmap.Create(envmap_options, error) ||
      !board_light.Create(internal::BoardLightOptions{}, error)) {
    return false;
  }
  if (o.daylight) {
    const Daylight daylight = *o.daylight;
    const double north = o.daylight_north_deg;
    envmap.SetSky([&](const glm::dvec3& d) {
      return DaylightSkyRadiance(daylight, EnuFromBoard(d.x, d.y, d.z, north));
    });
  }
  solids.Create();
  walls_mesh.Create(o.optics.glass_thickness_m);
  height.Create();
  caustics.Create(CausticsOptionsFor(o));
  timer.Create(o.timing);
  target.Create();
  if (!AllocateOutput(error)) return false;
  if (!CheckGlError("Renderer::Init")) {
    *error = "GL error during initialisation";
    return false;
  }
  return true;
}

const WaterShading& Renderer::Impl::Shading(const SceneInputs& scene) {
  const TankGeometry& t = scene.tank;
  const bool same_tank = shading_valid && internal::SameTank(t, shading_tank);
  if (!same_tank) {
    under_glass_view = internal::TraceUnderGlassView(t, options.optics);
    under_glass_view.albedo = internal::kPaperRadiance;
  }
  if (!same_tank || scene.light_in_tank != shading_light) {
    shading_light = scene.light_in_tank;
    shading_tank = t;
    shading_valid = true;
    shading = ComputeWaterShading(options.optics, t.water_level, shading_light,
                                  under_glass_view);
  }
  return shading;
}

glm::ivec4 Renderer::Impl::Window(const VideoFrame& video,
                                  const internal::FrameState* f) {
  const glm::ivec4 whole(0, 0, k.width, k.height);
  if (video.bgr == nullptr) return last_video.bgr ? last_window : whole;
  last_video = video;
  // A window (GLFW) shows the FBO itself (Present): all of it is drawn.
  if (options.full_frame_output || context->backend() == Backend::kGlfw ||
      !this->video.DirectWindow(video, k)) {
    last_window = whole;
  } else {
    // Two pixels of margin for the edges' linear filtering.
    last_window = f ? internal::OutputWindow(*f, 2) : glm::ivec4(0);
  }
  return last_window;
}

bool Renderer::Impl::AllocateOutput(std::string* error) {
  if (!target.Allocate(k.width, k.height, error)) return false;
  const bool ok = obstacles.AllocateOutput(k.width, k.height) &&
                  video.AllocateOutput(k.width, k.height) &&
                  real.AllocateOutput(k.width, k.height) &&
                  mirror.AllocateOutput(k.width, k.height) &&
                  water.AllocateOutput(k.width, k.height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!ok) *error = "video framebuffers incomplete";
  return ok;
}

void Renderer::Impl::BindFrameTextures() {
  const struct {
    int unit;
    GLuint texture;
  } bindings[] = {
      {internal::kUnitHeight, height.texture()},
      {internal::kUnitShadow, shadow.shadow_texture()},
      {internal::kUnitCaustics, caustics.texture()},
      {internal::kUnitReflection, video.reflection_texture()},
      {internal::kUnitReceiver, shadow.receiver_texture()},
      {internal::kUnitVideo, video.video_texture()},
  };
  for (const auto& b : bindings) {
    glActiveTexture(GL_TEXTURE0 + b.unit);
    glBindTexture(GL_TEXTURE_2D, b.texture);
  }
  glActiveTexture(GL_TEXTURE0 + internal::kUnitEnvCube);
  glBindTexture(GL_TEXTURE_CUBE_MAP, envmap.texture());
  glActiveTexture(GL_TEXTURE0 + internal::kUnitSky);
  glBindTexture(GL_TEXTURE_CUBE_MAP, envmap.sky_texture());
}

void Renderer::Impl::StartTimings() {
  timings = PassTimings{};
  timings.timing = options.timing;
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() {
  if (impl_ && impl_->context) impl_->context->MakeCurrent();
}

std::unique_ptr<Renderer> Renderer::TryCreate(Context* context,
                                              const Intrinsics& intrinsics,
                                              const RendererOptions& options,
                                              std::string* error) {
  std::string local;
  if (error == nullptr) error = &local;
  if (context == nullptr) {
    *error = "renderer: no GL context";
    return nullptr;
  }
  if (!intrinsics.IsValid(error) || !options.IsValid(error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  impl->context = context;
  impl->k = intrinsics;
  impl->options = options;
  if (!impl->Init(error)) return nullptr;
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

void Renderer::SetIntrinsics(const Intrinsics& intrinsics) {
  if (intrinsics == impl_->k) return;
  impl_->k = intrinsics;
  std::string error;
  if (!impl_->AllocateOutput(&error)) {
    std::fprintf(stderr, "ripple render: %s\n", error.c_str());
  }
}

const Intrinsics& Renderer::intrinsics() const { return impl_->k; }
const RendererOptions& Renderer::options() const { return impl_->options; }
const PassTimings& Renderer::timings() const { return impl_->timings; }
glm::ivec2 Renderer::water_grid() const {
  const internal::CoarseGrid& g = impl_->water.grid();
  return {g.width, g.height};
}

glm::dmat4 Renderer::ClipFromTank(const glm::dmat4& cam_from_tank) const {
  return ClipFromCam(impl_->k) * cam_from_tank;
}

bool Renderer::Render(const SceneInputs& scene,
                      const std::function<void()>& inputs_copied) {
  Impl& m = *impl_;
  const Effects& fx = scene.effects;
  const auto t_start = Clock::now();
  m.StartTimings();
  internal::FrameState f = internal::MakeFrameState(
      scene, m.k, m.options.optics, m.options.video_transfer);
  f.shading = m.Shading(scene);
  const bool tank_shadow =
      fx.tank_shadow && (scene.video.bgr != nullptr || m.video.have_video());
  if ((!scene.obstacles.empty() || tank_shadow) && scene.video.bgr != nullptr) {
    m.ground =
        internal::MeasureGroundRadiance(scene, m.k, f.srgb_output, m.ground);
  }
  f.ground = m.ground;
  // Caustics before the floor's light, which takes the map's mean.
  m.timings.caustics_recomputed =
      fx.caustics && m.caustics.Update(scene, &m.timings.caustics_ms);
  f.caustics_mean = fx.caustics ? m.caustics.mean() : 1.0f;
  m.water.UpdateFloorLight(f);
  if (tank_shadow) {
    m.board_light.Update(f, m.water.floor_return_light().floor_seen);
    f.board_light_rect = m.board_light.rect();
  }
  const glm::ivec4 window = m.Window(scene.video, &f);
  m.timings.window = window;

  // Inputs: video, height field, wall mesh (each only if it changed).
  m.video.Upload(scene.video, m.k, window);
  m.timings.surface_uploaded = m.height.Update(scene);
  f.height = m.height.info();
  m.walls_mesh.Update(scene.tank);
  m.real.Upload(scene, &m.real_state);
  // The caustics' CPU time, spent above, is its own figure.
  m.timings.upload_ms = MsSince(t_start) - m.timings.caustics_ms;

  // Effects maps, only when their keys changed.
  if (fx.shadows && m.shadow.NeedsRedraw(scene)) {
    m.timer.Begin(PassTimer::kShadow);
    m.shadow.Draw(f, m.solids);
    m.timings.shadow_ms = m.timer.End(PassTimer::kShadow);
    m.timings.shadow_redrawn = true;
  }
  f.shadow = m.shadow.transform();
  if (inputs_copied) inputs_copied();

  // The environment cube map, only when the frame changed enough. From the
  // quarter-size map, which Upload made from this frame (without lens
  // distortion at the output's size; otherwise it is the last frame's).
  if (fx.reflection && m.video.have_video() &&
      m.options.reflection_map == ReflectionMap::kCubeMap &&
      m.envmap.NeedsRebuild(m.k, scene.cam_from_tank, scene.tank,
                            m.video.thumbnail())) {
    m.timer.Begin(PassTimer::kEnvMap);
    m.envmap.Rebuild(m.video.reflection_texture(), m.k, scene.cam_from_tank,
                     scene.tank, m.video.thumbnail(), m.target.fbo());
    m.timings.envmap_ms = m.timer.End(PassTimer::kEnvMap);
    m.timings.envmap_rebuilt = true;
  }
  f.cube_from_tank = m.envmap.cube_from_tank();

  // The output, every frame.
  m.timer.Begin(PassTimer::kMain);
  // The mirror first, into its own target: switching targets in the middle
  // of the main pass makes llvmpipe flush it. The pen's colour comes from
  // the last frame's scene copy (one frame old; the pen moves little).
  m.mirror.Draw(f, m.target.fbo(), m.obstacles.scene_texture(), m.solids);
  m.video.Draw(m.k, m.target.fbo(), fx.reflection, window);
  m.target.BeginFrame(/*keep_color=*/m.video.have_video(), window);
  m.BindFrameTextures();
  m.real.Draw(f, m.real_state);
  if (tank_shadow) m.board_light.Draw(f, m.real_state);
  const bool water_shades_pen =
      internal::WaterPass::ShadesRealPen(f, m.video.have_video(), m.real_state);
  m.obstacles.Draw(f, m.target.fbo(), m.solids, m.water.floor_return_light(),
                   water_shades_pen);
  m.water.Draw(f, m.video.have_video(), m.real_state, m.target.fbo());
  if (water_shades_pen) {
    m.pen_outline.Draw(f, m.real_state, internal::PenPhantomInset(f),
                       internal::PenShaftPixelM(f), m.target.fbo(),
                       m.target.srgb_fbo());
    m.obstacles.DrawPenPhantom(f, m.solids);
  }
  if (fx.walls) {
    m.walls.Draw(f, m.walls_mesh, m.water.floor_return_light(),
                 fx.reflection && m.video.have_video(), m.target.fbo(),
                 m.target.srgb_fbo());
  }
  m.timings.main_ms = m.timer.End(PassTimer::kMain);

  if (m.options.timing == RendererOptions::Timing::kGpuQueries) {
    m.timings.main_ms = m.timer.Result(PassTimer::kMain);
    if (m.timings.shadow_redrawn) {
      m.timings.shadow_ms = m.timer.Result(PassTimer::kShadow);
    }
    if (m.timings.envmap_rebuilt) {
      m.timings.envmap_ms = m.timer.Result(PassTimer::kEnvMap);
    }
  }
  m.timings.total_ms = MsSince(t_start);
  return CheckGlError("Renderer::Render");
}

bool Renderer::UpdateCaustics(const SceneInputs& scene, double* ms) {
  *ms = 0;
  return scene.effects.caustics && impl_->caustics.Trace(scene, ms);
}

bool Renderer::RenderVideoOnly(const VideoFrame& video) {
  Impl& m = *impl_;
  const auto t_start = Clock::now();
  m.StartTimings();
  // Nothing is drawn over the video: no window, unless the whole frame
  // must go through GL.
  const glm::ivec4 window = m.Window(video, nullptr);
  m.timings.window = window;
  m.video.Upload(video, m.k, window);
  m.timings.upload_ms = MsSince(t_start);
  m.timer.Begin(PassTimer::kMain);
  m.video.Draw(m.k, m.target.fbo(), /*reflection=*/false, window);
  m.target.BeginFrame(/*keep_color=*/m.video.have_video(), window);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m.timings.main_ms = m.timer.End(PassTimer::kMain);
  if (m.options.timing == RendererOptions::Timing::kGpuQueries) {
    m.timings.main_ms = m.timer.Result(PassTimer::kMain);
  }
  m.timings.total_ms = MsSince(t_start);
  return CheckGlError("Renderer::RenderVideoOnly");
}

void Renderer::Finish() { glFinish(); }

bool Renderer::ReadBgr(std::uint8_t* bgr, int stride_bytes) {
  return impl_->target.ReadBgr(*impl_->context, impl_->last_video, bgr,
                               stride_bytes);
}

void Renderer::SetOverlay(const std::uint8_t* bgra, int width, int height,
                          int stride_bytes) {
  impl_->present.SetOverlay(bgra, width, height, stride_bytes);
}

void Renderer::Present() {
  Impl& m = *impl_;
  m.present.Present(m.context, m.target.fbo(), m.k.width, m.k.height);
}

}  // namespace ripple::render
