#include "tracking/tag_detector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>

#include "tests/tracking/tag_scene.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {
namespace {

using testing::PlacedTag;
using testing::RenderTags;

Camera TestCamera() { return MakeIdealCamera(640, 480, 60.0); }

// A tag at `distance` metres, tilted by (ax, ay) radians, centred at (x, y).
Pose TagPose(double x, double y, double distance, double ax, double ay,
             double az) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(az, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(ax, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(ay, Eigen::Vector3d::UnitY());
  return Pose(q, Eigen::Vector3d(x, y, distance));
}

std::array<Eigen::Vector2d, 4> TrueCorners(const Camera& camera,
                                           const PlacedTag& tag) {
  TagPlacement p;
  p.id = tag.id;
  p.edge_m = tag.edge_m;
  return testing::ProjectCorners(camera, p, tag.cam_from_tag);
}

TEST(TagDetectorTest, TinyImagesFindNothingAndDoNotCrash) {
  // libapriltag's quad search read past the edges of 1x1 and 4x3 frames.
  TagDetector detector{TagDetectorOptions()};
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(4, 3), cv::Size(7, 40),
                              cv::Size(40, 7), cv::Size(8, 8)}) {
    const cv::Mat image(size, CV_8UC1, cv::Scalar(128));
    EXPECT_TRUE(detector.Detect(image).empty()) << size;
    EXPECT_TRUE(detector.Detect(image, {cv::Rect(0, 0, 3, 3)}).empty()) << size;
  }
}

TEST(TagDetectorTest, FindsIdsWithCornersInTagImageOrder) {
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  // Rotated 30 degrees in the image plane: the order must follow the tag,
  // not the image axes.
  const std::vector<PlacedTag> tags = {
      {3, 0.04, TagPose(-0.05, 0.0, 0.35, 0.3, 0.2, 0.5)},
      {7, 0.04, TagPose(0.06, 0.02, 0.4, -0.2, 0.4, 2.0)}};
  const cv::Mat image = RenderTags(camera, *family, tags);
  TagDetector detector(TagDetectorOptions{});
  const std::vector<TagDetection> found = detector.Detect(image);
  ASSERT_EQ(found.size(), 2u);
  for (const TagDetection& d : found) {
    const PlacedTag& tag = d.id == 3 ? tags[0] : tags[1];
    ASSERT_TRUE(d.id == 3 || d.id == 7);
    const auto truth = TrueCorners(camera, tag);
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((d.corners[k] - truth[k]).norm(), 0.3) << "corner " << k;
    EXPECT_GT(d.decision_margin, 50);
  }
}

TEST(TagDetectorTest, CorrectCornersShiftsEdgesOutward) {
  const std::array<Eigen::Vector2d, 4> square = {
      Eigen::Vector2d(10.5, 10.5), Eigen::Vector2d(30.5, 10.5),
      Eigen::Vector2d(30.5, 30.5), Eigen::Vector2d(10.5, 30.5)};
  const auto out = CorrectCorners(square, 0.5, 0.25);
  EXPECT_NEAR(out[0].x(), 9.75, 1e-12);
  EXPECT_NEAR(out[0].y(), 9.75, 1e-12);
  EXPECT_NEAR(out[2].x(), 30.25, 1e-12);
  EXPECT_NEAR(out[2].y(), 30.25, 1e-12);
}

TEST(TagDetectorTest, RoiSearchMatchesFullSearch) {
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  const std::vector<PlacedTag> tags = {
      {1, 0.03, TagPose(-0.06, -0.03, 0.4, 0.2, 0.1, 0.1)},
      {2, 0.03, TagPose(0.07, 0.04, 0.45, -0.1, 0.3, -0.2)}};
  const cv::Mat image = RenderTags(camera, *family, tags);
  TagDetector detector(TagDetectorOptions{});
  const auto full = detector.Detect(image);
  ASSERT_EQ(full.size(), 2u);
  std::vector<cv::Rect> rois;
  for (const TagDetection& d : full) {
    cv::Rect r(int(d.corners[0].x()), int(d.corners[0].y()), 1, 1);
    for (const auto& c : d.corners) r |= cv::Rect(int(c.x()), int(c.y()), 1, 1);
    rois.push_back(r + cv::Size(40, 40) - cv::Point(20, 20));
  }
  const auto roi = detector.Detect(image, rois);
  ASSERT_EQ(roi.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(roi[i].id, full[i].id);
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((roi[i].corners[k] - full[i].corners[k]).norm(), 0.15);
  }
  // A region that holds no tag finds nothing.
  EXPECT_TRUE(detector.Detect(image, {cv::Rect(0, 0, 60, 60)}).empty());
}

