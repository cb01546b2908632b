#include "calib/sheet_writer.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <sstream>

#include "calib/calib_io.h"
#include "calib/sheet_geometry.h"
#include "tracking/tag_family.h"

namespace ripple::calib {
namespace {

using Eigen::Vector2d;
using sheet::Box;
using sheet::FamilyInfo;
using sheet::GetFamily;
using sheet::kMm;
using sheet::TagLabel;

// sRGB encoding (IEC 61966-2-1) of a linear value in [0, 1].
double LinearToSrgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

// The device colour that prints `albedo` on paper of reflectance kPaperBgr
// (the page's white is the paper itself).
void SetAlbedo(cairo_t* cr, const cv::Vec3f& albedo_bgr) {
  const cv::Vec3f& paper = synth::kPaperBgr;
  cairo_set_source_rgb(cr, LinearToSrgb(albedo_bgr[2] / paper[2]),
                       LinearToSrgb(albedo_bgr[1] / paper[1]),
                       LinearToSrgb(albedo_bgr[0] / paper[0]));
}

// The floor pattern inside the tank outline: tiles as vector rectangles,
// an image as an image pattern stretched over the floor.
void DrawFloor(cairo_t* cr, const Sheet& sheet) {
  const synth::FloorPattern& floor = sheet.floor;
  const Vector2d o = sheet.tank_origin_m;
  // Tank (x, y) -> sheet (o.x + x, o.y - y): a tank box's top-left on the
  // page is its (min x, max y) corner.
  auto fill_box = [&](const Eigen::AlignedBox2d& b) {
    cairo_rectangle(cr, o.x() + b.min().x(), o.y() - b.max().y(), b.sizes().x(),
                    b.sizes().y());
    cairo_fill(cr);
  };
  if (floor.kind() == synth::FloorKind::kTiles) {
    for (const synth::FloorPattern::Cell& cell : floor.TileCells()) {
      SetAlbedo(cr, cell.bgr);
      fill_box(cell.rect);
    }
  } else if (floor.kind() == synth::FloorKind::kImage) {
    const cv::Mat& img = floor.image_bgr8();
    if (img.empty()) return;
    // The surface owns its pixels (the PDF and SVG surfaces may read them
    // when the page is finished). CAIRO_FORMAT_RGB24 is one native-endian
    // 32-bit word per pixel, x R G B from the high byte down.
    cairo_surface_t* s =
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, img.cols, img.rows);
    cairo_surface_flush(s);
    unsigned char* data = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int r = 0; r < img.rows; ++r) {
      uint32_t* row = reinterpret_cast<uint32_t*>(data + size_t(r) * stride);
      for (int c = 0; c < img.cols; ++c) {
        const cv::Vec3b p = img.at<cv::Vec3b>(r, c);
        row[c] =
            (uint32_t(p[2]) << 16) | (uint32_t(p[1]) << 8) | uint32_t(p[0]);
      }
    }
    cairo_surface_mark_dirty(s);
    const Eigen::AlignedBox2d& b = floor.rect();
    cairo_save(cr);
    cairo_translate(cr, o.x() + b.min().x(), o.y() - b.max().y());
    cairo_scale(cr, b.sizes().x() / img.cols, b.sizes().y() / img.rows);
    cairo_set_source_surface(cr, s, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_GOOD);
    cairo_pattern_set_extend(cairo_get_source(cr), CAIRO_EXTEND_PAD);
    cairo_rectangle(cr, 0, 0, img.cols, img.rows);
    cairo_fill(cr);
    cairo_restore(cr);
    cairo_surface_destroy(s);
  }
}

