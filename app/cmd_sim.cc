// `ripple sim`: the water simulation alone, headless, driven by scripted pen
// strokes and released drops. Prints statistics (surface slopes among them)
// and timings; optionally writes the height field as float32 .npy frames
// (metres) with frames.csv, as PNG frames or as a video (top view, +y up,
// grey = rest level).
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
#include "app/app_water.h"
#include "app/command.h"
#include "bench/stats.h"
#include "sim/water_factory.h"

namespace ripple::app {
namespace {

// A straight stroke: the tip moves from (x0, y0) to (x1, y1) in the tank
// frame between t0 and t1 seconds, `depth` below the rest level.
struct Stroke {
  double x0, y0, x1, y1, t0, t1;
};

// A Gaussian drop released from rest: displacement amp * exp(-r^2/(2 s^2))
// added at time t (metres, seconds).
struct Impulse {
  double x, y, t, amp, radius;
};

struct SimArgs {
  std::string rig = DefaultRigPath();
  std::string out;
  std::string format;  // npy | png | video; empty: from --out
  double duration_s = 3.0;
  double fps = 60.0;
  double depth_m = 0.005;
  std::vector<std::string> strokes;
  std::vector<std::string> impulses;
  std::string obstacles = "reflect";
  int every = 1;
  double scale_m = 0.001;
  int zoom = 0;
  double print_every_s = 0.5;
  WaterArgs water;
  double courant = -1;  // paper model only
  int max_substeps = -1;
};

// Comma-separated finite numbers; false on anything else.
bool ParseNumbers(const std::string& text, std::vector<double>* out) {
  std::vector<double>& v = *out;
  v.clear();
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
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return !v.empty();
}

bool ParseStroke(const std::string& text, Stroke* s) {
  std::vector<double> v;
  if (!ParseNumbers(text, &v) || v.size() != 6) return false;
  *s = {v[0], v[1], v[2], v[3], v[4], v[5]};
  return s->t1 >= s->t0 && s->t0 >= 0;
}

bool ParseImpulse(const std::string& text, Impulse* s) {
  std::vector<double> v;
  if (!ParseNumbers(text, &v) || v.size() != 5) return false;
  *s = {v[0], v[1], v[2], v[3], v[4]};
  return s->t >= 0 && s->radius > 0 && std::abs(s->amp) <= 1;
}

// Surface slope |grad h| over the water cells: RMS and 99th percentile.
void SlopeStats(const sim::HeightFieldView& view, std::vector<float>* gx,
                std::vector<float>* gy, double* rms, double* p99) {
  sim::ComputeGradients(view, gx, gy);
  std::vector<double> m;
  m.reserve(gx->size());
  double sum = 0;
  for (std::size_t c = 0; c < gx->size(); ++c) {
    if (!view.water[c]) continue;
    const double s = std::hypot((*gx)[c], (*gy)[c]);
    m.push_back(s);
    sum += s * s;
  }
  *rms = m.empty() ? 0 : std::sqrt(sum / m.size());
  *p99 = m.empty() ? 0 : bench::Percentile(m, 99);
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
  std::vector<Impulse> impulses;
  for (const std::string& text : args.impulses) {
    Impulse s;
    if (!ParseImpulse(text, &s))
      return Fail(kExitBadInput,
                  "--impulse '" + text +
                      "': expected X,Y,T,AMP,RADIUS (metres in the tank "
                      "frame, seconds >= 0, |AMP| <= 1 m, RADIUS > 0)");
    impulses.push_back(s);
  }
  if (args.strokes.empty() && impulses.empty()) {
    // A default stir: across the tank and back, clear of the default pillar.
    strokes.push_back({-0.06, -0.025, 0.02, -0.025, 0.2, 0.8});
    strokes.push_back({0.0, 0.035, -0.05, 0.0, 1.2, 1.5});
  }
  std::string error;
  sim::WaterModelOptions model;
  int cells = 0;
  if (!ResolveWaterOptions(args.water, &model, &cells, &error))
    return Fail(kExitBadInput, error);
  const bool paper = model.waves == sim::WaveModel::kPaper;
  if (!paper && (args.courant != -1 || args.max_substeps != -1 ||
                 args.obstacles == "zero"))
    return Fail(kExitBadInput,
                "--courant, --max-substeps and --obstacles zero are the "
                "paper model's (--waves paper)");
  if (args.courant != -1) model.paper.courant = args.courant;
  if (args.max_substeps != -1) model.paper.max_substeps = args.max_substeps;
  model.paper.obstacles = args.obstacles == "zero"
                              ? sim::ObstacleMode::kZero
                              : sim::ObstacleMode::kReflect;
  sim::GridSpec grid;
  if (!WaterForRig(*rig, cells, args.water.radius_m.given, &model, &grid,
                   &error))
    return Fail(kExitBadInput, args.rig + ": " + error);
  std::vector<sim::Obstacle> obstacles;
  if (args.obstacles != "off" && !SimObstaclesFromRig(*rig, &obstacles, &error))
    return Fail(kExitBadInput, args.rig + ": " + error);

  std::string format = args.format;
  if (format.empty() && !args.out.empty())
    format = IsVideoPath(args.out) ? "video" : "png";
  if (!format.empty() && args.out.empty())
    return Fail(kExitBadInput, "--format needs --out");
  if (format != "" && format != "npy" && format != "png" && format != "video")
    return Fail(kExitBadInput,
                "--format '" + format + "': use npy, png or video");
  if (format == "video" && !IsVideoPath(args.out))
    return Fail(kExitBadInput, "--format video: --out '" + args.out +
                                   "' must end in .mp4, .mkv or .avi");
  if ((format == "npy" || format == "png") && IsVideoPath(args.out))
    return Fail(kExitBadInput, "--format " + format + ": --out '" + args.out +
                                   "' must be a folder");
  const bool video_out = format == "video";
  const bool png_out = format == "png";
  const bool npy_out = format == "npy";
  if ((png_out || npy_out) && !MakeDirectories(args.out, &error))
    return Fail(kExitBadInput, error);
  std::FILE* frames_csv = nullptr;
  if (npy_out) {
    const std::string path = args.out + "/frames.csv";
    frames_csv = std::fopen(path.c_str(), "w");
    if (!frames_csv) return Fail(kExitBadInput, "cannot write '" + path + "'");
    std::fprintf(frames_csv, "frame,time_s,tip_x_m,tip_y_m,tip_z_m\n");
  }
  const int zoom =
      args.zoom > 0 ? args.zoom : std::max(1, (640 + grid.nx - 1) / grid.nx);
  VideoOut video;
  if (video_out &&
      !video.Open(args.out, args.fps / args.every,
                  cv::Size(grid.nx * zoom, grid.ny * zoom), &error))
    return Fail(kExitBadInput, error);

  auto water_ptr = sim::CreateWater(grid, model, &error);
  if (!water_ptr) return Fail(kExitBadInput, "water: " + error);
  sim::WaterSurface& water = *water_ptr;
  for (const sim::Obstacle& o : obstacles) {
    if (water.AddObstacle(o, &error) < 0)
      return Fail(kExitBadInput, args.rig + ": obstacle: " + error);
  }
  if (paper) {
    std::printf(
        "sim: paper waves, grid %dx%d, cell %.3f mm (c %.3g m/s, courant "
        "%.2g), damping %.3g 1/s, walls %s, obstacles %s (%zu)",
        grid.nx, grid.ny, 1e3 * grid.cell_m, model.paper.wave_speed_m_per_s,
        model.paper.courant, model.paper.viscosity_per_s,
        args.water.walls.c_str(), args.obstacles.c_str(), obstacles.size());
  } else {
    const sim::SpectralWaterOptions& c = model.spectral;
    std::printf(
        "sim: capillary-gravity waves, grid %dx%d, cell %.3f mm, depth %.1f "
        "mm, nu %.2g m^2/s, sub-step %.3f ms, shortest wave %.1f mm, pen %s "
        "(shaft r %.1f mm, push r %.1f mm), walls %s, obstacles %s (%zu)",
        grid.nx, grid.ny, 1e3 * grid.cell_m, 1e3 * grid.rest_level_m,
        c.physics.kinematic_viscosity_m2_per_s, 1e3 * c.substep_s,
        1e3 * c.shortest_wavelength_m, sim::PenModelName(c.pen),
        1e3 * c.pen_shaft_radius_m, 1e3 * c.pen_radius_m,
        args.water.walls.c_str(), args.obstacles.c_str(), obstacles.size());
  }
  std::printf(", %zu stroke(s), %zu impulse(s), %.3g s at %.3g fps\n",
              strokes.size(), impulses.size(), args.duration_s, args.fps);

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
  std::printf("%8s %8s %6s %12s %12s %10s %10s %8s %8s %s\n", "time_s",
              "advance_ms", "steps", "volume_m3", "energy", "max|h|_m",
              "max|v|_m/s", "slope", "slope99", "flags");
  std::vector<bool> impulse_done(impulses.size(), false);
  std::vector<float> drop, gx, gy;
  std::vector<double> active_p99, active_rms;
  for (int f = 0; f <= frames; ++f) {
    const double t = f * dt;
    std::array<double, 3> tip;
    const bool pen = tip_at(t, &tip);
    if (pen) {
      water.SetPenTip(tip);
    } else {
      water.ClearPen();
    }
    for (std::size_t k = 0; k < impulses.size(); ++k) {
      const Impulse& im = impulses[k];
      if (impulse_done[k] || t + 1e-9 < im.t) continue;
      impulse_done[k] = true;
      drop.assign(static_cast<std::size_t>(grid.nx) * grid.ny, 0.0f);
      const sim::HeightFieldView v = water.View();
      for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
          const double dx = v.CellCentreX(i) - im.x,
                       dy = v.CellCentreY(j) - im.y;
          drop[static_cast<std::size_t>(j) * grid.nx + i] = static_cast<float>(
              im.amp *
              std::exp(-(dx * dx + dy * dy) / (2 * im.radius * im.radius)));
        }
      water.AddHeights(drop);
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
    const bool print = f % print_stride == 0 || f == frames;
    double rms = 0, p99 = 0;
    if (print || s.pen_touched) {
      SlopeStats(water.View(), &gx, &gy, &rms, &p99);
      if (s.pen_touched) {
        active_rms.push_back(rms);
        active_p99.push_back(p99);
      }
    }
    if (print) {
      std::printf(
          "%8.3f %8.3f %6d %12.4e %12.4e %10.3e %10.3e %8.4f %8.4f%s%s%s\n", t,
          ms, s.substeps, s.volume_m3, s.energy, s.max_abs_height_m,
          s.max_speed_m_per_s, rms, p99, s.pen_touched ? " pen" : "",
          s.at_rest ? " rest" : "", s.dropped_s > 0 ? " dropped" : "");
    }
    if (npy_out && f % args.every == 0) {
      char name[64];
      std::snprintf(name, sizeof(name), "/frame_%06d.npy", f);
      const sim::HeightFieldView v = water.View();
      if (!WriteNpy(args.out + name, v.heights, v.ny, v.nx)) {
        std::fclose(frames_csv);
        return Fail(kExitRuntime, "cannot write '" + args.out + name + "'");
      }
      if (pen)
        std::fprintf(frames_csv, "%d,%.6f,%.6f,%.6f,%.6f\n", f, t, tip[0],
                     tip[1], tip[2]);
      else
        std::fprintf(frames_csv, "%d,%.6f,,,\n", f, t);
      ++written;
      continue;
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
  std::string video_error;
  if (!video.Close(&video_error)) return Fail(kExitRuntime, video_error);
  if (frames_csv && std::fclose(frames_csv) != 0)
    return Fail(kExitRuntime, "cannot write '" + args.out + "/frames.csv'");
  if (!active_p99.empty())
    std::printf(
        "sim: surface slope while the pen acts (%zu frames): RMS median "
        "%.4f, 99th percentile median %.4f, max %.4f\n",
        active_p99.size(), bench::Percentile(active_rms, 50),
        bench::Percentile(active_p99, 50),
        *std::max_element(active_p99.begin(), active_p99.end()));
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
                  "Height frames: a folder (npy or PNG), or a video file "
                  "(.mp4, .mkv, .avi)");
  sub->add_option("--format", args->format,
                  "npy (float32 heights in metres, ny x nx, + frames.csv), "
                  "png or video; default from --out");
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
      ->capture_default_str()
      ->check(CLI::Range(-1.0, 1.0));
  sub->add_option("--impulse", args->impulses,
                  "Drop X,Y,T,AMP,RADIUS: a Gaussian displacement AMP "
                  "(metres, std RADIUS) released from rest at time T; "
                  "repeatable. With impulses and no --stroke the pen stays "
                  "out")
      ->allow_extra_args(false);
  AddWaterOptions(sub, &args->water);
  sub->add_option("--courant", args->courant,
                  "Sub-step c*dt/d, (0, 0.5] (paper model)");
  sub->add_option("--max-substeps", args->max_substeps,
                  "Sub-steps per frame before time is dropped (paper model)");
  sub->add_option("--obstacles", args->obstacles,
                  "Rig obstacles: reflect, zero (the paper model's h=v=0) or "
                  "off")
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
