#include "tracking/tag_detector.h"

#include <apriltag.h>
#include <common/image_u8.h>
#include <common/zarray.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>

#include "geometry/check.h"
#include "tracking/bilinear.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {

double TagDetection::SizePx() const {
  double sum = 0;
  for (int k = 0; k < 4; ++k) sum += (corners[(k + 1) % 4] - corners[k]).norm();
  return 0.25 * sum;
}

bool TagDetectorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!TagFamily::Create(family))
    return fail("unknown tag family '" + family + "'");
  if (!(quad_decimate >= 1.0 && quad_decimate <= 8.0))
    return fail("quad_decimate must be in [1, 8]");
  if (!(quad_sigma >= 0.0)) return fail("quad_sigma must be >= 0");
  if (threads < 1 || threads > 64) return fail("threads must be in [1, 64]");
  if (max_hamming < 0 || max_hamming > 2)
    return fail("max_hamming must be 0, 1 or 2");
  if (min_white_black_diff < 0 || min_white_black_diff > 255)
    return fail("min_white_black_diff must be in [0, 255]");
  if (!(min_decision_margin >= 0.0))
    return fail("min_decision_margin must be >= 0");
  if (!(std::abs(pixel_offset_px) <= 2.0 && std::abs(edge_outward_px) <= 2.0))
    return fail("corner corrections must be within 2 px");
  return true;
}

std::array<Eigen::Vector2d, 4> CorrectCorners(
    const std::array<Eigen::Vector2d, 4>& raw, double pixel_offset_px,
    double edge_outward_px) {
  std::array<Eigen::Vector2d, 4> out;
  const Eigen::Vector2d offset(pixel_offset_px, pixel_offset_px);
  for (int k = 0; k < 4; ++k) out[k] = raw[k] - offset;
  if (edge_outward_px == 0.0) return out;
  const Eigen::Vector2d centre = 0.25 * (out[0] + out[1] + out[2] + out[3]);
  // Outward unit normal of edge k (corner k -> k+1).
  std::array<Eigen::Vector2d, 4> normal;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = out[k], b = out[(k + 1) % 4];
    Eigen::Vector2d n(b.y() - a.y(), a.x() - b.x());
    const double len = n.norm();
    if (len < 1e-9) return out;
    n /= len;
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    normal[k] = n;
  }
  std::array<Eigen::Vector2d, 4> shifted = out;
  for (int k = 0; k < 4; ++k) {
    // Corner k lies on edges k-1 and k; move it so that both lines shift
    // outward by edge_outward_px.
    Eigen::Matrix2d m;
    m.row(0) = normal[(k + 3) % 4].transpose();
    m.row(1) = normal[k].transpose();
    const double det = m.determinant();
    if (std::abs(det) < 1e-6) continue;
    shifted[k] = out[k] + m.inverse() *
                              Eigen::Vector2d(edge_outward_px, edge_outward_px);
  }
  return shifted;
}

