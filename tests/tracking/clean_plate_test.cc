// The clean plate against synthetic truth: hands over the tank are found
// (mask IoU against the renderer's own coverage), shadows, exposure drift
// and the pen are not foreground, and a board revealed by a hand that was
// there from the start takes over the plate.
#include "tracking/clean_plate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "tests/shipped_data.h"
#include "tests/tracking/synth_sequence.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/synth/synth.h"

namespace ripple::tracking {
namespace {

constexpr int kPadPx = 4;

cv::Rect Window(const Camera& camera, const Rig& rig,
                const Pose& cam_from_tank) {
  return TankWindow(camera, cam_from_tank, rig.tank.size_x_m, rig.tank.size_y_m,
                    rig.tank.wall_height_m, kPadPx);
}

cv::Mat PenMask(const Camera& camera, const Rig& rig,
                const synth::SceneState& scene) {
  cv::Mat mask;
  if (!scene.tank_from_pen || !rig.pen) return mask;
  DrawPenSilhouette(camera, scene.cam_from_tank * *scene.tank_from_pen,
                    rig.pen->cube_edge_m, rig.pen->shaft_radius_m,
                    rig.pen->tip_in_pen, 1.5, &mask);
  return mask;
}

// A plate with the printed board's design as its prior (linear frames, as
// the synthetic renderer writes by default).
void SetPrior(const Rig& rig, CleanPlate* plate) {
  cv::Mat levels, valid;
  const cv::Point2d o = plate->plate_origin_m();
  synth::BoardDesignLevels(rig, synth::FloorPattern(), {o.x, o.y},
                           plate->texel_m(), plate->plate_size(),
                           /*srgb=*/false, &levels, &valid);
  ASSERT_TRUE(plate->SetBoardPrior(levels, valid));
}

// Pixels of the tank's box (floor to the wall tops) in the ideal image:
// where the renderer draws, so where the mask matters.
cv::Mat BoxSilhouette(const Camera& camera, const Rig& rig,
                      const Pose& cam_from_tank) {
  std::vector<cv::Point> pts;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p =
        cam_from_tank *
        Eigen::Vector3d((c & 1 ? 0.5 : -0.5) * rig.tank.size_x_m,
                        (c & 2 ? 0.5 : -0.5) * rig.tank.size_y_m,
                        c & 4 ? rig.tank.wall_height_m : 0.0);
    pts.emplace_back(cvRound(camera.fx * p.x() / p.z() + camera.cx),
                     cvRound(camera.fy * p.y() / p.z() + camera.cy));
  }
  std::vector<cv::Point> hull;
  cv::convexHull(pts, hull);
  cv::Mat mask(camera.height, camera.width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(mask, hull, cv::Scalar(255));
  return mask;
}

struct MaskScore {
  long long inter = 0, uni = 0, truth = 0, missed = 0, false_px = 0;
  double IoU() const { return uni > 0 ? double(inter) / uni : 1.0; }
};

// Scores `found` against the hands' coverage inside `region`, leaving out
// the pen's pixels (`exclude`: known geometry, which the renderer handles).
void Score(const cv::Mat& found, const cv::Mat& hands, const cv::Mat& exclude,
           const cv::Mat& region, MaskScore* s) {
  for (int y = 0; y < region.rows; ++y) {
    for (int x = 0; x < region.cols; ++x) {
      if (!region.at<std::uint8_t>(y, x)) continue;
      if (!exclude.empty() && exclude.at<std::uint8_t>(y, x)) continue;
      const bool t = hands.at<float>(y, x) >= 0.5f;
      const bool f = found.at<std::uint8_t>(y, x) != 0;
      s->inter += t && f;
      s->uni += t || f;
      s->truth += t;
      s->missed += t && !f;
      s->false_px += f && !t;
    }
  }
}

TEST(CleanPlateTest, OptionsAreValidated) {
  CleanPlateOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.low_threshold = 40;
  o.high_threshold = 20;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("threshold"), std::string::npos);
  o = CleanPlateOptions();
  o.texel_m = 0;
  EXPECT_FALSE(o.IsValid(&error));
}

// Hands over the tank in the `hands` preset, scored against the renderer's
// coverage over the tank's box from the third frame on; `worst_false` is the
// largest share of one frame's hand pixels that the mask adds where no hand
// is.
MaskScore ScoreHands(int frames, std::uint64_t seed, int* scored_frames,
                     double* worst_false) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  const synth::SceneRenderer renderer(camera, rig);
  const auto specs =
      test_data::SynthSpecs(camera, rig, "hands", frames, 40, seed);
  EXPECT_EQ(specs.size(), static_cast<size_t>(frames));
  CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                   rig.tank.wall_height_m);
  SetPrior(rig, &plate);
  MaskScore score;
  *scored_frames = 0;
  *worst_false = 0;
  for (const synth::FrameSpec& f : specs) {
    const synth::RenderedFrame r =
        renderer.Render(f.scene, f.imaging, f.noise_seed);
    const cv::Mat exclude = PenMask(camera, rig, f.scene);
    plate.Process(r.image, f.scene.cam_from_tank, exclude);
    // A cut (a new segment) moves the camera, not the board: the plate
    // carries over. Scoring starts after the first few frames of learning.
    if (f.index < 2) continue;
    cv::Mat hands, pen;
    renderer.OccluderCoverage(f.scene, &hands, &pen);
    MaskScore one;
    Score(plate.foreground(), hands, exclude,
          BoxSilhouette(camera, rig, f.scene.cam_from_tank), &one);
    if (one.truth > 1000)
      *worst_false = std::max(*worst_false, double(one.false_px) / one.truth);
    score.inter += one.inter;
    score.uni += one.uni;
    score.truth += one.truth;
    score.missed += one.missed;
    score.false_px += one.false_px;
    ++*scored_frames;
  }
  return score;
}