struct BiasStats {
  Eigen::Vector2d mean_xy = Eigen::Vector2d::Zero();
  double mean_outward = 0;  // along the corner's outward diagonal
  double rms = 0;
  int n = 0;
};

// Corner errors over randomly posed tags rendered exactly (edge_m metres
// wide at 0.25-0.45 m) over a grey background (110) or white paper (255),
// blurred by a Gaussian of blur_px when above 0.
BiasStats MeasureBias(const TagDetectorOptions& options, int num_images,
                      uint32_t seed, double edge_m = 0.035, double blur_px = 0,
                      double background = 110) {
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  TagDetector detector(options);
  BiasStats s;
  double sum_sq = 0;
  for (int i = 0; i < num_images; ++i) {
    std::vector<PlacedTag> tags;
    for (int j = 0; j < 4; ++j) {
      const double x = (j % 2 ? 0.065 : -0.065) + 0.01 * u(rng);
      const double y = (j / 2 ? 0.045 : -0.045) + 0.01 * u(rng);
      tags.push_back({j + 4 * (i % 5), edge_m,
                      TagPose(x, y, 0.35 + 0.1 * u(rng), 0.6 * u(rng),
                              0.6 * u(rng), M_PI * u(rng))});
    }
    cv::Mat image = RenderTags(camera, *family, tags, 6, background);
    if (blur_px > 0) cv::GaussianBlur(image, image, cv::Size(), blur_px);
    for (const TagDetection& d : detector.Detect(image)) {
      const PlacedTag* tag = nullptr;
      for (const PlacedTag& t : tags)
        if (t.id == d.id) tag = &t;
      if (!tag) continue;
      const auto truth = TrueCorners(camera, *tag);
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const auto& c : truth) centre += 0.25 * c;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d e = d.corners[k] - truth[k];
        s.mean_xy += e;
        s.mean_outward += e.dot((truth[k] - centre).normalized());
        sum_sq += e.squaredNorm();
        ++s.n;
      }
    }
  }
  s.mean_xy /= s.n;
  s.mean_outward /= s.n;
  s.rms = std::sqrt(sum_sq / s.n);
  return s;
}

TEST(TagDetectorTest, RawCornersAreOffsetByHalfAPixel) {
  TagDetectorOptions raw;
  raw.pixel_offset_px = 0.0;
  raw.edge_outward_px = 0.0;
  raw.edge_fit = false;
  const BiasStats s = MeasureBias(raw, 10, 7);
  std::printf("raw: mean (%.3f, %.3f) px, outward %.3f px, rms %.3f px, n %d\n",
              s.mean_xy.x(), s.mean_xy.y(), s.mean_outward, s.rms, s.n);
  EXPECT_NEAR(s.mean_xy.x(), 0.5, 0.1);
  EXPECT_NEAR(s.mean_xy.y(), 0.5, 0.1);
}

TEST(TagDetectorTest, CorrectedCornersHaveNoMeasurableBias) {
  for (double decimate : {1.0, 2.0}) {
    TagDetectorOptions options;
    options.quad_decimate = decimate;
    const BiasStats s = MeasureBias(options, 10, 11);
    std::printf(
        "decimate %.0f: mean (%.3f, %.3f) px, outward %.3f px, rms %.3f px, "
        "n %d\n",
        decimate, s.mean_xy.x(), s.mean_xy.y(), s.mean_outward, s.rms, s.n);
    EXPECT_GT(s.n, 100);
    EXPECT_LE(std::abs(s.mean_xy.x()), 0.05);
    EXPECT_LE(std::abs(s.mean_xy.y()), 0.05);
    EXPECT_LE(std::abs(s.mean_outward), 0.05);
    EXPECT_LT(s.rms, 0.25);
  }
}

