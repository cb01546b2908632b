#include "tracking/synth/synth.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "geometry/check.h"
#include "geometry/polygon2d.h"
#include "tracking/synth/raster.h"
#include "tracking/tag_family.h"

namespace ripple::synth {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// Reflectances (linear BGR) of the materials in the scene.
const cv::Vec3f& kPaper = kPaperBgr;
const cv::Vec3f& kInk = kInkBgr;
const cv::Vec3f& kTable = kTableBgr;
const cv::Vec3f kCube(0.80f, 0.80f, 0.78f);
const cv::Vec3f kShaft(0.16f, 0.14f, 0.12f);
// Light direction in the tank frame (from the surface toward the light).
const Vector3d kLightInTank = Vector3d(0.3, 0.4, 1.0).normalized();

// A rectangle of a planar layer's (x, y) plane with a colour.
struct CellRect {
  double x0, y0, x1, y1;
};

// A tag's cells in its own frame: a grid of `n` x `n` cells of size `cell`
// starting at (origin, origin); black cells are marked.
struct TagCells {
  int id = -1;
  int n = 0;
  double cell = 0;
  double origin = 0;
  std::vector<uint8_t> black;
};

// What a planar layer paints in its own frame's z = 0 plane: a rectangle of
// `base` colour (optionally over an infinite `outside` colour) and a tag's
// black cells on top, or the floor pattern (in the tank frame) over its own
// rectangle.
struct PlanarLayer {
  Pose cam_from_plane;
  CellRect rect{0, 0, 0, 0};
  bool infinite = false;  // paint `outside` everywhere else too
  cv::Vec3f base, outside;
  const TagCells* tag = nullptr;
  const FloorPattern* floor = nullptr;
  // Illumination: a constant, or the board's soft spotlight when `board`.
  float shade = 1.0f;
  bool board = false;
};

float BoardShade(double x, double y) {
  const double dx = x - 0.04, dy = y - 0.03;
  return static_cast<float>(1.0 -
                            0.25 * std::min(1.0, (dx * dx + dy * dy) / 0.16));
}

bool PointInPolygon(const std::vector<Vector2d>& poly, const Vector2d& p) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) /
                        (poly[j].y() - poly[i].y()) +
                    poly[i].x())
      inside = !inside;
  }
  return inside;
}

// Share of a disc covered by a half-plane whose edge lies `x` disc radii
// from the disc's centre (x > 0: the centre outside the half-plane).
double DiscCovered(double x) {
  if (x <= -1) return 1.0;
  if (x >= 1) return 0.0;
  return (std::acos(x) - x * std::sqrt(1 - x * x)) / M_PI;
}

