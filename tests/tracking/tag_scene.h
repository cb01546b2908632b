// Test helpers for the tracking tests: a small exact ray-caster of planar
// tags (area-correct edges by supersampling, pinhole camera) and exact
// corner projections, so that detector and pose tests synthesize their own
// data (CONVENTIONS.md) independently of the synth module.
#ifndef RIPPLE_TESTS_TRACKING_TAG_SCENE_H_
#define RIPPLE_TESTS_TRACKING_TAG_SCENE_H_

#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "tracking/camera.h"
#include "tracking/object_pose.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"
#include "tracking/tag_family.h"

namespace ripple::tracking::testing {

struct PlacedTag {
  int id = 0;
  double edge_m = 0.03;
  Pose cam_from_tag;
};

// Renders tags (with their white margin) over a grey background. The camera
// must have no distortion. `supersample`^2 samples per pixel.
inline cv::Mat RenderTags(const Camera& camera, const TagFamily& family,
                          const std::vector<PlacedTag>& tags,
                          int supersample = 6, double background = 110) {
  cv::Mat acc(camera.height, camera.width, CV_64F, cv::Scalar(background));
  for (const PlacedTag& tag : tags) {
    const TagBitmap bitmap = *MakeTagBitmap(family, tag.id);
    const double cell = tag.edge_m / bitmap.width_at_border;
    const int border = (bitmap.total_width - bitmap.width_at_border) / 2;
    const double half_total = 0.5 * cell * bitmap.total_width;
    const Eigen::Matrix3d r = tag.cam_from_tag.R();
    const Eigen::Vector3d t = tag.cam_from_tag.translation;
    const Eigen::Vector3d n = r.col(2);
    // Bounding box of the whole bitmap.
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (int k = 0; k < 4; ++k) {
      const double sx = (k == 1 || k == 2) ? 1 : -1;
      const double sy = (k >= 2) ? 1 : -1;
      const Eigen::Vector2d uv = camera.Project(Eigen::Vector3d(
          r * Eigen::Vector3d(sx * half_total, sy * half_total, 0) + t));
      x0 = std::min(x0, uv.x());
      y0 = std::min(y0, uv.y());
      x1 = std::max(x1, uv.x());
      y1 = std::max(y1, uv.y());
    }
    const int u0 = std::max(0, int(std::floor(x0)) - 1);
    const int v0 = std::max(0, int(std::floor(y0)) - 1);
    const int u1 = std::min(camera.width - 1, int(std::ceil(x1)) + 1);
    const int v1 = std::min(camera.height - 1, int(std::ceil(y1)) + 1);
    const double nt = n.dot(t);
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        double sum = 0;
        int covered = 0;
        for (int i = 0; i < supersample; ++i) {
          for (int j = 0; j < supersample; ++j) {
            const double pu = u - 0.5 + (j + 0.5) / supersample;
            const double pv = v - 0.5 + (i + 0.5) / supersample;
            const Eigen::Vector3d d((pu - camera.cx) / camera.fx,
                                    (pv - camera.cy) / camera.fy, 1.0);
            const double s = nt / n.dot(d);
            if (!(s > 0)) continue;
            const Eigen::Vector3d local = r.transpose() * (s * d - t);
            const int col = int(std::floor((local.x() + half_total) / cell));
            const int row = int(std::floor((local.y() + half_total) / cell));
            if (col < 0 || row < 0 || col >= bitmap.total_width ||
                row >= bitmap.total_width)
              continue;
            (void)border;
            sum += bitmap.black(row, col) ? 25.0 : 230.0;
            ++covered;
          }
        }
        if (covered == 0) continue;
        const double frac = double(covered) / (supersample * supersample);
        double& px = acc.at<double>(v, u);
        px = px * (1 - frac) + sum / (supersample * supersample);
      }
    }
  }
  cv::Mat out;
  acc.convertTo(out, CV_8U);
  return out;
}

// Exact corners of a tag (TL, TR, BR, BL) in distorted pixels.
inline std::array<Eigen::Vector2d, 4> ProjectCorners(
    const Camera& camera, const TagPlacement& tag,
    const Pose& cam_from_object) {
  std::array<Eigen::Vector2d, 4> c;
  for (int k = 0; k < 4; ++k)
    c[k] = camera.Project(
        Eigen::Vector3d(cam_from_object * tag.CornerInObject(k)));
  return c;
}

// Detections of the given tags of an object, with Gaussian corner noise
// (pixels); tags facing away or behind the camera are skipped.
inline std::vector<TagDetection> ProjectDetections(
    const Camera& camera, const std::vector<TagPlacement>& tags,
    const Pose& cam_from_object, double noise_px, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<TagDetection> out;
  for (const TagPlacement& tag : tags) {
    const Pose cam_from_tag = cam_from_object * tag.object_from_tag;
    if (cam_from_tag.R().col(2).dot(cam_from_tag.translation) <= 0) continue;
    TagDetection d;
    d.id = tag.id;
    d.corners = ProjectCorners(camera, tag, cam_from_object);
    bool inside = true;
    for (auto& c : d.corners) {
      if (noise_px > 0) c += Eigen::Vector2d(noise(*rng), noise(*rng));
      inside = inside && c.x() > 0 && c.y() > 0 && c.x() < camera.width - 1 &&
               c.y() < camera.height - 1;
    }
    d.decision_margin = 100;
    if (inside) out.push_back(d);
  }
  return out;
}

inline std::vector<PlacedTag> PlaceObjectTags(
    const std::vector<TagPlacement>& tags, const Pose& cam_from_object) {
  std::vector<PlacedTag> out;
  for (const TagPlacement& t : tags)
    out.push_back({t.id, t.edge_m, cam_from_object * t.object_from_tag});
  return out;
}

}  // namespace ripple::tracking::testing

#endif  // RIPPLE_TESTS_TRACKING_TAG_SCENE_H_