TEST(CleanPlateTest, FindsHandsOverTheTankOnSyntheticSequences) {
  int scored_frames = 0;
  double worst_false = 0;
  const MaskScore score = ScoreHands(80, 7, &scored_frames, &worst_false);
  ASSERT_GT(score.truth, 20000) << "the sequence must put hands over the tank";
  EXPECT_GE(score.IoU(), 0.9) << "missed " << score.missed << " of "
                              << score.truth << ", false " << score.false_px;
  EXPECT_LE(double(score.missed) / score.truth, 0.05);
  EXPECT_GT(scored_frames, 60);
  std::printf("hands over the tank: IoU %.3f, missed %.1f%%, false %.1f%%\n",
              score.IoU(), 100.0 * score.missed / score.truth,
              100.0 * score.false_px / score.truth);
}

// A hand that sweeps in over plain paper covers much of the board at once;
// its pixels are not in the last frame's mask, so they enter the exposure
// estimate, and over plain paper they agree on a ratio of their own (skin
// over paper). Taken as the exposure, the whole board read brighter than
// the plate and joined the hand (IoU 0.46 on this sequence, the false
// pixels twice the hand's), and stayed so: the flooded mask left too few
// samples to correct it.
TEST(CleanPlateTest, AHandEnteringOverPaperDoesNotMoveTheExposure) {
  int scored_frames = 0;
  double worst_false = 0;
  const MaskScore score = ScoreHands(40, 3, &scored_frames, &worst_false);
  ASSERT_GT(score.truth, 100000) << "a hand must enter over the tank";
  std::printf(
      "a hand entering over paper: IoU %.3f, missed %.1f%%, false %.1f%%, "
      "worst frame's false %.1f%% of its hand\n",
      score.IoU(), 100.0 * score.missed / score.truth,
      100.0 * score.false_px / score.truth, 100.0 * worst_false);
  EXPECT_GE(score.IoU(), 0.9);
  EXPECT_LE(worst_false, 0.15);
}

// The pen's masks as the pipeline hands them to the plate (its 1 mm
// margin); `margin_as_body` marks the margin as the shaft's own, as every
// object pixel was once judged.
void PenLevels(const Camera& camera, const Rig& rig, const Pose& cam_from_pen,
               bool margin_as_body, cv::Mat* exclude, cv::Mat* object) {
  DrawPenPlateMasks(camera, cam_from_pen, rig.pen->cube_edge_m,
                    rig.pen->shaft_radius_m, rig.pen->tip_in_pen, 0.001,
                    exclude, object);
  if (margin_as_body)
    object->setTo(CleanPlate::kObjectBody,
                  *object == CleanPlate::kObjectMargin);
}