// The pen's shadow on the board plane z = 0 under a distant light of angular
// radius `radius_rad`. Works in the light's view: points are projected along
// the light onto a plane perpendicular to it, where the shaft (the cylinder
// the renderer draws: flat ends at the tip and `shaft_length_m` up the axis)
// is the convex hull of its two end circles and the cube the hull of its
// corners. A board point sees the light's disc as a disc of radius
// s tan(radius) at an occluder s metres up the ray (plus the pixel's
// footprint); the hidden share is the part of that disc behind the
// outline's nearest edge (taken as straight).
class PenShadow {
 public:
  PenShadow(const tracking::PenSpec& pen, const Pose& tank_from_pen,
            const Vector3d& light_in_tank, double radius_rad)
      : light_(light_in_tank.normalized()),
        tan_radius_(std::tan(std::max(0.0, radius_rad))) {
    e1_ = light_.unitOrthogonal();
    e2_ = light_.cross(e1_);
    const Vector3d tip = pen.tip_in_pen;
    const Vector3d axis = (-tip).normalized();  // tip -> cube
    const Vector3d a = tank_from_pen * tip;
    const Vector3d b = tank_from_pen * (tip + axis * pen.shaft_length_m);
    axis_a_ = View(a);
    axis_b_ = View(b);
    depth_a_ = light_.dot(a);
    depth_b_ = light_.dot(b);
    const Vector3d axis_in_tank = tank_from_pen.R() * axis;
    const Vector3d u = axis_in_tank.unitOrthogonal();
    const Vector3d w = axis_in_tank.cross(u);
    std::vector<Vector2d> rims;
    constexpr int kAround = 24;
    for (int k = 0; k < kAround; ++k) {
      const double t = 2 * M_PI * k / kAround;
      const Vector3d off =
          pen.shaft_radius_m * (std::cos(t) * u + std::sin(t) * w);
      rims.push_back(View(a + off));
      rims.push_back(View(b + off));
    }
    shaft_ = geometry::ConvexHull(std::move(rims));
    const double h = 0.5 * pen.cube_edge_m;
    std::vector<Vector2d> corners;
    for (int i = 0; i < 8; ++i) {
      const Vector3d c =
          tank_from_pen *
          Vector3d(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
      corners.push_back(View(c));
    }
    cube_ = geometry::ConvexHull(std::move(corners));
    cube_depth_ = light_.dot(tank_from_pen.translation);
    top_depth_ = std::max({depth_a_, depth_b_, cube_depth_ + 2 * h});
    box_ = Eigen::AlignedBox2d(shaft_.front());
    for (const Vector2d& c : shaft_) box_.extend(c);
    for (const Vector2d& c : cube_) box_.extend(c);
  }

  // Share of the light's disc hidden from the board point `p_in_tank` (z =
  // 0), 0..1; `footprint_m`: radius of the pixel's footprint on the board.
  double Hidden(const Vector2d& p_in_tank, double footprint_m) const {
    const Vector3d p(p_in_tank.x(), p_in_tank.y(), 0.0);
    const Vector2d q = View(p);
    const double depth = light_.dot(p);
    const double reach =
        std::max(0.0, top_depth_ - depth) * tan_radius_ + footprint_m;
    if (q.x() < box_.min().x() - reach || q.x() > box_.max().x() + reach ||
        q.y() < box_.min().y() - reach || q.y() > box_.max().y() + reach)
      return 0.0;
    // Shaft: the occluder's height up the ray at the axis point nearest q.
    const Vector2d ab = axis_b_ - axis_a_;
    const double len2 = ab.squaredNorm();
    const double t =
        len2 > 0 ? std::clamp((q - axis_a_).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double s_shaft =
        std::max(0.0, depth_a_ + t * (depth_b_ - depth_a_) - depth);
    const double hidden_shaft =
        DiscCovered(geometry::SignedDistanceToConvexPolygon(shaft_, q) /
                    (s_shaft * tan_radius_ + footprint_m));
    const double s_cube = std::max(0.0, cube_depth_ - depth);
    const double hidden_cube =
        DiscCovered(geometry::SignedDistanceToConvexPolygon(cube_, q) /
                    (s_cube * tan_radius_ + footprint_m));
    return std::max(hidden_shaft, hidden_cube);
  }

 private:
  Vector2d View(const Vector3d& x) const { return {e1_.dot(x), e2_.dot(x)}; }

  Vector3d light_, e1_, e2_;
  double tan_radius_ = 0;
  Vector2d axis_a_, axis_b_;
  double depth_a_ = 0, depth_b_ = 0, cube_depth_ = 0, top_depth_ = 0;
  std::vector<Vector2d> shaft_, cube_;  // counter-clockwise
  Eigen::AlignedBox2d box_;             // of both
};

}  // namespace

// Per-camera and per-rig precomputation shared by all frames.
struct SceneRenderer::Impl {
  int width = 0, height = 0;
  // Undistorted normalised ray (x, y) through each pixel corner: corner
  // (u, v) sits at pixel coordinates (u - 0.5, v - 0.5).
  std::vector<Vector2d> corner_rays;
  std::vector<TagCells> tank_tags;  // parallel to rig.tank_tags
  std::vector<TagCells> pen_tags;   // parallel to rig.pen->faces
  CellRect sheet{0, 0, 0, 0};       // the printed sheet in the tank plane
  // kPointSampled: the undistorted normalised ray through each sample of
  // the (N W) x (N H) sample grid, row-major.
  int samples = 1;
  std::vector<Vector2d> sample_rays;
};

namespace {

TagCells MakeTagCells(const tracking::TagFamily& family, int id,
                      double edge_m) {
  TagCells cells;
  cells.id = id;
  const auto bitmap = tracking::MakeTagBitmap(family, id);
  if (!bitmap) return cells;  // the rig validated ids; keep an empty tag
  cells.n = bitmap->total_width;
  cells.cell = edge_m / bitmap->width_at_border;
  cells.origin = -0.5 * cells.n * cells.cell;
  cells.black.resize(size_t(cells.n) * cells.n);
  for (int r = 0; r < cells.n; ++r)
    for (int c = 0; c < cells.n; ++c)
      cells.black[r * cells.n + c] = bitmap->black(r, c);
  return cells;
}

// Integral of a layer's colour over the pixel whose pre-image in the plane
// is `quad`. Areas are measured in the undistorted normalised image (through
// the plane-to-image homography `h`), so coverage is exact in image space for
// a pinhole camera and exact to second order under lens distortion. `area` is
// the pixel's own normalised area. Returns the covered fraction and writes
// the colour contribution (already divided by `area`) to `*value`.
float IntegrateLayer(const PlanarLayer& layer, const Vector2d quad[4],
                     const Eigen::Matrix3d& h, double area, cv::Vec3f* value) {
  const CellRect& r = layer.rect;
  double qx0 = quad[0].x(), qx1 = qx0, qy0 = quad[0].y(), qy1 = qy0;
  for (int i = 1; i < 4; ++i) {
    qx0 = std::min(qx0, quad[i].x());
    qx1 = std::max(qx1, quad[i].x());
    qy0 = std::min(qy0, quad[i].y());
    qy1 = std::max(qy1, quad[i].y());
  }
  // Area of the pixel inside [x0,x1]x[y0,y1] with the bbox fast paths.
  auto covered_area = [&](double x0, double y0, double x1, double y1) {
    if (qx1 <= x0 || qx0 >= x1 || qy1 <= y0 || qy0 >= y1) return 0.0;
    if (qx0 >= x0 && qx1 <= x1 && qy0 >= y0 && qy1 <= y1) return area;
    return QuadRectMappedArea(quad, x0, y0, x1, y1, h);
  };
  if (layer.floor) {
    // Image texels no smaller than the pixel's footprint: at most 2 x 2 of
    // them under a pixel, each integrated exactly.
    double covered = 0;
    const cv::Vec3d sum = layer.floor->Integrate(
        Eigen::AlignedBox2d(Vector2d(qx0, qy0), Vector2d(qx1, qy1)),
        std::max(qx1 - qx0, qy1 - qy0), covered_area, &covered);
    if (covered <= 0) return 0.0f;
    *value = cv::Vec3f(sum * (1.0 / area));
    return static_cast<float>(std::min(1.0, covered / area));
  }
  const double inside = covered_area(r.x0, r.y0, r.x1, r.y1);
  double covered = inside;
  cv::Vec3d sum = cv::Vec3d(layer.base) * inside;
  if (layer.infinite) {
    sum += cv::Vec3d(layer.outside) * (area - inside);
    covered = area;
  }
  if (layer.tag && inside > 0 && layer.tag->n > 0) {
    const TagCells& t = *layer.tag;
    const int c0 = std::max(0, int(std::floor((qx0 - t.origin) / t.cell)));
    const int c1 =
        std::min(t.n - 1, int(std::floor((qx1 - t.origin) / t.cell)));
    const int r0 = std::max(0, int(std::floor((qy0 - t.origin) / t.cell)));
    const int r1 =
        std::min(t.n - 1, int(std::floor((qy1 - t.origin) / t.cell)));
    const cv::Vec3d delta = cv::Vec3d(kInk) - cv::Vec3d(layer.base);
    for (int row = r0; row <= r1; ++row) {
      for (int col = c0; col <= c1; ++col) {
        if (!t.black[row * t.n + col]) continue;
        // Cells are trimmed to the layer's rectangle (a trimmed sticker).
        const double x0 = std::max(r.x0, t.origin + col * t.cell);
        const double y0 = std::max(r.y0, t.origin + row * t.cell);
        const double x1 = std::min(r.x1, t.origin + (col + 1) * t.cell);
        const double y1 = std::min(r.y1, t.origin + (row + 1) * t.cell);
        if (x1 <= x0 || y1 <= y0) continue;
        sum += delta * covered_area(x0, y0, x1, y1);
      }
    }
  }
  if (covered <= 0) return 0.0f;
  *value = cv::Vec3f(sum * (1.0 / area));
  return static_cast<float>(std::min(1.0, covered / area));
}

}  // namespace

bool ParseFormation(const std::string& name, Formation* formation) {
  if (name == "exact") {
    *formation = Formation::kExactArea;
    return true;
  }
  if (name == "supersampled") {
    *formation = Formation::kPointSampled;
    return true;
  }
  return false;
}

const char* FormationName(Formation formation) {
  return formation == Formation::kPointSampled ? "supersampled" : "exact";
}

bool FormationOptions::IsValid(std::string* error) const {
  if (samples_per_axis < 1 || samples_per_axis > 8) {
    if (error) *error = "samples per axis must be in [1, 8]";
    return false;
  }
  if (busy_table && formation != Formation::kPointSampled) {
    if (error) *error = "a busy table needs the supersampled formation";
    return false;
  }
  return true;
}

SceneRenderer::SceneRenderer(const tracking::Camera& camera,
                             const tracking::Rig& rig, FloorPattern floor,
                             FormationOptions formation)
    : camera_(camera),
      rig_(rig),
      floor_(std::move(floor)),
      formation_(formation) {
  std::string error;
  RIPPLE_CHECK(formation.IsValid(&error), "SceneRenderer: " + error);
  auto impl = std::make_shared<Impl>();
  if (formation.formation == Formation::kPointSampled) {
    // Sample rays through OpenCV's own undistortion (not the camera model's
    // inverse used by the exact formation), iterated to convergence.
    const int n = formation.samples_per_axis;
    impl->samples = n;
    const int sw = camera.width * n, sh = camera.height * n;
    std::vector<cv::Point2d> px(size_t(sw) * sh), rays;
    for (int j = 0; j < sh; ++j)
      for (int i = 0; i < sw; ++i)
        px[size_t(j) * sw + i] =
            cv::Point2d((i + 0.5) / n - 0.5, (j + 0.5) / n - 0.5);
    const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0,
                        1);
    const std::vector<double> dist(camera.dist.begin(), camera.dist.end());
    cv::undistortPoints(
        px, rays, k, dist, cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100,
                         1e-12));
    impl->sample_rays.resize(rays.size());
    for (size_t i = 0; i < rays.size(); ++i)
      impl->sample_rays[i] = Vector2d(rays[i].x, rays[i].y);
  }
  impl->width = camera.width;
  impl->height = camera.height;
  const int cw = camera.width + 1, ch = camera.height + 1;
  impl->corner_rays.resize(size_t(cw) * ch);
  cv::parallel_for_(cv::Range(0, ch), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v)
      for (int u = 0; u < cw; ++u)
        impl->corner_rays[size_t(v) * cw + u] =
            camera.UndistortToNormalized(Vector2d(u - 0.5, v - 0.5));
  });
  const auto family = tracking::TagFamily::Create(rig.family);
  for (const tracking::TagPlacement& t : rig.tank_tags)
    impl->tank_tags.push_back(family ? MakeTagCells(*family, t.id, t.edge_m)
                                     : TagCells{});
  const Eigen::AlignedBox2d sheet = BoardSheetRect(rig);
  impl->sheet = {sheet.min().x(), sheet.min().y(), sheet.max().x(),
                 sheet.max().y()};
  if (rig.pen) {
    for (const tracking::TagPlacement& t : rig.pen->faces)
      impl->pen_tags.push_back(family ? MakeTagCells(*family, t.id, t.edge_m)
                                      : TagCells{});
  }
  impl_ = std::move(impl);
}

