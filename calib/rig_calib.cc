#include "calib/rig_calib.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

#include "tracking/object_pose.h"

namespace ripple::calib {
namespace {

using tracking::TagObservation;

// x_in_cam = init * D(view) * nominal_tag * D(tag) * x_in_tag, with D(p) the
// rigid correction (angle-axis p[0..2], translation p[3..5]) applied on the
// right, so that a tag's correction rotates about its own centre.
struct LayoutCornerCost {
  LayoutCornerCost(const tracking::Camera* camera,
                   const Eigen::Vector3d& x_in_tag, const Pose& object_from_tag,
                   const Pose& cam_from_object, const Eigen::Vector2d& pixel)
      : camera(camera),
        x(x_in_tag),
        tag(object_from_tag),
        view(cam_from_object),
        obs(pixel) {}

  template <typename T>
  bool operator()(const T* view_delta, const T* tag_delta, T* residual) const {
    T p[3] = {T(x.x()), T(x.y()), T(x.z())};
    T q[3];
    ceres::AngleAxisRotatePoint(tag_delta, p, q);
    Eigen::Matrix<T, 3, 1> in_tag(q[0] + tag_delta[3], q[1] + tag_delta[4],
                                  q[2] + tag_delta[5]);
    const Eigen::Matrix<T, 3, 1> in_object = tag.Cast<T>() * in_tag;
    T a[3] = {in_object.x(), in_object.y(), in_object.z()};
    T b[3];
    ceres::AngleAxisRotatePoint(view_delta, a, b);
    const Eigen::Matrix<T, 3, 1> corrected(
        b[0] + view_delta[3], b[1] + view_delta[4], b[2] + view_delta[5]);
    const Eigen::Matrix<T, 3, 1> in_cam = view.Cast<T>() * corrected;
    if (!(in_cam.z() > T(1e-6))) return false;
    const Eigen::Matrix<T, 2, 1> uv = camera->Project(in_cam);
    residual[0] = uv.x() - T(obs.x());
    residual[1] = uv.y() - T(obs.y());
    return true;
  }