void Draw(cairo_t* cr, const Sheet& sheet, const tracking::TagFamily& family,
          const FamilyInfo& f) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, sheet.width_m, sheet.height_m);
  cairo_fill(cr);
  DrawFloor(cr, sheet);
  cairo_set_source_rgb(cr, 1, 1, 1);
  for (const Box& b : sheet.white_boxes) {
    cairo_rectangle(cr, b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
    cairo_fill(cr);
  }
  // Tags: their white margin (over the floor where they reach it), then
  // every black cell of the family's bitmap, one path per tag so that
  // neighbouring cells leave no seams.
  for (const SheetTag& tag : sheet.tags) {
    const double half = 0.5 * f.total * tag.edge_m / f.border;
    cairo_save(cr);
    cairo_translate(cr, tag.centre_m.x(), tag.centre_m.y());
    cairo_rotate(cr, tag.angle_rad);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_rectangle(cr, -half, -half, 2 * half, 2 * half);
    cairo_fill(cr);
    cairo_restore(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  for (const SheetTag& tag : sheet.tags) {
    auto bitmap = tracking::MakeTagBitmap(family, tag.id);
    if (!bitmap) continue;
    const double cell = tag.edge_m / bitmap->width_at_border;
    const double first =
        -0.5 * tag.edge_m -
        0.5 * (bitmap->total_width - bitmap->width_at_border) * cell;
    cairo_save(cr);
    cairo_translate(cr, tag.centre_m.x(), tag.centre_m.y());
    cairo_rotate(cr, tag.angle_rad);
    cairo_new_path(cr);
    for (int r = 0; r < bitmap->total_width; ++r)
      for (int c = 0; c < bitmap->total_width; ++c)
        if (bitmap->black(r, c))
          cairo_rectangle(cr, first + c * cell, first + r * cell, cell, cell);
    cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
    cairo_fill(cr);
    cairo_restore(cr);
  }
  for (const Box& b : sheet.black_boxes) {
    cairo_rectangle(cr, b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
  }
  cairo_fill(cr);
  auto stroke_style = [&](SheetLine::Style s) {
    double dash[2] = {3 * kMm, 2 * kMm};
    switch (s) {
      case SheetLine::Style::kCut:
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, 0.3 * kMm);
        cairo_set_dash(cr, nullptr, 0, 0);
        break;
      case SheetLine::Style::kFold:
        cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
        cairo_set_line_width(cr, 0.3 * kMm);
        cairo_set_dash(cr, dash, 2, 0);
        break;
      case SheetLine::Style::kThin:
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, 0.15 * kMm);
        cairo_set_dash(cr, nullptr, 0, 0);
        break;
      case SheetLine::Style::kGuide:
        cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
        cairo_set_line_width(cr, 0.2 * kMm);
        dash[0] = 1.5 * kMm;
        dash[1] = 1.5 * kMm;
        cairo_set_dash(cr, dash, 2, 0);
        break;
    }
  };
  for (const SheetLine& l : sheet.lines) {
    stroke_style(l.style);
    cairo_move_to(cr, l.a.x(), l.a.y());
    cairo_line_to(cr, l.b.x(), l.b.y());
    cairo_stroke(cr);
  }
  for (const SheetCircle& c : sheet.circles) {
    stroke_style(c.style);
    cairo_new_path(cr);
    cairo_arc(cr, c.centre.x(), c.centre.y(), c.radius_m, 0, 2 * M_PI);
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         CAIRO_FONT_WEIGHT_NORMAL);
  std::vector<SheetText> texts = sheet.texts;
  for (const SheetTag& tag : sheet.tags)
    if (!tag.label_dir.isZero()) texts.push_back(TagLabel(tag, f));
  for (const SheetText& t : texts) {
    cairo_save(cr);
    cairo_set_font_size(cr, t.size_m);
    cairo_translate(cr, t.at.x(), t.at.y());
    cairo_rotate(cr, t.angle_rad);
    cairo_text_extents_t e;
    cairo_text_extents(cr, t.text.c_str(), &e);
    cairo_move_to(cr, -0.5 * e.width - e.x_bearing,
                  -0.5 * e.height - e.y_bearing);
    cairo_show_text(cr, t.text.c_str());
    cairo_restore(cr);
  }
}

uint32_t Crc32(const uint8_t* data, size_t n, uint32_t crc = 0) {
  static uint32_t table[256];
  static bool init = false;
  if (!init) {
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      table[i] = c;
    }
    init = true;
  }
  crc = ~crc;
  for (size_t i = 0; i < n; ++i)
    crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

// Inserts a pHYs chunk (pixels per metre) after IHDR so that viewers and
// printers know the physical size.
bool AddPngResolution(const std::string& path, double dpi) {
  std::ifstream in(path, std::ios::binary);
  std::string png((std::istreambuf_iterator<char>(in)), {});
  in.close();
  if (png.size() < 33 || png.compare(12, 4, "IHDR") != 0) return false;
  if (png.find("pHYs") != std::string::npos) return true;
  const uint32_t ppm = static_cast<uint32_t>(std::lround(dpi / 0.0254));
  uint8_t chunk[21] = {0, 0, 0, 9, 'p', 'H', 'Y', 's'};
  for (int i = 0; i < 2; ++i) {
    chunk[8 + 4 * i] = ppm >> 24;
    chunk[9 + 4 * i] = (ppm >> 16) & 0xFF;
    chunk[10 + 4 * i] = (ppm >> 8) & 0xFF;
    chunk[11 + 4 * i] = ppm & 0xFF;
  }
  chunk[16] = 1;  // unit: metre
  const uint32_t crc = Crc32(chunk + 4, 13);
  chunk[17] = crc >> 24;
  chunk[18] = (crc >> 16) & 0xFF;
  chunk[19] = (crc >> 8) & 0xFF;
  chunk[20] = crc & 0xFF;
  png.insert(33, reinterpret_cast<const char*>(chunk), 21);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(png.data(), png.size());
  return static_cast<bool>(out);
}

}  // namespace

