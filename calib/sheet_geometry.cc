#include "calib/sheet_geometry.h"

#include <cmath>

#include "tracking/tag_family.h"

namespace ripple::calib::sheet {

using Eigen::Vector2d;

Eigen::Matrix2d Rot2(double a) {
  Eigen::Matrix2d r;
  r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return r;
}

double TextWidth(const std::string& s, double size) {
  return 0.56 * size * s.size();
}

Box BoxOf(std::initializer_list<Vector2d> points) {
  Box b;
  for (const Vector2d& p : points) b.extend(p);
  return b;
}

Box TextBox(const SheetText& t) {
  const Eigen::Matrix2d r = Rot2(t.angle_rad);
  const double hw = 0.5 * TextWidth(t.text, t.size_m), hh = 0.5 * t.size_m;
  return BoxOf({t.at + r * Vector2d(-hw, -hh), t.at + r * Vector2d(hw, -hh),
                t.at + r * Vector2d(hw, hh), t.at + r * Vector2d(-hw, hh)});
}

bool GetFamily(const std::string& name, FamilyInfo* info, std::string* error) {
  auto family = tracking::TagFamily::Create(name);
  if (!family) {
    *error = "unknown tag family '" + name + "'";
    return false;
  }
  info->total = family->total_width();
  info->border = family->width_at_border();
  return true;
}

SheetText TagLabel(const SheetTag& tag, const FamilyInfo& f) {
  const double cell = tag.edge_m / f.border;
  const double half = 0.5 * f.total * cell;
  const Vector2d dir = tag.label_dir.normalized();
  SheetText t;
  t.text = "id " + std::to_string(tag.id);
  t.size_m = kLabelSize;
  const double along = std::abs(dir.x()) > 0.5
                           ? 0.5 * TextWidth(t.text, t.size_m)
                           : 0.5 * t.size_m;
  t.at = tag.centre_m +
         Rot2(tag.angle_rad) *
             (dir * (half + 0.6 * kMm + tag.label_offset_m + along));
  t.angle_rad = tag.angle_rad;
  return t;
}

Box TagBox(const SheetTag& tag, const FamilyInfo& f) {
  const double half = 0.5 * f.total * tag.edge_m / f.border;
  const Eigen::Matrix2d r = Rot2(tag.angle_rad);
  Box b = BoxOf({tag.centre_m + r * Vector2d(-half, -half),
                 tag.centre_m + r * Vector2d(half, -half),
                 tag.centre_m + r * Vector2d(half, half),
                 tag.centre_m + r * Vector2d(-half, half)});
  if (!tag.label_dir.isZero()) b.extend(TextBox(TagLabel(tag, f)));
  return b;
}

}  // namespace ripple::calib::sheet
