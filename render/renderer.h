// The AR renderer: draws the virtual tank and water over each camera frame.
//
// Per frame (Render()):
//   1. upload the video frame (and undistort it on the GPU if the intrinsics
//      have lens distortion: the output is the ideal pinhole image with the
//      same fx, fy, cx, cy);
//   2. upload the height field, only if its change counter moved;
//   3. shadow pass, only if an occluder moved or the light changed;
//   4. caustics on the CPU, only if the surface or the light changed;
//   5. main pass into an FBO: video background, obstacles, pen phantom in
//      depth, water surface, glass walls.
// Each step is a pass of its own (render/pass_*.h) with its redraw key.
// Nothing is read back unless ReadBgr() is called.
//
// Typical use, once per camera frame:
//   auto ctx = Context::TryCreate(Backend::kEgl, w, h, &err);
//   auto renderer = Renderer::TryCreate(ctx.get(), intrinsics, {}, &err);
//   SceneInputs scene;                 // keep it; update the fields per frame
//   scene.video = {frame.data, w, h, (int)frame.step};
//   scene.cam_from_tank = ...;         // from tracking
//   scene.water = {sim.heights(), nx, ny, d, sim.change_counter()};
//   renderer->Render(scene);
//   renderer->ReadBgr(out.data, out.step);   // or renderer->Present();
//
// In a window (GLFW), once per frame:
//   if (hud_changed) renderer->SetOverlay(hud.data, hud.cols, hud.rows,
//                                         hud.step);
//   tracked ? renderer->Render(scene) : renderer->RenderVideoOnly(video);
//   renderer->Present();               // scaled, letterboxed, HUD on top
//   for (int key : ctx->TakeTypedKeys()) ...;
//   if (ctx->ShouldClose()) break;
#ifndef RIPPLE_RENDER_RENDERER_H_
#define RIPPLE_RENDER_RENDERER_H_

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <string>

#include "render/camera.h"
#include "render/caustics.h"
#include "render/context.h"
#include "render/optics.h"
#include "render/scene.h"
#include "render/sun.h"

