// Geometry shared by laying out a marker sheet (marker_sheet.cc) and drawing
// it (sheet_writer.cc): text extents, tag labels and tag boxes in sheet
// coordinates (metres, y down). Internal to ripple_calib.
#ifndef RIPPLE_CALIB_SHEET_GEOMETRY_H_
#define RIPPLE_CALIB_SHEET_GEOMETRY_H_

#include <Eigen/Geometry>
#include <initializer_list>
#include <string>

#include "calib/marker_sheet.h"

namespace ripple::calib::sheet {

using Box = Eigen::AlignedBox2d;

inline constexpr double kMm = 1e-3;
inline constexpr double kLabelSize = 2.2 * kMm;  // tag id labels
inline constexpr double kTextSize = 3.0 * kMm;

// Rotation by `a` radians (clockwise on the page, since y points down).
Eigen::Matrix2d Rot2(double a);
// Width of `s` at text size `size` (metres), as the sheet's font runs.
double TextWidth(const std::string& s, double size);
Box BoxOf(std::initializer_list<Eigen::Vector2d> points);
Box TextBox(const SheetText& t);

// The tag family's bitmap size, in cells.
struct FamilyInfo {
  int total = 10, border = 8;
};
bool GetFamily(const std::string& name, FamilyInfo* info, std::string* error);

// The tag's id label (text) for a tag placed on a sheet.
SheetText TagLabel(const SheetTag& tag, const FamilyInfo& f);
// The tag with its white margin and its label.
Box TagBox(const SheetTag& tag, const FamilyInfo& f);

}  // namespace ripple::calib::sheet

#endif  // RIPPLE_CALIB_SHEET_GEOMETRY_H_