  const tracking::Camera* camera;
  Eigen::Vector3d x;
  Pose tag, view;
  Eigen::Vector2d obs;
};

Pose DeltaPose(const std::array<double, 6>& d) {
  return Pose::FromAxisAngle(Eigen::Vector3d(d[0], d[1], d[2]),
                             Eigen::Vector3d(d[3], d[4], d[5]));
}

Eigen::Vector3d CornerInTag(double edge_m, int k) {
  static const double kSign[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  return Eigen::Vector3d(0.5 * edge_m * kSign[k][0], 0.5 * edge_m * kSign[k][1],
                         0.0);
}

struct UsedView {
  Pose cam_from_object;  // initial
  std::vector<TagObservation> observations;
};

}  // namespace

bool RigCalibOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (min_tags_per_view < 2) return fail("min_tags_per_view must be >= 2");
  if (min_views < 1) return fail("min_views must be >= 1");
  if (min_views_per_tag < 1) return fail("min_views_per_tag must be >= 1");
  if (!(max_initial_rmse_px > 0))
    return fail("max_initial_rmse_px must be > 0");
  if (!(loss_scale_px > 0)) return fail("loss_scale_px must be > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  return true;
}

std::string RigCalibSummary::BriefReport() const {
  std::string s;
  char line[256];
  std::snprintf(line, sizeof(line),
                "views used %d of %d, %d corners, reference tag %d\n"
                "reprojection RMS %.3f px before, %.3f px after (%d "
                "iterations%s)\n",
                views_used, views_total, num_corners, reference_id,
                rms_before_px, rms_after_px, iterations,
                converged ? "" : ", not converged");
  s += line;
  s += "  tag  views  moved_mm  rotated_deg\n";
  for (const TagAdjustment& t : tags) {
    if (t.id == reference_id) {
      std::snprintf(line, sizeof(line), "  %3d  %5d  reference\n", t.id,
                    t.views);
    } else if (!t.refined) {
      std::snprintf(line, sizeof(line),
                    "  %3d  %5d  not refined (too few views)\n", t.id, t.views);
    } else {
      std::snprintf(line, sizeof(line), "  %3d  %5d  %8.2f  %11.2f\n", t.id,
                    t.views, 1e3 * t.moved_m, t.rotated_rad * 180.0 / M_PI);
    }
    s += line;
  }
  return s;
}

bool CalibrateTagLayout(
    const RigCalibOptions& options, const tracking::Camera& camera,
    const std::vector<tracking::TagPlacement>& nominal,
    const std::vector<std::vector<tracking::TagDetection>>& detections_per_view,
    std::vector<tracking::TagPlacement>* calibrated, RigCalibSummary* summary,
    std::string* error) {
  if (!options.IsValid(error)) return false;
  if (nominal.empty()) {
    *error = "the object has no tags to calibrate";
    return false;
  }
  *summary = RigCalibSummary();
  summary->views_total = static_cast<int>(detections_per_view.size());

  // Views with enough of the object's tags, each with an initial pose from
  // the nominal layout.
  tracking::PoseEstimatorOptions pose_options;
  std::vector<UsedView> views;
  int views_with_any_tag = 0;
  for (const auto& detections : detections_per_view) {
    std::vector<TagObservation> obs =
        tracking::MatchObservations(camera, nominal, detections);
    if (!obs.empty()) ++views_with_any_tag;
    if (static_cast<int>(obs.size()) < options.min_tags_per_view) continue;
    tracking::ObjectPose pose;
    if (!tracking::EstimateObjectPose(pose_options, camera, obs, {}, &pose))
      continue;
    if (pose.rmse_px > options.max_initial_rmse_px) continue;
    views.push_back({pose.cam_from_object, std::move(obs)});
  }
  if (views_with_any_tag == 0) {
    *error = "no target found: none of the object's tags was detected in " +
             std::to_string(summary->views_total) + " views";
    return false;
  }

  // Tags per view and the reference.
  std::map<int, int> views_per_tag;
  for (const UsedView& v : views)
    for (const TagObservation& o : v.observations) ++views_per_tag[o.id];
  int reference = options.reference_id;
  if (reference >= 0) {
    bool known = false;
    for (const auto& t : nominal) known |= t.id == reference;
    if (!known) {
      *error = "reference tag " + std::to_string(reference) +
               " is not a tag of the object";
      return false;
    }
  } else {
    int best = 0;
    for (const auto& [id, n] : views_per_tag)
      if (n > best) best = n, reference = id;
  }
  // Tags to refine: seen often enough. Observations of other tags are
  // dropped (holding them at a wrong nominal pose would bias the rest).
  std::set<int> refine;
  for (const auto& [id, n] : views_per_tag)
    if (id != reference && n >= options.min_views_per_tag) refine.insert(id);
  std::vector<UsedView> kept;
  for (UsedView& v : views) {
    std::vector<TagObservation> obs;
    for (TagObservation& o : v.observations)
      if (o.id == reference || refine.count(o.id)) obs.push_back(std::move(o));
    if (static_cast<int>(obs.size()) >= options.min_tags_per_view)
      kept.push_back({v.cam_from_object, std::move(obs)});
  }
  views = std::move(kept);
  summary->views_used = static_cast<int>(views.size());
  summary->reference_id = reference;
  if (summary->views_used < options.min_views) {
    *error = "too few views: " + std::to_string(summary->views_used) +
             " views show at least " +
             std::to_string(options.min_tags_per_view) +
             " of the object's tags together (need " +
             std::to_string(options.min_views) + ")";
    return false;
  }
  views_per_tag.clear();
  for (const UsedView& v : views)
    for (const TagObservation& o : v.observations) ++views_per_tag[o.id];
  if (!views_per_tag.count(reference)) {
    *error = "reference tag " + std::to_string(reference) +
             " is not seen together with other tags in any view";
    return false;
  }

  // Unknowns (all start at zero: corrections of the initial values).
  std::vector<std::array<double, 6>> view_delta(views.size());
  std::map<int, std::array<double, 6>> tag_delta;
  std::map<int, const tracking::TagPlacement*> placement;
  for (const auto& t : nominal) placement[t.id] = &t;
  for (const auto& [id, n] : views_per_tag) tag_delta[id].fill(0.0);
  for (auto& d : view_delta) d.fill(0.0);

  ceres::Problem problem;
  double sse_before = 0;
  int corners = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    int n = 0;
    sse_before += tracking::ReprojectionSse(camera, views[v].observations,
                                            views[v].cam_from_object, &n);
    corners += n;
    for (const TagObservation& o : views[v].observations) {
      for (int k = 0; k < 4; ++k) {
        auto* cost = new ceres::AutoDiffCostFunction<LayoutCornerCost, 2, 6, 6>(
            new LayoutCornerCost(&camera, CornerInTag(o.edge_m, k),
                                 o.object_from_tag, views[v].cam_from_object,
                                 o.pixels[k]));
        problem.AddResidualBlock(cost,
                                 new ceres::HuberLoss(options.loss_scale_px),
                                 view_delta[v].data(), tag_delta[o.id].data());
      }
    }
  }
  problem.SetParameterBlockConstant(tag_delta[reference].data());
  if (options.in_plane_only) {
    // Delta components: rotation x, y and translation z leave the plane.
    for (auto& [id, d] : tag_delta)
      if (id != reference)
        problem.SetManifold(d.data(), new ceres::SubsetManifold(6, {0, 1, 5}));
  }

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.num_threads = 1;
  ceres::Solver::Summary result;
  ceres::Solve(solver, &problem, &result);