// A hand holding the pen is found in front of its shaft, also over the
// shaft's outline and the margin grown round it; where no hand is, the
// board that shows in that margin (and the outline's mix of shaft and
// board) is mostly not taken for one. Judging the margin as the shaft's own
// put a ring of "occluder" round every bare shaft, where the renderer then
// shows the dry video over the water.
TEST(CleanPlateTest, AHandOverTheShaftIsFoundTheBoardBesideItIsNot) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  ASSERT_TRUE(rig.pen);
  const synth::SceneRenderer renderer(camera, rig);
  const auto specs = test_data::SynthSpecs(camera, rig, "hands", 80, 40, 7);
  struct Count {
    long long free = 0, free_found = 0, held = 0, held_found = 0;
  };
  // The frames and their hands' coverage, once for both rules.
  std::vector<cv::Mat> images, coverage;
  for (const synth::FrameSpec& f : specs) {
    images.push_back(renderer.Render(f.scene, f.imaging, f.noise_seed).image);
    cv::Mat hands, pen;
    renderer.OccluderCoverage(f.scene, &hands, &pen);
    coverage.push_back(hands);
  }
  Count counts[2];
  for (int as_body = 0; as_body < 2; ++as_body) {
    CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                     rig.tank.wall_height_m);
    SetPrior(rig, &plate);
    Count& n = counts[as_body];
    for (size_t i = 0; i < specs.size(); ++i) {
      const synth::FrameSpec& f = specs[i];
      cv::Mat exclude, object;
      if (f.scene.tank_from_pen)
        PenLevels(camera, rig, f.scene.cam_from_tank * *f.scene.tank_from_pen,
                  as_body != 0, &exclude, &object);
      plate.Process(images[i], f.scene.cam_from_tank, exclude, object);
      if (f.index < 2 || object.empty()) continue;
      const cv::Mat& hands = coverage[i];
      // The outline and the margin: the shaft less its pixels a pixel
      // inside its outline. Free: no hand within the reach that a hand's
      // pixels may grow into the margin.
      cv::Mat core = object >= CleanPlate::kObjectBody, near_hand;
      cv::erode(core, core, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
      const int reach = 2 * CleanPlate::kObjectMarginPx + 1;
      cv::dilate(hands >= 0.05f, near_hand,
                 cv::getStructuringElement(cv::MORPH_RECT, {reach, reach}));
      const cv::Rect w = plate.foreground_window();
      for (int y = w.y; y < w.y + w.height; ++y) {
        for (int x = w.x; x < w.x + w.width; ++x) {
          if (!object.at<std::uint8_t>(y, x) || core.at<std::uint8_t>(y, x))
            continue;
          const float h = hands.at<float>(y, x);
          const bool found = plate.foreground().at<std::uint8_t>(y, x) != 0;
          if (!near_hand.at<std::uint8_t>(y, x)) {
            ++n.free;
            n.free_found += found;
          } else if (h >= 0.5f) {
            ++n.held;
            n.held_found += found;
          }
        }
      }
    }
  }
  const Count& now = counts[0];
  const Count& before = counts[1];
  ASSERT_GT(now.held, 500) << "the sequence must put a hand over the shaft";
  ASSERT_GT(now.free, 5000);
  const double free_share = double(now.free_found) / now.free;
  const double held_share = double(now.held_found) / now.held;
  const double free_before = double(before.free_found) / before.free;
  const double held_before = double(before.held_found) / before.held;
  std::printf(
      "the shaft's outline and 1 mm margin: %lld pixels without a hand, "
      "%.1f%% taken for one (margin judged as the shaft: %.1f%%); %lld under "
      "a hand, %.1f%% found (%.1f%%)\n",
      now.free, 100 * free_share, 100 * free_before, now.held, 100 * held_share,
      100 * held_before);
  // What is still taken for a hand there grows from the shaft's own pixels
  // that its one-colour model rejects (its shading and motion blur).
  EXPECT_LT(free_share, 0.15);
  EXPECT_LT(free_share, 0.25 * free_before);
  EXPECT_GE(held_share, 0.9);
}

