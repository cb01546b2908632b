// The printed tank floor: the pattern inside the tank outline of the board
// sheet, which gives the virtual water's refraction something to bend and its
// caustics a surface to show on. One definition serves the printed sheet
// (calib/marker_sheet.h), the synthetic renderer (synth.h) and anything that
// needs the board's albedo in the tank frame (RenderFloorAlbedo,
// RenderBoardAlbedo).
//
// Albedos are linear reflectances, BGR, 0..1, on the same scale as the
// paper (kPaperBgr): a printed colour reflects its albedo when printed on
// paper of reflectance kPaperBgr, so the sheet writer prints albedo / paper,
// sRGB-encoded. Points are in the tank frame (metres, origin at the tank
// centre, x along the long side, y across, z up; the floor is z = 0): on the
// printed page, tank x runs to the right and tank y up the page.
#ifndef RIPPLE_TRACKING_SYNTH_FLOOR_PATTERN_H_
#define RIPPLE_TRACKING_SYNTH_FLOOR_PATTERN_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tracking/rig.h"

namespace ripple::synth {

// Linear reflectances (BGR, 0..1) of the printed paper, of the tag ink and
// of the table the board lies on.
extern const cv::Vec3f kPaperBgr;
extern const cv::Vec3f kInkBgr;
extern const cv::Vec3f kTableBgr;

enum class FloorKind {
  kPlain,  // blank paper
  kTiles,  // square tiles with grout lines
  kImage,  // an image file stretched over the tank's inner floor rectangle
};

// "plain", "tiles", "image".
const char* ToString(FloorKind kind);

struct FloorOptions {
  FloorKind kind = FloorKind::kTiles;

  // Tiles: a square grid with a tile centred on the tank centre (the default
  // tank, 170 x 110 mm, holds 17 x 11 whole tiles), tiles alternating
  // between two tints like a checker. The tints are light and of equal
  // luminance (0.299 R + 0.587 G + 0.114 B = 0.742, the weights of OpenCV's
  // BGR2GRAY), so a grey image shows only the grout grid: light squares
  // ringed by darker lines, which the tag detector rejects as reversed-border
  // quads before decoding. Against the tags' 0.05 ink on 0.88 paper the
  // pattern is low contrast (grout 0.40 against tiles 0.74).
  double tile_m = 0.010;    // tile pitch, grout centre to grout centre
  double grout_m = 0.0008;  // width of the grout lines, metres
  cv::Vec3f grout_bgr{0.40f, 0.40f, 0.40f};  // neutral grey
  // Pale grey (the centre tile): no warm tint, so that skin over the floor
  // stands apart from it in colour as well as brightness (the clean plate,
  // tracking/clean_plate.h; a sand tile read as skin in shade).
  cv::Vec3f tile_a_bgr{0.742f, 0.742f, 0.742f};
  cv::Vec3f tile_b_bgr{0.80f, 0.793f, 0.62f};  // pale aqua

  // Image: a PNG or JPEG file (8-bit sRGB, at most 16384 px each way)
  // stretched over the floor rectangle, its top-left corner at the floor's
  // (-x, +y) corner (top-left on the printed page). White (255) is the
  // paper's own reflectance.
  std::string image_path;

  // Tile pitch in [0.5 mm, 1 m], grout in [0, pitch), every reflectance in
  // [0, 1] and at most the paper's (what paper can print); an image path for
  // kImage.
  bool IsValid(std::string* error) const;
};

// The floor pattern of one tank: piecewise constant over axis-aligned
// rectangles of the tank frame (tiles and grout, or the image's texels), so
// that coverage can be integrated exactly. Cheap to copy (the image is
// shared); thread-safe to use. A default-constructed pattern is plain paper.
class FloorPattern {
 public:
  FloorPattern();

  // The pattern of `options` over the inner floor of a tank of `size_x_m` x
  // `size_y_m` (centred on the tank origin). nullopt with a one-line `error`
  // for invalid options, a bad tank size or an image that cannot be read
  // (the message names the file).
  static std::optional<FloorPattern> Create(const FloorOptions& options,
                                            double size_x_m, double size_y_m,
                                            std::string* error);
  // The same for a rig's tank.
  static std::optional<FloorPattern> Create(const FloorOptions& options,
                                            const tracking::TankSpec& tank,
                                            std::string* error);

  FloorKind kind() const;
  const FloorOptions& options() const;
  // The floor rectangle in the tank frame (empty for a default pattern).
  const Eigen::AlignedBox2d& rect() const;

