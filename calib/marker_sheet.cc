#include "calib/marker_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "calib/sheet_geometry.h"
#include "calib/tip_check.h"
#include "tracking/tag_family.h"

namespace ripple::calib {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using sheet::Box;
using sheet::BoxOf;
using sheet::FamilyInfo;
using sheet::GetFamily;
using sheet::kLabelSize;
using sheet::kMm;
using sheet::kTextSize;
using sheet::Rot2;
using sheet::TagBox;
using sheet::TagLabel;
using sheet::TextBox;
using sheet::TextWidth;

bool Overlaps(const Box& b, const std::vector<Box>& occupied) {
  for (const Box& o : occupied)
    if (b.intersects(o)) return true;
  return false;
}

// Finds a free place for a w x h box on the page, nearest to `prefer` (its
// centre); false when nothing fits.
bool PlaceBox(const Sheet& sheet, const std::vector<Box>& occupied, double w,
              double h, const Vector2d& prefer, Box* placed) {
  const double step = 1.0 * kMm, gap = 1.5 * kMm;
  double best = 1e9;
  for (double y = kSheetMargin; y + h <= sheet.height_m - kSheetMargin;
       y += step) {
    for (double x = kSheetMargin; x + w <= sheet.width_m - kSheetMargin;
         x += step) {
      const Box b(Vector2d(x, y), Vector2d(x + w, y + h));
      const Box padded(b.min() - Vector2d(gap, gap),
                       b.max() + Vector2d(gap, gap));
      if (Overlaps(padded, occupied)) continue;
      const double d = (b.center() - prefer).norm();
      if (d < best) best = d, *placed = b;
    }
  }
  return best < 1e9;
}

// 100 mm scale bar (ten 10 mm blocks) with its caption; horizontal or
// vertical. Adds its shapes and its box to `occupied`; `white_ground` paints
// the box white first (when it has to sit on the printed floor). False if it
// fits nowhere.
bool AddScaleBar(Sheet* sheet, std::vector<Box>* occupied,
                 const Vector2d& prefer, bool white_ground = false) {
  const double len = 100 * kMm, bar = 2.5 * kMm;
  const std::string caption = "100 mm - check with a ruler: print at 100 %";
  const double depth = bar + 1.0 * kMm + kLabelSize;
  for (int vertical = 0; vertical < 2; ++vertical) {
    const double w = vertical ? depth : len, h = vertical ? len : depth;
    Box b;
    if (!PlaceBox(*sheet, *occupied, w, h, prefer, &b)) continue;
    const Vector2d o = b.min();
    if (white_ground) {
      const Vector2d pad(1.0 * kMm, 1.0 * kMm);
      sheet->white_boxes.push_back(Box(b.min() - pad, b.max() + pad));
    }
    for (int i = 0; i < 10; ++i) {
      const double s = i * 10 * kMm, e = (i + 1) * 10 * kMm;
      const Box block = vertical
                            ? Box(o + Vector2d(0, s), o + Vector2d(bar, e))
                            : Box(o + Vector2d(s, 0), o + Vector2d(e, bar));
      if (i % 2 == 0) sheet->black_boxes.push_back(block);
    }
    const Vector2d c0 = o, c1 = vertical ? o + Vector2d(bar, len)
                                         : o + Vector2d(len, bar);
    const Vector2d c01(c1.x(), c0.y()), c10(c0.x(), c1.y());
    for (auto [p, q] : {std::pair{c0, c01}, std::pair{c01, c1},
                        std::pair{c1, c10}, std::pair{c10, c0}})
      sheet->lines.push_back({p, q, SheetLine::Style::kThin});
    SheetText t;
    t.text = caption;
    t.size_m = kLabelSize;
    if (vertical) {
      t.at = o + Vector2d(bar + 1.0 * kMm + 0.5 * kLabelSize, 0.5 * len);
      t.angle_rad = -M_PI / 2;
    } else {
      t.at = o + Vector2d(0.5 * len, bar + 1.0 * kMm + 0.5 * kLabelSize);
    }
    sheet->texts.push_back(t);
    occupied->push_back(b);
    return true;
  }
  return false;
}

// A line of text somewhere free near `prefer` (skipped if nowhere).
void AddFreeText(Sheet* sheet, std::vector<Box>* occupied,
                 const std::string& text, double size, const Vector2d& prefer) {
  Box b;
  const double w = TextWidth(text, size), h = size;
  if (!PlaceBox(*sheet, *occupied, w, h, prefer, &b)) return;
  sheet->texts.push_back({b.center(), text, size, 0.0});
  occupied->push_back(b);
}

std::string Millimetres(double m) {
  char s[32];
  std::snprintf(s, sizeof(s), "%g", std::round(m * 1e4) / 10);
  return s;
}

}  // namespace

