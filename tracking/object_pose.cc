#include "tracking/object_pose.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/calib3d.hpp>

namespace ripple::tracking {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

struct CornerCost {
  CornerCost(const Camera* camera, const Eigen::Vector3d& x_in_object,
             const Eigen::Vector2d& observed, double scale)
      : camera(camera), x(x_in_object), obs(observed), scale(scale) {}

  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> translation(t);
    const Eigen::Matrix<T, 3, 1> p = rotation * x.cast<T>() + translation;
    if (!(p.z() > T(1e-6))) return false;
    const Eigen::Matrix<T, 2, 1> uv = camera->Project(p);
    residual[0] = (uv.x() - T(obs.x())) * scale;
    residual[1] = (uv.y() - T(obs.y())) * scale;
    return true;
  }

  const Camera* camera;
  Eigen::Vector3d x;
  Eigen::Vector2d obs;
  double scale;  // square root of the corner's weight
};

bool InFront(const std::vector<TagObservation>& observations,
             const Pose& cam_from_object) {
  for (const TagObservation& o : observations)
    for (const Eigen::Vector3d& c : o.corners_in_object)
      if ((cam_from_object * c).z() <= 1e-6) return false;
  return true;
}

// Fast score without distortion (normalised coordinates, scaled to pixels).
double NormalizedSse(const Camera& camera,
                     const std::vector<TagObservation>& observations,
                     const Pose& cam_from_object) {
  const Eigen::Matrix3d r = cam_from_object.R();
  const Eigen::Vector3d& t = cam_from_object.translation;
  double sse = 0;
  for (const TagObservation& o : observations) {
    for (int k = 0; k < 4; ++k) {
      if (o.occluded[k]) continue;
      const Eigen::Vector3d p = r * o.corners_in_object[k] + t;
      if (p.z() <= 1e-6) return std::numeric_limits<double>::infinity();
      const double dx = camera.fx * (p.x() / p.z() - o.normalized[k].x());
      const double dy = camera.fy * (p.y() / p.z() - o.normalized[k].y());
      sse += dx * dx + dy * dy;
    }
  }
  return sse;
}

std::vector<int> TagIds(const std::vector<TagObservation>& observations) {
  std::vector<int> ids;
  for (const TagObservation& o : observations) ids.push_back(o.id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

void Finish(const Camera& camera,
            const std::vector<TagObservation>& observations, const Pose& pose,
            int iterations, ObjectPose* out) {
  out->cam_from_object = pose;
  out->sse_px2 = ReprojectionSse(camera, observations, pose, &out->num_corners);
  out->rmse_px =
      out->num_corners > 0 ? std::sqrt(out->sse_px2 / out->num_corners) : 0.0;
  out->tag_ids = TagIds(observations);
  out->iterations = iterations;
}

// Ceres refinement from `initial`; returns the refined pose and iterations.
Pose Refine(const PoseEstimatorOptions& options, const Camera& camera,
            const std::vector<TagObservation>& observations,
            const Pose& initial, int* iterations) {
  double q[4] = {initial.rotation.x(), initial.rotation.y(),
                 initial.rotation.z(), initial.rotation.w()};
  double t[3] = {initial.translation.x(), initial.translation.y(),
                 initial.translation.z()};
  std::unique_ptr<ceres::LossFunction> loss;
  const double s = options.loss_scale_px;
  if (options.loss == RobustLoss::kHuber) {
    loss = std::make_unique<ceres::HuberLoss>(s);
  } else if (options.loss == RobustLoss::kCauchy) {
    loss = std::make_unique<ceres::CauchyLoss>(s);
  }
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const TagObservation& o : observations) {
    double scale = 1.0;
    if (options.weight_by_view_angle && observations.size() > 1) {
      const Pose cam_from_tag = initial * o.object_from_tag;
      const double c =
          cam_from_tag.R().col(2).dot(cam_from_tag.translation.normalized());
      scale = std::clamp(c, 0.05, 1.0);  // weight c^2
    }
    for (int k = 0; k < 4; ++k) {
      if (o.occluded[k]) continue;
      auto* cost = new ceres::AutoDiffCostFunction<CornerCost, 2, 4, 3>(
          new CornerCost(&camera, o.corners_in_object[k], o.pixels[k], scale));
      problem.AddResidualBlock(cost, loss.get(), q, t);
    }
  }
  if (problem.NumResidualBlocks() == 0) return initial;
  problem.SetManifold(q, new ceres::EigenQuaternionManifold);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.function_tolerance = 1e-10;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-10;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  *iterations = static_cast<int>(summary.iterations.size());
  if (!summary.IsSolutionUsable()) return initial;
  Pose refined(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized(),
               Eigen::Vector3d(t[0], t[1], t[2]));
  return refined;
}

}  // namespace

