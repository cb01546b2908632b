// Drawing a laid-out marker sheet (calib/marker_sheet.h) with Cairo: PDF,
// SVG (width/height in mm) and PNG (its resolution in the pHYs chunk), each
// written atomically (calib/calib_io.h).
#ifndef RIPPLE_CALIB_SHEET_WRITER_H_
#define RIPPLE_CALIB_SHEET_WRITER_H_

#include <string>
#include <vector>

#include "calib/marker_sheet.h"

namespace ripple::calib {

// Writes `base`.pdf, `base`.svg and `base`.png (at `png_dpi`), each through
// a temporary file; appends the written paths to `written`.
bool WriteSheet(const Sheet& sheet, const std::string& base, double png_dpi,
                std::vector<std::string>* written, std::string* error);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_SHEET_WRITER_H_
