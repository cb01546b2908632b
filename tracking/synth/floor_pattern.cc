#include "tracking/synth/floor_pattern.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/synth/image_file.h"
#include "tracking/synth/raster.h"
#include "tracking/tag_family.h"

namespace ripple::synth {

const cv::Vec3f kPaperBgr(0.88f, 0.88f, 0.86f);
const cv::Vec3f kInkBgr(0.05f, 0.05f, 0.05f);
const cv::Vec3f kTableBgr(0.22f, 0.33f, 0.45f);

namespace {

using Box = Eigen::AlignedBox2d;
using Eigen::Vector2d;

constexpr int kMaxImageSide = 16384;

// sRGB decoding (IEC 61966-2-1).
float SrgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

bool InUnitRange(const cv::Vec3f& c) {
  for (int i = 0; i < 3; ++i)
    if (!(c[i] >= 0 && c[i] <= kPaperBgr[i] + 1e-6f)) return false;
  return true;
}

}  // namespace

const char* ToString(FloorKind kind) {
  switch (kind) {
    case FloorKind::kPlain:
      return "plain";
    case FloorKind::kTiles:
      return "tiles";
    case FloorKind::kImage:
      return "image";
  }
  return "?";
}

bool FloorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (kind == FloorKind::kTiles) {
    if (!(tile_m >= 5e-4 && tile_m <= 1.0))
      return fail("floor tile pitch must be in [0.5 mm, 1 m]");
    if (!(grout_m >= 0 && grout_m < tile_m))
      return fail("floor grout width must be in [0, tile pitch)");
    if (!InUnitRange(grout_bgr) || !InUnitRange(tile_a_bgr) ||
        !InUnitRange(tile_b_bgr))
      return fail(
          "floor reflectances must be in [0, 1] and at most the paper's");
  }
  if (kind == FloorKind::kImage && image_path.empty())
    return fail("the image floor needs an image file");
  return true;
}

struct FloorPattern::Impl {
  FloorOptions options;
  Box rect;
  // kImage: the file as read, and its linear albedo at levels of detail
  // (level 0 the file's texels, each next level a 2x2 box average).
  cv::Mat bgr8;
  std::vector<cv::Mat> levels;

  // Tile (i, j) centred at (i, j) * pitch: its interior inside the grout.
  Box TileInterior(int i, int j) const {
    const double p = options.tile_m, h = 0.5 * (p - options.grout_m);
    return Box(Vector2d(i * p - h, j * p - h), Vector2d(i * p + h, j * p + h));
  }
  const cv::Vec3f& TileColour(int i, int j) const {
    return ((i + j) % 2 == 0) ? options.tile_a_bgr : options.tile_b_bgr;
  }
  // Level whose texel is at least `detail_m` on both axes (the coarsest when
  // none is).
  int LevelFor(double detail_m) const {
    int l = 0;
    while (l + 1 < static_cast<int>(levels.size())) {
      const cv::Mat& m = levels[l];
      const double tx = rect.sizes().x() / m.cols,
                   ty = rect.sizes().y() / m.rows;
      if (std::min(tx, ty) >= detail_m) break;
      ++l;
    }
    return l;
  }
};

FloorPattern::FloorPattern() {
  auto impl = std::make_shared<Impl>();
  impl->options.kind = FloorKind::kPlain;
  impl_ = std::move(impl);
}