bool PoseEstimatorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(loss_scale_px > 0)) return fail("loss_scale_px must be positive");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (max_init_tags < 1) return fail("max_init_tags must be >= 1");
  if (!(distinct_deg > 0 && distinct_deg < 180))
    return fail("distinct_deg must be in (0, 180)");
  if (!(ambiguity_ratio >= 1)) return fail("ambiguity_ratio must be >= 1");
  return true;
}

std::vector<TagObservation> MatchObservations(
    const Camera& camera, const std::vector<TagPlacement>& tags,
    const std::vector<TagDetection>& detections) {
  std::vector<TagObservation> out;
  for (const TagDetection& d : detections) {
    const TagPlacement* placement = nullptr;
    for (const TagPlacement& t : tags)
      if (t.id == d.id) placement = &t;
    if (!placement) continue;
    TagObservation o;
    o.id = d.id;
    o.edge_m = placement->edge_m;
    o.object_from_tag = placement->object_from_tag;
    for (int k = 0; k < 4; ++k) {
      o.corners_in_object[k] = placement->CornerInObject(k);
      o.pixels[k] = d.corners[k];
      o.normalized[k] = camera.UndistortToNormalized(d.corners[k]);
      o.occluded[k] = d.corner_occluded[k];
    }
    o.size_px = d.SizePx();
    out.push_back(o);
  }
  int usable = 0;
  for (const TagObservation& o : out)
    usable += static_cast<int>(
        std::count(o.occluded.begin(), o.occluded.end(), false));
  if (usable < 3)
    for (TagObservation& o : out) o.occluded.fill(false);
  return out;
}

