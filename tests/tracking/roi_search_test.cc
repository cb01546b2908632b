#include "tracking/roi_search.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/shipped_data.h"
#include "tests/tracking/tag_scene.h"
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

// A frame of `others` (found at decimation 2) and a 30 mm tag `id` at the
// nearest distance where decimation 2 loses it and full resolution finds
// it; `image` stays empty when no such distance is found.
struct LostByDecimation {
  cv::Mat image;
  Pose cam_from_tag;
  double side_px = 0;
};
LostByDecimation FrameLostByDecimation(
    const Camera& camera, const TagFamily& family, TagDetector* detector,
    int id, const std::vector<testing::PlacedTag>& others) {
  LostByDecimation out;
  for (double z = 0.6; z < 3.0 && out.image.empty(); z += 0.05) {
    const Pose pose(
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
        Eigen::Vector3d(0.02, -0.01, z));
    std::vector<testing::PlacedTag> tags = others;
    tags.push_back({id, 0.03, pose});
    const cv::Mat frame = testing::RenderTags(camera, family, tags);
    if (detector->Detect(frame).size() == others.size() &&
        detector->Detect(frame, {}, 1.0).size() == others.size() + 1) {
      out.image = frame;
      out.cam_from_tag = pose;
      out.side_px = camera.fx * 0.03 / z;
    }
  }
  return out;
}

// A face at the detector's limit: a tag that the decimated quad search
// (decimation 2, the default) loses at this size but the full-resolution one
// finds. Tracked, it is found again in its own region at full resolution,
// without a whole-frame search; without the retry the search falls back to
// the whole frame, at decimation 2, and finds nothing.
TEST(RoiSearchTest, AFaceTheDecimatedSearchLosesIsFoundInItsRegion) {
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  auto family = TagFamily::Create("tag36h11");
  ASSERT_TRUE(family);
  TagDetector detector(TagDetectorOptions{});
  ASSERT_GT(detector.options().quad_decimate, 1.0);
  const int id = 5;
  const LostByDecimation lost =
      FrameLostByDecimation(camera, *family, &detector, id, {});
  const cv::Mat& image = lost.image;
  const Pose& cam_from_tag = lost.cam_from_tag;
  ASSERT_FALSE(image.empty()) << "no size lost by decimation alone";
  std::printf("a %.1f px face: lost at decimation 2, found at 1\n",
              lost.side_px);
  const std::vector<TagPlacement> tags = {{id, 0.03, Pose()}};
  for (const bool retry : {true, false}) {
    RoiSearchOptions options;
    options.retry_full_resolution = retry;
    RoiSearch search(options);
    bool full = false;
    const std::vector<TagDetection> found = search.Detect(
        &detector, image, camera, {{&cam_from_tag, &tags}}, &full);
    if (retry) {
      ASSERT_EQ(found.size(), 1u);
      EXPECT_EQ(found[0].id, id);
      EXPECT_FALSE(full) << "found in its region, no whole-frame search";
    } else {
      EXPECT_TRUE(found.empty());
      EXPECT_TRUE(full) << "missing from its region: the whole frame";
    }
  }
}

// The periodic whole-frame search, with the board tracked and the pen not
// yet acquired: a face that decimation 2 loses is found by the finer search
// of the whole frame, and only its tags are taken from there.
TEST(RoiSearchTest, AnObjectNotYetAcquiredIsSearchedForFiner) {
  const Camera camera = MakeIdealCamera(640, 480, 60.0);
  auto family = TagFamily::Create("tag36h11");
  ASSERT_TRUE(family);
  TagDetector detector(TagDetectorOptions{});
  ASSERT_GT(detector.options().quad_decimate, 1.0);
  const int board_id = 7, pen_id = 5;
  const Pose cam_from_board(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(-0.15, 0.0, 0.8));
  const cv::Mat image =
      FrameLostByDecimation(camera, *family, &detector, pen_id,
                            {{board_id, 0.08, cam_from_board}})
          .image;
  ASSERT_FALSE(image.empty()) << "no size lost by decimation alone";
  const std::vector<TagPlacement> board = {{board_id, 0.08, Pose()}};
  const std::vector<TagPlacement> pen = {{pen_id, 0.03, Pose()}};
  auto count = [](const std::vector<TagDetection>& found, int id) {
    return std::count_if(found.begin(), found.end(),
                         [id](const TagDetection& d) { return d.id == id; });
  };
  for (const bool finer : {true, false}) {
    RoiSearchOptions options;
    options.acquire_finer = finer;
    options.full_search_period = 1;  // every frame a periodic search
    RoiSearch search(options);
    bool full = false;
    const std::vector<TagDetection> found =
        search.Detect(&detector, image, camera,
                      {{&cam_from_board, &board}, {nullptr, &pen}}, &full);
    EXPECT_TRUE(full);
    EXPECT_EQ(count(found, board_id), 1) << "the board once, decimated";
    EXPECT_EQ(count(found, pen_id), finer ? 1 : 0);
  }
  // With nothing tracked every frame searches the whole frame: no second,
  // finer search there.
  RoiSearch search;
  const std::vector<TagDetection> found = search.Detect(
      &detector, image, camera, {{nullptr, &board}, {nullptr, &pen}}, nullptr);
  EXPECT_EQ(count(found, board_id), 1);
  EXPECT_EQ(count(found, pen_id), 0);
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