namespace {

// Everything one frame draws, in paint order, with image-space polygons for
// the non-planar parts.
struct DrawItem {
  enum class Kind { kPlanar, kPolygon } kind = Kind::kPlanar;
  PlanarLayer layer;
  std::vector<Vector2d> polygon_px;
  cv::Vec3f polygon_bgr;
  double depth = 0;  // for sorting the pen's parts
};

// Projects a polyline through the camera, densified so distorted edges stay
// within ~0.05 px of the true curve. Returns false if a point is behind.
bool ProjectOutline(const tracking::Camera& cam,
                    const std::vector<Vector3d>& pts_in_cam, bool closed,
                    std::vector<Vector2d>* out) {
  out->clear();
  const size_t n = pts_in_cam.size();
  const size_t segs = closed ? n : n - 1;
  for (size_t i = 0; i < segs; ++i) {
    const Vector3d& a = pts_in_cam[i];
    const Vector3d& b = pts_in_cam[(i + 1) % n];
    const int steps = cam.HasDistortion() ? 16 : 1;
    for (int s = 0; s < steps; ++s) {
      const Vector3d p = a + (b - a) * (double(s) / steps);
      if (p.z() <= 1e-4) return false;
      out->push_back(cam.Project(p));
    }
  }
  if (!closed) {
    if (pts_in_cam.back().z() <= 1e-4) return false;
    out->push_back(cam.Project(pts_in_cam.back()));
  }
  return true;
}

// The pen shaft's silhouette in the image: the convex hull of projected
// rings along the cylinder (a convex body projects to a convex region).
// False when part of it is behind the camera.
bool ShaftOutline(const tracking::Camera& cam, const tracking::PenSpec& pen,
                  const Pose& cam_from_pen, std::vector<Vector2d>* hull) {
  const Vector3d tip = pen.tip_in_pen;
  const Vector3d axis = (-tip).normalized();  // tip -> cube
  const Vector3d u = axis.unitOrthogonal(), w = axis.cross(u);
  std::vector<Vector2d> pts;
  const int rings = 12, around = 40;
  for (int r = 0; r <= rings; ++r) {
    const Vector3d c = tip + axis * (pen.shaft_length_m * r / rings);
    for (int k = 0; k < around; ++k) {
      const double a = 2 * M_PI * k / around;
      const Vector3d p =
          cam_from_pen *
          (c + pen.shaft_radius_m * (std::cos(a) * u + std::sin(a) * w));
      if (p.z() <= 1e-4) return false;
      pts.push_back(cam.Project(p));
    }
  }
  *hull = geometry::ConvexHull(std::move(pts));
  return true;
}

// Image region of a planar layer: its projected rectangle (densified for
// distortion) plus a margin, or the whole image for the infinite board
// layer. False when the layer misses the image.
bool LayerRegion(const tracking::Camera& camera, const PlanarLayer& layer,
                 cv::Rect* region) {
  const int W = camera.width, H = camera.height;
  *region = cv::Rect(0, 0, W, H);
  if (layer.infinite) return true;
  std::vector<Vector3d> outline = {
      layer.cam_from_plane * Vector3d(layer.rect.x0, layer.rect.y0, 0),
      layer.cam_from_plane * Vector3d(layer.rect.x1, layer.rect.y0, 0),
      layer.cam_from_plane * Vector3d(layer.rect.x1, layer.rect.y1, 0),
      layer.cam_from_plane * Vector3d(layer.rect.x0, layer.rect.y1, 0)};
  std::vector<Vector2d> px;
  if (!ProjectOutline(camera, outline, true, &px)) return true;
  double minx = 1e9, miny = 1e9, maxx = -1e9, maxy = -1e9;
  for (const Vector2d& p : px) {
    minx = std::min(minx, p.x());
    maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y());
    maxy = std::max(maxy, p.y());
  }
  const int x0 = std::max(0, int(std::floor(minx)) - 2);
  const int y0 = std::max(0, int(std::floor(miny)) - 2);
  const int x1 = std::min(W, int(std::ceil(maxx)) + 3);
  const int y1 = std::min(H, int(std::ceil(maxy)) + 3);
  if (x1 <= x0 || y1 <= y0) return false;
  *region = cv::Rect(x0, y0, x1 - x0, y1 - y0);
  return true;
}