namespace ripple::render {

// How the shadow map is filtered where a receiver looks it up (Shadow() in
// render/shaders/common.glsl). Fixed per renderer: each is a compile-time
// variant of the programs that sample the map (llvmpipe would run every
// branch).
enum class ShadowFilter {
  // Percentage-closer filtering: 4 bilinear hardware-compared taps 1.2 mm
  // apart on the tank's scale (about 3 map texels): a wide edge with a
  // plateau of half light between the taps' two edges.
  kPcf,
  // Gaussian-filtered semi-soft shadow (after Kolivand & Sunar's Z-GaF:
  // a Gaussian-weighted PCF): 3x3 bilinear hardware-compared taps spaced
  // clamp(sigma, 1, 2) texels apart, weighted exp(-d^2 / (2 sigma^2)) and
  // normalised, a 4x4 to 6x6-texel footprint with a smooth edge.
  kGauss,
  // One hardware-compared tap, nearest texel: the aliased hard edge.
  kHard,
};

// "pcf", "gauss", "hard".
const char* ShadowFilterName(ShadowFilter filter);
// Parses a ShadowFilterName; false for anything else.
bool ParseShadowFilter(const std::string& name, ShadowFilter* filter);

// How the water reads the camera's frame where a refracted ray meets the
// floor (or the pen, or the board beyond a wall). Seen through flat water
// the floor is magnified by about n = 1.33, so every output pixel falls
// between the frame's pixels: a bilinear lookup's response to a pattern of
// 4 pixels' period falls to 0.71 at half a pixel's offset, Catmull-Rom's
// to 0.88 (docs/render.md, "The refracted floor, sharp").
enum class RefractionFilter {
  // One bilinear fetch.
  kLinear,
  // Catmull-Rom (cubic) interpolation from five bilinear fetches (the
  // centre's 2x2 and one texel pair on each side; the four corner taps,
  // each under 0.6% of the weight, left out and the rest renormalised).
  kCubic,
};

// "linear", "cubic".
const char* RefractionFilterName(RefractionFilter filter);
// Parses a RefractionFilterName; false for anything else.
bool ParseRefractionFilter(const std::string& name, RefractionFilter* filter);

// Where the water's and the glass's reflections find the surroundings.
enum class ReflectionMap {
  // The flat fold: the reflected ray's vanishing point (the surroundings
  // taken as far away) in a quarter-size blurred copy of the frame, after
  // Ropinski et al.'s virtual reflections; a direction behind the camera or
  // beyond the image, which the frame does not show, takes the sky overhead;
  // the glass reflects the uniform sky (the ambient share).
  kFold,
  // The environment cube map folded from the frame (pass_envmap.h:
  // Ropinski et al.'s cube map as Milsap & Bourland build it), looked up by
  // the reflected ray, for the water and the glass; rebuilt only when the
  // frame changed enough (EnvMapOptions).
  kCubeMap,
};

// "fold", "cubemap".
const char* ReflectionMapName(ReflectionMap map);
// Parses a ReflectionMapName; false for anything else.
bool ParseReflectionMap(const std::string& name, ReflectionMap* map);

// The cube map's fold and its rebuild rule (pass_envmap.h).
struct EnvMapOptions {
  int face_size = 64;        // texels per face side, [8, 1024]
  double box_scale = 1.15;   // the tank's projected box grown by, [1, 2]
  double box_margin = 0.04;  // image share kept outside the box, [0, 0.2]
  // Rebuilt when the camera turned by more than this since the last
  // rebuild, radians ...
  double rebuild_turn_rad = 1.0 * 3.14159265358979 / 180.0;
  // ... or an edge of the box moved by more than this, pixels ...
  double rebuild_box_px = 4.0;
  // ... or the frame's 32 x 24 thumbnail changed by more than this mean
  // absolute difference, 8-bit levels.
  double rebuild_mean_levels = 3.0;
};

// RendererOptions::water_shading_columns: chosen from the output's width.
inline constexpr int kWaterColumnsAuto = -1;

// Whether the tank's shadow on the board (Effects::tank_shadow) is on by
// default for an output `width` pixels wide: up to 640 columns, where the
// water is shaded at every pixel and a frame leaves room for it (docs/
// render.md, "The tank's shadow by default").
inline bool TankShadowByDefault(int width) { return width <= 640; }

struct RendererOptions {
  // Quads per side of the water mesh. It only lays the water's depth and
  // marks its pixels (the shading finds the surface per pixel), so only the
  // water's silhouette against the walls and the waterline on objects
  // follow it: 8 quads sample the tank's sloshing waves (85 mm and longer)
  // 4 times a wavelength over 17 cm, and the pen's shorter waves (under a
  // millimetre high) move those lines by less than a pixel at 32 quads or
  // 8 alike. llvmpipe spends ~1,900 instructions a triangle (set-up,
  // binning, blocks): 16 quads cost 4% more of the main pass, 32 quads 9%.
  int surface_grid = 8;
  int shadow_map_size = 512;  // texels per side
  ShadowFilter shadow_filter = ShadowFilter::kPcf;
  RefractionFilter refraction_filter = RefractionFilter::kCubic;
  // kGauss: the Gaussian's standard deviation, shadow map texels, in
  // [0.5, 4]. A light disc of angular radius r seen from a receiver d metres
  // below an occluder's edge spreads that edge with the standard deviation
  // d r / 2 (the disc's one-dimensional marginal); for the default 2 degree
  // disc and occluder edges 2-3 cm above the receivers that is 0.6-0.9 mm,
  // 1.5-2.3 texels of the default 512^2 map over the 0.17 m tank's light
  // frame (about 0.4 mm per texel).
  float shadow_gauss_sigma_texels = 1.5f;
  int caustics_map_size = 256;  // texels per side, over the tank floor
  // CPU threads for the caustics map. One: the map is about a millisecond
  // of work, the frame loop's second core finds the real objects in front
  // of the tank meanwhile, and each of the kernel's four parallel phases
  // starts its threads anew, so under any background load a started thread
  // waits for a core (the demo's caustics stage with two nice-19 processes
  // running: 7.2 ms with two threads, 1.2 ms with one; docs/render.md,
  // "Caustics").
  int caustics_threads = 1;
  // The shadow map is redrawn only when an occluder moved relative to the
  // tank by more than these since the last redraw, or the light changed.
  double shadow_move_threshold_m = 0.001;
  double shadow_turn_threshold_rad = 0.5 * 3.14159265358979 / 180.0;
  // Optics of the water, the glass and the light (render/optics.h).
  WaterOptics optics = WaterOptics::ForLook(WaterLook::kClear);
  // How the video's 8-bit values encode light: the renderer decodes them
  // to linear light, shades, and encodes its output the same way, so the
  // pixels outside the water are the video's own.
  Transfer video_transfer = Transfer::kSrgb;
  ReflectionMap reflection_map = ReflectionMap::kFold;
  EnvMapOptions envmap;
  // The mirrored obstacles and pen fade with height above the water, with
  // this e-folding height (Nelson & Kolsch's falloff; pass_mirror.h).
  float reflection_fade_m = 0.1f;
  // The real pen's shadow is in the video already (the real lamp casts it on
  // the real board), so by default only the virtual obstacles cast shadows:
  // re-casting the pen doubled its shadow (`ripple bench render`, FLIP with
  // shadows on and off). true: the pen casts too (and its moves redraw the
  // shadow map).
  bool pen_casts_shadow = false;
  glm::vec3 obstacle_albedo{0.80f, 0.76f, 0.70f};  // linear RGB
  // false: only the output's window (the tank's box and the obstacles'
  // boxes on screen) goes through GL; the rest of the output is the video as
  // it came, copied by ReadBgr. A webcam frame is mostly table, so this
  // spares most of the upload, blit, clears and read-back at high
  // resolutions. true: every pixel is drawn. A GLFW window (Present shows
  // the FBO) and a lens with distortion (the output is the undistorted
  // video) always take the whole frame.
  bool full_frame_output = false;
  // The water shades the real pen, the clean plate and the mirrored objects
  // only inside screen rectangles that bound where they can appear
  // (render/water_regions.h) and the rest of the water with a program
  // without them: the same image for less work. false: every water pixel
  // runs every effect (the reference for that claim).
  bool water_regions = true;
  // The water's shading runs on a grid of at most this many columns (the
  // output's aspect) and is upsampled into the water's own output pixels
  // (render/coarse_grid.h): its edges against walls, obstacles and the
  // video stay sharp, its interior is interpolated. On llvmpipe the water's
  // shading is about half of a frame's work and grows with the water's
  // pixels (three to nine times 640x480's at a webcam's 1280x720 and
  // 1920x1080). -1 (kWaterColumnsAuto, the default): the output's pixels
  // up to 640 columns (at 640x480 a grid of fewer columns saves 4% of the
  // frame's work and moves the water away from the physically based
  // reference), a grid of 640 columns above: the water of larger outputs at
  // about 640x480's cost (docs/render.md, "Webcam resolutions: the water on
  // a coarse grid"). 0: always the output's pixels; N >= 64: at most N
  // columns.
  int water_shading_columns = kWaterColumnsAuto;
  // Outdoors (--sun): the daylight sky (render/sun.h) is what reflected rays
  // climbing above the surroundings the video shows see: the reflection
  // takes the sky's radiance (DaylightSkyRadiance) in place of the video's
  // surroundings by smoothstep(sin 20 deg, sin 60 deg, r.z) for a ray r
  // (tank frame); the glass likewise in place of its uniform sky. The
  // optics' ambient share and tints are the caller's (SetDaylight).
  // `north_deg`: the compass bearing of the tank's +y, degrees clockwise
  // from true north.
  std::optional<Daylight> daylight;
  double daylight_north_deg = 0;