// Small tags printed on white paper, under blur: the one-cell black border
// is lightened by the white cells inside it, so a profile's own dark end
// overstates the border's black and its edges move outward; the border's
// black read where a black cell backs it takes most of that bias away.
TEST(TagDetectorTest, BlurredSmallTagsKeepTheirSizeWithTheBordersOwnBlack) {
  for (double blur : {0.8, 1.2}) {
    TagDetectorOptions options;
    options.quad_decimate = 1;
    // 20 mm tags at 0.25-0.45 m: 25-45 px, cells of 3-5.5 px.
    const BiasStats fit = MeasureBias(options, 10, 13, 0.02, blur, 255);
    options.edge_fit_border_black = false;
    const BiasStats local = MeasureBias(options, 10, 13, 0.02, blur, 255);
    std::printf(
        "blur %.1f px: outward %.3f px, rms %.3f px (local dark: %.3f px, "
        "rms %.3f px), n %d\n",
        blur, fit.mean_outward, fit.rms, local.mean_outward, local.rms, fit.n);
    EXPECT_GT(fit.n, 100);
    // What remains at the heavier blur (sigma 0.4 cell on the smallest
    // tags): the white cells diagonal to a black-backed border cell still
    // lift its black a little.
    EXPECT_LE(std::abs(fit.mean_outward), blur < 1 ? 0.025 : 0.08) << blur;
    EXPECT_LT(std::abs(fit.mean_outward), 0.5 * local.mean_outward) << blur;
    EXPECT_LT(fit.rms, 0.6 * local.rms) << blur;
  }
}

TEST(TagDetectorTest, BorderBlackNeedsTheTagsCellsAndSmallCells) {
  // No bitmap: each profile's own dark end, as before; an all-white bitmap
  // (no black cell inside the border) the same; a tag whose cells are over
  // 7 px the same (the correction fades out from 5 to 7 px).
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  const std::vector<PlacedTag> tags = {
      {5, 0.02, TagPose(0.0, 0.0, 0.4, 0.2, -0.1, 0.3)}};
  cv::Mat image = RenderTags(camera, *family, tags);
  cv::GaussianBlur(image, image, cv::Size(), 1.0);
  const auto truth = TrueCorners(camera, tags[0]);
  const double cell =
      0.25 *
      ((truth[1] - truth[0]).norm() + (truth[2] - truth[1]).norm() +
       (truth[3] - truth[2]).norm() + (truth[0] - truth[3]).norm()) /
      family->width_at_border();
  const auto plain = FitTagEdges(image, truth, cell, {}).corners;
  std::optional<TagBitmap> white = MakeTagBitmap(*family, 5);
  ASSERT_TRUE(white);
  for (auto& c : white->cells) c = 255;
  const auto same = FitTagEdges(image, truth, cell, {}, &*white).corners;
  const std::optional<TagBitmap> bitmap = MakeTagBitmap(*family, 5);
  const auto fitted = FitTagEdges(image, truth, cell, {}, &*bitmap).corners;
  double moved = 0;
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(same[k], plain[k]);
    moved += (fitted[k] - plain[k]).norm();
  }
  EXPECT_GT(moved, 0.01);

  const std::vector<PlacedTag> large = {
      {5, 0.04, TagPose(0.0, 0.0, 0.25, 0.2, -0.1, 0.3)}};  // ~11 px cells
  cv::Mat near = RenderTags(camera, *family, large);
  cv::GaussianBlur(near, near, cv::Size(), 1.0);
  const auto large_truth = TrueCorners(camera, large[0]);
  const double large_cell =
      (large_truth[1] - large_truth[0]).norm() / family->width_at_border();
  ASSERT_GT(large_cell, 7.5);
  const auto large_plain =
      FitTagEdges(near, large_truth, large_cell, {}).corners;
  const auto large_fitted =
      FitTagEdges(near, large_truth, large_cell, {}, &*bitmap).corners;
  for (int k = 0; k < 4; ++k) EXPECT_EQ(large_fitted[k], large_plain[k]);
}