// A cluttered table: per 4-40 mm patch (three nested grids, hashed) a grey
// or tinted albedo of 0.08-0.75, over a wood-like grain of +-8%.
cv::Vec3f BusyTableAlbedo(const Vector2d& p_in_tank) {
  auto hash = [](int64_t a, int64_t b, uint64_t salt) {
    uint64_t h =
        uint64_t(a) * 0x9e3779b97f4a7c15ULL ^
        (uint64_t(b) + 0x632be59bd9b4e019ULL + salt) * 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 31;
    h *= 0x94d049bb133111ebULL;
    h ^= h >> 29;
    return double(h >> 11) / double(1ULL << 53);
  };
  cv::Vec3f c(0.30f, 0.36f, 0.45f);  // the plain table's brown-grey
  const double sizes[3] = {0.040, 0.013, 0.004};
  for (int level = 0; level < 3; ++level) {
    const double s = sizes[level];
    const int64_t i = int64_t(std::floor(p_in_tank.x() / s));
    const int64_t j = int64_t(std::floor(p_in_tank.y() / s));
    if (hash(i, j, 11 * level) < 0.45) continue;  // keep the coarser patch
    const double v = 0.08 + 0.67 * hash(i, j, 11 * level + 1);
    const double tint = hash(i, j, 11 * level + 2);
    c = cv::Vec3f(float(v * (0.8 + 0.4 * tint)), float(v),
                  float(v * (1.2 - 0.4 * tint)));
  }
  const double grain =
      1.0 + 0.08 * std::sin(2 * M_PI *
                            (p_in_tank.y() * 180.0 +
                             3.0 * std::sin(p_in_tank.x() * 25.0)));
  return c * float(grain);
}

// A layer's albedo at one point of its plane (no area integration); false
// where the layer does not cover the point.
bool LayerAlbedoAt(const PlanarLayer& layer, const Vector2d& q, bool busy_table,
                   cv::Vec3f* albedo) {
  const CellRect& r = layer.rect;
  const bool inside =
      q.x() >= r.x0 && q.x() < r.x1 && q.y() >= r.y0 && q.y() < r.y1;
  if (layer.floor) {
    if (!inside) return false;
    *albedo = layer.floor->AlbedoAt(q);
    return true;
  }
  if (!inside) {
    if (!layer.infinite) return false;
    *albedo = busy_table ? BusyTableAlbedo(q) : layer.outside;
    return true;
  }
  *albedo = layer.base;
  if (layer.tag && layer.tag->n > 0) {
    const TagCells& t = *layer.tag;
    const int col = int(std::floor((q.x() - t.origin) / t.cell));
    const int row = int(std::floor((q.y() - t.origin) / t.cell));
    if (col >= 0 && row >= 0 && col < t.n && row < t.n &&
        t.black[row * t.n + col])
      *albedo = kInk;
  }
  return true;
}

// Where the camera rays meet a planar layer's z = 0 plane.
struct PlaneHits {
  PlaneHits(const Pose& cam_from_plane, const Pose& cam_from_tank)
      : R(cam_from_plane.R()),
        Rt(R.transpose()),
        t(cam_from_plane.translation),
        n(R.col(2)),
        nt(n.dot(t)),
        tank_from_plane(cam_from_tank.Inverse() * cam_from_plane) {}
  // The plane point `q` hit by the normalised ray (x, y, 1) at `*depth`
  // times the ray; false when the plane is behind or parallel.
  bool Hit(const Vector2d& ray_xy, Vector2d* q, double* depth) const {
    const Vector3d ray(ray_xy.x(), ray_xy.y(), 1.0);
    const double denom = n.dot(ray);
    const double s = std::abs(denom) > 1e-12 ? nt / denom : -1.0;
    if (!(s > 0)) return false;
    *q = (Rt * (s * ray - t)).head<2>();
    *depth = s;
    return true;
  }
  Eigen::Matrix3d R, Rt;
  Vector3d t, n;
  double nt;
  Pose tank_from_plane;
};

