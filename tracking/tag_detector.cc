#include "tracking/tag_detector.h"

#include <apriltag.h>
#include <common/image_u8.h>
#include <common/zarray.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>

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

struct TagDetector::Impl {
  std::unique_ptr<TagFamily> family;
  apriltag_detector_t* detector = nullptr;
  cv::Mat gray;  // conversion buffer for colour input

  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), impl_(new Impl) {
  std::string error;
  if (!options.IsValid(&error)) {
    std::fprintf(stderr, "TagDetector: invalid options: %s\n", error.c_str());
    std::abort();
  }
  impl_->family = TagFamily::Create(options.family);
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family->get(),
                                    std::max(options.max_hamming, 1));
  apriltag_detector_t* td = impl_->detector;
  td->quad_decimate = static_cast<float>(options.quad_decimate);
  td->quad_sigma = static_cast<float>(options.quad_sigma);
  td->nthreads = options.threads;
  td->refine_edges = options.refine_edges;
  td->decode_sharpening = options.decode_sharpening;
  td->debug = false;
}

TagDetector::~TagDetector() = default;
TagDetector::TagDetector(TagDetector&&) noexcept = default;
TagDetector& TagDetector::operator=(TagDetector&&) noexcept = default;

std::vector<TagDetection> TagDetector::Detect(
    const cv::Mat& image, const std::vector<cv::Rect>& rois) {
  assert(image.depth() == CV_8U);
  const cv::Mat* gray = &image;
  if (image.channels() == 3) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGR2GRAY);
    gray = &impl_->gray;
  } else if (image.channels() == 4) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGRA2GRAY);
    gray = &impl_->gray;
  }
  std::vector<cv::Rect> regions;
  const cv::Rect whole(0, 0, gray->cols, gray->rows);
  if (rois.empty()) {
    regions.push_back(whole);
  } else {
    for (const cv::Rect& r : rois) {
      const cv::Rect c = r & whole;
      if (c.width >= 8 && c.height >= 8) regions.push_back(c);
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
      d.corners = CorrectCorners(raw, options_.pixel_offset_px,
                                 options_.edge_outward_px);
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
