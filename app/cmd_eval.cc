// `ripple eval`: the error table of `ripple bench tracking` for any pose CSV
// against a ground-truth one (`ripple synth`'s groundtruth.csv), so that a
// tracker written elsewhere can be measured on Ripple's synthetic frames.
// With --out it also writes the per-frame errors, the summary row and a plot
// of the errors over frames.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "app/app_common.h"
#include "app/command.h"
#include "bench/pose_eval.h"
#include "bench/tracking_plot.h"
#include "tracking/pose_csv.h"

namespace ripple::app {
namespace {

struct EvalArgs {
  std::string truth, poses, out;
  bench::PoseErrorOptions options;
};

int FramesIn(const std::vector<bench::FrameRange>& runs) {
  int n = 0;
  for (const bench::FrameRange& r : runs) n += r.end - r.begin;
  return n;
}

bool InRuns(const std::vector<bench::FrameRange>& runs, int i) {
  for (const bench::FrameRange& r : runs)
    if (i >= r.begin && i < r.end) return true;
  return false;
}

bool WriteFramesCsv(const std::string& path, const bench::PairedPoses& pairs,
                    const bench::PoseErrorAccumulator& acc,
                    const bench::PoseErrorSummary& summary) {
  std::ofstream csv(path);
  if (!csv) return false;
  csv << "frame,tank_rot_deg,tank_mm,pen_rot_deg,pen_mm,tip_mm,flip,"
         "tank_tracked,pen_tracked,tank_static,pen_static,tip_static\n";
  const auto& errors = acc.frame_errors();
  for (size_t i = 0; i < errors.size(); ++i) {
    const bench::FrameErrors& e = errors[i];
    const bench::EstimateFrame& est = pairs.estimates[i];
    const int k = static_cast<int>(i);
    csv << pairs.truth[i].frame << ',' << e.tank_rot_deg << ',' << e.tank_mm
        << ',' << e.pen_rot_deg << ',' << e.pen_mm << ',' << e.tip_mm << ','
        << e.flip << ',' << est.tank_tracked << ',' << est.pen_tracked << ','
        << InRuns(summary.tank_static, k) << ','
        << InRuns(summary.pen_static, k) << ',' << InRuns(summary.tip_static, k)
        << '\n';
  }
  csv.flush();
  return static_cast<bool>(csv);
}

int RunEval(const EvalArgs& args) {
  std::string error;
  if (!args.options.IsValid(&error)) return Fail(kExitBadInput, error);
  const auto truth = tracking::ReadPoseCsv(args.truth, &error);
  if (!truth) return Fail(kExitBadInput, "--truth: " + error);
  const auto poses = tracking::ReadPoseCsv(args.poses, &error);
  if (!poses) return Fail(kExitBadInput, "--poses: " + error);
  bench::PairedPoses pairs;
  if (!bench::PairPoseRows(*truth, args.truth, *poses, args.poses, &pairs,
                           &error))
    return Fail(kExitBadInput, error);
  if (!args.out.empty() && !MakeDirectories(args.out, &error))
    return Fail(kExitBadInput, error);

  bench::PoseErrorAccumulator acc(args.options);
  for (size_t i = 0; i < pairs.truth.size(); ++i)
    acc.Add(pairs.truth[i], pairs.estimates[i]);
  const bench::PoseErrorSummary s = acc.Summarize();

  const std::string name = std::filesystem::path(args.poses).filename();
  std::printf(
      "\n### %s against %s: %d frames (%d to %d)\n\n| poses "
      "%s|\n|---%s|\n| %s %s|\n",
      args.poses.c_str(), args.truth.c_str(), s.frames,
      pairs.truth.front().frame, pairs.truth.back().frame,
      bench::ErrorTableHeaderCells().c_str(),
      bench::ErrorTableSeparatorCells().c_str(), name.c_str(),
      bench::ErrorTableCells(s).c_str());
  std::printf(
      "\nflip: a rotation error over %g°. static segments (truth within "
      "%g° and %g mm for >= %d frames): tank %zu (%d frames), pen %zu (%d "
      "frames), tip %zu (%d frames)\n",
      args.options.flip_deg, args.options.static_rotation_deg,
      1e3 * args.options.static_translation_m, args.options.static_min_frames,
      s.tank_static.size(), FramesIn(s.tank_static), s.pen_static.size(),
      FramesIn(s.pen_static), s.tip_static.size(), FramesIn(s.tip_static));
  if (pairs.derived_tips > 0)
    std::printf(
        "tip: %d pen rows without tip columns; their tip was made from the "
        "estimated poses\n",
        pairs.derived_tips);
  if (args.out.empty()) return kExitOk;

  const std::string frames_csv = args.out + "/eval_frames.csv";
  if (!WriteFramesCsv(frames_csv, pairs, acc, s))
    return Fail(kExitRuntime, "cannot write '" + frames_csv + "'");
  const std::string summary_csv = args.out + "/eval_summary.csv";
  {
    std::ofstream csv(summary_csv);
    csv << "poses,truth,frames," << bench::ErrorCsvHeader() << '\n'
        << '"' << args.poses << "\",\"" << args.truth << "\"," << s.frames
        << ',' << bench::ErrorCsvFields(s) << '\n';
    csv.flush();
    if (!csv) return Fail(kExitRuntime, "cannot write '" + summary_csv + "'");
  }
  std::vector<int> frames;
  std::vector<bool> pen_in_truth;
  for (const bench::TruthFrame& t : pairs.truth) {
    frames.push_back(t.frame);
    pen_in_truth.push_back(t.cam_from_pen.has_value());
  }
  const std::string png = args.out + "/eval_errors.png";
  if (!bench::PlotErrorsOverFrames(
          frames, acc.frame_errors(), pen_in_truth, s,
          "ripple eval: " + name + " against " +
              std::filesystem::path(args.truth).filename().string(),
          png))
    return Fail(kExitRuntime, "cannot write '" + png + "'");
  std::printf("wrote %s, %s and %s\n", frames_csv.c_str(), summary_csv.c_str(),
              png.c_str());
  return kExitOk;
}

CommandAction SetupEval(CLI::App* sub) {
  auto args = std::make_shared<EvalArgs>();
  sub->add_option("--truth", args->truth,
                  "Ground-truth pose CSV (ripple synth's groundtruth.csv)")
      ->required();
  sub->add_option("--poses", args->poses,
                  "Estimated poses in the same CSV format (ripple track's, or "
                  "any tracker's)")
      ->required();
  sub->add_option("--out", args->out,
                  "Report folder: eval_frames.csv, eval_summary.csv, "
                  "eval_errors.png");
  sub->add_option("--flip-deg", args->options.flip_deg,
                  "Rotation error counted as a flip, degrees")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--static-deg", args->options.static_rotation_deg,
                  "Static segments: most rotation from the segment's first "
                  "true pose, degrees")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--static-m", args->options.static_translation_m,
                  "Static segments: most translation from the segment's first "
                  "true pose, metres")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--static-frames", args->options.static_min_frames,
                  "Static segments: fewest frames")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  sub->footer(
      "Rotation and translation errors are of cam_from_object; the tip's is "
      "in the tank frame. Jitter is the standard deviation of the estimate "
      "(rotation: angle from the mean rotation; tip: 3-D distance from the "
      "mean tip) over runs of frames where the truth is static.");
  return [args] { return RunEval(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(eval,
                        "Error table of any pose CSV against ground truth",
                        SetupEval);

}  // namespace ripple::app