// The largest distance of a detected corner from the truth among corners
// the detector did not report hidden, and how many it reported hidden.
struct CornerCheck {
  double worst_trusted_px = 0;
  int hidden = 0;
};
CornerCheck CheckCorners(const TagDetection& d,
                         const std::array<Eigen::Vector2d, 4>& truth) {
  CornerCheck c;
  for (int k = 0; k < 4; ++k) {
    if (d.corner_occluded[k]) {
      ++c.hidden;
    } else {
      c.worst_trusted_px =
          std::max(c.worst_trusted_px, (d.corners[k] - truth[k]).norm());
    }
  }
  return c;
}

// A tag running off the bottom of the frame: libapriltag outlines what is
// in the image, so its two lower corners sit on the frame's last rows. The
// edge fit cannot read profiles beyond the image; those corners are
// reported hidden (or placed by the lines, when those can be fitted).
TEST(TagDetectorTest, CornersBeyondTheImagesBorderAreReportedHidden) {
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  int hidden = 0, detected = 0;
  for (double y : {0.150, 0.153, 0.156}) {
    const std::vector<PlacedTag> tags = {
        {4, 0.04, TagPose(0.0, y, 0.4, 0.2, -0.1, 0.1)}};
    cv::Mat image = RenderTags(camera, *family, tags, 6, 200);
    cv::GaussianBlur(image, image, cv::Size(), 0.8);
    const auto truth = TrueCorners(camera, tags[0]);
    TagDetectorOptions options;
    options.quad_decimate = 1;
    TagDetector detector(options);
    for (const TagDetection& d : detector.Detect(image)) {
      ++detected;
      const CornerCheck c = CheckCorners(d, truth);
      std::printf(
          "tag off the border (y %.3f m, lowest corner at %.1f px): "
          "%d hidden, worst trusted corner %.3f px\n",
          y, std::max(truth[2].y(), truth[3].y()), c.hidden,
          c.worst_trusted_px);
      EXPECT_LT(c.worst_trusted_px, 0.3);
      hidden += c.hidden;
    }
  }
  EXPECT_GT(detected, 0);
  EXPECT_GT(hidden, 0);
}

// A finger over a tag's corner, as bright as 0.65 of the paper: along the
// covered part of the two edges the border meets the finger, not the
// margin, and libapriltag's outline follows the finger. The edge fit leaves
// those profiles out and places the corner by the uncovered rest of its
// edges, or reports it hidden; without the margin test it is pulled off.
TEST(TagDetectorTest, AFingerOverACornerIsSeenPastOrReportedHidden) {
  const Camera camera = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  double worst_with = 0, worst_without = 0;
  for (int corner = 0; corner < 4; ++corner) {
    const std::vector<PlacedTag> tags = {
        {9, 0.03, TagPose(0.01, -0.01, 0.45, 0.3, 0.2, 0.4)}};
    cv::Mat image = RenderTags(camera, *family, tags);
    const auto truth = TrueCorners(camera, tags[0]);
    const double cell = (truth[1] - truth[0]).norm() / 8;
    // A finger along the edge that ends at the corner: it covers the
    // margin there and a third of a cell of the border, on the edge's half
    // next to the corner, and reaches past the corner.
    const Eigen::Vector2d a = truth[(corner + 3) % 4], b = truth[corner];
    const Eigen::Vector2d along = (b - a).normalized();
    Eigen::Vector2d out(along.y(), -along.x());
    if (out.dot(b - 0.5 * (truth[0] + truth[2])) < 0) out = -out;
    const Eigen::Vector2d from = 0.5 * (a + b) - 0.33 * cell * out;
    const Eigen::Vector2d to = b + 2.0 * cell * along + 2.5 * cell * out;
    const Eigen::Vector2d quad[4] = {from,
                                     from + (to - from).dot(along) * along, to,
                                     from + (to - from).dot(out) * out};
    std::vector<cv::Point> poly;
    for (const auto& q : quad)
      poly.emplace_back(static_cast<int>(std::lround(q.x() * 16)),
                        static_cast<int>(std::lround(q.y() * 16)));
    cv::fillConvexPoly(image, poly, cv::Scalar(150), cv::LINE_AA, 4);
    cv::GaussianBlur(image, image, cv::Size(), 0.7);
    for (bool margin_test : {true, false}) {
      TagDetectorOptions options;
      options.quad_decimate = 1;
      if (!margin_test) options.edge_fit_limits.margin_share = 0;
      TagDetector detector(options);
      const std::vector<TagDetection> found = detector.Detect(image);
      ASSERT_EQ(found.size(), 1u);
      const CornerCheck c = CheckCorners(found[0], truth);
      std::printf(
          "finger over corner %d, margin test %s: %d hidden, worst "
          "trusted corner %.3f px\n",
          corner, margin_test ? "on" : "off", c.hidden, c.worst_trusted_px);
      double& worst = margin_test ? worst_with : worst_without;
      worst = std::max(worst, c.worst_trusted_px);
    }
  }
  EXPECT_LT(worst_with, 0.3);
  EXPECT_GT(worst_without, 0.5);
}

