// `ripple markers`: printable sheets at exact scale (board with its tank
// floor, cube net, calibration chessboard) as PDF, SVG and PNG.
#include <cstdio>
#include <memory>

#include "app/app_common.h"
#include "app/app_floor.h"
#include "app/app_wxh.h"
#include "app/command.h"
#include "calib/marker_sheet.h"
#include "calib/sheet_writer.h"

namespace ripple::app {
namespace {

struct MarkersArgs {
  std::string rig = DefaultRigPath();
  std::string out;
  std::vector<std::string> papers = {"a4", "letter"};
  double dpi = 300;
  std::string chessboard = "9x6";
  double square = 0.025;
  std::string floor;
};

int RunMarkers(const MarkersArgs& args) {
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  auto floor = MakeFloorOrReport(args.floor, *rig);
  if (!floor) return kExitBadInput;
  WxH pattern;
  ParseWxH(args.chessboard, &pattern, WxHLimits::Pattern());  // validated
  std::string error;
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);
  std::vector<std::string> written;
  int skipped = 0;
  for (const std::string& name : args.papers) {
    const calib::PaperSize paper =
        name == "letter" ? calib::PaperLetter() : calib::PaperA4();
    auto emit = [&](const char* what, bool ok, const calib::Sheet& sheet) {
      if (!ok) {
        std::fprintf(stderr, "ripple: warning: %s sheet skipped: %s\n", what,
                     error.c_str());
        ++skipped;
        return true;
      }
      return calib::WriteSheet(sheet, args.out + "/" + what + "_" + paper.name,
                               args.dpi, &written, &error);
    };
    calib::Sheet sheet;
    std::vector<calib::NetFace> faces;
    if (!emit("board",
              calib::MakeBoardSheet(*rig, paper, *floor, &sheet, &error),
              sheet))
      return Fail(kExitRuntime, error);
    if (rig->pen) {
      if (!emit("cube_net",
                calib::MakeCubeNetSheet(*rig, paper, &sheet, &faces, &error),
                sheet))
        return Fail(kExitRuntime, error);
    }
    if (!emit("chessboard",
              calib::MakeChessboardSheet(pattern.width, pattern.height,
                                         args.square, paper, &sheet, &error),
              sheet))
      return Fail(kExitRuntime, error);
  }
  for (const std::string& path : written) std::printf("%s\n", path.c_str());
  std::printf(
      "markers: %zu files (PDF, SVG, PNG at %.0f dpi) in %s; print at 100 %% "
      "and check the 100 mm scale bar%s\n",
      written.size(), args.dpi, args.out.c_str(),
      skipped ? " (some sheets skipped, see the warnings)" : "");
  if (written.empty()) return Fail(kExitRuntime, "no sheet could be laid out");
  return kExitOk;
}

CommandAction SetupMarkers(CLI::App* sub) {
  auto args = std::make_shared<MarkersArgs>();
  sub->add_option("--rig", args->rig, "Rig YAML (tags, cube)")
      ->capture_default_str();
  sub->add_option("--out", args->out,
                  "Output folder (board_*, cube_net_*, chessboard_*)")
      ->required();
  sub->add_option("--paper", args->papers, "Paper sizes: a4, letter")
      ->capture_default_str()
      ->check(CLI::IsMember({"a4", "letter"}))
      ->delimiter(',');
  sub->add_option("--dpi", args->dpi, "PNG resolution (dots per inch)")
      ->capture_default_str()
      ->check(CLI::Range(50.0, 1200.0));
  sub->add_option("--chessboard", args->chessboard,
                  "Calibration chessboard, inner corners COLSxROWS")
      ->capture_default_str()
      ->check(WxHValidator(WxHLimits::Pattern()));
  sub->add_option("--square", args->square, "Chessboard square edge, metres")
      ->capture_default_str()
      ->check(CLI::Range(0.003, 0.2));
  AddFloorOption(sub, &args->floor);
  return [args] { return RunMarkers(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(
    markers,
    "Print sheets at exact scale: tank board, pen-cube net, chessboard",
    SetupMarkers);

}  // namespace ripple::app