// A frame of the board alone (no pen, no hands), linear-light imaging.
cv::Mat BoardFrame(const synth::SceneRenderer& renderer,
                   const Pose& cam_from_tank, double exposure,
                   std::uint64_t seed) {
  synth::SceneState scene;
  scene.cam_from_tank = cam_from_tank;
  synth::ImagingOptions imaging;
  imaging.exposure = exposure;
  imaging.read_noise_dn = 2;
  imaging.defocus_sigma_px = 0.5;
  return renderer.Render(scene, imaging, seed).image;
}

Pose BoardView() {
  return LookAt({0.0, -0.25, 0.3}, {0.0, 0.0, 0.0}, Eigen::Vector3d::UnitZ())
      .Inverse();
}

TEST(CleanPlateTest, ShadowsAndExposureDriftAreNotForeground) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  const synth::SceneRenderer renderer(camera, rig);
  const Pose cam_from_tank = BoardView();
  const cv::Rect window = Window(camera, rig, cam_from_tank);
  CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                   rig.tank.wall_height_m);
  for (int i = 0; i < 10; ++i)
    plate.Process(BoardFrame(renderer, cam_from_tank, 1.0, i + 1),
                  cam_from_tank, cv::Mat());
  EXPECT_GT(plate.summary().known_texels, 10000);
  // 20% darker everywhere, and a soft-edged shadow at 55% of the light.
  cv::Mat frame = BoardFrame(renderer, cam_from_tank, 0.8, 99);
  cv::Mat shade(frame.size(), CV_32F, cv::Scalar(1.0));
  cv::ellipse(shade,
              {window.x + window.width / 2, window.y + window.height / 2},
              {60, 25}, 20, 0, 360, cv::Scalar(0.55), -1);
  cv::GaussianBlur(shade, shade, {0, 0}, 3);
  cv::Mat f32;
  frame.convertTo(f32, CV_32FC3);
  cv::Mat shade3;
  cv::merge(std::vector<cv::Mat>{shade, shade, shade}, shade3);
  f32 = f32.mul(shade3);
  f32.convertTo(frame, CV_8UC3);
  const CleanPlateSummary& s = plate.Process(frame, cam_from_tank, cv::Mat());
  EXPECT_NEAR(s.gain, 0.8, 0.05);
  EXPECT_LT(s.foreground_px, 50) << "shadow or drift taken for an occluder";
  // A hand-coloured patch in the same place is foreground.
  cv::Mat with_patch = BoardFrame(renderer, cam_from_tank, 1.0, 100);
  const cv::Rect patch(window.x + window.width / 3,
                       window.y + window.height / 3, 40, 30);
  with_patch(patch).setTo(cv::Scalar(110, 140, 190));
  plate.Process(with_patch, cam_from_tank, cv::Mat());
  const int found = cv::countNonZero(plate.foreground()(patch));
  EXPECT_GE(found, patch.area() * 95 / 100);
  EXPECT_LE(plate.summary().foreground_px, patch.area() * 11 / 10);
}

// The known texels are counted as they become known: the count must stay
// the plate's opaque texels (alpha 255), through learning and a Reset.
TEST(CleanPlateTest, KnownTexelsAreThePlatesOpaqueTexels) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  const synth::SceneRenderer renderer(camera, rig);
  const Pose cam_from_tank = BoardView();
  CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                   rig.tank.wall_height_m);
  auto opaque = [&]() {
    cv::Mat alpha;
    cv::extractChannel(plate.plate(), alpha, 3);
    return cv::countNonZero(alpha == 255);
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 4; ++i) {
      plate.Process(BoardFrame(renderer, cam_from_tank, 1.0 - 0.05 * i, i + 1),
                    cam_from_tank, cv::Mat());
      EXPECT_GT(plate.summary().known_texels, 10000);
      EXPECT_EQ(plate.summary().known_texels, opaque()) << "frame " << i;
    }
    plate.Reset();
    EXPECT_EQ(opaque(), 0);
  }
  plate.Process(BoardFrame(renderer, cam_from_tank, 1.0, 50), cam_from_tank,
                cv::Mat());
  EXPECT_EQ(plate.summary().known_texels, opaque());
}