PaperSize PaperA4() { return {"a4", 0.210, 0.297}; }
PaperSize PaperLetter() { return {"letter", 0.2159, 0.2794}; }

Vector2d SheetTag::Corner(int k) const {
  static const double kSign[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  return centre_m + Rot2(angle_rad) * Vector2d(0.5 * edge_m * kSign[k][0],
                                               0.5 * edge_m * kSign[k][1]);
}

Vector3d NetFace::PenPoint(const Vector2d& on_sheet) const {
  const Vector2d d = on_sheet - centre_m;
  return 0.5 * edge_m * normal_in_pen + pen_from_page.col(0) * d.x() +
         pen_from_page.col(1) * d.y();
}

bool MakeBoardSheet(const tracking::Rig& rig, const PaperSize& paper,
                    Sheet* sheet, std::string* error) {
  return MakeBoardSheet(rig, paper, synth::FloorPattern(), sheet, error);
}

bool MakeBoardSheet(const tracking::Rig& rig, const PaperSize& paper,
                    const synth::FloorPattern& floor, Sheet* sheet,
                    std::string* error) {
  if (floor.kind() != synth::FloorKind::kPlain &&
      !(std::abs(floor.rect().sizes().x() - rig.tank.size_x_m) < 1e-9 &&
        std::abs(floor.rect().sizes().y() - rig.tank.size_y_m) < 1e-9 &&
        floor.rect().center().norm() < 1e-9)) {
    *error = "the floor pattern was not made for this rig's tank";
    return false;
  }
  FamilyInfo f;
  if (!GetFamily(rig.family, &f, error)) return false;
  if (rig.tank_tags.empty()) {
    *error = "the rig has no tank tags";
    return false;
  }
  *sheet = Sheet();
  sheet->family = rig.family;
  sheet->width_m = paper.height_m;  // landscape
  sheet->height_m = paper.width_m;
  const Vector2d centre(0.5 * sheet->width_m, 0.5 * sheet->height_m);
  auto to_sheet = [&](const Vector3d& p) {
    return Vector2d(centre.x() + p.x(), centre.y() - p.y());
  };
  // Page frame (x right, y down, z into the page) = tank (x, -y, -z).
  const Eigen::Matrix3d page_from_tank =
      Eigen::Vector3d(1, -1, -1).asDiagonal();
  std::vector<Box> occupied;
  Box all;
  const Box page(
      Vector2d(kSheetMargin, kSheetMargin),
      Vector2d(sheet->width_m - kSheetMargin, sheet->height_m - kSheetMargin));
  const double hx = 0.5 * rig.tank.size_x_m, hy = 0.5 * rig.tank.size_y_m;
  const Box tank_box = BoxOf({to_sheet({-hx, hy, 0}), to_sheet({hx, -hy, 0})});
  for (const tracking::TagPlacement& t : rig.tank_tags) {
    const Eigen::Matrix3d r = page_from_tank * t.object_from_tag.R();
    if (r(2, 2) < std::cos(1.0 * M_PI / 180) ||
        std::abs(t.object_from_tag.translation.z()) > 1e-3) {
      *error = "tank tag " + std::to_string(t.id) +
               " does not lie flat on the board (z = 0, facing up)";
      return false;
    }
    SheetTag tag;
    tag.id = t.id;
    tag.edge_m = t.edge_m;
    tag.centre_m = to_sheet(t.object_from_tag.translation);
    tag.angle_rad = std::atan2(r(1, 0), r(0, 0));
    // The id label goes below the tag image, or beside it (above it last:
    // the title needs the page's top edge) when that would print it over
    // the tank floor.
    for (const Vector2d& d :
         {Vector2d(0, 1), Vector2d(1, 0), Vector2d(-1, 0), Vector2d(0, -1)}) {
      tag.label_dir = d;
      const Box b = TagBox(tag, f);
      if (page.contains(b) && !(hx > 0 && hy > 0 && b.intersects(tank_box)))
        break;
      tag.label_dir = Vector2d(0, 1);
    }
    sheet->tags.push_back(tag);
    occupied.push_back(TagBox(tag, f));
    all.extend(occupied.back());
  }
  if (!page.contains(all)) {
    *error = "the board (" + Millimetres(all.sizes().x()) + " x " +
             Millimetres(all.sizes().y()) +
             " mm with tag margins) does not fit on " + paper.name +
             " landscape (" + Millimetres(page.sizes().x()) + " x " +
             Millimetres(page.sizes().y()) + " mm printable)";
    return false;
  }
  sheet->floor = floor;
  sheet->tank_origin_m = centre;
  // Tank outline (a guide for where the water will appear); the scale bar
  // and the title keep off the floor inside it.
  if (hx > 0 && hy > 0) {
    const Vector2d c[4] = {to_sheet({-hx, hy, 0}), to_sheet({hx, hy, 0}),
                           to_sheet({hx, -hy, 0}), to_sheet({-hx, -hy, 0})};
    for (int k = 0; k < 4; ++k)
      sheet->lines.push_back({c[k], c[(k + 1) % 4], SheetLine::Style::kGuide});
  }
  // Check points for `ripple calib check`.
  for (const CheckPoint& p : BoardCheckPoints(rig)) {
    const Vector2d s = to_sheet(p.point_in_tank);
    const double arm = 3 * kMm;
    sheet->lines.push_back(
        {s - Vector2d(arm, 0), s + Vector2d(arm, 0), SheetLine::Style::kThin});
    sheet->lines.push_back(
        {s - Vector2d(0, arm), s + Vector2d(0, arm), SheetLine::Style::kThin});
    sheet->circles.push_back({s, 1.0 * kMm, SheetLine::Style::kThin});
    sheet->texts.push_back(
        {s + Vector2d(3.5 * kMm, -2.5 * kMm), p.name, kLabelSize, 0.0});
    occupied.push_back(Box(s - Vector2d(arm, arm), s + Vector2d(arm, arm)));
    occupied.push_back(TextBox(sheet->texts.back()));
  }
  sheet->title =
      "Ripple tank board (" + rig.family + ") - " + paper.name + " landscape";
  // The scale bar off the floor where there is room (A4), else on a white
  // ground over it (Letter's narrower page).
  const Vector2d bar_at(centre.x(), sheet->height_m);
  std::vector<Box> off_floor = occupied;
  if (hx > 0 && hy > 0) off_floor.push_back(tank_box);
  if (AddScaleBar(sheet, &off_floor, bar_at)) {
    occupied = off_floor;
  } else {
    const bool on_floor = floor.kind() != synth::FloorKind::kPlain;
    if (!AddScaleBar(sheet, &occupied, bar_at, on_floor)) {
      *error = "no room for the 100 mm scale bar on " + paper.name;
      return false;
    }
    if (hx > 0 && hy > 0) occupied.push_back(tank_box);
  }
  AddFreeText(sheet, &occupied,
              sheet->title + " - print at 100 % (no fit to page)", kLabelSize,
              Vector2d(centre.x(), 0));
  return true;
}

bool MakeCubeNetSheet(const tracking::Rig& rig, const PaperSize& paper,
                      Sheet* sheet, std::vector<NetFace>* faces,
                      std::string* error) {
  FamilyInfo f;
  if (!GetFamily(rig.family, &f, error)) return false;
  if (!rig.pen || rig.pen->faces.empty() || !(rig.pen->cube_edge_m > 0)) {
    *error = "the rig has no pen cube";
    return false;
  }
  const tracking::PenSpec& pen = *rig.pen;
  const double a = pen.cube_edge_m;
  // Which cube side each tag sits on (outward normal = -tag z).
  const Vector3d axes[6] = {Vector3d::UnitX(), -Vector3d::UnitX(),
                            Vector3d::UnitY(), -Vector3d::UnitY(),
                            Vector3d::UnitZ(), -Vector3d::UnitZ()};
  int tag_on_side[6] = {-1, -1, -1, -1, -1, -1};
  std::map<int, const tracking::TagPlacement*> by_id;
  for (const tracking::TagPlacement& t : pen.faces) {
    const Vector3d normal = -t.object_from_tag.R().col(2);
    int side = -1;
    for (int s = 0; s < 6; ++s)
      if (normal.dot(axes[s]) > std::cos(10 * M_PI / 180)) side = s;
    if (side < 0 || tag_on_side[side] >= 0) {
      *error = "pen face " + std::to_string(t.id) +
               (side < 0 ? " does not face along a cube axis"
                         : " shares a cube side with face " +
                               std::to_string(tag_on_side[side]));
      return false;
    }
    tag_on_side[side] = t.id;
    by_id[t.id] = &t;
  }
  // Centre of the cross: opposite the untagged (pen) side, else +z.
  int centre_side = 4;
  for (int s = 0; s < 6; ++s)
    if (tag_on_side[s] < 0) {
      centre_side = s ^ 1;
      break;
    }
  NetFace c;
  c.edge_m = a;
  c.normal_in_pen = axes[centre_side];
  c.tag_id = tag_on_side[centre_side];
  if (c.tag_id >= 0) {
    c.pen_from_page = by_id[c.tag_id]->object_from_tag.R();
  } else {
    const Vector3d w = -c.normal_in_pen;
    const Vector3d u = std::abs(w.x()) < 0.9 ? Vector3d::UnitX().cross(w)
                                             : Vector3d::UnitY().cross(w);
    c.pen_from_page.col(0) = u.normalized();
    c.pen_from_page.col(2) = w;
    c.pen_from_page.col(1) = w.cross(c.pen_from_page.col(0));
  }
  // Rolling the cube one face along page direction d (see DESIGN: the flap
  // folds away from the printed side).
  auto roll = [&](const NetFace& from, const Vector2d& d) {
    NetFace to = from;
    const Vector3d dir =
        from.pen_from_page.col(0) * d.x() + from.pen_from_page.col(1) * d.y();
    const Vector3d axis = from.normal_in_pen.cross(dir);
    to.pen_from_page =
        Eigen::AngleAxisd(M_PI / 2, axis.normalized()).toRotationMatrix() *
        from.pen_from_page;
    to.normal_in_pen = dir;
    to.centre_m = from.centre_m + a * d;
    to.tag_id = -1;
    for (int s = 0; s < 6; ++s)
      if (dir.dot(axes[s]) > 0.5) to.tag_id = tag_on_side[s];
    return to;
  };
  // Cross: centre (1,1); up, left, right, down; the tail below the down face.
  *sheet = Sheet();
  sheet->family = rig.family;
  sheet->width_m = paper.width_m;
  sheet->height_m = paper.height_m;
  const Vector2d origin(0.5 * sheet->width_m - 1.5 * a, 0.035);
  c.centre_m = origin + a * Vector2d(1.5, 1.5);
  faces->clear();
  faces->push_back(c);
  faces->push_back(roll(c, {0, -1}));
  faces->push_back(roll(c, {-1, 0}));
  faces->push_back(roll(c, {1, 0}));
  faces->push_back(roll(c, {0, 1}));
  faces->push_back(roll(faces->back(), {0, 1}));

  std::vector<Box> occupied;
  // Edges: shared ones fold; open ones pair up (same cube edge) and one of
  // each pair carries a glue tab.
  const Vector2d dirs[4] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};
  auto has_face_at = [&](const Vector2d& p) {
    for (const NetFace& nf : *faces)
      if ((nf.centre_m - p).norm() < 1e-6) return true;
    return false;
  };
  std::vector<std::pair<Vector3d, int>> tabbed_edges;  // 3D midpoint, face
  const double tab = std::min(0.3 * a, 0.008);
  std::map<int, std::vector<Vector2d>> open_dirs;  // face index -> dirs
  for (size_t i = 0; i < faces->size(); ++i) {
    const NetFace& nf = (*faces)[i];
    for (const Vector2d& d : dirs) {
      const Vector2d perp(-d.y(), d.x());
      const Vector2d p0 = nf.centre_m + 0.5 * a * (d + perp);
      const Vector2d p1 = nf.centre_m + 0.5 * a * (d - perp);
      if (has_face_at(nf.centre_m + a * d)) {
        // Draw each shared fold once.
        if (d.x() > 0 || d.y() > 0)
          sheet->lines.push_back({p0, p1, SheetLine::Style::kFold});
        continue;
      }
      open_dirs[i].push_back(d);
      const Vector3d mid = nf.PenPoint(0.5 * (p0 + p1));
      bool partner_has_tab = false;
      for (const auto& [m, face] : tabbed_edges)
        partner_has_tab |= (m - mid).norm() < 1e-6;
      if (partner_has_tab) {
        sheet->lines.push_back({p0, p1, SheetLine::Style::kCut});
        continue;
      }
      tabbed_edges.push_back({mid, static_cast<int>(i)});
      const Vector2d q0 = p0 + tab * d - tab * perp;
      const Vector2d q1 = p1 + tab * d + tab * perp;
      sheet->lines.push_back({p0, p1, SheetLine::Style::kFold});
      sheet->lines.push_back({p0, q0, SheetLine::Style::kCut});
      sheet->lines.push_back({q0, q1, SheetLine::Style::kCut});
      sheet->lines.push_back({q1, p1, SheetLine::Style::kCut});
      occupied.push_back(BoxOf({p0, p1, q0, q1}));
    }
  }
  // Tags, with their id just outside their face on an open edge (the
  // tag and its white margin usually fill the face).
  for (size_t i = 0; i < faces->size(); ++i) {
    const NetFace& nf = (*faces)[i];
    occupied.push_back(Box(nf.centre_m - Vector2d(0.5 * a, 0.5 * a),
                           nf.centre_m + Vector2d(0.5 * a, 0.5 * a)));
    if (nf.tag_id < 0) {
      sheet->circles.push_back({nf.centre_m,
                                std::max(pen.shaft_radius_m, 0.001),
                                SheetLine::Style::kCut});
      sheet->texts.push_back({nf.centre_m + Vector2d(0, 0.3 * a),
                              "pen side: cut the hole", kLabelSize, 0.0});
      continue;
    }
    const tracking::TagPlacement& t = *by_id[nf.tag_id];
    const Eigen::Matrix3d page_from_pen = nf.pen_from_page.transpose();
    const Vector3d in_page = page_from_pen * (t.object_from_tag.translation -
                                              0.5 * a * nf.normal_in_pen);
    const Eigen::Matrix3d r = page_from_pen * t.object_from_tag.R();
    SheetTag tag;
    tag.id = t.id;
    tag.edge_m = t.edge_m;
    tag.centre_m = nf.centre_m + in_page.head<2>();
    tag.angle_rad = std::atan2(r(1, 0), r(0, 0));
    // Label direction (tag image coordinates) pointing at an open edge,
    // preferring below the tag; placed beyond the face edge. A face with no
    // open edge (the middle of the cross) gets a free-standing label.
    const Eigen::Matrix2d page_from_tag2 = Rot2(tag.angle_rad);
    tag.label_dir.setZero();
    for (const Vector2d& d_tag :
         {Vector2d(0, 1), Vector2d(0, -1), Vector2d(1, 0), Vector2d(-1, 0)}) {
      const Vector2d d_page = page_from_tag2 * d_tag;
      bool open = false;
      for (const Vector2d& od : open_dirs[i])
        open |= (od - d_page).norm() < 1e-6;
      if (!open) continue;
      tag.label_dir = d_tag;
      const double half = 0.5 * f.total * t.edge_m / f.border;
      const double to_edge = 0.5 * a - d_page.dot(in_page.head<2>());
      tag.label_offset_m = std::max(0.0, to_edge - half) + 0.4 * kMm;
      break;
    }
    sheet->tags.push_back(tag);
  }
  sheet->title = "Ripple pen cube net (" + Millimetres(a) + " mm cube, " +
                 rig.family + ") - " + paper.name;
  for (const SheetTag& tag : sheet->tags)
    if (!tag.label_dir.isZero()) occupied.push_back(TagBox(tag, f));
  for (const SheetTag& tag : sheet->tags) {
    if (!tag.label_dir.isZero()) continue;
    const NetFace* nf = nullptr;
    for (const NetFace& face : *faces)
      if (face.tag_id == tag.id) nf = &face;
    AddFreeText(sheet, &occupied,
                "id " + std::to_string(tag.id) + " (the face here)", kLabelSize,
                nf->centre_m + Vector2d(-a, a));
    if (!sheet->lines.empty()) {
      // A leader from the label to the face's corner.
      const SheetText& t = sheet->texts.back();
      sheet->lines.push_back({t.at + Vector2d(0, -0.6 * kLabelSize),
                              nf->centre_m + Vector2d(-0.5 * a, 0.5 * a),
                              SheetLine::Style::kThin});
    }
  }
  Box net;
  for (const Box& b : occupied) net.extend(b);
  occupied.assign(1, net);
  AddFreeText(sheet, &occupied, sheet->title, kTextSize,
              Vector2d(0.5 * sheet->width_m, 0));
  AddFreeText(sheet, &occupied,
              "Cut the solid lines, fold the dashed lines away from you, glue "
              "the tabs inside.",
              kLabelSize, Vector2d(0.5 * sheet->width_m, net.max().y() + 0.01));
  AddFreeText(sheet, &occupied,
              "Print at 100 % (no fit to page). Ids are printed beside their "
              "faces.",
              kLabelSize, Vector2d(0.5 * sheet->width_m, net.max().y() + 0.01));
  if (!AddScaleBar(sheet, &occupied,
                   Vector2d(0.5 * sheet->width_m, net.max().y() + 0.03))) {
    *error = "no room for the 100 mm scale bar on " + paper.name;
    return false;
  }
  return true;
}

