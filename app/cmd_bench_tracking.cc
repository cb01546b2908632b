// `ripple bench tracking`: the command around bench/tracking_bench.h. It
// scales the camera to each --sizes entry, prints the table, and writes
// bench_tracking.csv, the optional per-frame CSV and one plot per size.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "app/app_bench.h"
#include "app/app_common.h"
#include "app/app_floor.h"
#include "app/app_wxh.h"
#include "app/command.h"
#include "bench/tracking_bench.h"
#include "bench/tracking_plot.h"
#include "tracking/synth/variant.h"

namespace ripple::app {
namespace {

struct BenchArgs {
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string out = "bench_tracking";
  std::vector<std::string> sizes = {"640x480", "1280x720"};
  std::string sweep = "short";
  bench::TrackingBenchOptions options;
  bool frames_csv = false;
  std::string floor;
  std::vector<std::string> variants = {"exact"};
  std::vector<std::string> smoothing_grid;
};

// One --smoothing-grid entry: fourteen numbers separated by '/': the pen's
// translation cut-off (Hz) and beta (Hz per m/s), rotation cut-off (Hz) and
// beta (Hz per rad/s), derivative cut-off (Hz); the tank's cut-off (Hz,
// both parts), translation beta, rotation beta, derivative cut-off, reset
// bounds (degrees, millimetres); the pen's reset bounds (degrees,
// millimetres); 1 to restart the pen's filter while it is ambiguous, 0 not.
bool ParseSmoothingEntry(const std::string& text,
                         tracking::SmoothingOptions* out, std::string* error) {
  std::vector<double> v;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find('/', start), text.size());
    const std::string part = text.substr(start, end - start);
    char* stop = nullptr;
    const double x = std::strtod(part.c_str(), &stop);
    if (part.empty() || *stop != '\0') {
      *error = "--smoothing-grid '" + text + "': not a number: '" + part + "'";
      return false;
    }
    v.push_back(x);
    start = end + 1;
  }
  if (v.size() != 14) {
    *error = "--smoothing-grid '" + text + "': give 14 numbers separated by /";
    return false;
  }
  tracking::SmoothingOptions s;
  s.enabled = true;
  s.pen.min_cutoff_translation_hz = v[0];
  s.pen.beta_translation_hz_per_m_s = v[1];
  s.pen.min_cutoff_rotation_hz = v[2];
  s.pen.beta_rotation_hz_per_rad_s = v[3];
  s.pen.derivative_cutoff_hz = v[4];
  s.tank.min_cutoff_translation_hz = s.tank.min_cutoff_rotation_hz = v[5];
  s.tank.beta_translation_hz_per_m_s = v[6];
  s.tank.beta_rotation_hz_per_rad_s = v[7];
  s.tank.derivative_cutoff_hz = v[8];
  s.tank.reset_rotation_deg = v[9];
  s.tank.reset_translation_m = v[10] / 1000;
  s.pen.reset_rotation_deg = v[11];
  s.pen.reset_translation_m = v[12] / 1000;
  s.reset_when_ambiguous = v[13] != 0;
  std::string why;
  if (!s.IsValid(&why)) {
    *error = "--smoothing-grid '" + text + "': " + why;
    return false;
  }
  *out = s;
  return true;
}

int RunBenchTracking(BenchArgs& args) {
  auto base_camera = LoadCameraOrReport(args.camera);
  if (!base_camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  auto floor = MakeFloorOrReport(args.floor, *rig);
  if (!floor) return kExitBadInput;
  args.options.floor = *floor;
  args.options.sweep = args.sweep == "full"        ? bench::Sweep::kFull
                       : args.sweep == "default"   ? bench::Sweep::kDefault
                       : args.sweep == "suspects"  ? bench::Sweep::kSuspects
                       : args.sweep == "smoothing" ? bench::Sweep::kSmoothing
                                                   : bench::Sweep::kShort;
  std::string error;
  for (const std::string& entry : args.smoothing_grid) {
    tracking::SmoothingOptions s;
    if (!ParseSmoothingEntry(entry, &s, &error))
      return Fail(kExitBadInput, error);
    args.options.smoothing_grid.push_back(s);
  }
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);
  const std::string csv_path = args.out + "/bench_tracking.csv";
  std::ofstream csv(csv_path);
  if (!csv) return Fail(kExitBadInput, "cannot write '" + csv_path + "'");
  std::ofstream frames_csv;
  if (args.frames_csv) {
    frames_csv.open(args.out + "/bench_tracking_frames.csv");
    if (!frames_csv) return Fail(kExitBadInput, "cannot write the frames CSV");
    bench::WriteTrackingFramesCsvHeader(&frames_csv);
  }
  bench::WriteTrackingCsvHeader(&csv);
  for (const std::string& variant : args.variants)
    for (const std::string& size : args.sizes) {
      args.options.variant = variant;
      // Plots and per-frame rows of other variants carry the variant's name.
      const std::string label =
          variant == "exact" ? size : size + "@" + variant;
      WxH wxh;
      ParseWxH(size, &wxh);  // checked by the option's validator
      const tracking::Camera camera =
          base_camera->Scaled(wxh.width, wxh.height);
      bench::TrackingBenchResult result;
      const auto progress = [&size](int done, int total) {
        std::fprintf(stderr, "\rbench tracking %s: %d/%d frames", size.c_str(),
                     done, total);
      };
      if (!bench::RunTrackingBench(args.options, camera, *rig, args.frames_csv,
                                   progress, &result, &error))
        return Fail(kExitBadInput, error);
      std::fprintf(stderr, "\n");
      std::printf(
          "%s", bench::FormatTrackingTable(args.options, size, result).c_str());
      bench::WriteTrackingCsvRows(args.options, size, result, &csv);
      if (frames_csv.is_open())
        bench::WriteTrackingFramesCsvRows(label, result, &frames_csv);
      std::fflush(stdout);
      bench::PlotTipErrorAgainstTime(
          result.settings,
          "ripple bench tracking, " + label + ", " +
              std::to_string(args.options.frames) +
              " frames: tip error against time",
          args.out + "/bench_tracking_" + label + ".png");
    }
  std::printf("\nwrote %s and %s/bench_tracking_<size>.png\n", csv_path.c_str(),
              args.out.c_str());
  return kExitOk;
}