bool WriteSheet(const Sheet& sheet, const std::string& base, double png_dpi,
                std::vector<std::string>* written, std::string* error) {
  auto family = tracking::TagFamily::Create(sheet.family);
  FamilyInfo f;
  if (!family || !GetFamily(sheet.family, &f, error)) {
    *error = "unknown tag family '" + sheet.family + "'";
    return false;
  }
  constexpr double kPtPerM = 72.0 / 0.0254;
  const double w_pt = sheet.width_m * kPtPerM, h_pt = sheet.height_m * kPtPerM;
  auto vector_writer = [&](bool pdf) {
    return [&, pdf](const std::string& temp, std::string* e) {
      // PDF in points; SVG in millimetres (document unit mm, so the file's
      // width/height say "297mm" and the viewBox is in mm too).
      const double scale = pdf ? kPtPerM : 1000.0;
      cairo_surface_t* s =
          pdf ? cairo_pdf_surface_create(temp.c_str(), w_pt, h_pt)
              : cairo_svg_surface_create(temp.c_str(), sheet.width_m * 1000.0,
                                         sheet.height_m * 1000.0);
      if (!pdf) cairo_svg_surface_set_document_unit(s, CAIRO_SVG_UNIT_MM);
      if (pdf)
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE,
                                       sheet.title.c_str());
      cairo_t* cr = cairo_create(s);
      cairo_scale(cr, scale, scale);
      Draw(cr, sheet, *family, f);
      cairo_destroy(cr);
      cairo_surface_finish(s);
      const bool ok = cairo_surface_status(s) == CAIRO_STATUS_SUCCESS;
      cairo_surface_destroy(s);
      if (!ok) *e = "cannot write '" + temp + "'";
      return ok;
    };
  };
  auto png_writer = [&](const std::string& temp, std::string* e) {
    const double px_per_m = png_dpi / 0.0254;
    const int w = static_cast<int>(std::lround(sheet.width_m * px_per_m));
    const int h = static_cast<int>(std::lround(sheet.height_m * px_per_m));
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_t* cr = cairo_create(s);
    cairo_scale(cr, px_per_m, px_per_m);
    Draw(cr, sheet, *family, f);
    cairo_destroy(cr);
    const bool ok =
        cairo_surface_write_to_png(s, temp.c_str()) == CAIRO_STATUS_SUCCESS &&
        AddPngResolution(temp, png_dpi);
    cairo_surface_destroy(s);
    if (!ok) *e = "cannot write '" + temp + "'";
    return ok;
  };
  for (const char* ext : {".pdf", ".svg", ".png"}) {
    const std::string path = base + ext;
    bool ok;
    if (std::string(ext) == ".png")
      ok = WriteAtomically(path, png_writer, error);
    else
      ok = WriteAtomically(path, vector_writer(std::string(ext) == ".pdf"),
                           error);
    if (!ok) return false;
    written->push_back(path);
  }
  return true;
}

}  // namespace ripple::calib