namespace {

struct Line {
  Eigen::Vector2d point, dir;  // dir is unit
};

// Edge points of the edge a -> b with outward normal n; see FitTagEdges.
bool FitEdgeLine(const cv::Mat& g, const Eigen::Vector2d& a,
                 const Eigen::Vector2d& b, const Eigen::Vector2d& n,
                 double half_width, Line* line) {
  const double length = (b - a).norm();
  const int samples = std::clamp(static_cast<int>(length / 3), 5, 16);
  constexpr int kSteps = 12;
  std::vector<Eigen::Vector2d> points;
  points.reserve(samples);
  for (int i = 0; i < samples; ++i) {
    const double t = 0.12 + 0.76 * (i + 0.5) / samples;
    Eigen::Vector2d p = a + t * (b - a);
    bool ok = false;
    for (int pass = 0; pass < 3; ++pass) {
      // The first pass looks wider for a coarse corner (decimated quads).
      const double hw = pass == 0 ? std::max(half_width, 2.0) : half_width;
      const double step = 2 * hw / kSteps;
      double v[kSteps + 1];
      ok = true;
      for (int j = 0; j <= kSteps && ok; ++j) {
        const Eigen::Vector2d q = p + (-hw + j * step) * n;
        ok = SampleBilinear(g, q.x(), q.y(), &v[j]);
      }
      if (!ok) break;
      const double dark = (v[0] + v[1]) / 2,
                   bright = (v[kSteps - 1] + v[kSteps]) / 2;
      if (bright - dark < 10) {
        ok = false;
        break;
      }
      const double mid = 0.5 * (dark + bright);
      // The crossing nearest the window centre.
      double best = 1e9, offset = 0;
      for (int j = 0; j < kSteps; ++j) {
        if ((v[j] < mid) != (v[j + 1] < mid) && v[j + 1] > v[j]) {
          const double r = -hw + (j + (mid - v[j]) / (v[j + 1] - v[j])) * step;
          if (std::abs(r) < std::abs(best)) {
            best = r;
            offset = r;
          }
        }
      }
      if (best > 1e8) {
        ok = false;
        break;
      }
      p += offset * n;  // re-centre the window on the edge, then refine
    }
    if (ok) points.push_back(p);
  }
  if (points.size() < 4) return false;
  for (int iteration = 0; iteration < 2; ++iteration) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : points) mean += p;
    mean /= points.size();
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    line->point = mean;
    line->dir = eig.eigenvectors().col(1);
    if (iteration == 1) break;
    // Drop points far from the first fit (a blemish, an occluding edge).
    const Eigen::Vector2d normal(-line->dir.y(), line->dir.x());
    std::vector<double> dist;
    for (const auto& p : points) dist.push_back(std::abs(normal.dot(p - mean)));
    std::vector<double> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                     sorted.end());
    const double limit = std::max(0.3, 3.0 * sorted[sorted.size() / 2]);
    std::vector<Eigen::Vector2d> kept;
    for (size_t i = 0; i < points.size(); ++i)
      if (dist[i] <= limit) kept.push_back(points[i]);
    if (kept.size() < 4) return false;
    points.swap(kept);
  }
  return true;
}

}  // namespace

cv::Mat DecodeToLinearLut(geometry::Transfer transfer) {
  cv::Mat lut(1, 256, CV_8U);
  for (int i = 0; i < 256; ++i) {
    const double v = i / 255.0;
    const double l = transfer == geometry::Transfer::kLinear ? v
                     : v <= 0.04045                          ? v / 12.92
                                    : std::pow((v + 0.055) / 1.055, 2.4);
    lut.at<uint8_t>(i) = cv::saturate_cast<uint8_t>(std::lround(255.0 * l));
  }
  return lut;
}

std::array<Eigen::Vector2d, 4> FitTagEdges(
    const cv::Mat& gray, const std::array<Eigen::Vector2d, 4>& corners,
    double cell_px, double max_shift_px) {
  const Eigen::Vector2d centre =
      0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  const double half_width = std::clamp(0.6 * cell_px, 1.0, 3.0);
  std::array<Line, 4> lines;
  std::array<bool, 4> ok;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[(k + 1) % 4];
    Eigen::Vector2d n(b.y() - a.y(), a.x() - b.x());
    if (n.norm() < 1e-9) return corners;
    n.normalize();
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    ok[k] = FitEdgeLine(gray, a, b, n, half_width, &lines[k]);
  }
  std::array<Eigen::Vector2d, 4> out = corners;
  for (int k = 0; k < 4; ++k) {
    const int prev = (k + 3) % 4;
    if (!ok[prev] || !ok[k]) continue;
    // point_prev + s dir_prev = point_k + u dir_k
    Eigen::Matrix2d m;
    m.col(0) = lines[prev].dir;
    m.col(1) = -lines[k].dir;
    if (std::abs(m.determinant()) < 1e-3) continue;
    const Eigen::Vector2d su =
        m.inverse() * (lines[k].point - lines[prev].point);
    const Eigen::Vector2d c = lines[prev].point + su(0) * lines[prev].dir;
    if ((c - corners[k]).norm() <= max_shift_px) out[k] = c;
  }
  return out;
}

struct TagDetector::Impl {
  std::unique_ptr<TagFamily> family;
  apriltag_detector_t* detector = nullptr;
  cv::Mat gray;        // conversion buffer for colour input
  cv::Mat decode_lut;  // 8-bit value -> linear 8-bit; empty when linear
  cv::Mat linear;      // the decoded frame

  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), impl_(new Impl) {
  std::string error;
  RIPPLE_CHECK(options.IsValid(&error),
               "TagDetector: invalid options: " + error);
  impl_->family = TagFamily::Create(options.family);
  if (options.transfer != geometry::Transfer::kLinear)
    impl_->decode_lut = DecodeToLinearLut(options.transfer);
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family->get(),
                                    std::max(options.max_hamming, 1));
  apriltag_detector_t* td = impl_->detector;
  td->quad_decimate = static_cast<float>(options.quad_decimate);
  td->quad_sigma = static_cast<float>(options.quad_sigma);
  td->nthreads = options.threads;
  td->refine_edges = options.refine_edges;
  td->decode_sharpening = options.decode_sharpening;
  td->qtp.min_white_black_diff = options.min_white_black_diff;
  td->debug = false;
}