// Tags near the edge of a barrel-distorting lens (k1 -0.28, k2 0.09: the
// synthetic `lens` variant's): their edges are curved in the image. Lines
// fitted in the lens's undistorted pixels put the corners where they are;
// lines fitted to the curved edges miss them by about twice as much.
TEST(TagDetectorTest, EdgesAreFittedStraightThroughTheLens) {
  Camera lens = TestCamera();
  lens.dist = {-0.28, 0.09, 0.0006, -0.0004, 0, 0, 0, 0};
  const Camera pinhole = TestCamera();
  auto family = TagFamily::Create("tag36h11");
  // The pinhole render, then each distorted pixel read from where the lens
  // maps it (bilinear, on a 6x6-supersampled render: its own blur is far
  // below the corners' errors measured here).
  cv::Mat map_x(lens.height, lens.width, CV_32F),
      map_y(lens.height, lens.width, CV_32F);
  for (int y = 0; y < lens.height; ++y) {
    for (int x = 0; x < lens.width; ++x) {
      const Eigen::Vector2d q = lens.UndistortToNormalized({x, y});
      map_x.at<float>(y, x) = static_cast<float>(lens.fx * q.x() + lens.cx);
      map_y.at<float>(y, x) = static_cast<float>(lens.fy * q.y() + lens.cy);
    }
  }
  double sq_with = 0, sq_without = 0, out_with = 0, out_without = 0;
  int n = 0;
  for (int i = 0; i < 6; ++i) {
    const double a = i * M_PI / 3 + 0.3;
    const std::vector<PlacedTag> tags = {
        {2 + i, 0.04,
         TagPose(0.17 * std::cos(a), 0.13 * std::sin(a), 0.45, 0.3, -0.2,
                 0.2 * i)}};
    const cv::Mat ideal = RenderTags(pinhole, *family, tags, 6, 200);
    cv::Mat image;
    cv::remap(ideal, image, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
              cv::Scalar(200));
    cv::GaussianBlur(image, image, cv::Size(), 0.7);
    const auto truth = TrueCorners(lens, tags[0]);
    const Eigen::Vector2d centre =
        0.25 * (truth[0] + truth[1] + truth[2] + truth[3]);
    for (bool with_lens : {true, false}) {
      TagDetectorOptions options;
      options.quad_decimate = 1;
      if (with_lens) options.lens = lens;
      TagDetector detector(options);
      const std::vector<TagDetection> found = detector.Detect(image);
      ASSERT_EQ(found.size(), 1u);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d e = found[0].corners[k] - truth[k];
        const double outward = e.dot((truth[k] - centre).normalized());
        (with_lens ? sq_with : sq_without) += e.squaredNorm();
        (with_lens ? out_with : out_without) += outward;
      }
    }
    n += 4;
  }
  const double rms_with = std::sqrt(sq_with / n),
               rms_without = std::sqrt(sq_without / n);
  std::printf(
      "tags through a distorting lens: corner RMS %.3f px (outward "
      "%+.3f) with the lens, %.3f px (%+.3f) without, %d corners\n",
      rms_with, out_with / n, rms_without, out_without / n, n);
  EXPECT_LT(rms_with, 0.7 * rms_without);
  EXPECT_LT(std::abs(out_with / n), 0.02);
}

}  // namespace
}  // namespace ripple::tracking