CommandAction SetupBenchTracking(CLI::App* sub) {
  auto args = std::make_shared<BenchArgs>();
  sub->add_option("--camera", args->camera,
                  "Camera calibration YAML (scaled to each size)")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--out", args->out, "Output folder (CSV, PNG plots)")
      ->capture_default_str();
  sub->add_option("--frames", args->options.frames, "Frames per size")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--sizes", args->sizes, "Image sizes, WIDTHxHEIGHT")
      ->capture_default_str()
      ->delimiter(',')
      ->check(WxHValidator(WxHLimits::Size()));
  sub->add_option("--sweep", args->sweep,
                  "full: decimation x refinement x pen mode x region search; "
                  "short: one factor at a time around the default; "
                  "default: the default setting only, no baselines; "
                  "suspects: the corner pipeline's and the pen refinement's "
                  "parts one at a time, with the plain SQPNP+LM baselines; "
                  "smoothing: smoothing off, on, and a grid of cut-offs")
      ->capture_default_str()
      ->check(
          CLI::IsMember({"full", "short", "default", "suspects", "smoothing"}));
  sub->add_option("--variants", args->variants,
                  "Data variants: exact (exact area coverage), supersampled "
                  "(3x3 ray-cast point samples, disc defocus), srgb "
                  "(supersampled, sRGB-encoded), lens (supersampled, "
                  "distorting lens, busy table), webcam (all of them)")
      ->capture_default_str()
      ->delimiter(',')
      ->check(CLI::IsMember(synth::DataVariantNames()));
  sub->add_option("--static-frames", args->options.static_frames,
                  "Frames of the static sequence (segments of 30, only noise "
                  "changing) for the jitter columns; 0: none")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  sub->add_option("--static-segment", args->options.static_segment_frames,
                  "Frames per static segment (each tracked by fresh trackers)")
      ->capture_default_str()
      ->check(CLI::Range(2, 100000));
  sub->add_option("--first", args->options.first,
                  "Skip (neither render nor track) the frames before this one "
                  "of the sequence (to look at one segment)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  sub->add_flag("--frames-csv", args->frames_csv,
                "Also write per-frame errors of every setting to "
                "bench_tracking_frames.csv");
  sub->add_option("--threads", args->options.threads, "Detector threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  sub->add_option("--seed", args->options.seed, "Sequence seed")
      ->capture_default_str();
  sub->add_option("--smoothing-grid", args->smoothing_grid,
                  "--sweep smoothing: settings to try instead of the built-in "
                  "grid, each PEN_T_HZ/PEN_T_BETA/PEN_R_HZ/PEN_R_BETA/PEN_D_HZ/"
                  "TANK_HZ/TANK_T_BETA/TANK_R_BETA/TANK_D_HZ/TANK_RESET_DEG/"
                  "TANK_RESET_MM/PEN_RESET_DEG/PEN_RESET_MM/AMBIGUOUS_RESET "
                  "(Hz, Hz per m/s, Hz per rad/s, degrees, millimetres, 1 or "
                  "0), comma-separated")
      ->delimiter(',');
  AddFloorOption(sub, &args->floor);
  return [args] { return RunBenchTracking(*args); };
}

}  // namespace

RIPPLE_REGISTER_BENCH(tracking,
                      "Tracking run time against error on synth frames",
                      SetupBenchTracking);

}  // namespace ripple::app