std::optional<FloorPattern> FloorPattern::Create(const FloorOptions& options,
                                                 double size_x_m,
                                                 double size_y_m,
                                                 std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  if (!(size_x_m > 0 && size_y_m > 0 && std::isfinite(size_x_m) &&
        std::isfinite(size_y_m))) {
    *error = "the floor needs a tank of positive size";
    return std::nullopt;
  }
  auto impl = std::make_shared<Impl>();
  impl->options = options;
  impl->rect = Box(Vector2d(-0.5 * size_x_m, -0.5 * size_y_m),
                   Vector2d(0.5 * size_x_m, 0.5 * size_y_m));
  if (options.kind == FloorKind::kImage) {
    const std::string& path = options.image_path;
    std::string why;
    const cv::Mat img = ReadImageFile(path, cv::IMREAD_COLOR, &why);
    if (img.empty()) {
      *error = "floor image '" + path + "': " + why;
      return std::nullopt;
    }
    if (img.cols > kMaxImageSide || img.rows > kMaxImageSide) {
      *error = "floor image '" + path + "': " + std::to_string(img.cols) + "x" +
               std::to_string(img.rows) + " is larger than " +
               std::to_string(kMaxImageSide) + " px on a side";
      return std::nullopt;
    }
    impl->bgr8 = img;
    float lut[256];
    for (int v = 0; v < 256; ++v) lut[v] = SrgbToLinear(v / 255.0f);
    cv::Mat level(img.size(), CV_32FC3);
    for (int r = 0; r < img.rows; ++r) {
      const cv::Vec3b* in = img.ptr<cv::Vec3b>(r);
      cv::Vec3f* out = level.ptr<cv::Vec3f>(r);
      for (int c = 0; c < img.cols; ++c)
        for (int k = 0; k < 3; ++k) out[c][k] = kPaperBgr[k] * lut[in[c][k]];
    }
    impl->levels.push_back(level);
    while (level.cols > 1 || level.rows > 1) {
      cv::Mat next;
      cv::resize(level, next,
                 cv::Size((level.cols + 1) / 2, (level.rows + 1) / 2), 0, 0,
                 cv::INTER_AREA);
      impl->levels.push_back(next);
      level = next;
    }
  }
  FloorPattern pattern;
  pattern.impl_ = std::move(impl);
  return pattern;
}

std::optional<FloorPattern> FloorPattern::Create(const FloorOptions& options,
                                                 const tracking::TankSpec& tank,
                                                 std::string* error) {
  return Create(options, tank.size_x_m, tank.size_y_m, error);
}

FloorKind FloorPattern::kind() const { return impl_->options.kind; }
const FloorOptions& FloorPattern::options() const { return impl_->options; }
const Box& FloorPattern::rect() const { return impl_->rect; }
const cv::Mat& FloorPattern::image_bgr8() const { return impl_->bgr8; }

cv::Vec3f FloorPattern::AlbedoAt(const Vector2d& p) const {
  const Impl& m = *impl_;
  if (m.options.kind == FloorKind::kPlain || m.rect.isEmpty() ||
      !m.rect.contains(p))
    return kPaperBgr;
  if (m.options.kind == FloorKind::kTiles) {
    const double pitch = m.options.tile_m;
    const int i = static_cast<int>(std::floor(p.x() / pitch + 0.5));
    const int j = static_cast<int>(std::floor(p.y() / pitch + 0.5));
    return m.TileInterior(i, j).contains(p) ? m.TileColour(i, j)
                                            : m.options.grout_bgr;
  }
  const cv::Mat& l0 = m.levels[0];
  const Vector2d s = m.rect.sizes();
  const int c =
      std::clamp(static_cast<int>((p.x() - m.rect.min().x()) / s.x() * l0.cols),
                 0, l0.cols - 1);
  const int r =
      std::clamp(static_cast<int>((m.rect.max().y() - p.y()) / s.y() * l0.rows),
                 0, l0.rows - 1);
  return l0.at<cv::Vec3f>(r, c);
}