// The board under something that never moved (a pen held still since
// tracking began) is never seen, so the plate does not know it; the shown
// plate takes it from the printed design, in the plate's units under this
// frame's light. Checked against a plate that saw that board: the tiled
// floor's texels (tiles and grout) under a still object, 10% under-exposed.
TEST(CleanPlateTest, ShownPlateTakesTheUnseenBoardFromTheDesign) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  std::string error;
  const auto tiles =
      synth::FloorPattern::Create(synth::FloorOptions(), rig.tank, &error);
  ASSERT_TRUE(tiles) << error;
  const synth::SceneRenderer renderer(camera, rig, *tiles);
  const Pose cam_from_tank = BoardView();
  const cv::Rect window = Window(camera, rig, cam_from_tank);
  cv::Mat still(camera.height, camera.width, CV_8U, cv::Scalar(0));
  const cv::Rect object(window.x + window.width / 3,
                        window.y + window.height / 3, 60, 40);
  still(object).setTo(255);
  auto make = [&](bool prior) {
    auto plate = std::make_unique<CleanPlate>(
        camera, rig.tank.size_x_m, rig.tank.size_y_m, rig.tank.wall_height_m);
    if (prior) {
      cv::Mat levels, valid;
      const cv::Point2d o = plate->plate_origin_m();
      synth::BoardDesignLevels(rig, *tiles, {o.x, o.y}, plate->texel_m(),
                               plate->plate_size(), /*srgb=*/false, &levels,
                               &valid);
      EXPECT_TRUE(plate->SetBoardPrior(levels, valid));
    }
    return plate;
  };
  auto with_design = make(true), without = make(false), seeing = make(true);
  for (int i = 0; i < 6; ++i) {
    const cv::Mat frame = BoardFrame(renderer, cam_from_tank, 0.9, i + 1);
    with_design->Process(frame, cam_from_tank, still);
    without->Process(frame, cam_from_tank, still);
    seeing->Process(frame, cam_from_tank, cv::Mat());
  }
  // The plate texels under the still object: unknown to the plates that
  // never saw them, known to the one that did.
  const cv::Mat& known = seeing->plate();
  const cv::Mat& plate = with_design->plate();
  const cv::Mat& shown = with_design->shown_plate();
  ASSERT_EQ(shown.size(), plate.size());
  int hidden = 0, lo = 255, hi = 0;
  std::vector<double> errors;
  for (int j = 0; j < plate.rows; ++j) {
    for (int i = 0; i < plate.cols; ++i) {
      const cv::Vec4b p = plate.at<cv::Vec4b>(j, i);
      const cv::Vec4b s = shown.at<cv::Vec4b>(j, i);
      const cv::Vec4b k = known.at<cv::Vec4b>(j, i);
      if (p[3] == 255) {
        ASSERT_EQ(s, p) << "a known texel is shown as learned";
        continue;
      }
      if (k[3] != 255) continue;
      ++hidden;
      ASSERT_EQ(s[3], 255);
      lo = std::min<int>(lo, k[1]);
      hi = std::max<int>(hi, k[1]);
      for (int c = 0; c < 3; ++c) errors.push_back(std::abs(s[c] - k[c]));
    }
  }
  ASSERT_GT(hidden, 300) << "the object must hide part of the board";
  ASSERT_GT(hi - lo, 40) << "the hidden board must hold tiles and grout";
  // Without a design the shown plate is the plate itself.
  EXPECT_EQ(without->shown_plate().data, without->plate().data);
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  const double p90 = errors[errors.size() * 9 / 10];
  std::printf(
      "board under a still object from the design: %d texels (green %d-%d), "
      "|design - learned| median %.0f, p90 %.0f levels\n",
      hidden, lo, hi, median, p90);
  EXPECT_LE(median, 4);
  EXPECT_LE(p90, 12);
  // A change of light recomposes it; the same light does not.
  const std::uint64_t counter = with_design->shown_plate_counter();
  with_design->Process(BoardFrame(renderer, cam_from_tank, 0.9, 50),
                       cam_from_tank, still);
  const std::uint64_t same = with_design->shown_plate_counter();
  with_design->Process(BoardFrame(renderer, cam_from_tank, 0.7, 51),
                       cam_from_tank, still);
  EXPECT_GT(with_design->shown_plate_counter(), same);
  EXPECT_GE(same, counter);
}