TagDetector::~TagDetector() = default;
TagDetector::TagDetector(TagDetector&&) noexcept = default;
TagDetector& TagDetector::operator=(TagDetector&&) noexcept = default;

std::vector<TagDetection> TagDetector::Detect(
    const cv::Mat& image, const std::vector<cv::Rect>& rois) {
  RIPPLE_CHECK(image.depth() == CV_8U, "TagDetector: image must be 8-bit");
  const cv::Mat* gray = &image;
  if (image.channels() == 3) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGR2GRAY);
    gray = &impl_->gray;
  } else if (image.channels() == 4) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGRA2GRAY);
    gray = &impl_->gray;
  }
  if (!impl_->decode_lut.empty()) {
    cv::LUT(*gray, impl_->decode_lut, impl_->linear);
    gray = &impl_->linear;
  }
  std::vector<cv::Rect> regions;
  const cv::Rect whole(0, 0, gray->cols, gray->rows);
  if (rois.empty()) {
    // libapriltag's quad search reads past the edges of images smaller than
    // a few pixels (it crashed on 1x1 and 4x3); no tag fits in them anyway.
    if (whole.width >= kMinImageSide && whole.height >= kMinImageSide)
      regions.push_back(whole);
  } else {
    for (const cv::Rect& r : rois) {
      const cv::Rect c = r & whole;
      if (c.width >= kMinImageSide && c.height >= kMinImageSide)
        regions.push_back(c);
    }
  }
  std::map<int, TagDetection> by_id;
  for (const cv::Rect& r : regions) {
    // A view into the frame: libapriltag reads rows with the parent stride.
    image_u8_t im{r.width, r.height, static_cast<int32_t>(gray->step[0]),
                  const_cast<uint8_t*>(gray->ptr<uint8_t>(r.y) + r.x)};
    zarray_t* found = apriltag_detector_detect(impl_->detector, &im);
    for (int i = 0; i < zarray_size(found); ++i) {
      apriltag_detection_t* det;
      zarray_get(found, i, &det);
      if (det->hamming > options_.max_hamming ||
          det->decision_margin < options_.min_decision_margin)
        continue;
      // libapriltag's p[] runs bottom-left, bottom-right, top-right,
      // top-left of the tag image (its tag frame has y down, p[0] at
      // (-1, +1)); ours is TL, TR, BR, BL.
      std::array<Eigen::Vector2d, 4> raw;
      for (int k = 0; k < 4; ++k) {
        raw[k] =
            Eigen::Vector2d(det->p[3 - k][0] + r.x, det->p[3 - k][1] + r.y);
      }
      TagDetection d;
      d.id = det->id;
      if (options_.edge_fit) {
        const auto shifted = CorrectCorners(raw, options_.pixel_offset_px, 0);
        double size = 0;
        for (int k = 0; k < 4; ++k)
          size += 0.25 * (shifted[(k + 1) % 4] - shifted[k]).norm();
        const double cell_px = size / impl_->family->width_at_border();
        d.corners = CorrectCorners(FitTagEdges(*gray, shifted, cell_px,
                                               options_.edge_fit_max_shift_px),
                                   0.0, options_.edge_outward_px);
      } else {
        d.corners = CorrectCorners(raw, options_.pixel_offset_px,
                                   options_.edge_outward_px);
      }
      d.decision_margin = det->decision_margin;
      d.hamming = det->hamming;
      auto it = by_id.find(d.id);
      if (it == by_id.end() || it->second.decision_margin < d.decision_margin)
        by_id[d.id] = d;
    }
    apriltag_detections_destroy(found);
  }
  std::vector<TagDetection> out;
  out.reserve(by_id.size());
  for (auto& [id, d] : by_id) out.push_back(d);
  return out;
}

}  // namespace ripple::tracking
