// Synthetic calibration data: perturbed rigs (the truth a real user's
// printing and gluing produce) and tag detections computed from projected
// corners plus Gaussian pixel noise.
#ifndef RIPPLE_TESTS_CALIB_CALIB_SCENE_H_
#define RIPPLE_TESTS_CALIB_CALIB_SCENE_H_

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"

namespace ripple::calib::testing {

using tracking::Pose;
using tracking::TagPlacement;

inline Eigen::Vector3d RandomUnit(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Vector3d v(n(*rng), n(*rng), n(*rng));
  return v.normalized();
}

// A rigid perturbation of up to `max_m` and `max_rad`, at least half of each.
inline Pose RandomPerturbation(std::mt19937* rng, double max_m,
                               double max_rad) {
  std::uniform_real_distribution<double> u(0.5, 1.0);
  return Pose::FromAxisAngle(RandomUnit(rng) * max_rad * u(*rng),
                             RandomUnit(rng) * max_m * u(*rng));
}

// Each tag moved about its own centre.
inline std::vector<TagPlacement> Perturbed(std::vector<TagPlacement> tags,
                                           std::mt19937* rng, double max_m,
                                           double max_rad) {
  for (TagPlacement& t : tags)
    t.object_from_tag =
        t.object_from_tag * RandomPerturbation(rng, max_m, max_rad);
  return tags;
}

// The truth re-expressed in the frame the calibration uses: the reference
// tag at its nominal pose.
inline std::vector<TagPlacement> Regauged(
    const std::vector<TagPlacement>& truth,
    const std::vector<TagPlacement>& nominal, int reference) {
  Pose fixed, moved;
  for (size_t i = 0; i < truth.size(); ++i)
    if (truth[i].id == reference) {
      fixed = nominal[i].object_from_tag;
      moved = truth[i].object_from_tag;
    }
  const Pose nominal_from_truth = fixed * moved.Inverse();
  std::vector<TagPlacement> out = truth;
  for (TagPlacement& t : out)
    t.object_from_tag = nominal_from_truth * t.object_from_tag;
  return out;
}

// `calibrated` moved by the rigid transform that best aligns its corners
// with `truth`'s (Umeyama): compares layouts independently of the gauge.
inline std::vector<TagPlacement> AlignedTo(
    const std::vector<TagPlacement>& calibrated,
    const std::vector<TagPlacement>& truth) {
  Eigen::Matrix3Xd a(3, 4 * truth.size()), b(3, 4 * truth.size());
  for (size_t i = 0; i < truth.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      a.col(4 * i + k) = calibrated[i].CornerInObject(k);
      b.col(4 * i + k) = truth[i].CornerInObject(k);
    }
  const Eigen::Matrix4d m = Eigen::umeyama(a, b, false);
  const Pose truth_from_calibrated =
      Pose::FromMatrix(m.topLeftCorner<3, 3>(), m.topRightCorner<3, 1>());
  std::vector<TagPlacement> out = calibrated;
  for (TagPlacement& t : out)
    t.object_from_tag = truth_from_calibrated * t.object_from_tag;
  return out;
}

// Detections of the tags facing the camera (within `max_view_deg` of the
// line of sight) whose corners are all inside the image, with Gaussian
// corner noise of `noise_px`.
inline std::vector<tracking::TagDetection> ProjectTags(
    const tracking::Camera& camera, const std::vector<TagPlacement>& tags,
    const Pose& cam_from_object, double noise_px, std::mt19937* rng,
    double max_view_deg = 70) {
  std::normal_distribution<double> noise(0, noise_px);
  std::vector<tracking::TagDetection> out;
  for (const TagPlacement& t : tags) {
    const Pose cam_from_tag = cam_from_object * t.object_from_tag;
    const Eigen::Vector3d into = cam_from_tag.R().col(2);  // into the tag
    const Eigen::Vector3d ray = cam_from_tag.translation.normalized();
    if (into.dot(ray) < std::cos(max_view_deg * M_PI / 180)) continue;
    tracking::TagDetection d;
    d.id = t.id;
    d.decision_margin = 100;
    bool inside = true;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = cam_from_object * t.CornerInObject(k);
      if (p.z() < 0.01) inside = false;
      d.corners[k] =
          camera.Project(p) + Eigen::Vector2d(noise(*rng), noise(*rng));
      inside = inside && d.corners[k].x() > 2 &&
               d.corners[k].x() < camera.width - 3 && d.corners[k].y() > 2 &&
               d.corners[k].y() < camera.height - 3;
    }
    if (inside) out.push_back(d);
  }
  return out;
}

// Uniformly random rotation.
inline Eigen::Quaterniond RandomRotation(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Quaterniond(n(*rng), n(*rng), n(*rng), n(*rng)).normalized();
}

}  // namespace ripple::calib::testing

#endif  // RIPPLE_TESTS_CALIB_CALIB_SCENE_H_
