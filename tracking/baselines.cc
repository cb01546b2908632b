#include "tracking/baselines.h"

#include <apriltag.h>
#include <apriltag_pose.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <opencv2/calib3d.hpp>

namespace ripple::tracking {
namespace {

Eigen::Vector2d UndistortedPixel(const Camera& camera,
                                 const Eigen::Vector2d& normalized) {
  return {camera.fx * normalized.x() + camera.cx,
          camera.fy * normalized.y() + camera.cy};
}

// Homography mapping (x, y) to (u, v) for four correspondences (h33 = 1).
Eigen::Matrix3d Homography4(const Eigen::Vector2d src[4],
                            const Eigen::Vector2d dst[4]) {
  Eigen::Matrix<double, 8, 8> a;
  Eigen::Matrix<double, 8, 1> b;
  for (int i = 0; i < 4; ++i) {
    const double x = src[i].x(), y = src[i].y(), u = dst[i].x(), v = dst[i].y();
    a.row(2 * i) << x, y, 1, 0, 0, 0, -u * x, -u * y;
    a.row(2 * i + 1) << 0, 0, 0, x, y, 1, -v * x, -v * y;
    b(2 * i) = u;
    b(2 * i + 1) = v;
  }
  const Eigen::Matrix<double, 8, 1> h = a.fullPivLu().solve(b);
  Eigen::Matrix3d m;
  m << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), 1.0;
  return m;
}

// A matd_t laid out as libapriltag allocates it (one block, flexible array
// member), so free() releases what estimate_tag_pose returns (DESIGN.md).
matd_t* NewMatd(int rows, int cols) {
  matd_t* m = static_cast<matd_t*>(
      std::calloc(1, sizeof(matd_t) + sizeof(double) * rows * cols));
  m->nrows = rows;
  m->ncols = cols;
  return m;
}

std::optional<Pose> ApriltagTagPose(const Camera& camera,
                                    const TagObservation& tag,
                                    double* object_error) {
  // libapriltag's corner order: BL, BR, TR, TL of the tag image; its
  // homography maps (-1,-1), (1,-1), (1,1), (-1,1) onto them.
  Eigen::Vector2d src[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  Eigen::Vector2d dst[4];
  apriltag_detection_t det{};
  for (int i = 0; i < 4; ++i) {
    dst[i] = UndistortedPixel(camera, tag.normalized[3 - i]);
    det.p[i][0] = dst[i].x();
    det.p[i][1] = dst[i].y();
  }
  const Eigen::Matrix3d h = Homography4(src, dst);
  det.H = NewMatd(3, 3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) det.H->data[r * 3 + c] = h(r, c);
  det.c[0] = 0.25 * (dst[0].x() + dst[1].x() + dst[2].x() + dst[3].x());
  det.c[1] = 0.25 * (dst[0].y() + dst[1].y() + dst[2].y() + dst[3].y());
  det.id = tag.id;
  apriltag_detection_info_t info{&det,      tag.edge_m, camera.fx,
                                 camera.fy, camera.cx,  camera.cy};
  apriltag_pose_t pose{nullptr, nullptr};
  const double err = estimate_tag_pose(&info, &pose);
  std::free(det.H);
  if (!pose.R || !pose.t) {
    std::free(pose.R);
    std::free(pose.t);
    return std::nullopt;
  }
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = pose.R->data[i * 3 + j];
    t(i) = pose.t->data[i];
  }
  std::free(pose.R);
  std::free(pose.t);
  if (!r.allFinite() || !t.allFinite() || t.z() <= 0) return std::nullopt;
  // Re-orthonormalise (orthogonal iteration leaves ~1e-12 drift).
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) return std::nullopt;
  if (object_error) *object_error = err;
  return Pose::FromMatrix(r, t);
}

}  // namespace

std::optional<Pose> PaperFrontalTagPose(
    const Camera& camera, const std::vector<TagObservation>& observations) {
  std::optional<Pose> best;
  double best_cos = -2;
  for (const TagObservation& o : observations) {
    double err = 0;
    const std::optional<Pose> cam_from_tag = ApriltagTagPose(camera, o, &err);
    if (!cam_from_tag) continue;
    const Eigen::Vector3d z = cam_from_tag->R().col(2);
    const double c = z.dot(cam_from_tag->translation.normalized());
    if (c > best_cos) {
      best_cos = c;
      best = *cam_from_tag * o.object_from_tag.Inverse();
    }
  }
  return best;
}

std::optional<Pose> OpenCvIppeBestTagPose(
    const Camera& camera, const std::vector<TagObservation>& observations,
    const Eigen::Vector3d& point_in_object) {
  std::optional<Pose> best;
  double best_sigma = std::numeric_limits<double>::infinity();
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0,
                      1);
  for (const TagObservation& o : observations) {
    const double h = 0.5 * o.edge_m;
    const std::vector<cv::Point3d> object = {
        {-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
    std::vector<cv::Point2d> image;
    for (int c : {3, 2, 1, 0}) {
      const Eigen::Vector2d u = UndistortedPixel(camera, o.normalized[c]);
      image.emplace_back(u.x(), u.y());
    }
    cv::Vec3d rvec, tvec;
    bool ok = false;
    try {
      ok = cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, false,
                        cv::SOLVEPNP_IPPE_SQUARE);
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) continue;
    const Pose cam_from_tag =
        Pose::FromAxisAngle(Eigen::Vector3d(rvec[0], rvec[1], rvec[2]),
                            Eigen::Vector3d(tvec[0], tvec[1], tvec[2]));
    const Pose cam_from_object = cam_from_tag * o.object_from_tag.Inverse();
    const double sigma =
        PointUncertainty(camera, {o}, cam_from_object, point_in_object);
    if (sigma < best_sigma || !best) {
      best_sigma = sigma;
      best = cam_from_object;
    }
  }
  return best;
}

std::optional<Pose> SqpnpLmPose(
    const Camera& camera, const std::vector<TagObservation>& observations) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const TagObservation& o : observations) {
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector3d& x = o.corners_in_object[c];
      object.emplace_back(x.x(), x.y(), x.z());
      const Eigen::Vector2d u = UndistortedPixel(camera, o.normalized[c]);
      image.emplace_back(u.x(), u.y());
    }
  }
  if (object.size() < 4) return std::nullopt;
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0,
                      1);
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, false,
                      cv::SOLVEPNP_SQPNP))
      return std::nullopt;
    cv::solvePnPRefineLM(object, image, k, cv::noArray(), rvec, tvec);
  } catch (const cv::Exception&) {
    return std::nullopt;
  }
  rvec.convertTo(rvec, CV_64F);
  tvec.convertTo(tvec, CV_64F);
  const Pose pose = Pose::FromAxisAngle(
      Eigen::Vector3d(rvec.at<double>(0), rvec.at<double>(1),
                      rvec.at<double>(2)),
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1),
                      tvec.at<double>(2)));
  if (pose.translation.z() <= 0) return std::nullopt;
  return pose;
}

}  // namespace ripple::tracking