  // Results.
  *calibrated = nominal;
  for (auto& t : *calibrated) {
    auto it = tag_delta.find(t.id);
    if (it != tag_delta.end() && t.id != reference)
      t.object_from_tag = t.object_from_tag * DeltaPose(it->second);
  }
  double sse_after = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const Pose cam_from_object =
        views[v].cam_from_object * DeltaPose(view_delta[v]);
    for (const TagObservation& o : views[v].observations) {
      const Pose object_from_tag =
          placement[o.id]->object_from_tag * DeltaPose(tag_delta[o.id]);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p =
            cam_from_object * (object_from_tag * CornerInTag(o.edge_m, k));
        sse_after += (camera.Project(p) - o.pixels[k]).squaredNorm();
      }
    }
  }
  summary->num_corners = corners;
  summary->rms_before_px = std::sqrt(sse_before / std::max(corners, 1));
  summary->rms_after_px = std::sqrt(sse_after / std::max(corners, 1));
  summary->iterations = static_cast<int>(result.iterations.size());
  summary->converged = result.termination_type == ceres::CONVERGENCE;
  for (size_t i = 0; i < nominal.size(); ++i) {
    TagAdjustment a;
    a.id = nominal[i].id;
    a.views = views_per_tag.count(a.id) ? views_per_tag[a.id] : 0;
    a.refined = a.id != reference && tag_delta.count(a.id) > 0;
    a.nominal = nominal[i].object_from_tag;
    a.calibrated = (*calibrated)[i].object_from_tag;
    a.moved_m = tracking::TranslationDistance(a.nominal, a.calibrated);
    a.rotated_rad = tracking::RotationDistance(a.nominal, a.calibrated);
    summary->tags.push_back(a);
  }
  std::sort(summary->tags.begin(), summary->tags.end(),
            [](const TagAdjustment& a, const TagAdjustment& b) {
              return a.id < b.id;
            });
  if (result.termination_type == ceres::FAILURE) {
    *error = "bundle adjustment failed: " + result.message;
    return false;
  }
  return true;
}

int ViewsWithTwoTags(const std::vector<tracking::TagPlacement>& tags,
                     const std::vector<std::vector<tracking::TagDetection>>&
                         detections_per_view) {
  int n = 0;
  for (const auto& detections : detections_per_view) {
    int seen = 0;
    for (const auto& d : detections)
      for (const auto& t : tags) seen += t.id == d.id;
    n += seen >= 2;
  }
  return n;
}

LayoutObject ChooseLayoutObject(
    const tracking::Rig& rig,
    const std::vector<std::vector<tracking::TagDetection>>&
        detections_per_view) {
  return rig.pen && ViewsWithTwoTags(rig.pen->faces, detections_per_view) >=
                        ViewsWithTwoTags(rig.tank_tags, detections_per_view)
             ? LayoutObject::kPen
             : LayoutObject::kTank;
}

}  // namespace ripple::calib