cv::Vec3d FloorPattern::Integrate(const Box& bounds, double detail_m,
                                  RectMeasure measure, double* covered) const {
  *covered = 0;
  const Impl& m = *impl_;
  if (m.rect.isEmpty()) return cv::Vec3d(0, 0, 0);
  const Box clip = bounds.intersection(m.rect);
  if (clip.isEmpty() || clip.sizes().minCoeff() <= 0) return cv::Vec3d(0, 0, 0);
  const Box& f = m.rect;
  const double inside =
      measure(f.min().x(), f.min().y(), f.max().x(), f.max().y());
  *covered = inside;
  if (inside <= 0) return cv::Vec3d(0, 0, 0);
  switch (m.options.kind) {
    case FloorKind::kPlain:
      return cv::Vec3d(kPaperBgr) * inside;
    case FloorKind::kTiles: {
      cv::Vec3d sum = cv::Vec3d(m.options.grout_bgr) * inside;
      const double pitch = m.options.tile_m;
      const int i0 = static_cast<int>(std::floor(clip.min().x() / pitch + 0.5));
      const int i1 = static_cast<int>(std::floor(clip.max().x() / pitch + 0.5));
      const int j0 = static_cast<int>(std::floor(clip.min().y() / pitch + 0.5));
      const int j1 = static_cast<int>(std::floor(clip.max().y() / pitch + 0.5));
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const Box t = m.TileInterior(i, j).intersection(f);
          if (t.isEmpty() || t.sizes().minCoeff() <= 0 || !t.intersects(clip))
            continue;
          const double a =
              measure(t.min().x(), t.min().y(), t.max().x(), t.max().y());
          if (a > 0)
            sum += (cv::Vec3d(m.TileColour(i, j)) -
                    cv::Vec3d(m.options.grout_bgr)) *
                   a;
        }
      }
      return sum;
    }
    case FloorKind::kImage: {
      const cv::Mat& level = m.levels[m.LevelFor(detail_m)];
      const double tx = f.sizes().x() / level.cols,
                   ty = f.sizes().y() / level.rows;
      // Columns run with x from the floor's left edge, rows down from its
      // top (+y) edge.
      const int c0 = std::max(
          0, static_cast<int>(std::floor((clip.min().x() - f.min().x()) / tx)));
      const int c1 = std::min(
          level.cols - 1,
          static_cast<int>(std::floor((clip.max().x() - f.min().x()) / tx)));
      const int r0 = std::max(
          0, static_cast<int>(std::floor((f.max().y() - clip.max().y()) / ty)));
      const int r1 = std::min(
          level.rows - 1,
          static_cast<int>(std::floor((f.max().y() - clip.min().y()) / ty)));
      cv::Vec3d sum(0, 0, 0);
      for (int r = r0; r <= r1; ++r) {
        const double y1 = f.max().y() - r * ty, y0 = y1 - ty;
        const cv::Vec3f* row = level.ptr<cv::Vec3f>(r);
        for (int c = c0; c <= c1; ++c) {
          const double x0 = f.min().x() + c * tx;
          const double a = measure(x0, y0, x0 + tx, y1);
          if (a > 0) sum += cv::Vec3d(row[c]) * a;
        }
      }
      return sum;
    }
  }
  return cv::Vec3d(0, 0, 0);
}

cv::Vec3f FloorPattern::AverageOver(const Box& box) const {
  const double area = box.isEmpty() ? 0.0 : box.volume();
  if (!(area > 0)) return AlbedoAt(box.center());
  auto rect_area = [&box](double x0, double y0, double x1, double y1) {
    const double w = std::min(x1, box.max().x()) - std::max(x0, box.min().x());
    const double h = std::min(y1, box.max().y()) - std::max(y0, box.min().y());
    return w > 0 && h > 0 ? w * h : 0.0;
  };
  double covered = 0;
  const cv::Vec3d sum =
      Integrate(box, 0.25 * box.sizes().maxCoeff(), rect_area, &covered);
  return cv::Vec3f((sum + cv::Vec3d(kPaperBgr) * (area - covered)) *
                   (1.0 / area));
}

std::vector<FloorPattern::Cell> FloorPattern::TileCells() const {
  const Impl& m = *impl_;
  std::vector<Cell> cells;
  if (m.options.kind != FloorKind::kTiles || m.rect.isEmpty()) return cells;
  cells.push_back({m.rect, m.options.grout_bgr});
  const double pitch = m.options.tile_m;
  const int i0 = static_cast<int>(std::floor(m.rect.min().x() / pitch + 0.5));
  const int i1 = static_cast<int>(std::floor(m.rect.max().x() / pitch + 0.5));
  const int j0 = static_cast<int>(std::floor(m.rect.min().y() / pitch + 0.5));
  const int j1 = static_cast<int>(std::floor(m.rect.max().y() / pitch + 0.5));
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const Box t = m.TileInterior(i, j).intersection(m.rect);
      if (t.isEmpty() || t.sizes().minCoeff() <= 0) continue;
      cells.push_back({t, m.TileColour(i, j)});
    }
  }
  return cells;
}