bool MakeChessboardSheet(int cols, int rows, double square_m,
                         const PaperSize& paper, Sheet* sheet,
                         std::string* error) {
  if (cols < 2 || rows < 2 || !(square_m > 0)) {
    *error = "chessboard needs at least 2x2 inner corners and a square > 0";
    return false;
  }
  *sheet = Sheet();
  sheet->width_m = paper.height_m;  // landscape
  sheet->height_m = paper.width_m;
  const double w = (cols + 1) * square_m, h = (rows + 1) * square_m;
  // The paper around the board is its white border (the detector needs some
  // quiet zone: at least the printer margin).
  if (w + 2 * kSheetMargin > sheet->width_m ||
      h + 2 * kSheetMargin > sheet->height_m) {
    *error = "a " + std::to_string(cols) + "x" + std::to_string(rows) +
             " chessboard of " + Millimetres(square_m) +
             " mm squares does not fit on " + paper.name;
    return false;
  }
  const Vector2d o(0.5 * (sheet->width_m - w), 0.5 * (sheet->height_m - h));
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= cols; ++c)
      if ((r + c) % 2 == 0)
        sheet->black_boxes.emplace_back(o + square_m * Vector2d(c, r),
                                        o + square_m * Vector2d(c + 1, r + 1));
  const Vector2d pad(2 * kMm, 2 * kMm);
  std::vector<Box> occupied = {Box(o - pad, o + Vector2d(w, h) + pad)};
  sheet->title = "Ripple calibration chessboard: " + std::to_string(cols) +
                 "x" + std::to_string(rows) + " inner corners, " +
                 Millimetres(square_m) + " mm squares (--chessboard " +
                 std::to_string(cols) + "x" + std::to_string(rows) +
                 " --square " + std::to_string(square_m) + ")";
  if (!AddScaleBar(sheet, &occupied,
                   Vector2d(sheet->width_m, 0.5 * sheet->height_m))) {
    *error = "no room for the 100 mm scale bar on " + paper.name;
    return false;
  }
  AddFreeText(sheet, &occupied, sheet->title, kLabelSize,
              Vector2d(0.5 * sheet->width_m, 0));
  return true;
}

}  // namespace ripple::calib
