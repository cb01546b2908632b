// `ripple sim`: the water simulation alone, headless, driven by scripted pen
// strokes. Prints statistics and timings; optionally writes the height field
// as PNG frames or a video (top view, +y up, grey = rest level).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/app_common.h"
#include "app/app_obstacles.h"
#include "app/app_video.h"
#include "app/command.h"
#include "bench/stats.h"
#include "sim/water.h"

namespace ripple::app {
namespace {

// A straight stroke: the tip moves from (x0, y0) to (x1, y1) in the tank
// frame between t0 and t1 seconds, `depth` below the rest level.
struct Stroke {
  double x0, y0, x1, y1, t0, t1;
};

struct SimArgs {
  std::string rig = DefaultRigPath();
  std::string out;
  int resolution = 128;
  double duration_s = 3.0;
  double fps = 60.0;
  double depth_m = 0.005;
  std::vector<std::string> strokes;
  std::string walls = "reflect";
  std::string obstacles = "reflect";
  int every = 1;
  double scale_m = 0.001;
  int zoom = 0;
  double print_every_s = 0.5;
  sim::WaterOptions water;
};

bool ParseStroke(const std::string& text, Stroke* s) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  if (v.size() != 6) return false;
  for (double x : v)
    if (!std::isfinite(x)) return false;
  *s = {v[0], v[1], v[2], v[3], v[4], v[5]};
  return s->t1 >= s->t0 && s->t0 >= 0;
}

bool IsVideoPath(const std::string& path) {
  auto ends = [&](const char* ext) {
    const std::string e(ext);
    return path.size() > e.size() &&
           path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  return ends(".mp4") || ends(".mkv") || ends(".avi");
}

// Top view: +x right, +y up; grey 128 at rest, +-scale saturates; blocked
// cells dark red; the pen tip a white dot while it is in the water.
cv::Mat HeightImage(const sim::HeightFieldView& v, double scale_m, int zoom,
                    const std::array<double, 3>* tip) {
  cv::Mat img(v.ny, v.nx, CV_8UC3);
  for (int j = 0; j < v.ny; ++j) {
    cv::Vec3b* row = img.ptr<cv::Vec3b>(v.ny - 1 - j);
    for (int i = 0; i < v.nx; ++i) {
      const size_t c = static_cast<size_t>(j) * v.nx + i;
      if (!v.water[c]) {
        row[i] = cv::Vec3b(30, 30, 120);
        continue;
      }
      const double g = 128.0 + 127.0 * v.heights[c] / scale_m;
      const auto q = static_cast<uchar>(std::clamp(g, 0.0, 255.0));
      row[i] = cv::Vec3b(q, q, q);
    }
  }
  cv::Mat big;
  cv::resize(img, big, cv::Size(), zoom, zoom, cv::INTER_NEAREST);
  if (tip) {
    const double px = ((*tip)[0] / v.cell_m + 0.5 * v.nx) * zoom;
    const double py = (v.ny - ((*tip)[1] / v.cell_m + 0.5 * v.ny)) * zoom;
    cv::circle(big, cv::Point(static_cast<int>(px), static_cast<int>(py)),
               std::max(2, zoom), cv::Scalar(255, 255, 255), cv::FILLED);
  }
  return big;
}

int RunSim(SimArgs args) {
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  std::vector<Stroke> strokes;
  for (const std::string& text : args.strokes) {
    Stroke s;
    if (!ParseStroke(text, &s))
      return Fail(kExitBadInput,
                  "--stroke '" + text +
                      "': expected x0,y0,x1,y1,t0,t1 (metres in the tank "
                      "frame, seconds, 0 <= t0 <= t1)");
    strokes.push_back(s);
  }
  if (args.strokes.empty()) {
    // A default stir: across the tank and back, clear of the default pillar.
    strokes.push_back({-0.06, -0.025, 0.02, -0.025, 0.2, 0.8});
    strokes.push_back({0.0, 0.035, -0.05, 0.0, 1.2, 1.5});
  }
  args.water.walls =
      args.walls == "absorb" ? sim::WallMode::kAbsorb : sim::WallMode::kReflect;
  args.water.obstacles = args.obstacles == "zero" ? sim::ObstacleMode::kZero
                                                  : sim::ObstacleMode::kReflect;
  std::string error;
  if (!args.water.IsValid(&error)) return Fail(kExitBadInput, error);
  const sim::GridSpec grid =
      sim::GridSpec::ForTank(rig->tank.size_x_m, rig->tank.size_y_m,
                             rig->tank.water_level_m, args.resolution);
  if (!grid.IsValid(&error))
    return Fail(kExitBadInput, "--resolution: " + error);
  std::vector<sim::Obstacle> obstacles;
  if (args.obstacles != "off" && !SimObstaclesFromRig(*rig, &obstacles, &error))
    return Fail(kExitBadInput, args.rig + ": " + error);

  const bool video_out = !args.out.empty() && IsVideoPath(args.out);
  const bool png_out = !args.out.empty() && !video_out;
  if (png_out && !MakeDirectories(args.out, &error))
    return Fail(kExitBadInput, error);
  const int zoom =
      args.zoom > 0 ? args.zoom : std::max(1, (640 + grid.nx - 1) / grid.nx);
  VideoOut video;
  if (video_out &&
      !video.Open(args.out, args.fps / args.every,
                  cv::Size(grid.nx * zoom, grid.ny * zoom), &error))
    return Fail(kExitBadInput, error);

  sim::Water water(grid, args.water);
  for (const sim::Obstacle& o : obstacles) {
    if (water.AddObstacle(o, &error) < 0)
      return Fail(kExitBadInput, args.rig + ": obstacle: " + error);
  }
  std::printf(
      "sim: grid %dx%d, cell %.3f mm, sub-step %.3f ms (c %.3g m/s, courant "
      "%.2g), viscosity %.3g 1/s (amplitude e-folding %.3g s), walls %s, "
      "obstacles %s (%zu, %d cells blocked), %zu stroke(s), %.3g s at %.3g "
      "fps\n",
      grid.nx, grid.ny, 1e3 * grid.cell_m, 1e3 * water.substep_s(),
      args.water.wave_speed_m_per_s, args.water.courant,
      args.water.viscosity_per_s,
      args.water.viscosity_per_s > 0 ? 2 / args.water.viscosity_per_s
                                     : INFINITY,
      args.walls.c_str(), args.obstacles.c_str(), obstacles.size(),
      grid.nx * grid.ny - water.num_water_cells(), strokes.size(),
      args.duration_s, args.fps);

  const double level = grid.rest_level_m;
  auto tip_at = [&](double t, std::array<double, 3>* tip) {
    for (const Stroke& s : strokes) {
      if (t < s.t0 || t > s.t1) continue;
      const double a = s.t1 > s.t0 ? (t - s.t0) / (s.t1 - s.t0) : 1.0;
      *tip = {s.x0 + a * (s.x1 - s.x0), s.y0 + a * (s.y1 - s.y0),
              level - args.depth_m};
      return true;
    }
    return false;
  };

  const int frames =
      std::max(1, static_cast<int>(std::lround(args.duration_s * args.fps)));
  const double dt = 1.0 / args.fps;
  std::vector<double> advance_ms;
  advance_ms.reserve(frames);
  long long substeps = 0, rest_frames = 0, written = 0;
  double dropped = 0, max_h = 0;
  int print_stride =
      std::max(1, static_cast<int>(std::lround(args.print_every_s * args.fps)));
  std::printf("%8s %8s %6s %12s %12s %10s %10s %s\n", "time_s", "advance_ms",
              "steps", "volume_m3", "energy", "max|h|_m", "max|v|_m/s",
              "flags");
  for (int f = 0; f <= frames; ++f) {
    const double t = f * dt;
    std::array<double, 3> tip;
    const bool pen = tip_at(t, &tip);
    if (pen) {
      water.SetPenTip(tip);
    } else {
      water.ClearPen();
    }
    const bench::Stopwatch watch;
    water.Advance(f == 0 ? 0.0 : dt);
    const double ms = watch.ElapsedMs();
    const sim::AdvanceStats& s = water.stats();
    if (f > 0) advance_ms.push_back(ms);
    substeps += s.substeps;
    dropped += s.dropped_s;
    rest_frames += s.at_rest;
    max_h = std::max(max_h, s.max_abs_height_m);
    if (f % print_stride == 0 || f == frames) {
      std::printf("%8.3f %8.3f %6d %12.4e %12.4e %10.3e %10.3e%s%s%s\n", t, ms,
                  s.substeps, s.volume_m3, s.energy, s.max_abs_height_m,
                  s.max_speed_m_per_s, s.pen_touched ? " pen" : "",
                  s.at_rest ? " rest" : "", s.dropped_s > 0 ? " dropped" : "");
    }
    if (!args.out.empty() && f % args.every == 0) {
      const cv::Mat img = HeightImage(water.View(), args.scale_m, zoom,
                                      pen && s.pen_touched ? &tip : nullptr);
      if (video_out) {
        video.Write(img);
      } else {
        char name[64];
        std::snprintf(name, sizeof(name), "/height_%06d.png", f);
        if (!cv::imwrite(args.out + name, img))
          return Fail(kExitRuntime, "cannot write '" + args.out + name + "'");
      }
      ++written;
    }
  }
  video.Close();
  const double total_ms = [&] {
    double sum = 0;
    for (double v : advance_ms) sum += v;
    return sum;
  }();
  std::printf(
      "sim: %d frames, %lld sub-steps (%.2f us each incl. statistics), "
      "advance median %.3f ms, p95 %.3f ms, max %.3f ms; %lld frames at rest; "
      "%.3g s dropped; max|h| %.3e m; final volume %.3e m^3 (|h| volume "
      "%.3e m^3)\n",
      frames, substeps, substeps > 0 ? 1e3 * total_ms / substeps : 0.0,
      bench::Percentile(advance_ms, 50), bench::Percentile(advance_ms, 95),
      advance_ms.empty()
          ? 0.0
          : *std::max_element(advance_ms.begin(), advance_ms.end()),
      rest_frames, dropped, max_h, water.stats().volume_m3,
      water.stats().abs_volume_m3);
  if (written > 0)
    std::printf("sim: wrote %lld frame(s) to %s\n", written, args.out.c_str());
  return kExitOk;
}

CommandAction SetupSim(CLI::App* sub) {
  auto args = std::make_shared<SimArgs>();
  sub->add_option("--rig", args->rig, "Rig YAML (tank size, level, obstacles)")
      ->capture_default_str();
  sub->add_option("--out", args->out,
                  "Height frames: a folder for PNGs, or a video file "
                  "(.mp4, .mkv, .avi)");
  sub->add_option("--resolution", args->resolution,
                  "Cells along the tank's long side (x); y follows")
      ->capture_default_str()
      ->check(CLI::Range(2, 16384));
  sub->add_option("--duration", args->duration_s, "Simulated time, seconds")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e5));
  sub->add_option("--fps", args->fps, "Frame rate of Advance() calls, Hz")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 1e4));
  sub->add_option("--stroke", args->strokes,
                  "Pen stroke x0,y0,x1,y1,t0,t1 (tank frame metres, seconds); "
                  "repeatable. Default: two stirs")
      ->allow_extra_args(false);
  sub->add_option("--depth", args->depth_m,
                  "Tip depth below the rest level during strokes, metres")
      ->capture_default_str();
  sub->add_option("--wave-speed", args->water.wave_speed_m_per_s,
                  "Wave speed c, m/s")
      ->capture_default_str();
  sub->add_option("--viscosity", args->water.viscosity_per_s,
                  "Velocity damping, 1/s (amplitude decays as exp(-v t/2))")
      ->capture_default_str();
  sub->add_option("--courant", args->water.courant, "Sub-step c*dt/d, (0, 0.5]")
      ->capture_default_str();
  sub->add_option("--max-substeps", args->water.max_substeps,
                  "Sub-steps per frame before time is dropped")
      ->capture_default_str();
  sub->add_option("--strength", args->water.pen_strength_m_per_s2,
                  "Pen force s, m/s^2")
      ->capture_default_str();
  sub->add_option("--radius", args->water.pen_radius_m,
                  "Pen radius r, metres (small r: high frequency)")
      ->capture_default_str();
  sub->add_option("--walls", args->walls, "Tank walls: reflect or absorb")
      ->capture_default_str()
      ->check(CLI::IsMember({"reflect", "absorb"}));
  sub->add_option("--obstacles", args->obstacles,
                  "Rig obstacles: reflect (volume-conserving), zero (the "
                  "paper's h=v=0) or off")
      ->capture_default_str()
      ->check(CLI::IsMember({"reflect", "zero", "off"}));
  sub->add_option("--every", args->every, "Write every N-th frame")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--scale", args->scale_m,
                  "Height (metres) that saturates the image grey")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--zoom", args->zoom,
                  "Image pixels per cell (0: about 640 px wide)")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  sub->add_option("--print-every", args->print_every_s,
                  "Seconds between statistics lines")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  return [args] { return RunSim(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(sim,
                        "Run the water simulation headless (scripted "
                        "strokes; statistics, timings, height frames)",
                        SetupSim);

}  // namespace ripple::app