// The draw list of one frame, far to near: the table and sheet, the floor,
// the board tags, the pen (far part first), then the occluders.
std::vector<DrawItem> BuildDrawItems(const tracking::Camera& camera,
                                     const tracking::Rig& rig,
                                     const FloorPattern& floor,
                                     const CellRect& sheet,
                                     const std::vector<TagCells>& tank_tags,
                                     const std::vector<TagCells>& pen_tags,
                                     const SceneState& scene) {
  std::vector<DrawItem> items;
  // 1. The table and the printed sheet.
  {
    DrawItem it;
    it.layer.cam_from_plane = scene.cam_from_tank;
    it.layer.rect = sheet;
    it.layer.infinite = true;
    it.layer.base = kPaper;
    it.layer.outside = kTable;
    it.layer.board = true;
    items.push_back(it);
  }
  // 1b. The floor pattern inside the tank outline (plain paper adds nothing).
  if (floor.kind() != FloorKind::kPlain && !floor.rect().isEmpty()) {
    DrawItem it;
    it.layer.cam_from_plane = scene.cam_from_tank;
    const Eigen::AlignedBox2d& f = floor.rect();
    it.layer.rect = {f.min().x(), f.min().y(), f.max().x(), f.max().y()};
    it.layer.floor = &floor;
    it.layer.board = true;
    items.push_back(it);
  }
  // 2. The board's tags.
  for (size_t i = 0; i < rig.tank_tags.size(); ++i) {
    const tracking::TagPlacement& t = rig.tank_tags[i];
    const TagCells& cells = tank_tags[i];
    DrawItem it;
    it.layer.cam_from_plane = scene.cam_from_tank * t.object_from_tag;
    const double h = -cells.origin;
    it.layer.rect = {-h, -h, h, h};
    it.layer.base = kPaper;
    it.layer.tag = &cells;
    it.layer.board = true;
    items.push_back(it);
  }
  // 3. The pen: shaft polygon and cube faces with their tags, painted far
  // part first.
  if (scene.tank_from_pen && rig.pen) {
    const tracking::PenSpec& pen = *rig.pen;
    const Pose cam_from_pen = scene.cam_from_tank * *scene.tank_from_pen;
    const Eigen::Matrix3d tank_r = scene.cam_from_tank.R();
    const Vector3d light_in_cam =
        tank_r * (scene.light_in_tank ? scene.light_in_tank->normalized()
                                      : kLightInTank);
    std::vector<DrawItem> pen_items;
    // Shaft: the convex hull of rings along the cylinder.
    {
      const Vector3d tip = pen.tip_in_pen;
      const Vector3d axis = (-tip).normalized();  // tip -> cube
      std::vector<Vector2d> hull;
      const bool ok = ShaftOutline(camera, pen, cam_from_pen, &hull);
      if (ok) {
        DrawItem it;
        it.kind = DrawItem::Kind::kPolygon;
        it.polygon_px = std::move(hull);
        it.polygon_bgr = kShaft * 0.9f;
        it.depth =
            (cam_from_pen * (tip + axis * 0.5 * pen.shaft_length_m)).norm();
        pen_items.push_back(it);
      }
    }
    // Cube faces (front-facing only; a convex body's faces never overlap).
    const double e = pen.cube_edge_m;
    static const Vector3d kNormals[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                         {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    const double cube_depth = cam_from_pen.translation.norm();
    for (const Vector3d& n : kNormals) {
      // Face frame: z into the cube (like a tag), x and y spanning the face.
      const Vector3d z = -n;
      const Vector3d x = z.unitOrthogonal();
      const Vector3d y = z.cross(x);
      Eigen::Matrix3d r;
      r << x, y, z;
      const Pose pen_from_face = Pose::FromMatrix(r, n * (0.5 * e));
      const Pose cam_from_face = cam_from_pen * pen_from_face;
      const Vector3d normal_in_cam = cam_from_pen.R() * n;
      if (normal_in_cam.dot(cam_from_face.translation) >= 0) continue;
      DrawItem it;
      it.layer.cam_from_plane = cam_from_face;
      it.layer.rect = {-0.5 * e, -0.5 * e, 0.5 * e, 0.5 * e};
      it.layer.base = kCube;
      it.layer.shade = static_cast<float>(
          0.55 + 0.45 * std::max(0.0, normal_in_cam.dot(light_in_cam)));
      it.depth = cube_depth;
      pen_items.push_back(it);
      // Tags glued on this face.
      for (size_t i = 0; i < pen.faces.size(); ++i) {
        const tracking::TagPlacement& t = pen.faces[i];
        const Vector3d tag_z = t.object_from_tag.R().col(2);
        if (tag_z.dot(z) < 0.9) continue;
        DrawItem tag_item;
        tag_item.layer.cam_from_plane = cam_from_pen * t.object_from_tag;
        // The printed square (tag plus white margin) is trimmed to the part
        // that lies on its face, as a sticker glued slightly off-centre
        // would be: the largest tag-aligned rectangle inside the face, so a
        // perturbed tag never overhangs onto a neighbouring face.
        const double h = -pen_tags[i].origin;
        const Pose face_from_tag = pen_from_face.Inverse() * t.object_from_tag;
        const Vector3d x_in_face = face_from_tag.R().col(0);
        const double turn =
            std::atan2(std::abs(x_in_face.y()), std::abs(x_in_face.x()));
        const double inner = 0.5 * e / (std::cos(turn) + std::sin(turn));
        const Vector3d centre_in_tag =
            face_from_tag.Inverse() * Vector3d::Zero();
        tag_item.layer.rect = {std::max(-h, centre_in_tag.x() - inner),
                               std::max(-h, centre_in_tag.y() - inner),
                               std::min(h, centre_in_tag.x() + inner),
                               std::min(h, centre_in_tag.y() + inner)};
        tag_item.layer.base = kPaper;
        tag_item.layer.tag = &pen_tags[i];
        tag_item.layer.shade = it.layer.shade;
        tag_item.depth = cube_depth;
        pen_items.push_back(tag_item);
      }
    }
    std::stable_sort(
        pen_items.begin(), pen_items.end(),
        [](const DrawItem& a, const DrawItem& b) { return a.depth > b.depth; });
    items.insert(items.end(), pen_items.begin(), pen_items.end());
  }
  // 4. Occluders in front of everything.
  for (const Occluder& o : scene.occluders) {
    std::vector<Vector3d> pts;
    for (const Vector2d& p : o.outline_m)
      pts.push_back(o.cam_from_occluder * Vector3d(p.x(), p.y(), 0));
    DrawItem it;
    it.kind = DrawItem::Kind::kPolygon;
    if (!ProjectOutline(camera, pts, true, &it.polygon_px)) continue;
    it.polygon_bgr = o.bgr;
    items.push_back(it);
  }

  return items;
}

// The pen's cast shadow on the board's layers, when the scene has one.
std::optional<PenShadow> MakePenShadow(const tracking::Rig& rig,
                                       const SceneState& scene) {
  std::optional<PenShadow> shadow;
  if (scene.light_in_tank && scene.tank_from_pen && rig.pen &&
      !scene.flat_lighting && scene.ambient_share < 1.0 &&
      scene.light_in_tank->z() > 0)
    shadow.emplace(*rig.pen, *scene.tank_from_pen, *scene.light_in_tank,
                   scene.light_radius_rad);
  return shadow;
}

}  // namespace

cv::Mat SceneRenderer::RenderLinear(const SceneState& scene) const {
  return formation_.formation == Formation::kPointSampled
             ? RenderPointSampled(scene)
             : RenderExactArea(scene);
}

cv::Mat SceneRenderer::RenderExactArea(const SceneState& scene) const {
  const Impl& impl = *impl_;
  const int W = impl.width, H = impl.height, CW = W + 1;
  cv::Mat out(H, W, CV_32FC3, cv::Scalar::all(0));
  const std::vector<DrawItem> items = BuildDrawItems(
      camera_, rig_, floor_, impl.sheet, impl.tank_tags, impl.pen_tags, scene);
  const std::optional<PenShadow> shadow = MakePenShadow(rig_, scene);
  const double direct_share = 1.0 - std::clamp(scene.ambient_share, 0.0, 1.0);

  // Paint.
  std::vector<Vector2d> plane_pts(impl.corner_rays.size());
  std::vector<uint8_t> valid(impl.corner_rays.size());
  for (const DrawItem& it : items) {
    if (it.kind == DrawItem::Kind::kPolygon) {
      cv::Mat cov;
      cv::Rect roi;
      if (!RasterizePolygon(it.polygon_px, W, H, &cov, &roi)) continue;
      for (int y = 0; y < roi.height; ++y) {
        cv::Vec3f* row = out.ptr<cv::Vec3f>(roi.y + y) + roi.x;
        const float* c = cov.ptr<float>(y);
        for (int x = 0; x < roi.width; ++x)
          row[x] = row[x] * (1.0f - c[x]) + it.polygon_bgr * c[x];
      }
      continue;
    }
    const PlanarLayer& layer = it.layer;
    cv::Rect region;
    if (!LayerRegion(camera_, layer, &region)) continue;
    const PlaneHits plane(layer.cam_from_plane, scene.cam_from_tank);
    const Pose& tank_from_plane = plane.tank_from_plane;
    // Plane (x, y) -> normalised image: [r1 r2 t].
    Eigen::Matrix3d homography;
    homography << plane.R.col(0), plane.R.col(1), plane.t;
    cv::parallel_for_(
        cv::Range(region.y, region.br().y + 1), [&](const cv::Range& rows) {
          for (int v = rows.start; v < rows.end; ++v) {
            for (int u = region.x; u <= region.br().x; ++u) {
              const size_t k = size_t(v) * CW + u;
              double depth;
              valid[k] = plane.Hit(impl.corner_rays[k], &plane_pts[k], &depth);
            }
          }
        });
    cv::parallel_for_(
        cv::Range(region.y, region.br().y), [&](const cv::Range& rows) {
          for (int v = rows.start; v < rows.end; ++v) {
            cv::Vec3f* row = out.ptr<cv::Vec3f>(v);
            for (int u = region.x; u < region.br().x; ++u) {
              const size_t k00 = size_t(v) * CW + u, k10 = k00 + 1,
                           k01 = k00 + CW, k11 = k01 + 1;
              if (!(valid[k00] && valid[k10] && valid[k01] && valid[k11]))
                continue;
              const Vector2d quad[4] = {plane_pts[k00], plane_pts[k10],
                                        plane_pts[k11], plane_pts[k01]};
              const Vector2d& n00 = impl.corner_rays[k00];
              const Vector2d& n10 = impl.corner_rays[k10];
              const Vector2d& n01 = impl.corner_rays[k01];
              const Vector2d& n11 = impl.corner_rays[k11];
              const double area =
                  0.5 * std::abs((n11 - n00).x() * (n01 - n10).y() -
                                 (n11 - n00).y() * (n01 - n10).x());
              if (!(area > 0)) continue;
              cv::Vec3f value;
              const float alpha =
                  IntegrateLayer(layer, quad, homography, area, &value);
              if (alpha <= 0) continue;
              float shade = scene.flat_lighting ? 1.0f : layer.shade;
              if (layer.board && !scene.flat_lighting) {
                const Vector2d c =
                    0.25 * (quad[0] + quad[1] + quad[2] + quad[3]);
                // Board tags live in their own frames; shade by the tank frame.
                const Vector3d in_tank =
                    tank_from_plane * Vector3d(c.x(), c.y(), 0);
                shade = BoardShade(in_tank.x(), in_tank.y());
                if (shadow) {
                  // Footprint: the radius of a disc of the pixel's area on
                  // the plane.
                  const double plane_area =
                      0.5 *
                      std::abs(
                          (quad[2] - quad[0]).x() * (quad[3] - quad[1]).y() -
                          (quad[2] - quad[0]).y() * (quad[3] - quad[1]).x());
                  const double hidden = shadow->Hidden(
                      in_tank.head<2>(), std::sqrt(plane_area / M_PI));
                  shade *= static_cast<float>(1.0 - direct_share * hidden);
                }
              }
              row[u] = row[u] * (1.0f - alpha) + value * shade;
            }
          }
        });
  }
  return out;
}

cv::Mat SceneRenderer::RenderPointSampled(const SceneState& scene) const {
  const Impl& impl = *impl_;
  const int W = impl.width, H = impl.height, N = impl.samples;
  const int SW = W * N, SH = H * N;
  cv::Mat hi(SH, SW, CV_32FC3, cv::Scalar::all(0));
  const std::vector<DrawItem> items = BuildDrawItems(
      camera_, rig_, floor_, impl.sheet, impl.tank_tags, impl.pen_tags, scene);
  const std::optional<PenShadow> shadow = MakePenShadow(rig_, scene);
  const double direct_share = 1.0 - std::clamp(scene.ambient_share, 0.0, 1.0);
  const bool busy = formation_.busy_table;
  for (const DrawItem& it : items) {
    if (it.kind == DrawItem::Kind::kPolygon) {
      // Sample (i, j) sits at pixel ((i + 0.5) / N - 0.5, ...): in sample
      // units a pixel point x maps to (x + 0.5) N - 0.5, and fillPoly fills
      // the samples whose centres are inside (4 fractional bits).
      constexpr int kShift = 4;
      std::vector<cv::Point> pts;
      for (const Vector2d& p : it.polygon_px)
        pts.emplace_back(
            int(std::lround(((p.x() + 0.5) * N - 0.5) * (1 << kShift))),
            int(std::lround(((p.y() + 0.5) * N - 0.5) * (1 << kShift))));
      if (pts.size() < 3) continue;
      cv::Mat mask(SH, SW, CV_8U, cv::Scalar(0));
      cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{pts},
                   cv::Scalar(255), cv::LINE_8, kShift);
      hi.setTo(
          cv::Scalar(it.polygon_bgr[0], it.polygon_bgr[1], it.polygon_bgr[2]),
          mask);
      continue;
    }
    const PlanarLayer& layer = it.layer;
    cv::Rect region;
    if (!LayerRegion(camera_, layer, &region)) continue;
    const PlaneHits plane(layer.cam_from_plane, scene.cam_from_tank);
    const Pose& tank_from_plane = plane.tank_from_plane;
    // A sample's footprint on the plane, for the shadow's penumbra: the
    // pixel's angular size over N at the plane's distance.
    const double sample_rad = 1.0 / (N * std::max(camera_.fx, camera_.fy));
    cv::parallel_for_(
        cv::Range(region.y * N, region.br().y * N), [&](const cv::Range& rows) {
          for (int j = rows.start; j < rows.end; ++j) {
            cv::Vec3f* row = hi.ptr<cv::Vec3f>(j);
            for (int i = region.x * N; i < region.br().x * N; ++i) {
              const Vector2d& ray = impl.sample_rays[size_t(j) * SW + i];
              Vector2d q;
              double s;
              if (!plane.Hit(ray, &q, &s)) continue;
              cv::Vec3f albedo;
              if (!LayerAlbedoAt(layer, q, busy, &albedo)) continue;
              float shade = scene.flat_lighting ? 1.0f : layer.shade;
              if (layer.board && !scene.flat_lighting) {
                const Vector3d in_tank =
                    tank_from_plane * Vector3d(q.x(), q.y(), 0);
                shade = BoardShade(in_tank.x(), in_tank.y());
                if (shadow) {
                  const double hidden = shadow->Hidden(
                      in_tank.head<2>(),
                      std::max(1e-6, s * std::sqrt(1 + ray.squaredNorm()) *
                                         sample_rad));
                  shade *= static_cast<float>(1.0 - direct_share * hidden);
                }
              }
              row[i] = albedo * shade;
            }
          }
        });
  }
  if (N == 1) return hi;
  cv::Mat out;
  cv::resize(hi, out, cv::Size(W, H), 0, 0, cv::INTER_AREA);  // box mean
  return out;
}

