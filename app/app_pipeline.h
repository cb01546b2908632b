// One frame of Ripple, as data flows (DESIGN.md): tracking -> interaction ->
// water -> render, with per-stage timings. live, replay and demo all drive
// this same pipeline through one frame loop (app/app_loop.h); only the frame
// source and the sinks differ.
#ifndef RIPPLE_APP_APP_PIPELINE_H_
#define RIPPLE_APP_APP_PIPELINE_H_

#include <future>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "app/app_worker.h"
#include "bench/stage_table.h"
#include "render/context.h"
#include "render/renderer.h"
#include "sim/water_surface.h"
#include "tracking/camera.h"
#include "tracking/clean_plate.h"
#include "tracking/light_from_shadow.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/tracker.h"

namespace ripple::app {

struct PipelineOptions {
  tracking::TrackerOptions tracker;
  sim::WaterModelOptions water;
  int sim_cells_x = 256;  // simulation cells along the tank's long side
  // The push radius as given (else it follows the rig's shaft radius).
  bool keep_push_radius = false;
  render::RendererOptions renderer;
  render::Effects effects;
  render::Backend backend = render::Backend::kEgl;
  bool window = false;  // GLFW: show a window (live)
  // Real objects in front of the tank (a hand): a clean plate of the board
  // is learned and its occluder mask composited in front of the water
  // (tracking/clean_plate.h).
  bool occluders = true;
  tracking::CleanPlateOptions clean_plate;
  // The printed board's floor, the clean plate's prior (the board's design);
  // nullopt: no prior.
  std::optional<synth::FloorPattern> board_floor;
  // The light: from the real pen's shadow on the board (held over time;
  // the default direction until one is found), or fixed (unit, towards the
  // light, tank frame).
  std::optional<Eigen::Vector3d> fixed_light;
  tracking::LightFromShadowOptions light_estimator;
  tracking::LightTrackerOptions light_tracker;
  int light_every_frames = 10;  // an estimate is started every this many
  // Tracking and water of frame n + 1 overlap the render of frame n, on
  // the second core, when the frame loop has frame n + 1 already (video
  // files, the demo). It spends a frame of latency for throughput
  // (StageTimes::lat); live, where waiting for the camera's next frame
  // would add its period, keeps it off.
  bool overlap_tracking = true;
  // With overlap, the next frame's real objects (the clean plate and the
  // occluder mask) and its caustics are prepared on the worker too, after
  // its water step, beside this frame's drawing: they then leave the start
  // of that frame. The output is the same either way; measured faster at
  // 640x480, 1280x720 and 1920x1080 (docs/render.md, "Two cores, four
  // jobs").
  bool prepare_ahead = true;
  // The detector's quad decimation grows with the frame's height
  // (QuadDecimateForHeight) above the tracker's own setting.
  bool decimate_by_resolution = true;
  // The tank's shadow on the board follows the camera's width
  // (render::TankShadowByDefault) instead of effects.tank_shadow.
  bool tank_shadow_by_resolution = true;

  bool IsValid(std::string* error) const;
};

struct FrameReport {
  tracking::FrameResult tracking;
  // The light the frame was rendered with, unit, tank frame, and whether it
  // comes from the pen's shadow.
  Eigen::Vector3d light_in_tank = Eigen::Vector3d::UnitZ();
  bool light_from_shadow = false;
  bool light_fixed = false;  // --light AZ,EL
  sim::AdvanceStats water;
  render::PassTimings passes;
  bench::StageTimes times;
  bool rendered = false;  // false when the tank was not seen: video only
  // The real objects and the caustics were prepared during the last frame
  // (PipelineOptions::prepare_ahead).
  bool prepared_ahead = false;
};

// The renderer's occluder mask (render/scene.h, OccluderMaskView): the clean
// plate's foreground (255) over `window`, and the pen's silhouette (128)
// where nothing is in front of it; `out` keeps the image's size and is
// cleared outside `window`.
void CombineRealMask(const cv::Mat& foreground, const cv::Rect& window,
                     const cv::Mat& pen_silhouette, cv::Mat* out);

// Points `scene`'s occluder mask at `mask` (over the plate's window) and its
// plate view at the clean plate's shown plate (the board it learned, and
// where it has not, the printed design), with this frame's gain. The scene
// holds pointers: both must outlive the render.
void SetRealObjectViews(const tracking::CleanPlate& plate, const cv::Mat& mask,
                        render::SceneInputs* scene);

// libapriltag's quad decimation for frames `height_px` rows high: one step
// per 240 rows (2 at 480, 3 at 720, 4 at 1080), never below `configured`.
// At one field of view a tag covers the same share of the frame at any
// resolution, so quad finding then sees about the same 240-row image;
// corners are refined at full resolution all the same.
double QuadDecimateForHeight(int height_px, double configured);

class Pipeline {
 public:
  // Builds tracker, water (with the rig's obstacles) and renderer; nullptr
  // with `error` on bad options, a bad obstacle or no GL context.
  static std::unique_ptr<Pipeline> Create(const tracking::Camera& camera,
                                          const tracking::Rig& rig,
                                          const PipelineOptions& options,
                                          std::string* error);
  ~Pipeline();

