#include "tracking/roi_search.h"

#include <gtest/gtest.h>

#include "tests/shipped_data.h"
#include "tracking/pen_hypotheses.h"

namespace ripple::tracking {
namespace {

using test_data::DefaultRig;

Pose CamFromTank() {
  return LookAt(Eigen::Vector3d(0, -0.3, 0.35), Eigen::Vector3d::Zero(),
                Eigen::Vector3d(0, 0, 1))
      .Inverse();
}

TEST(RoiSearchTest, BoxesHoldEveryPredictedCornerWithItsMargin) {
  const Rig rig = DefaultRig();
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  const Pose cam_from_tank = CamFromTank();
  RoiSearchOptions options;
  options.margin_fraction = 0;
  options.margin_px = 5;
  const std::vector<cv::Rect> rois =
      PredictTagRois(options, camera, {{&cam_from_tank, &rig.tank_tags}});
  ASSERT_FALSE(rois.empty());
  for (const TagPlacement& tag : rig.tank_tags) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d uv = camera.Project(
          Eigen::Vector3d(cam_from_tank * tag.CornerInObject(k)));
      if (uv.x() < 5 || uv.y() < 5 || uv.x() > 634 || uv.y() > 474) continue;
      bool inside = false;
      for (const cv::Rect& r : rois)
        inside = inside ||
                 (uv.x() - 5 >= r.x && uv.y() - 5 >= r.y &&
                  uv.x() + 5 <= r.x + r.width && uv.y() + 5 <= r.y + r.height);
      EXPECT_TRUE(inside) << "tag " << tag.id << " corner " << k;
    }
  }
  // Merged: no two boxes overlap.
  for (size_t i = 0; i < rois.size(); ++i)
    for (size_t j = i + 1; j < rois.size(); ++j)
      EXPECT_EQ((rois[i] & rois[j]).area(), 0);
  // No pose, no boxes.
  EXPECT_TRUE(
      PredictTagRois(options, camera, {{nullptr, &rig.tank_tags}}).empty());
}

TEST(RoiSearchTest, OptionsValidate) {
  std::string error;
  EXPECT_TRUE(RoiSearchOptions{}.IsValid(&error)) << error;
  RoiSearchOptions options;
  options.full_search_period = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("full_search_period"), std::string::npos);
  options = RoiSearchOptions{};
  options.margin_px = -1;
  EXPECT_FALSE(options.IsValid(&error));
}

TEST(PenHypothesesTest, OptionsValidate) {
  std::string error;
  EXPECT_TRUE(PenHypothesisOptions{}.IsValid(&error)) << error;
  PenHypothesisOptions options;
  options.resolve_ratio = 1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("resolve_ratio"), std::string::npos);
  options = PenHypothesisOptions{};
  options.min_frames = 0;
  EXPECT_FALSE(options.IsValid(&error));
}

}  // namespace
}  // namespace ripple::tracking