void SceneRenderer::VisibleTags(const SceneState& scene,
                                std::vector<int>* tank_tags,
                                std::vector<int>* pen_tags) const {
  tank_tags->clear();
  pen_tags->clear();
  const int W = camera_.width, H = camera_.height;
  // Occluding outlines in the image, each with the depth it sits at.
  struct Blocker {
    std::vector<Vector2d> poly;
    bool is_pen_shaft = false;
    bool is_cube = false;
    bool is_occluder = false;
  };
  std::vector<Blocker> blockers;
  std::optional<Pose> cam_from_pen;
  if (scene.tank_from_pen && rig_.pen) {
    cam_from_pen = scene.cam_from_tank * *scene.tank_from_pen;
    const tracking::PenSpec& pen = *rig_.pen;
    std::vector<Vector2d> hull;
    bool ok = ShaftOutline(camera_, pen, *cam_from_pen, &hull);
    if (ok) blockers.push_back({std::move(hull), true, false, false});
    std::vector<Vector2d> pts;
    ok = true;
    const double h = 0.5 * pen.cube_edge_m;
    for (int i = 0; i < 8 && ok; ++i) {
      const Vector3d p =
          *cam_from_pen *
          Vector3d(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
      ok = p.z() > 1e-4;
      if (ok) pts.push_back(camera_.Project(p));
    }
    if (ok) blockers.push_back({geometry::ConvexHull(pts), false, true, false});
  }
  for (const Occluder& o : scene.occluders) {
    std::vector<Vector3d> pts;
    for (const Vector2d& p : o.outline_m)
      pts.push_back(o.cam_from_occluder * Vector3d(p.x(), p.y(), 0));
    Blocker b;
    b.is_occluder = true;
    if (ProjectOutline(camera_, pts, true, &b.poly)) blockers.push_back(b);
  }
  // A tag counts when a 9x9 grid over its black square is in the image,
  // seen from the front at under ~84 degrees, and not hidden.
  auto visible = [&](const Pose& cam_from_tag, double edge, bool on_pen) {
    const Vector3d z = cam_from_tag.R().col(2);
    const Vector3d centre = cam_from_tag.translation;
    if (z.dot(centre.normalized()) < 0.1) return false;
    for (int i = 0; i <= 8; ++i) {
      for (int j = 0; j <= 8; ++j) {
        const Vector3d p = cam_from_tag * Vector3d(edge * (i / 8.0 - 0.5),
                                                   edge * (j / 8.0 - 0.5), 0);
        if (p.z() <= 1e-4) return false;
        const Vector2d px = camera_.Project(p);
        if (!(px.x() >= 0 && px.y() >= 0 && px.x() <= W - 1 && px.y() <= H - 1))
          return false;
        for (const Blocker& b : blockers) {
          if (on_pen && b.is_cube) continue;  // its own faces never overlap
          if (on_pen && b.is_pen_shaft) {
            // The shaft hides a face only when it is nearer than the cube.
            const Vector3d tip_in_cam = *cam_from_pen * rig_.pen->tip_in_pen;
            if (tip_in_cam.norm() > cam_from_pen->translation.norm()) continue;
          }
          if (PointInPolygon(b.poly, px)) return false;
        }
      }
    }
    return true;
  };
  for (const tracking::TagPlacement& t : rig_.tank_tags)
    if (visible(scene.cam_from_tank * t.object_from_tag, t.edge_m, false))
      tank_tags->push_back(t.id);
  if (cam_from_pen) {
    for (const tracking::TagPlacement& t : rig_.pen->faces)
      if (visible(*cam_from_pen * t.object_from_tag, t.edge_m, true))
        pen_tags->push_back(t.id);
  }
}

void SceneRenderer::OccluderCoverage(const SceneState& scene, cv::Mat* hands,
                                     cv::Mat* pen) const {
  const int W = camera_.width, H = camera_.height;
  auto paint = [&](const std::vector<Vector2d>& poly, cv::Mat* target) {
    cv::Mat cov;
    cv::Rect roi;
    if (!RasterizePolygon(poly, W, H, &cov, &roi)) return;
    for (int y = 0; y < roi.height; ++y) {
      float* row = target->ptr<float>(roi.y + y) + roi.x;
      const float* c = cov.ptr<float>(y);
      for (int x = 0; x < roi.width; ++x)
        row[x] = row[x] + c[x] * (1.0f - row[x]);
    }
  };
  hands->create(H, W, CV_32F);
  hands->setTo(0);
  pen->create(H, W, CV_32F);
  pen->setTo(0);
  for (const Occluder& o : scene.occluders) {
    std::vector<Vector3d> pts;
    for (const Vector2d& p : o.outline_m)
      pts.push_back(o.cam_from_occluder * Vector3d(p.x(), p.y(), 0));
    std::vector<Vector2d> poly;
    if (ProjectOutline(camera_, pts, true, &poly)) paint(poly, hands);
  }
  if (scene.tank_from_pen && rig_.pen) {
    const tracking::PenSpec& spec = *rig_.pen;
    const Pose cam_from_pen = scene.cam_from_tank * *scene.tank_from_pen;
    std::vector<Vector2d> hull;
    if (ShaftOutline(camera_, spec, cam_from_pen, &hull)) paint(hull, pen);
    std::vector<Vector2d> pts;
    const double h = 0.5 * spec.cube_edge_m;
    bool ok = true;
    for (int i = 0; i < 8 && ok; ++i) {
      const Vector3d p = cam_from_pen * Vector3d(i & 1 ? h : -h, i & 2 ? h : -h,
                                                 i & 4 ? h : -h);
      ok = p.z() > 1e-4;
      if (ok) pts.push_back(camera_.Project(p));
    }
    if (ok) paint(geometry::ConvexHull(pts), pen);
  }
  // Hands are drawn in front of the pen.
  *pen = pen->mul(1.0f - *hands);
}

namespace {

cv::Mat MotionBlurKernel(double length_px, double angle_rad) {
  const int size = 2 * int(std::ceil(0.5 * length_px)) + 3;
  cv::Mat k(size, size, CV_32F, cv::Scalar(0));
  const double c = 0.5 * (size - 1);
  const int samples = 64;
  for (int i = 0; i < samples; ++i) {
    const double s = length_px * ((i + 0.5) / samples - 0.5);
    const double x = c + s * std::cos(angle_rad),
                 y = c + s * std::sin(angle_rad);
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    k.at<float>(y0, x0) += float((1 - fx) * (1 - fy));
    k.at<float>(y0, x0 + 1) += float(fx * (1 - fy));
    k.at<float>(y0 + 1, x0) += float((1 - fx) * fy);
    k.at<float>(y0 + 1, x0 + 1) += float(fx * fy);
  }
  return k / cv::sum(k)[0];
}

// A uniform disc of radius `radius_px`, each kernel pixel weighted by the
// disc's area in it (16 x 16 sub-samples), normalised to sum 1.
cv::Mat DiscKernel(double radius_px) {
  const int half = int(std::ceil(radius_px));
  const int size = 2 * half + 1;
  cv::Mat k(size, size, CV_32F, cv::Scalar(0));
  constexpr int kSub = 16;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      int in = 0;
      for (int b = 0; b < kSub; ++b)
        for (int a = 0; a < kSub; ++a) {
          const double dx = x - half - 0.5 + (a + 0.5) / kSub;
          const double dy = y - half - 0.5 + (b + 0.5) / kSub;
          in += dx * dx + dy * dy <= radius_px * radius_px;
        }
      k.at<float>(y, x) = float(in);
    }
  return k / cv::sum(k)[0];
}

}  // namespace