  // Processes one BGR frame taken at `time_s` (seconds, from the source's
  // timestamps; the water advances by the difference to the last frame).
  // With `read_back`, composite() holds the finished frame afterwards.
  // With `next` (the frame after this one, and its time), its tracking and
  // then its water step run on a worker thread beside this frame's render,
  // and are waited for before returning; the next call must then be for
  // that frame.
  FrameReport Process(const cv::Mat& bgr, double time_s, double cap_ms,
                      bool read_back, const cv::Mat* next = nullptr,
                      double next_time_s = 0);
  bool overlap_tracking() const { return options_.overlap_tracking; }
  const cv::Mat& composite() const { return composite_; }

  // Interactive controls (live keys).
  sim::WaterSurface& water() { return *water_; }
  render::Effects& effects() { return options_.effects; }
  render::Renderer& renderer() { return *renderer_; }
  render::Context& context() { return *context_; }
  tracking::Tracker& tracker() { return *tracker_; }
  const tracking::Rig& rig() const { return rig_; }
  // Adds a cylinder obstacle at a tank-frame point (metres); false if it
  // could not be placed.
  bool AddObstacleAt(double x_m, double y_m, std::string* error);
  // Removes the most recently added obstacle (rig obstacles included).
  bool RemoveLastObstacle();
  // Obstacles in the water now (removed ones excluded).
  int num_obstacles() const;

 private:
  Pipeline() = default;

  tracking::Camera camera_;
  tracking::Rig rig_;
  PipelineOptions options_;
  std::unique_ptr<tracking::Tracker> tracker_;
  // The next frame's tracking, done by the last Process (overlap_tracking),
  // and which frame it is.
  std::optional<tracking::FrameResult> next_tracking_;
  const std::uint8_t* next_data_ = nullptr;
  double next_time_s_ = 0;
  std::unique_ptr<sim::WaterSurface> water_;
  // One step of the water: its statistics, the caustics' coarse view of
  // the surface (empty without caustics) and its CPU time.
  struct WaterStep {
    sim::AdvanceStats stats;
    sim::HeightFieldView coarse;
    double ms = 0;
  };
  // Sets the pen from the frame's tracking and advances the water to
  // `time_s`.
  WaterStep AdvanceWater(const tracking::FrameResult& tracking, double time_s);
  // Points a scene's surfaces at the water's current heights.
  void SetSceneWater(const WaterStep& step, render::SceneInputs* scene) const;
  // The caustics traced for the water's current heights, scene_'s tank and
  // light and the options' effects (Renderer::UpdateCaustics; no GL), in a
  // scene of their own (caustics_scene_), with the CPU time in `ms` (0 when
  // nothing changed).
  void TraceCaustics(const WaterStep& step, double* ms);
  render::SceneInputs caustics_scene_;
  // The next frame's water step, done with its tracking (next_tracking_).
  std::optional<WaterStep> next_water_;
  // The next frame's real objects and caustics, when the job prepared them
  // (prepare_ahead): the clean plate's views, and their times for the
  // stage table.
  struct RealViews {
    render::OccluderMaskView occluders;
    render::BoardPlateView plate;
  };
  struct Prepared {
    RealViews real;
    double occ_ms = 0;
    double caustics_ms = 0;
  };
  std::optional<Prepared> next_prepared_;
  std::unique_ptr<render::Context> context_;
  std::unique_ptr<render::Renderer> renderer_;
  std::unique_ptr<tracking::CleanPlate> plate_;
  cv::Mat pen_mask_;    // the pen's silhouette, for the clean plate
  cv::Mat shaft_mask_;  // its shaft alone
  bool warned_design_ = false;
  cv::Mat real_mask_;  // CombineRealMask's output, for the renderer
  // The light from the pen's shadow: estimated on a worker thread on copies
  // of every light_every_frames-th frame, held by the tracker.
  tracking::LightTracker light_tracker_;
  JoinedFuture<tracking::LightEstimate> light_job_;
  int frames_since_light_job_ = 0;
  void UpdateLight(const cv::Mat& bgr, const tracking::FrameResult& tracking,
                   FrameReport* report);
  // Runs the clean plate on this frame and returns the views of its
  // occluder mask and plate for the scene (empty when the plate is off or
  // the tank not seen); writes nothing of scene_.
  RealViews UpdateRealObjects(const cv::Mat& bgr,
                              const tracking::FrameResult& tracking);
  std::vector<sim::Obstacle> sim_obstacles_;
  // Parallel to sim_obstacles_: how each is drawn (nullopt: not drawn, as
  // voxel volumes and removed obstacles).
  std::vector<std::optional<render::Obstacle>> drawn_obstacles_;
  // Rebuilds scene_.obstacles from drawn_obstacles_ (on add and remove only).
  void UpdateSceneObstacles();
  render::SceneInputs scene_;
  cv::Mat composite_;
  double last_time_s_ = 0;
  bool have_time_ = false;
  // The threads of the next frame's tracking, the real objects and the
  // light estimate: the same three for every frame. Last, so that they are
  // destroyed first, finishing their jobs while the state those use exists.
  Worker tracking_worker_;
  Worker occ_worker_;
  Worker light_worker_;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_PIPELINE_H_
