// Printable marker sheets at exact physical scale: the tank board, the pen
// cube's net (cut and fold lines, glue tabs) and a camera-calibration
// chessboard. A sheet is first laid out as plain shapes in sheet
// coordinates (metres, origin at the top-left corner of the page, x right,
// y down), then drawn with Cairo to PDF, SVG (width/height in mm) and PNG
// (with its resolution in the pHYs chunk) by calib/sheet_writer.h. Tags are
// drawn cell by cell from the family's own bitmap (tracking::MakeTagBitmap).
#ifndef RIPPLE_CALIB_MARKER_SHEET_H_
#define RIPPLE_CALIB_MARKER_SHEET_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"

namespace ripple::calib {

// Page size, portrait (width < height), metres.
struct PaperSize {
  std::string name;  // "a4", "letter"
  double width_m = 0, height_m = 0;
};
PaperSize PaperA4();
PaperSize PaperLetter();

// A tag on a sheet: the centre of its black square, its edge, and the
// rotation of the tag image on the page (radians, clockwise on the page as
// seen, since y points down).
struct SheetTag {
  int id = -1;
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double edge_m = 0;
  double angle_rad = 0;
  // Where the id label goes, as a direction in the tag image (x right, y
  // down): {0, 1} below the tag, outside its white margin.
  Eigen::Vector2d label_dir = Eigen::Vector2d(0, 1);
  double label_offset_m = 0;  // extra distance beyond the tag's margin

  // Corner k (TL, TR, BR, BL of the tag image) on the sheet.
  Eigen::Vector2d Corner(int k) const;
};

struct SheetLine {
  enum class Style { kCut, kFold, kThin, kGuide };
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  Style style = Style::kCut;
};

struct SheetText {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // centre of the text
  std::string text;
  double size_m = 0.003;  // font size
  double angle_rad = 0;
};

struct SheetCircle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius_m = 0;
  SheetLine::Style style = SheetLine::Style::kThin;
};

struct Sheet {
  std::string title;
  std::string family = "tag36h11";
  double width_m = 0, height_m = 0;  // the page as printed
  std::vector<SheetTag> tags;
  std::vector<Eigen::AlignedBox2d> black_boxes;  // filled (chessboard)
  // Filled white over the floor: the scale bar's ground when it has to sit
  // on the printed floor.
  std::vector<Eigen::AlignedBox2d> white_boxes;
  std::vector<SheetLine> lines;
  std::vector<SheetText> texts;
  std::vector<SheetCircle> circles;
  // The tank floor, printed under everything else (tags keep their white
  // margin over it): the pattern in the tank frame and the sheet point of
  // the tank origin (tank x to the right, tank y up the page). Plain paper
  // prints nothing.
  synth::FloorPattern floor;
  Eigen::Vector2d tank_origin_m = Eigen::Vector2d::Zero();
};

// One face of the folded cube net: where it lies on the sheet and how the
// sheet maps onto the cube in the pen frame.
struct NetFace {
  Eigen::Vector3d normal_in_pen = Eigen::Vector3d::Zero();  // outward
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();       // on the sheet
  // Columns: the page's x (right), y (down) and into-the-page directions in
  // the pen frame once folded.
  Eigen::Matrix3d pen_from_page = Eigen::Matrix3d::Identity();
  double edge_m = 0;  // cube edge
  int tag_id = -1;    // -1: the untagged face that holds the pen

  // A point of this face on the sheet -> the same point on the folded cube.
  Eigen::Vector3d PenPoint(const Eigen::Vector2d& on_sheet) const;
};

// Printer margin kept clear on every sheet, metres.
inline constexpr double kSheetMargin = 0.006;

// Board sheet (landscape): the rig's tank tags at their places (the board
// centre at the page centre, tank x to the right, tank y up the page), the
// floor pattern inside the tank outline, the check points
// (calib/tip_check.h), a 100 mm scale bar. `floor` is made for the rig's
// tank (synth::FloorPattern::Create(options, rig.tank, ...)). False with
// `error` when a tag is not flat on the board, the board does not fit the
// paper or the floor is not the tank's size.
bool MakeBoardSheet(const tracking::Rig& rig, const PaperSize& paper,
                    const synth::FloorPattern& floor, Sheet* sheet,
                    std::string* error);
// The same with a plain (blank paper) floor.
bool MakeBoardSheet(const tracking::Rig& rig, const PaperSize& paper,
                    Sheet* sheet, std::string* error);

// Cube net sheet (portrait): the pen cube unfolded as a cross, each tag on
// its face exactly as the rig places it, the pen face with the shaft hole,
// glue tabs on one side of every open edge. False with `error` when the rig
// has no pen or its faces are not on the sides of a cube.
bool MakeCubeNetSheet(const tracking::Rig& rig, const PaperSize& paper,
                      Sheet* sheet, std::vector<NetFace>* faces,
                      std::string* error);

// Chessboard target (landscape) with cols x rows inner corners.
bool MakeChessboardSheet(int cols, int rows, double square_m,
                         const PaperSize& paper, Sheet* sheet,
                         std::string* error);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_MARKER_SHEET_H_