RenderedFrame SceneRenderer::Render(const SceneState& scene,
                                    const ImagingOptions& imaging,
                                    uint64_t seed) const {
  cv::Mat img = RenderLinear(scene);
  if (imaging.exposure != 1.0) img *= imaging.exposure;
  if (imaging.defocus_sigma_px > 0) {
    if (imaging.defocus_kernel == DefocusKernel::kDisc)
      cv::filter2D(img, img, -1, DiscKernel(2 * imaging.defocus_sigma_px),
                   cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    else
      cv::GaussianBlur(img, img, cv::Size(0, 0), imaging.defocus_sigma_px, 0,
                       cv::BORDER_REPLICATE);
  }
  if (imaging.motion_blur_px > 0.05)
    cv::filter2D(
        img, img, -1,
        MotionBlurKernel(imaging.motion_blur_px, imaging.motion_angle_rad),
        cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  img *= 255.0;
  cv::RNG rng(seed ? seed : 0x9e3779b97f4a7c15ULL);
  if (imaging.shot_noise_gain > 0) {
    // Poisson shot noise, Gaussian approximation: variance = gain * signal.
    cv::Mat sigma;
    cv::max(img * imaging.shot_noise_gain, 0.0, sigma);
    cv::sqrt(sigma, sigma);
    cv::Mat n(img.size(), img.type());
    rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    img += n.mul(sigma);
  }
  if (imaging.read_noise_dn > 0) {
    cv::Mat n(img.size(), img.type());
    rng.fill(n, cv::RNG::NORMAL, 0.0, imaging.read_noise_dn);
    img += n;
  }
  if (imaging.srgb) {
    // IEC 61966-2-1 on the signal in [0, 1] (DN / 255).
    img.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
      for (int c = 0; c < 3; ++c) {
        const float l = std::clamp(p[c] / 255.0f, 0.0f, 1.0f);
        p[c] = 255.0f * (l <= 0.0031308f
                             ? 12.92f * l
                             : 1.055f * std::pow(l, 1.0f / 2.4f) - 0.055f);
      }
    });
  }
  RenderedFrame frame;
  img.convertTo(frame.image, CV_8UC3);  // rounds and saturates
  if (imaging.jpeg_quality > 0) {
    std::vector<uchar> buf;
    cv::imencode(".jpg", frame.image, buf,
                 {cv::IMWRITE_JPEG_QUALITY, imaging.jpeg_quality});
    frame.image = cv::imdecode(buf, cv::IMREAD_COLOR);
  }
  VisibleTags(scene, &frame.tank_tags, &frame.pen_tags);
  return frame;
}

}  // namespace ripple::synth
