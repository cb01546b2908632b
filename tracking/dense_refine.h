// Dense photometric refinement of an object's pose over the known look of
// its tags, after the dense pose refinement of Wu et al., "DodecaPen:
// Accurate 6DoF Tracking of a Passive Stylus" (UIST 2017).
//
// Corners alone pose a small, nearly frontal tag poorly: the tilt of a
// 25-pixel square is set by sub-pixel differences in its edge lengths. But
// every cell boundary of every face that faces the camera carries pose
// information, and faces seen at grazing angles, which libapriltag cannot
// decode, still show their black borders. This step samples each face's
// bitmap near its cell boundaries, blurred as the image blurs it (a blur
// round in pixels, so stretched in the tag plane of an oblique face, with
// the width that fits the image best), projects the samples through the
// camera model, and runs Gauss-Newton on the 6-DoF pose to make the image
// match the template up to a per-face gain and offset (fitted in closed form
// each iteration). The loss is Huber's, and constant for residuals far
// beyond the start's spread: samples an occluder covers do not pull. The
// template's blur must match the image's: a small square blurred more than
// its template loses its corners, and the fit shrinks it (reads it farther).
//
// The result is kept only when it lowers the photometric cost and stays
// within a few degrees and millimetres of the corner-based pose it starts
// from (DenseRefineOptions).
#ifndef RIPPLE_TRACKING_DENSE_REFINE_H_
#define RIPPLE_TRACKING_DENSE_REFINE_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {

struct DenseRefineOptions {
  bool enabled = true;
  int samples_per_cell = 3;  // per cell side, in the tag plane
  // Samples where a level's template is flat carry no pose information at
  // that level; each face iterates only over samples whose gradient at its
  // chosen level is above this (per cell).
  double min_template_gradient = 0.15;
  // Faces seen more obliquely than this (cosine between the face normal and
  // the line of sight) are left out.
  double min_facing_cos = 0.15;
  // A face whose fitted black-to-white contrast is below this (grey levels)
  // is not what the model says it is (occluded, out of focus) and is left
  // out.
  double min_contrast_dn = 25.0;
  // Gauss-Newton iterations. More iterations fit the template more tightly
  // but not more truly: on the benchmark preset (blur, noise, JPEG) 2-3 gave
  // a lower tip error than 6 on both seeds tried, and 2 costs less
  // (docs/tracking.md).
  int max_iterations = 2;
  // Of those, the first run on a template blurred at least 0.35 cells
  // (coarse to fine; a sharp template's basin is about a pixel wide).
  int coarse_iterations = 1;
  double huber_dn = 6.0;  // residual (grey levels) where the loss turns robust
  // The image's blur is round in pixels, so on a face seen obliquely it is
  // stretched in the tag plane across the foreshortened direction. With
  // this, each face's template is blurred that way (its round blur level
  // corrected to first order by the templates' second derivatives); without
  // it the template's blur is round in the tag plane, too sharp across the
  // foreshortening and too wide along it, which biases a small face's
  // fitted scale: its distance.
  bool anisotropic_blur = true;
  // Occluders (a finger on the cube, a hand passing in front of it): a
  // sample whose residual at the start exceeds this many robust spreads of
  // the start's residuals (1.4826 times their median absolute value), and
  // at least `outlier_min_dn`, neither sets its face's gain and offset nor
  // pulls the pose: the loss is constant beyond that clip. 0 keeps every
  // sample (Huber's loss alone, whose pull per sample never vanishes).
  double outlier_spreads = 4.0;
  double outlier_min_dn = 12.0;
  // The refined pose must stay this close to the starting one.
  double max_rotation_deg = 8.0;
  double max_translation_m = 0.01;

  bool IsValid(std::string* error) const;
};

struct DenseRefineResult {
  bool refined = false;  // the pose was replaced
  int faces = 0;         // faces used
  int samples = 0;       // samples used in the last iteration
  int iterations = 0;
  // Chosen template blur per face used: a continuous level, blending
  // DenseTagModel::kBlurCells[floor] and [ceil].
  std::vector<double> blur_levels;
  double rms_before_dn = 0, rms_after_dn = 0;  // photometric RMS residual
  // The refined pose's information from its photometric residuals (J^T W J
  // of the last fine iteration over the final RMS residual squared), in the
  // perturbation R' = exp(omega) R, t' = t + v of (omega, v); zero when the
  // pose was not replaced.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

// Template samples of an object's tags, in the object frame; built once per
// object.
class DenseTagModel {
 public:
  // False with `error` when a tag id is outside the family.
  static std::optional<DenseTagModel> Create(
      const TagFamily& family, const std::vector<TagPlacement>& tags,
      const DenseRefineOptions& options, std::string* error);

  // The bitmap is blurred by Gaussians of these sigmas (cells); each face
  // uses the blend of two neighbouring levels that fits the image best at
  // the starting pose, so that the template's blur matches the image's.
  static constexpr int kBlurLevels = 5;
  static constexpr double kBlurCells[kBlurLevels] = {0.08, 0.2, 0.35, 0.55,
                                                     0.8};
  struct Sample {
    Eigen::Vector3d point;  // object frame
    // Blurred template per level: 0 black .. 1 white.
    std::array<float, kBlurLevels> value{};
    // Bit l: the level-l template's gradient reaches min_template_gradient
    // here (only such samples carry pose information at that level).
    unsigned informative = 0;
    // Second derivatives of each level's template in the tag plane (per
    // cell squared): uu, uv, vv (u along the bitmap's columns, v its rows).
    std::array<std::array<float, 3>, kBlurLevels> curvature{};
  };
  struct Face {
    int id = -1;
    Eigen::Vector3d centre;  // object frame
    Eigen::Vector3d normal;  // object frame, out of the face (towards a viewer)
    // One cell along the bitmap's columns (u) and rows (v), object frame.
    Eigen::Vector3d cell_u, cell_v;
    std::vector<Sample> samples;
  };
  const std::vector<Face>& faces() const { return faces_; }

 private:
  std::vector<Face> faces_;
};

// Refines `cam_from_object` in place on an 8-bit grey image (the camera's
// size). Returns true when the pose was replaced (result->refined).
bool DenseRefinePose(const cv::Mat& gray, const Camera& camera,
                     const DenseTagModel& model,
                     const DenseRefineOptions& options, Pose* cam_from_object,
                     DenseRefineResult* result = nullptr);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_DENSE_REFINE_H_