std::vector<Pose> IppeSquare(const TagObservation& tag, double edge_m) {
  const float h = static_cast<float>(0.5 * edge_m);
  // SOLVEPNP_IPPE_SQUARE's fixed point order: (-h, h), (h, h), (h, -h),
  // (-h, -h) in the tag frame, i.e. our BL, BR, TR, TL.
  const std::vector<cv::Point3f> object = {
      {-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  std::vector<cv::Point2f> image;
  for (int k : {3, 2, 1, 0})
    image.emplace_back(static_cast<float>(tag.normalized[k].x()),
                       static_cast<float>(tag.normalized[k].y()));
  std::vector<cv::Mat> rvecs, tvecs;
  const cv::Matx33d k_identity = cv::Matx33d::eye();
  std::vector<Pose> poses;
  try {
    cv::solvePnPGeneric(object, image, k_identity, cv::noArray(), rvecs, tvecs,
                        false, cv::SOLVEPNP_IPPE_SQUARE);
  } catch (const cv::Exception&) {
    return poses;
  }
  for (size_t i = 0; i < rvecs.size(); ++i) {
    cv::Mat rv, tv;
    rvecs[i].convertTo(rv, CV_64F);
    tvecs[i].convertTo(tv, CV_64F);
    const Eigen::Vector3d aa(rv.at<double>(0), rv.at<double>(1),
                             rv.at<double>(2));
    const Eigen::Vector3d tt(tv.at<double>(0), tv.at<double>(1),
                             tv.at<double>(2));
    poses.push_back(Pose::FromAxisAngle(aa, tt));
  }
  return poses;
}

double ReprojectionSse(const Camera& camera,
                       const std::vector<TagObservation>& observations,
                       const Pose& cam_from_object, int* num_corners) {
  double sse = 0;
  int n = 0;
  for (const TagObservation& o : observations) {
    for (int k = 0; k < 4; ++k) {
      if (o.occluded[k]) continue;
      const Eigen::Vector3d p = cam_from_object * o.corners_in_object[k];
      if (p.z() <= 1e-6) {
        sse = std::numeric_limits<double>::infinity();
      } else {
        sse += (camera.Project(p) - o.pixels[k]).squaredNorm();
      }
      ++n;
    }
  }
  if (num_corners) *num_corners = n;
  return sse;
}

bool RefineObjectPose(const PoseEstimatorOptions& options, const Camera& camera,
                      const std::vector<TagObservation>& observations,
                      const Pose& initial, ObjectPose* out) {
  if (observations.empty() || !InFront(observations, initial)) return false;
  int iterations = 0;
  Pose pose = initial;
  if (options.refine)
    pose = Refine(options, camera, observations, initial, &iterations);
  if (!InFront(observations, pose)) return false;
  Finish(camera, observations, pose, iterations, out);
  return true;
}

bool EstimateObjectPose(const PoseEstimatorOptions& options,
                        const Camera& camera,
                        const std::vector<TagObservation>& observations,
                        const std::vector<Pose>& extra_candidates,
                        ObjectPose* out) {
  if (observations.empty()) return false;
  // IPPE candidates from the largest tags.
  std::vector<const TagObservation*> by_size;
  for (const TagObservation& o : observations) by_size.push_back(&o);
  std::sort(by_size.begin(), by_size.end(),
            [](const TagObservation* a, const TagObservation* b) {
              return a->size_px > b->size_px;
            });
  std::vector<Pose> candidates = extra_candidates;
  const int n_init =
      std::min<int>(options.max_init_tags, static_cast<int>(by_size.size()));
  for (int i = 0; i < n_init; ++i) {
    const TagObservation& o = *by_size[i];
    const Pose tag_from_object = o.object_from_tag.Inverse();
    for (const Pose& cam_from_tag : IppeSquare(o, o.edge_m))
      candidates.push_back(cam_from_tag * tag_from_object);
  }
  // Score all on all corners.
  struct Scored {
    double sse;
    Pose pose;
  };
  std::vector<Scored> scored;
  for (const Pose& c : candidates) {
    const double sse = NormalizedSse(camera, observations, c);
    if (std::isfinite(sse)) scored.push_back({sse, c});
  }
  if (scored.empty()) return false;
  std::sort(scored.begin(), scored.end(),
            [](const Scored& a, const Scored& b) { return a.sse < b.sse; });
  const Scored& best = scored.front();
  const Scored* alternative = nullptr;
  for (const Scored& s : scored) {
    if (RotationDistance(s.pose, best.pose) >
        options.distinct_deg * kDegToRad) {
      alternative = &s;
      break;
    }
  }
  ObjectPose first;
  if (!RefineObjectPose(options, camera, observations, best.pose, &first))
    return false;
  if (alternative &&
      alternative->sse <= options.ambiguity_ratio * best.sse + 1e-9) {
    ObjectPose second;
    if (RefineObjectPose(options, camera, observations, alternative->pose,
                         &second)) {
      const bool distinct =
          RotationDistance(second.cam_from_object, first.cam_from_object) >
          options.distinct_deg * kDegToRad;
      if (second.sse_px2 < first.sse_px2) std::swap(first, second);
      if (distinct) {
        first.alternative_rmse_px = second.rmse_px;
        first.alternative = second.cam_from_object;
      }
    }
  } else if (alternative) {
    int n = 0;
    const double sse =
        ReprojectionSse(camera, observations, alternative->pose, &n);
    first.alternative_rmse_px = n > 0 ? std::sqrt(sse / n) : first.rmse_px;
  }
  *out = first;
  return true;
}

double PointUncertainty(const Camera& camera,
                        const std::vector<TagObservation>& observations,
                        const Pose& cam_from_object,
                        const Eigen::Vector3d& point_in_object) {
  using Jet3 = ceres::Jet<double, 3>;
  const Eigen::Matrix3d r = cam_from_object.R();
  const Eigen::Vector3d& t = cam_from_object.translation;
  auto skew = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d m;
    m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return m;
  };
  // Perturbation delta = (omega, v): R' = exp(omega) R, t' = t + v, so
  // d(R x + t)/d delta = [-[R x]_x, I].
  Eigen::Matrix<double, 6, 6> jtj = Eigen::Matrix<double, 6, 6>::Zero();
  for (const TagObservation& o : observations) {
    for (int k = 0; k < 4; ++k) {
      if (o.occluded[k]) continue;
      const Eigen::Vector3d y = r * o.corners_in_object[k];
      const Eigen::Vector3d p = y + t;
      if (p.z() <= 1e-6) return std::numeric_limits<double>::infinity();
      Eigen::Matrix<Jet3, 3, 1> pj;
      for (int i = 0; i < 3; ++i) pj[i] = Jet3(p[i], i);
      const Eigen::Matrix<Jet3, 2, 1> uv = camera.Project(pj);
      Eigen::Matrix<double, 2, 3> jp;
      jp.row(0) = uv.x().v.transpose();
      jp.row(1) = uv.y().v.transpose();
      Eigen::Matrix<double, 3, 6> dp;
      dp << -skew(y), Eigen::Matrix3d::Identity();
      const Eigen::Matrix<double, 2, 6> j = jp * dp;
      jtj += j.transpose() * j;
    }
  }
  Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(jtj);
  if (!lu.isInvertible()) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix<double, 6, 6> cov = lu.inverse();
  Eigen::Matrix<double, 3, 6> dq;
  dq << -skew(r * point_in_object), Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d cov_q = dq * cov * dq.transpose();
  return std::sqrt(std::max(0.0, cov_q.trace()));
}

}  // namespace ripple::tracking