namespace {

cv::Size AlbedoImageSize(const Box& rect, double px_per_m) {
  CV_Assert(px_per_m > 0 && !rect.isEmpty());
  return cv::Size(
      std::max(1, static_cast<int>(std::lround(rect.sizes().x() * px_per_m))),
      std::max(1, static_cast<int>(std::lround(rect.sizes().y() * px_per_m))));
}

Box PixelBox(const Box& rect, double px_per_m, int col, int row) {
  const Vector2d lo = rect.min() + Vector2d(col, row) / px_per_m;
  return Box(lo, lo + Vector2d::Constant(1.0 / px_per_m));
}

}  // namespace

cv::Mat RenderFloorAlbedo(const FloorPattern& floor, const Box& rect_in_tank_m,
                          double px_per_m) {
  const cv::Size size = AlbedoImageSize(rect_in_tank_m, px_per_m);
  cv::Mat out(size, CV_32FC3);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int r = rows.start; r < rows.end; ++r) {
      cv::Vec3f* row = out.ptr<cv::Vec3f>(r);
      for (int c = 0; c < size.width; ++c)
        row[c] = floor.AverageOver(PixelBox(rect_in_tank_m, px_per_m, c, r));
    }
  });
  return out;
}

Box BoardSheetRect(const tracking::Rig& rig) {
  Box b;
  for (const tracking::TagPlacement& t : rig.tank_tags)
    for (int k = 0; k < 4; ++k)
      b.extend(Vector2d(t.CornerInObject(k).head<2>()));
  const Vector2d half(0.5 * rig.tank.size_x_m, 0.5 * rig.tank.size_y_m);
  b.extend(-half);
  b.extend(half);
  const Vector2d margin(0.02, 0.02);
  return Box(b.min() - margin, b.max() + margin);
}

