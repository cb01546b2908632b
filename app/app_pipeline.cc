#include "app/app_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>

#include "app/app_obstacles.h"
#include "app/app_water.h"
#include "bench/stats.h"
#include "geometry/check.h"
#include "sim/water_factory.h"

namespace ripple::app {

bool PipelineOptions::IsValid(std::string* error) const {
  if (!tracker.IsValid(error)) return false;
  if (!water.IsValid(error)) return false;
  if (!renderer.IsValid(error)) return false;
  if (sim_cells_x < 2 || sim_cells_x > 4096) {
    if (error) *error = "--sim-cells must be in [2, 4096]";
    return false;
  }
  return true;
}

double QuadDecimateForHeight(int height_px, double configured) {
  const double steps = std::floor(height_px / 240.0);
  return std::clamp(std::max(configured, steps), 1.0, 8.0);
}

Pipeline::~Pipeline() {
  // GL objects die before their context.
  renderer_.reset();
  context_.reset();
}

std::unique_ptr<Pipeline> Pipeline::Create(const tracking::Camera& camera,
                                           const tracking::Rig& rig,
                                           const PipelineOptions& options,
                                           std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  if (options.occluders && !options.clean_plate.IsValid(error)) return nullptr;
  if (!options.light_tracker.IsValid(error) ||
      !options.light_estimator.IsValid(error))
    return nullptr;
  if (options.light_every_frames < 1) {
    if (error) *error = "light_every_frames must be >= 1";
    return nullptr;
  }
  std::unique_ptr<Pipeline> p(new Pipeline());
  p->camera_ = camera;
  p->rig_ = rig;
  p->options_ = options;
  if (options.tank_shadow_by_resolution)
    p->options_.effects.tank_shadow = render::TankShadowByDefault(camera.width);
  const bool tank_shadow = p->options_.effects.tank_shadow;
  // The detector decodes the frames as the camera file says they encode
  // light (its edge fit and the dense refinement work in linear light).
  tracking::TrackerOptions tracker_options = options.tracker;
  tracker_options.detector.transfer = camera.transfer;
  if (options.decimate_by_resolution) {
    tracker_options.detector.quad_decimate = QuadDecimateForHeight(
        camera.height, tracker_options.detector.quad_decimate);
  }
  p->tracker_ =
      std::make_unique<tracking::Tracker>(camera, rig, tracker_options);

  sim::GridSpec grid;
  if (!WaterForRig(rig, options.sim_cells_x, options.keep_push_radius,
                   &p->options_.water, &grid, error))
    return nullptr;
  p->water_ = sim::CreateWater(grid, p->options_.water, error);
  if (!p->water_) return nullptr;

  // The rig's obstacles: in the sim (all shapes) and drawn (box, cylinder).
  if (!SimObstaclesFromRig(rig, &p->sim_obstacles_, error)) return nullptr;
  for (const sim::Obstacle& o : p->sim_obstacles_)
    if (p->water_->AddObstacle(o, error) < 0) return nullptr;
  p->drawn_obstacles_ = RenderObstaclesFromRig(rig);
  p->UpdateSceneObstacles();

  // With the next frame's tracking and water on the second core, llvmpipe
  // rasterises on the drawing thread: its own threads would take that core
  // from the worker in the middle of every frame. Measured on two cores
  // (docs/render.md, "Two cores, four jobs"): 640x480 0.7 ms and 1280x720
  // 0.5 ms a frame faster, 1920x1080 the same; without overlap the same.
  if (options.overlap_tracking) render::SetSoftwareRasterThreads(0);
  p->context_ = render::Context::TryCreate(
      options.backend, camera.width, camera.height, error, options.window);
  if (!p->context_) return nullptr;
  render::Intrinsics k;
  k.width = camera.width;
  k.height = camera.height;
  k.fx = camera.fx;
  k.fy = camera.fy;
  k.cx = camera.cx;
  k.cy = camera.cy;
  k.dist = camera.dist;
  k.transfer = camera.transfer;
  render::RendererOptions renderer_options = options.renderer;
  renderer_options.video_transfer = camera.transfer;
  p->renderer_ = render::Renderer::TryCreate(p->context_.get(), k,
                                             renderer_options, error);
  if (!p->renderer_) return nullptr;

  render::SceneInputs& s = p->scene_;
  s.tank.size_x = static_cast<float>(rig.tank.size_x_m);
  s.tank.size_y = static_cast<float>(rig.tank.size_y_m);
  s.tank.wall_height = static_cast<float>(rig.tank.wall_height_m);
  s.tank.water_level = static_cast<float>(rig.tank.water_level_m);
  if (rig.pen) {
    s.pen.cube_edge = static_cast<float>(rig.pen->cube_edge_m);
    s.pen.shaft_radius = static_cast<float>(rig.pen->shaft_radius_m);
    s.pen.shaft_length = static_cast<float>(rig.pen->shaft_length_m);
  }
  if (options.occluders) {
    // Hands over the board around the tank too, where the renderer draws
    // the tank's shadow.
    tracking::CleanPlateOptions plate_options = options.clean_plate;
    if (tank_shadow) {
      plate_options.surround_m =
          render::TankShadowReach(s.tank, options.renderer.optics);
      plate_options.margin_m =
          std::max(plate_options.margin_m, plate_options.surround_m);
      plate_options.grow_px = std::max(plate_options.grow_px, 1);
    }
    p->plate_ = std::make_unique<tracking::CleanPlate>(
        camera, rig.tank.size_x_m, rig.tank.size_y_m,
        std::max(rig.tank.wall_height_m, rig.tank.water_level_m + 0.01),
        plate_options);
    if (options.board_floor) {
      cv::Mat levels, valid;
      const cv::Point2d o = p->plate_->plate_origin_m();
      synth::BoardDesignLevels(rig, *options.board_floor, {o.x, o.y},
                               p->plate_->texel_m(), p->plate_->plate_size(),
                               camera.transfer == geometry::Transfer::kSrgb,
                               &levels, &valid);
      p->plate_->SetBoardPrior(levels, valid);
    }
  }
  p->light_tracker_ = tracking::LightTracker(options.light_tracker);
  if (options.fixed_light) {
    const Eigen::Vector3d l = options.fixed_light->normalized();
    s.light_in_tank = {l.x(), l.y(), l.z()};
  }
  p->composite_.create(camera.height, camera.width, CV_8UC3);
  return p;
}

void Pipeline::UpdateLight(const cv::Mat& bgr, const tracking::FrameResult& tr,
                           FrameReport* report) {
  report->light_in_tank = {scene_.light_in_tank.x, scene_.light_in_tank.y,
                           scene_.light_in_tank.z};
  report->light_fixed = options_.fixed_light.has_value();
  if (options_.fixed_light) return;
  // A finished estimate feeds the tracker; the scene's light follows the
  // held light when it moved by more than a degree (each change redraws
  // the shadow map and the caustics).
  if (light_job_.valid() && light_job_.wait_for(std::chrono::seconds(0)) ==
                                std::future_status::ready) {
    const auto& held = light_tracker_.Update(light_job_.get());
    if (held) {
      const Eigen::Vector3d now =
          Eigen::Vector3d(scene_.light_in_tank.x, scene_.light_in_tank.y,
                          scene_.light_in_tank.z)
              .normalized();
      if (std::acos(std::clamp(now.dot(held->light_in_tank), -1.0, 1.0)) >
          M_PI / 180.0) {
        const Eigen::Vector3d& l = held->light_in_tank;
        scene_.light_in_tank = {l.x(), l.y(), l.z()};
      }
    }
  }
  report->light_from_shadow = light_tracker_.current().has_value();
  ++frames_since_light_job_;
  if (light_job_.valid() || !rig_.pen || !tr.tank.has_pose() ||
      !tr.pen.has_pose() ||
      frames_since_light_job_ < options_.light_every_frames)
    return;
  frames_since_light_job_ = 0;
  auto input = std::make_shared<tracking::LightFromShadowInput>();
  input->bgr = bgr.clone();
  input->cam_from_tank = *tr.tank.cam_from_object;
  input->tank_from_pen =
      tr.tank.cam_from_object->Inverse() * *tr.pen.cam_from_object;
  input->board_in_tank = synth::BoardSheetRect(rig_);
  auto reference = std::make_shared<tracking::BoardReference>();
  // The printed design is the shadow-free board everywhere on the sheet
  // (the learned plate covers only the tank's surroundings).
  if (plate_ && !plate_->board_prior().empty()) {
    reference->bgra = plate_->board_prior();
    reference->origin_m = {plate_->plate_origin_m().x,
                           plate_->plate_origin_m().y};
    reference->texel_m = plate_->texel_m();
    input->reference = reference.get();
  }
  if (plate_) input->exclude = plate_->foreground().clone();
  light_job_ = JoinedFuture<tracking::LightEstimate>(
      light_worker_.Run([input, reference, options = options_.light_estimator,
                         camera = camera_, pen = *rig_.pen] {
        tracking::LightEstimate estimate;
        tracking::EstimateLightFromShadow(options, camera, pen, *input,
                                          &estimate);
        return estimate;
      }));
}

bool Pipeline::AddObstacleAt(double x_m, double y_m, std::string* error) {
  sim::Obstacle o;
  o.shape = sim::Obstacle::Shape::kCylinder;
  o.radius_m = 0.01;
  o.height_m = rig_.tank.wall_height_m * 1.2;
  o.tank_from_obstacle = sim::RigidTransform::FromTranslation(x_m, y_m, 0);
  if (water_->AddObstacle(o, error) < 0) return false;
  sim_obstacles_.push_back(o);
  render::Obstacle r;
  r.shape = render::Obstacle::Shape::kCylinder;
  r.size = glm::vec3(o.radius_m, o.radius_m, o.height_m);
  r.tank_from_obstacle = glm::dmat4(1.0);
  r.tank_from_obstacle[3] = glm::dvec4(x_m, y_m, 0, 1);
  drawn_obstacles_.push_back(r);
  UpdateSceneObstacles();
  return true;
}

bool Pipeline::RemoveLastObstacle() {
  for (int id = static_cast<int>(sim_obstacles_.size()) - 1; id >= 0; --id) {
    if (!water_->RemoveObstacle(id)) continue;  // removed before
    drawn_obstacles_[id].reset();
    UpdateSceneObstacles();
    return true;
  }
  return false;
}

int Pipeline::num_obstacles() const { return water_->num_obstacles(); }

void CombineRealMask(const cv::Mat& foreground, const cv::Rect& window,
                     const cv::Mat& pen_silhouette, cv::Mat* out) {
  out->create(foreground.size(), CV_8U);
  out->setTo(0);
  if (window.area() <= 0) return;
  cv::Mat w = (*out)(window);
  foreground(window).copyTo(w);
  if (!pen_silhouette.empty())
    w.setTo(128, (pen_silhouette(window) != 0) & (w == 0));
}

void SetRealObjectViews(const tracking::CleanPlate& plate, const cv::Mat& mask,
                        render::SceneInputs* scene) {
  const cv::Rect w = plate.foreground_window();
  scene->occluders = {mask.data, mask.cols, mask.rows,
                      static_cast<int>(mask.step),
                      glm::ivec4(w.x, w.y, w.width, w.height)};
  const cv::Mat& p = plate.shown_plate();
  scene->plate = {p.data,
                  p.cols,
                  p.rows,
                  static_cast<int>(p.step),
                  {plate.plate_origin_m().x, plate.plate_origin_m().y},
                  plate.texel_m(),
                  static_cast<float>(plate.summary().gain),
                  plate.shown_plate_counter()};
}

Pipeline::RealViews Pipeline::UpdateRealObjects(
    const cv::Mat& bgr, const tracking::FrameResult& tr) {
  if (!plate_ || !tr.tank.has_pose()) return {};
  const tracking::Pose& cam_from_tank = *tr.tank.cam_from_object;
  cv::Mat exclude;
  if (tr.pen.has_pose() && rig_.pen) {
    tracking::DrawPenPlateMasks(camera_, *tr.pen.cam_from_object,
                                rig_.pen->cube_edge_m, rig_.pen->shaft_radius_m,
                                rig_.pen->tip_in_pen, scene_.pen_margin_m,
                                &pen_mask_, &shaft_mask_);
    exclude = pen_mask_;
  }
  plate_->Process(bgr, cam_from_tank, exclude,
                  exclude.empty() ? cv::Mat() : shaft_mask_);
  if (plate_->design_dropped() && !warned_design_) {
    std::fprintf(stderr,
                 "ripple: warning: the printed board (--floor and the rig's "
                 "tags) does not match what the camera sees; the clean plate "
                 "learns the board without it\n");
    warned_design_ = true;
  }
  CombineRealMask(plate_->foreground(), plate_->foreground_window(), exclude,
                  &real_mask_);
  render::SceneInputs views;
  SetRealObjectViews(*plate_, real_mask_, &views);
  return {views.occluders, views.plate};
}

void Pipeline::UpdateSceneObstacles() {
  scene_.obstacles.clear();
  for (const auto& o : drawn_obstacles_)
    if (o) scene_.obstacles.push_back(*o);
}

Pipeline::WaterStep Pipeline::AdvanceWater(const tracking::FrameResult& tr,
                                           double time_s) {
  const bench::Stopwatch watch;
  if (tr.tip_in_tank && tr.pen.status == tracking::TrackStatus::kTracked) {
    // A non-finite tip is refused: the pen counts as not seen.
    if (!water_->SetPenTip(
            {tr.tip_in_tank->x(), tr.tip_in_tank->y(), tr.tip_in_tank->z()}))
      water_->ClearPen();
  } else {
    water_->ClearPen();
  }
  const double dt = have_time_ ? std::max(0.0, time_s - last_time_s_) : 0.0;
  last_time_s_ = time_s;
  have_time_ = true;
  water_->Advance(dt);
  WaterStep step;
  step.stats = water_->stats();
  // The caustics' coarse view is synthesised here (when the surface
  // changed), so its cost counts as the water's.
  if (options_.effects.caustics) step.coarse = water_->CoarseView();
  step.ms = watch.ElapsedMs();
  return step;
}

void Pipeline::TraceCaustics(const WaterStep& step, double* ms) {
  *ms = 0;
  // A scene of its own: on the worker this runs while the render may still
  // read scene_ (which the worker only reads).
  render::SceneInputs& s = caustics_scene_;
  s.tank = scene_.tank;
  s.light_in_tank = scene_.light_in_tank;
  s.effects = options_.effects;
  SetSceneWater(step, &s);
  renderer_->UpdateCaustics(s, ms);
}

void Pipeline::SetSceneWater(const WaterStep& step,
                             render::SceneInputs* scene) const {
  const sim::HeightFieldView view = water_->View();
  scene->water.heights = view.heights;
  scene->water.nx = view.nx;
  scene->water.ny = view.ny;
  scene->water.cell_size = static_cast<float>(view.cell_m);
  scene->water.change_counter = view.counter;
  scene->caustics_water = {};
  const sim::HeightFieldView& coarse = step.coarse;
  if (coarse.heights != nullptr && coarse.heights != view.heights) {
    scene->caustics_water.heights = coarse.heights;
    scene->caustics_water.nx = coarse.nx;
    scene->caustics_water.ny = coarse.ny;
    scene->caustics_water.cell_size = static_cast<float>(coarse.cell_m);
    scene->caustics_water.change_counter = coarse.counter;
  }
}

FrameReport Pipeline::Process(const cv::Mat& bgr, double time_s, double cap_ms,
                              bool read_back, const cv::Mat* next,
                              double next_time_s) {
  FrameReport report;
  const bench::Stopwatch frame_watch;
  report.times.cap = cap_ms;

  // Tracking and water (and with prepare_ahead the real objects and the
  // caustics): done during the last frame, or now.
  std::optional<WaterStep> water_step;
  std::optional<Prepared> prepared;
  if (next_tracking_) {
    RIPPLE_CHECK(next_data_ == bgr.data && next_time_s_ == time_s,
                 "Pipeline::Process: not the frame whose tracking was done");
    report.tracking = std::move(*next_tracking_);
    next_tracking_.reset();
    water_step = std::move(next_water_);
    next_water_.reset();
    prepared = next_prepared_;
    next_prepared_.reset();
  } else {
    report.tracking = tracker_->Track(bgr, time_s);
  }
  const tracking::FrameResult& tr = report.tracking;
  report.times.det = tr.timings.detect_ms;
  report.times.pose = tr.timings.pose_ms;
  const bool draw = tr.tank.has_pose();
  double caustics_ahead_ms = 0;
  report.prepared_ahead = prepared.has_value();
  if (prepared) {
    report.times.occ = prepared->occ_ms;
    caustics_ahead_ms = prepared->caustics_ms;
    scene_.occluders = prepared->real.occluders;
    scene_.plate = prepared->real.plate;
    // The effects may have changed since (live keys): the caustics are then
    // traced again here; else this is a no-op.
    if (draw) {
      double again_ms = 0;
      TraceCaustics(*water_step, &again_ms);
      caustics_ahead_ms += again_ms;
    }
  } else {
    // Real objects in front of the tank, on the second core while the water
    // advances and its caustics are traced (they share nothing: the plate
    // reads the frame and the poses, the water the tip).
    RealViews real;
    JoinedFuture<double> occ(occ_worker_.Run([&] {
      const bench::Stopwatch occ_watch;
      real = UpdateRealObjects(bgr, tr);
      return occ_watch.ElapsedMs();
    }));
    if (!water_step) water_step = AdvanceWater(tr, time_s);
    if (draw) TraceCaustics(*water_step, &caustics_ahead_ms);
    report.times.occ = occ.get();
    scene_.occluders = real.occluders;
    scene_.plate = real.plate;
  }
  report.water = water_step->stats;
  report.times.sim = water_step->ms;
  if (draw) {
    SetSceneWater(*water_step, &scene_);
    scene_.effects = options_.effects;
  }
  UpdateLight(bgr, tr, &report);

  // The next frame's tracking and water, on a worker thread beside this
  // frame's render (the tracker is this thread's no more until the job is
  // joined below). The water waits until the render has taken this
  // frame's surface: Render copies the heights, the occluder mask and the
  // plate into GL and then says so (before it draws), and reads them no
  // more; the job may then also prepare the next frame's real objects and
  // caustics, into those buffers and buffers of its own (it writes nothing
  // of scene_). The latch is declared after the job so that it is
  // released, on every way out, before the job is waited for.
  struct NextFrame {
    tracking::FrameResult tracking;
    WaterStep water;
    std::optional<Prepared> prepared;
  };
  JoinedFuture<NextFrame> next_job;
  std::promise<void> surface_taken;
  struct Release {
    std::promise<void>* promise;
    bool done = false;
    void operator()() {
      if (!done) promise->set_value();
      done = true;
    }
    ~Release() { (*this)(); }
  } release_surface{&surface_taken};
  if (next != nullptr && !next->empty()) {
    next_data_ = next->data;
    next_time_s_ = next_time_s;
    const bool prepare = options_.prepare_ahead;
    next_job = JoinedFuture<NextFrame>(tracking_worker_.Run(
        [this, next, next_time_s, prepare, taken = surface_taken.get_future()] {
          NextFrame out;
          out.tracking = tracker_->Track(*next, next_time_s);
          taken.wait();
          out.water = AdvanceWater(out.tracking, next_time_s);
          if (prepare) {
            Prepared p;
            const bench::Stopwatch occ_watch;
            p.real = UpdateRealObjects(*next, out.tracking);
            p.occ_ms = occ_watch.ElapsedMs();
            if (out.tracking.tank.has_pose())
              TraceCaustics(out.water, &p.caustics_ms);
            out.prepared = p;
          }
          return out;
        }));
  }

  // Render.
  const bench::Stopwatch render_watch;
  if (draw) {
    scene_.video = {bgr.data, bgr.cols, bgr.rows, static_cast<int>(bgr.step)};
    scene_.cam_from_tank = ToGlm(*tr.tank.cam_from_object);
    scene_.pen_visible = tr.pen.has_pose() && rig_.pen.has_value();
    if (scene_.pen_visible)
      scene_.tank_from_pen =
          ToGlm(tr.tank.cam_from_object->Inverse() * *tr.pen.cam_from_object);
    renderer_->Render(scene_, [&release_surface] { release_surface(); });
    release_surface();
    report.passes = renderer_->timings();
    report.rendered = true;
    if (read_back) {
      renderer_->ReadBgr(composite_.data, static_cast<int>(composite_.step));
    } else {
      renderer_->Finish();
    }
    report.times.shadow = report.passes.shadow_ms;
    // A light that moved in UpdateLight makes Render trace them again.
    report.times.caustics = caustics_ahead_ms + report.passes.caustics_ms;
    report.times.drw =
        std::max(0.0, render_watch.ElapsedMs() - report.times.shadow -
                          report.passes.caustics_ms);
  } else if (read_back) {
    // Nothing to register the water to: the video passes through.
    bgr.copyTo(composite_);
    report.times.drw = render_watch.ElapsedMs();
  }
  release_surface();
  if (next_job.valid()) {
    NextFrame ahead = next_job.get();
    next_tracking_ = std::move(ahead.tracking);
    next_water_ = ahead.water;
    next_prepared_ = ahead.prepared;
  }
  report.times.total = frame_watch.ElapsedMs();
  // Without overlap the frame's latency is its own time; with it, the
  // frame loop adds the last frame's time, during which it was tracked.
  report.times.lat = report.times.total;
  return report;
}

}  // namespace ripple::app