  enum class Timing {
    kNone,        // only CPU-side timings (uploads, caustics)
    kGpuQueries,  // GL timer queries; Render() waits for their results
    kCpuFinish,   // glFinish after each pass; wall-clock milliseconds
  };
  Timing timing = Timing::kNone;

  bool IsValid(std::string* error) const;
};

// What the last Render() did and what it cost, milliseconds.
struct PassTimings {
  double upload_ms = 0;    // CPU: video and height-field upload calls
  double shadow_ms = 0;    // shadow pass (0 when skipped)
  double caustics_ms = 0;  // CPU caustics map + upload (0 when skipped)
  double main_ms = 0;      // main pass incl. undistortion
  double envmap_ms = 0;    // cube map rebuild (0 when skipped)
  double total_ms = 0;     // CPU wall time of Render()
  // The output's window this frame (x, y, w, h, pixels, top row first):
  // what went through GL; the whole frame, or less (full_frame_output).
  glm::ivec4 window{0};
  bool shadow_redrawn = false;
  bool caustics_recomputed = false;
  bool surface_uploaded = false;
  bool envmap_rebuilt = false;
  // kGpuQueries: shadow_ms/main_ms are GPU times; kCpuFinish: wall times
  // with glFinish; kNone: 0.
  RendererOptions::Timing timing = RendererOptions::Timing::kNone;
};

// Where Present() puts an image_width x image_height frame in a window
// framebuffer of window_width x window_height pixels: (x, y, width, height)
// with (x, y) the top-left corner counted from the window's top-left, the
// largest rectangle of the image's aspect ratio, centred. Zero-size for
// empty inputs.
glm::ivec4 LetterboxRect(int image_width, int image_height, int window_width,
                         int window_height);

// How far beyond the tank's inner outline the board around it may change
// (Effects::tank_shadow: the tank's shadow, the light its glass sends down,
// the sky it hides), metres: an occluder over that board must be in the
// occluder mask to keep its pixels.
double TankShadowReach(const TankGeometry& tank, const WaterOptics& optics);

// The options the renderer computes its caustics map with: the map's size
// and threads from `options`, the optics' indices, glass and light disc,
// and the water's mean absorption along the refracted path (Nishita's
// attenuation); for tools and tests that want the same map.
CausticsOptions CausticsOptionsFor(const RendererOptions& options);

class Renderer {
 public:
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Builds shaders and GL objects in `context` (which must be current and
  // outlive the renderer). The output image has the intrinsics' size.
  // nullptr with `error` on invalid options or a GL failure.
  static std::unique_ptr<Renderer> TryCreate(Context* context,
                                             const Intrinsics& intrinsics,
                                             const RendererOptions& options,
                                             std::string* error);

  // Changes the camera; a new size reallocates the output.
  void SetIntrinsics(const Intrinsics& intrinsics);
  const Intrinsics& intrinsics() const;
  const RendererOptions& options() const;

  // Draws one frame into the renderer's FBO. False (with a message on
  // stderr, in every build type) if GL reported an error.
  // `inputs_copied`, when given, is called once, before the drawing, when
  // Render has copied what the scene's buffers hold (the heights, the
  // occluder mask, the plate) into GL and traced the caustics: from then on
  // the caller may write into those buffers on other threads while the
  // frame is drawn (not into `scene` itself, nor the video).
  bool Render(const SceneInputs& scene,
              const std::function<void()>& inputs_copied = nullptr);

  // Recomputes the caustics map for `scene`'s water, light and tank if they
  // changed since it was last computed: the CPU part of Render's caustics,
  // which Render then finds up to date (it uploads the map). A caller may
  // run it first, beside work of its own on other threads; it makes no GL
  // call, so it may also run on a thread other than the GL thread while no
  // other Renderer call is in flight. True if it was recomputed, with its
  // CPU time in `ms`; false without scene.effects.caustics.
  bool UpdateCaustics(const SceneInputs& scene, double* ms);

  // Draws only the video into the FBO: the background of Render(),
  // undistorted the same way, without water, tank, pen or effects. For
  // frames where the tank is not tracked. Without any video so far the
  // frame is black. Timings: upload_ms, main_ms, total_ms.
  bool RenderVideoOnly(const VideoFrame& video);

  // Copies the last frame as BGR8, top row first, into `bgr` (rows of
  // `stride_bytes`, 0 = width * 3). Blocks until the frame is finished. Uses
  // OSMesa's own buffer on OSMesa, a pixel-pack buffer otherwise. Outside
  // the output's window (PassTimings::window) the pixels are copied from the
  // last video frame given, whose buffer must still hold it.
  bool ReadBgr(std::uint8_t* bgr, int stride_bytes = 0);

  // Sets the HUD overlay that Present() draws over the frame: BGRA8
  // (B, G, R, A bytes per pixel), top row first, rows of `stride_bytes`
  // (0 = width * 4), straight (non-premultiplied) alpha. The pixels are
  // copied into a texture now, so call it only when the HUD changes; the
  // buffer may be freed afterwards. nullptr (or an empty size) clears it.
  // Headless backends keep it but never show it.
  void SetOverlay(const std::uint8_t* bgra, int width, int height,
                  int stride_bytes = 0);

  // GLFW: shows the last frame (Render or RenderVideoOnly) in the window,
  // scaled with linear filtering to the window's current framebuffer size
  // keeping its aspect ratio (black bars; see LetterboxRect), then
  // alpha-blends the overlay from SetOverlay at the window's top-left corner
  // at 1:1 framebuffer pixels (not scaled with the frame), swaps buffers and
  // polls window events. No-op on headless backends. There are no overlay
  // parameters here by design: the overlay is uploaded by SetOverlay only
  // when it changes, and Present() may run every frame.
  void Present();

  // Waits until the GPU finished the last frame (for benchmarks).
  void Finish();

  const PassTimings& timings() const;
  // The grid the water is shaded on (RendererOptions::
  // water_shading_columns), columns x rows; (0, 0): the output's pixels.
  glm::ivec2 water_grid() const;

  // The matrix the main pass uses: tank frame -> GL clip coordinates.
  glm::dmat4 ClipFromTank(const glm::dmat4& cam_from_tank) const;

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_RENDERER_H_