cv::Mat RenderBoardAlbedo(const tracking::Rig& rig, const FloorPattern& floor,
                          const Box& rect_in_tank_m, double px_per_m) {
  const cv::Size size = AlbedoImageSize(rect_in_tank_m, px_per_m);
  const Box sheet = BoardSheetRect(rig);
  // Each tag as its cells in its own frame, and its 2D pose on the board.
  struct FlatTag {
    Eigen::Matrix2d r_tag_from_tank;
    Vector2d t_tag_from_tank;
    Box box_in_tank;  // the printed square with its margin
    double half = 0, cell = 0;
    int n = 0;
    std::vector<uint8_t> black;
  };
  std::vector<FlatTag> tags;
  const auto family = tracking::TagFamily::Create(rig.family);
  for (const tracking::TagPlacement& t : rig.tank_tags) {
    if (!family) break;
    const auto bitmap = tracking::MakeTagBitmap(*family, t.id);
    if (!bitmap) continue;
    FlatTag f;
    f.n = bitmap->total_width;
    f.cell = t.edge_m / bitmap->width_at_border;
    f.half = 0.5 * f.n * f.cell;
    f.black.resize(size_t(f.n) * f.n);
    for (int r = 0; r < f.n; ++r)
      for (int c = 0; c < f.n; ++c) f.black[r * f.n + c] = bitmap->black(r, c);
    const tracking::Pose tag_from_tank = t.object_from_tag.Inverse();
    f.r_tag_from_tank = tag_from_tank.R().topLeftCorner<2, 2>();
    f.t_tag_from_tank = tag_from_tank.translation.head<2>();
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0})
        f.box_in_tank.extend(Vector2d(
            (t.object_from_tag * Eigen::Vector3d(sx * f.half, sy * f.half, 0))
                .head<2>()));
    tags.push_back(std::move(f));
  }
  cv::Mat out(size, CV_32FC3);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int r = rows.start; r < rows.end; ++r) {
      cv::Vec3f* row = out.ptr<cv::Vec3f>(r);
      for (int c = 0; c < size.width; ++c) {
        const Box px = PixelBox(rect_in_tank_m, px_per_m, c, r);
        const double area = px.volume();
        // Table, paper and floor.
        const Box on_sheet = px.intersection(sheet);
        const double paper_area =
            on_sheet.isEmpty() ? 0.0 : std::max(0.0, on_sheet.volume());
        cv::Vec3d v = cv::Vec3d(kTableBgr) * ((area - paper_area) / area);
        if (paper_area > 0)
          v += cv::Vec3d(floor.AverageOver(on_sheet)) * (paper_area / area);
        // Tags on top: margin in paper, black cells in ink.
        for (const FlatTag& t : tags) {
          if (!t.box_in_tank.intersects(px)) continue;
          Vector2d quad[4];
          const Vector2d corners[4] = {
              px.corner(Box::BottomLeft), px.corner(Box::BottomRight),
              px.corner(Box::TopRight), px.corner(Box::TopLeft)};
          Box qbox;
          for (int k = 0; k < 4; ++k) {
            quad[k] = t.r_tag_from_tank * corners[k] + t.t_tag_from_tank;
            qbox.extend(quad[k]);
          }
          const double margin =
              QuadRectArea(quad, -t.half, -t.half, t.half, t.half) / area;
          if (margin <= 0) continue;
          v = v * (1.0 - margin) + cv::Vec3d(kPaperBgr) * margin;
          const int c0 = std::max(
              0,
              static_cast<int>(std::floor((qbox.min().x() + t.half) / t.cell)));
          const int c1 = std::min(
              t.n - 1,
              static_cast<int>(std::floor((qbox.max().x() + t.half) / t.cell)));
          const int r0 = std::max(
              0,
              static_cast<int>(std::floor((qbox.min().y() + t.half) / t.cell)));
          const int r1 = std::min(
              t.n - 1,
              static_cast<int>(std::floor((qbox.max().y() + t.half) / t.cell)));
          const cv::Vec3d delta = cv::Vec3d(kInkBgr) - cv::Vec3d(kPaperBgr);
          for (int tr = r0; tr <= r1; ++tr)
            for (int tc = c0; tc <= c1; ++tc) {
              if (!t.black[tr * t.n + tc]) continue;
              const double x0 = -t.half + tc * t.cell,
                           y0 = -t.half + tr * t.cell;
              v +=
                  delta *
                  (QuadRectArea(quad, x0, y0, x0 + t.cell, y0 + t.cell) / area);
            }
        }
        row[c] = cv::Vec3f(v);
      }
    }
  });
  return out;
}

void BoardDesignLevels(const tracking::Rig& rig, const FloorPattern& floor,
                       const Eigen::Vector2d& corner_m, double texel_m,
                       cv::Size size, bool srgb, cv::Mat* levels,
                       cv::Mat* valid) {
  const Box rect(corner_m,
                 corner_m + texel_m * Vector2d(size.width, size.height));
  cv::Mat albedo = RenderBoardAlbedo(rig, floor, rect, 1.0 / texel_m);
  if (albedo.size() != size) cv::resize(albedo, albedo, size);
  const Box sheet = BoardSheetRect(rig);
  levels->create(size, CV_32FC3);
  valid->create(size, CV_8U);
  auto encode = [srgb](float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    if (!srgb) return 255.0f * v;
    return 255.0f * (v <= 0.0031308f
                         ? 12.92f * v
                         : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f);
  };
  for (int r = 0; r < size.height; ++r) {
    const cv::Vec3f* a = albedo.ptr<cv::Vec3f>(r);
    cv::Vec3f* out = levels->ptr<cv::Vec3f>(r);
    std::uint8_t* v = valid->ptr(r);
    const double y = corner_m.y() + texel_m * (r + 0.5);
    for (int c = 0; c < size.width; ++c) {
      const double x = corner_m.x() + texel_m * (c + 0.5);
      for (int k = 0; k < 3; ++k) out[c][k] = encode(a[c][k] / kPaperBgr[k]);
      v[c] = sheet.contains(Vector2d(x, y)) ? 255 : 0;
    }
  }
}

}  // namespace ripple::synth