  // Albedo at a point of the board plane: the pattern inside the floor
  // rectangle (an image's nearest texel), paper outside it.
  cv::Vec3f AlbedoAt(const Eigen::Vector2d& p_in_tank) const;

  // Mean albedo over an axis-aligned rectangle of the board plane (paper
  // outside the floor): exact for plain and tiles, the exact mean of the
  // image's texels at a level of detail finer than a quarter of the box.
  cv::Vec3f AverageOver(const Eigen::AlignedBox2d& box_in_tank) const;

  // A non-owning reference to a callable `double(double x0, double y0,
  // double x1, double y1)` (see Integrate).
  class RectMeasure {
   public:
    template <typename F>
    RectMeasure(const F& f)  // NOLINT: implicit from any such callable
        : object_(&f),
          call_([](const void* o, double x0, double y0, double x1, double y1) {
            return (*static_cast<const F*>(o))(x0, y0, x1, y1);
          }) {}
    double operator()(double x0, double y0, double x1, double y1) const {
      return call_(object_, x0, y0, x1, y1);
    }

   private:
    const void* object_;
    double (*call_)(const void*, double, double, double, double);
  };

  // Integral of the albedo over a region R of the board plane, restricted to
  // the floor rectangle. R is given by its bounding box `bounds` and by
  // `measure(x0, y0, x1, y1)`, the measure of R inside that rectangle: its
  // plane area, or its image area through the plane's homography (the
  // synthetic renderer's pixel pre-images). Tiles are integrated exactly;
  // images over the texels of the finest level of detail (2x2 box averages
  // per level) whose texel is at least `detail_m`. Writes measure(R ∩
  // floor) to `covered`; the caller paints the rest.
  cv::Vec3d Integrate(const Eigen::AlignedBox2d& bounds, double detail_m,
                      RectMeasure measure, double* covered) const;

  // A constant-albedo rectangle of the pattern, tank frame.
  struct Cell {
    Eigen::AlignedBox2d rect;
    cv::Vec3f bgr;
  };
  // The pattern as vector shapes for printing: the floor rectangle in the
  // base colour (grout) followed by every tile on top, clipped to the floor.
  // Empty for plain and image patterns.
  std::vector<Cell> TileCells() const;

  // The image as read (CV_8UC3 BGR, sRGB-encoded); empty unless kImage.
  const cv::Mat& image_bgr8() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
};

// The floor pattern alone as an albedo image in the tank frame (paper
// outside the floor): pixel (col, row) is the exact mean albedo over the
// square [x0 + col / px_per_m, x0 + (col + 1) / px_per_m] x [y0 + row /
// px_per_m, y0 + (row + 1) / px_per_m] with (x0, y0) = rect_in_tank_m.min(),
// so rows grow with tank y (the printed page seen from below: cv::flip(img,
// img, 0) shows it as printed). round(size * px_per_m) pixels each way.
// CV_32FC3, linear BGR. A texture for anything that traces rays to the
// floor.
cv::Mat RenderFloorAlbedo(const FloorPattern& floor,
                          const Eigen::AlignedBox2d& rect_in_tank_m,
                          double px_per_m);

// The whole board as an albedo image in the same layout: the table
// (kTableBgr) outside the sheet (BoardSheetRect), paper, the floor pattern
// inside the tank, and the rig's board tags (white margin and black cells,
// exact area coverage, tags taken as lying flat on the board) on top.
cv::Mat RenderBoardAlbedo(const tracking::Rig& rig, const FloorPattern& floor,
                          const Eigen::AlignedBox2d& rect_in_tank_m,
                          double px_per_m);

// The printed board as the clean plate's prior (tracking/clean_plate.h):
// RenderBoardAlbedo over the plate's grid (`size` texels of `texel_m` from
// the corner `corner_m`, rows growing with tank y), relative to the paper
// (paper = 255 levels) and encoded with `srgb` or linearly, as a camera under
// white light would record it; `valid` is 255 on the sheet and 0 on the
// table, whose look is not known.
void BoardDesignLevels(const tracking::Rig& rig, const FloorPattern& floor,
                       const Eigen::Vector2d& corner_m, double texel_m,
                       cv::Size size, bool srgb, cv::Mat* levels,
                       cv::Mat* valid);

// The printed sheet as the synthetic renderer draws it, tank frame: the
// extent of the board tags' black squares plus a 20 mm paper margin, and at
// least the tank plus that margin.
Eigen::AlignedBox2d BoardSheetRect(const tracking::Rig& rig);

}  // namespace ripple::synth

#endif  // RIPPLE_TRACKING_SYNTH_FLOOR_PATTERN_H_