TEST(CleanPlateTest, BoardRevealedByAStartingHandTakesOver) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  const synth::SceneRenderer renderer(camera, rig);
  const Pose cam_from_tank = BoardView();
  const cv::Rect window = Window(camera, rig, cam_from_tank);
  const cv::Rect patch(window.x + window.width / 3,
                       window.y + window.height / 3, 40, 30);
  CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                   rig.tank.wall_height_m);
  // A hand lies there for the first 5 frames: it is learned as board.
  for (int i = 0; i < 5; ++i) {
    cv::Mat frame = BoardFrame(renderer, cam_from_tank, 1.0, i + 1);
    frame(patch).setTo(cv::Scalar(110, 140, 190));
    plate.Process(frame, cam_from_tank, cv::Mat());
  }
  // Then it leaves: its ghost shows until the board has been seen for the
  // takeover time.
  const int takeover = CleanPlateOptions().takeover_frames;
  int frames_with_ghost = 0;
  for (int i = 0; i < takeover + 2; ++i) {
    plate.Process(BoardFrame(renderer, cam_from_tank, 1.0, i + 10),
                  cam_from_tank, cv::Mat());
    if (cv::countNonZero(plate.foreground()(patch)) > 0) ++frames_with_ghost;
  }
  EXPECT_GE(frames_with_ghost, takeover - 2);
  EXPECT_LE(frames_with_ghost, takeover);
  EXPECT_EQ(plate.summary().foreground_px, 0);
}

TEST(CleanPlateTest, ExcludedPixelsAreNeitherReportedNorLearned) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  const synth::SceneRenderer renderer(camera, rig);
  const Pose cam_from_tank = BoardView();
  const cv::Rect window = Window(camera, rig, cam_from_tank);
  const cv::Rect patch(window.x + window.width / 2,
                       window.y + window.height / 2, 30, 30);
  cv::Mat exclude(camera.height, camera.width, CV_8U, cv::Scalar(0));
  exclude(patch).setTo(255);
  CleanPlate plate(camera, rig.tank.size_x_m, rig.tank.size_y_m,
                   rig.tank.wall_height_m);
  for (int i = 0; i < 8; ++i) {
    cv::Mat frame = BoardFrame(renderer, cam_from_tank, 1.0, i + 1);
    frame(patch).setTo(cv::Scalar(20, 20, 20));  // the pen, always there
    plate.Process(frame, cam_from_tank, exclude);
    EXPECT_EQ(plate.summary().foreground_px, 0);
  }
  // Once the pen leaves, the texels it hid have never been learned: they
  // are unknown (not foreground), and the pen was never learned as board.
  cv::Mat frame = BoardFrame(renderer, cam_from_tank, 1.0, 50);
  plate.Process(frame, cam_from_tank, cv::Mat());
  EXPECT_EQ(plate.summary().foreground_px, 0);
  frame(patch).setTo(cv::Scalar(20, 20, 20));
  plate.Process(frame, cam_from_tank, cv::Mat());
  EXPECT_GT(cv::countNonZero(plate.foreground()(patch)), patch.area() / 2);
}

TEST(CleanPlateTest, PenSilhouetteCoversTheRenderedPen) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  ASSERT_TRUE(rig.pen);
  const synth::SceneRenderer renderer(camera, rig);
  const auto specs = test_data::SynthSpecs(camera, rig, "clean", 10, 10, 3);
  for (const synth::FrameSpec& f : specs) {
    cv::Mat hands, pen;
    renderer.OccluderCoverage(f.scene, &hands, &pen);
    const cv::Mat mask = PenMask(camera, rig, f.scene);
    ASSERT_FALSE(mask.empty());
    const int truth = cv::countNonZero(pen >= 0.05f);
    ASSERT_GT(truth, 200);
    cv::Mat outside = (pen >= 0.05f) & (mask == 0);
    EXPECT_EQ(cv::countNonZero(outside), 0) << "frame " << f.index;
    // Grown by 1.5 px, not by more than the shaft's outline warrants.
    EXPECT_LT(cv::countNonZero(mask), 1.6 * truth) << "frame " << f.index;
  }
}

}  // namespace
}  // namespace ripple::tracking
