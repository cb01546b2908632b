// Synth -> track end to end: corner bias on ray-cast frames, and tracking
// accuracy on the benchmark preset (blur, noise, JPEG, hand occluders, cuts)
// with thresholds derived from the measured corner noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "tests/shipped_data.h"
#include "tests/tracking/synth_sequence.h"
#include "tracking/object_pose.h"
#include "tracking/synth/synth.h"
#include "tracking/synth/variant.h"
#include "tracking/tracker.h"

namespace ripple::tracking {
namespace {

using test_data::DefaultCamera;

constexpr double kDeg = M_PI / 180.0;

using test_data::DefaultRig;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

struct CornerErrors {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double mean_outward = 0, rms = 0;
  int n = 0;
};

// Corrected corners of every fully visible tag against their true
// projections.
CornerErrors MeasureCorners(const std::string& preset, int frames,
                            const Camera& base_camera, const Rig& rig,
                            const TagDetectorOptions& options,
                            const std::string& variant_name = "exact",
                            bool decode = true) {
  synth::DataVariant variant;
  EXPECT_TRUE(synth::GetDataVariant(variant_name, &variant));
  const Camera camera = synth::VariantCamera(variant, base_camera);
  std::vector<synth::FrameSpec> specs =
      test_data::SynthSpecs(camera, rig, preset, frames, 3, 5);
  for (synth::FrameSpec& f : specs) synth::ApplyVariant(variant, &f.imaging);
  synth::SceneRenderer renderer(camera, rig, synth::FloorPattern(),
                                variant.formation);
  // The detector decodes the values as the variant's camera file says.
  TagDetectorOptions with_transfer = options;
  if (decode) with_transfer.transfer = camera.transfer;
  TagDetector detector(with_transfer);
  CornerErrors e;
  double sq = 0;
  for (const synth::FrameSpec& spec : specs) {
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    for (const TagDetection& d : detector.Detect(frame.image)) {
      const TagPlacement* tag = rig.FindTankTag(d.id);
      Pose cam_from_object = spec.scene.cam_from_tank;
      bool visible =
          std::count(frame.tank_tags.begin(), frame.tank_tags.end(), d.id) > 0;
      if (!tag) {
        tag = rig.FindPenFace(d.id);
        if (!tag || !spec.scene.tank_from_pen) continue;
        cam_from_object = spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
        visible =
            std::count(frame.pen_tags.begin(), frame.pen_tags.end(), d.id) > 0;
      }
      if (!visible) continue;
      Eigen::Vector2d truth[4], centre = Eigen::Vector2d::Zero();
      for (int k = 0; k < 4; ++k) {
        truth[k] = camera.Project(
            Eigen::Vector3d(cam_from_object * tag->CornerInObject(k)));
        centre += 0.25 * truth[k];
      }
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d err = d.corners[k] - truth[k];
        if (err.norm() > 3) continue;  // a gross outlier is not bias
        e.mean += err;
        e.mean_outward += err.dot((truth[k] - centre).normalized());
        sq += err.squaredNorm();
        ++e.n;
      }
    }
  }
  e.mean /= std::max(e.n, 1);
  e.mean_outward /= std::max(e.n, 1);
  e.rms = std::sqrt(sq / std::max(e.n, 1));
  return e;
}

TEST(SynthTrackTest, CornerBiasOnRayCastFrames) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  for (double decimate : {1.0, 2.0}) {
    TagDetectorOptions options;
    options.quad_decimate = decimate;
    const CornerErrors e = MeasureCorners("clean", 8, camera, rig, options);
    std::printf(
        "clean, decimate %.0f: mean (%.3f, %.3f) px, outward %.3f px, rms "
        "%.3f px over %d corners\n",
        decimate, e.mean.x(), e.mean.y(), e.mean_outward, e.rms, e.n);
    EXPECT_GT(e.n, 200);
    EXPECT_LE(std::abs(e.mean.x()), 0.05);
    EXPECT_LE(std::abs(e.mean.y()), 0.05);
    EXPECT_LE(std::abs(e.mean_outward), 0.05);
  }
  for (double decimate : {1.0, 2.0}) {
    TagDetectorOptions options;
    options.quad_decimate = decimate;
    const CornerErrors e =
        MeasureCorners("benchmark", 12, camera, rig, options);
    std::printf(
        "benchmark, decimate %.0f: mean (%.3f, %.3f) px, outward %.3f px, rms "
        "%.3f px over %d corners\n",
        decimate, e.mean.x(), e.mean.y(), e.mean_outward, e.rms, e.n);
    EXPECT_LE(std::abs(e.mean.x()), 0.05);
    EXPECT_LE(std::abs(e.mean.y()), 0.05);
    EXPECT_LE(std::abs(e.mean_outward), 0.05);
  }
  TagDetectorOptions uncorrected;
  uncorrected.pixel_offset_px = 0;
  uncorrected.edge_outward_px = 0;
  uncorrected.edge_fit = false;
  const CornerErrors raw = MeasureCorners("clean", 4, camera, rig, uncorrected);
  std::printf("clean, uncorrected: mean (%.3f, %.3f) px, outward %.3f px\n",
              raw.mean.x(), raw.mean.y(), raw.mean_outward);
  EXPECT_NEAR(raw.mean.x(), 0.5, 0.1);
  EXPECT_NEAR(raw.mean.y(), 0.5, 0.1);
}

// The same corner bias on frames formed independently of the renderer the
// corrections were measured on (point sampling, a disc defocus kernel; a
// distorting lens, an sRGB-encoded camera and a busy table for "webcam").
TEST(SynthTrackTest, CornerBiasOnEveryVariant) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  for (const std::string& variant : synth::DataVariantNames()) {
    // The default edge fit, the former one (each profile's own dark end as
    // the border's black), and none.
    double outward_default = 0;
    for (int setting : {0, 1, 2}) {
      TagDetectorOptions options;
      options.edge_fit = setting != 2;
      options.edge_fit_border_black = setting == 0;
      const CornerErrors e =
          MeasureCorners("benchmark", 6, camera, rig, options, variant);
      const char* name[] = {"on", "on, local dark", "off"};
      std::printf(
          "%s, edge fit %s: mean (%.3f, %.3f) px, outward %.3f px, rms %.3f "
          "px over %d corners\n",
          variant.c_str(), name[setting], e.mean.x(), e.mean.y(),
          e.mean_outward, e.rms, e.n);
      EXPECT_GT(e.n, 100) << variant;
      if (setting == 0) {
        outward_default = e.mean_outward;
        EXPECT_LE(std::abs(e.mean.x()), 0.05) << variant;
        EXPECT_LE(std::abs(e.mean.y()), 0.05) << variant;
        // A uniform outward shift scales the tag: on a 25 px face 0.05 px
        // sets it 0.4% too close. What remains is mostly the tags under
        // 24 px, where the border's black fades back to the local one.
        EXPECT_LE(std::abs(e.mean_outward), 0.06) << variant;
        EXPECT_LT(e.rms, 0.16) << variant;
      } else if (setting == 1) {
        // The one-cell border lightened by white cells inside it under blur:
        // its local dark end lifts the mid level and pushes the edges out.
        EXPECT_GT(e.mean_outward, outward_default + 0.03) << variant;
      }
    }
  }
  // Without decoding, the sRGB frames' corners sit ~0.5 px inside the black
  // square, and half of the tags are lost at decimation 2.
  TagDetectorOptions encoded;
  const CornerErrors undecoded =
      MeasureCorners("benchmark", 6, camera, rig, encoded, "srgb",
                     /*decode=*/false);
  const CornerErrors decoded =
      MeasureCorners("benchmark", 6, camera, rig, encoded, "srgb");
  std::printf("srgb, not decoded: outward %.3f px over %d corners\n",
              undecoded.mean_outward, undecoded.n);
  EXPECT_LT(undecoded.mean_outward, -0.3);
  EXPECT_LT(undecoded.n, 0.7 * decoded.n);
}

TEST(SynthTrackTest, BenchmarkPresetEndToEnd) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  const std::vector<synth::FrameSpec> specs =
      test_data::SynthSpecs(camera, rig, "benchmark", 60, 20, 3);
  ASSERT_FALSE(specs.empty());
  synth::SceneRenderer renderer(camera, rig);
  Tracker tracker(camera, rig, TrackerOptions{});
  std::vector<double> tip_err, tank_rot, tip_sigma;
  int tank_visible = 0, tank_tracked = 0, flips = 0, cuts = 0;
  for (const synth::FrameSpec& spec : specs) {
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    const FrameResult r = tracker.Track(frame.image, spec.time_s);
    cuts += r.cut;
    if (!frame.tank_tags.empty()) {
      ++tank_visible;
      if (r.tank.status == TrackStatus::kTracked) ++tank_tracked;
    }
    if (r.tank.status == TrackStatus::kLost) {
      EXPECT_FALSE(r.tank.has_pose());
      continue;
    }
    const double rot =
        RotationDistance(*r.tank.cam_from_object, spec.scene.cam_from_tank);
    tank_rot.push_back(rot / kDeg);
    if (rot > 10 * kDeg) ++flips;
    if (r.tip_in_tank && spec.scene.tank_from_pen &&
        r.pen.status == TrackStatus::kTracked) {
      const Pose cam_from_pen =
          spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
      if (RotationDistance(*r.pen.cam_from_object, cam_from_pen) > 10 * kDeg)
        ++flips;
      const Eigen::Vector3d tip =
          *spec.scene.tank_from_pen * rig.pen->tip_in_pen;
      tip_err.push_back((*r.tip_in_tank - tip).norm());
      // Predicted tip standard deviation for this frame's faces at the
      // measured reprojection error (the noise level of the corners).
      const auto obs = MatchObservations(camera, rig.pen->faces, r.detections);
      tip_sigma.push_back(
          PointUncertainty(camera, obs, cam_from_pen, rig.pen->tip_in_pen) *
          std::max(r.pen.rmse_px, 0.05));
    }
  }
  std::printf(
      "benchmark preset, 60 frames: tank tracked %d/%d, tank rot median "
      "%.3f deg, tip median %.2f mm (predicted sigma median %.2f mm), %zu "
      "tip frames, %d cuts, %d flips\n",
      tank_tracked, tank_visible, Median(tank_rot), 1000 * Median(tip_err),
      1000 * Median(tip_sigma), tip_err.size(), cuts, flips);
  EXPECT_EQ(flips, 0);
  EXPECT_GE(tank_tracked, int(0.95 * tank_visible));
  EXPECT_LT(Median(tank_rot), 0.1);
  ASSERT_GE(tip_err.size(), 30u);
  // The median tip error stays within a few predicted standard deviations.
  EXPECT_LT(Median(tip_err), 3 * Median(tip_sigma) + 0.0005);
  EXPECT_LT(Median(tip_err), 0.0015);
  EXPECT_GE(cuts, 2);  // segments join by cuts
}

// The pen's rotation errors (rotation vectors, degrees) over the frames of
// `specs` where it is tracked, by a fresh tracker per 30-frame segment.
std::vector<Eigen::Vector3d> PenRotationErrors(
    const std::vector<synth::FrameSpec>& specs, const TrackerOptions& options) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  synth::SceneRenderer renderer(camera, rig);
  std::unique_ptr<Tracker> tracker;
  std::vector<Eigen::Vector3d> errors;
  for (const synth::FrameSpec& spec : specs) {
    if (spec.index % 30 == 0)
      tracker = std::make_unique<Tracker>(camera, rig, options);
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    const FrameResult r = tracker->Track(frame.image, spec.time_s);
    if (!spec.scene.tank_from_pen || r.pen.status != TrackStatus::kTracked)
      continue;
    const Pose truth = spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
    const Eigen::AngleAxisd e(r.pen.cam_from_object->rotation *
                              truth.rotation.conjugate());
    errors.push_back(e.angle() / kDeg * e.axis());
  }
  return errors;
}

// A pen acquired through its most oblique visible face alone (corners
// projected exactly, 0.15 px of noise) on rendered frames: IPPE's two
// branches often explain them alike and the track starts ambiguous. Where
// the image shows the shaft where one branch puts it and not where the
// other does, the tracker keeps that branch alone; it never keeps the wrong
// one.
TEST(SynthTrackTest, AnAmbiguousFaceIsResolvedByTheShaft) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.15);
  struct Count {
    int ambiguous = 0, right = 0, wrong = 0;
  };
  Count with, without;
  TrackerOptions options;
  Tracker with_shaft(camera, rig, options);
  options.pen_shaft_resolve_ratio = 0;
  Tracker without_shaft(camera, rig, options);
  int views = 0;
  for (const test_data::PenView& view : test_data::RenderPenViews(
           camera, rig,
           test_data::SynthSpecs(camera, rig, "benchmark", 48, 4, 11))) {
    // The visible face whose normal is most nearly across the line of
    // sight.
    const TagPlacement* seen = nullptr;
    double seen_cos = 1;
    for (const TagPlacement& face : rig.pen->faces) {
      if (std::find(view.pen_tags.begin(), view.pen_tags.end(), face.id) ==
          view.pen_tags.end())
        continue;
      const Pose cam_from_tag = view.cam_from_pen * face.object_from_tag;
      const double c = std::abs(
          cam_from_tag.R().col(2).dot(cam_from_tag.translation.normalized()));
      if (c < seen_cos) {
        seen = &face;
        seen_cos = c;
      }
    }
    if (!seen) continue;
    TagDetection d;
    d.id = seen->id;
    d.decision_margin = 100;
    for (int k = 0; k < 4; ++k)
      d.corners[k] = camera.Project(Eigen::Vector3d(view.cam_from_pen *
                                                    seen->CornerInObject(k))) +
                     Eigen::Vector2d(noise(rng), noise(rng));
    ++views;
    for (const bool shaft : {true, false}) {
      Tracker& tracker = shaft ? with_shaft : without_shaft;
      tracker.Reset();
      const FrameResult r = tracker.TrackDetections({d}, 0.0, 0, &view.gray);
      if (!r.pen.has_pose()) continue;
      Count& c = shaft ? with : without;
      const bool right = RotationDistance(*r.pen.cam_from_object,
                                          view.cam_from_pen) < 10 * kDeg;
      if (r.pen.ambiguous) {
        ++c.ambiguous;
      } else if (right) {
        ++c.right;
      } else {
        ++c.wrong;
        ADD_FAILURE() << "view " << view.index << (shaft ? " with" : " without")
                      << " the shaft: a confident wrong branch";
      }
    }
  }
  std::printf(
      "%d single-face acquisitions: with the shaft %d ambiguous, %d right, %d "
      "wrong; without %d ambiguous, %d right, %d wrong\n",
      views, with.ambiguous, with.right, with.wrong, without.ambiguous,
      without.right, without.wrong);
  EXPECT_GE(without.ambiguous, 4);
  EXPECT_LE(with.ambiguous, without.ambiguous / 2);
  EXPECT_EQ(with.wrong, 0);
}

// A turn the shaft contradicts is not taken (TrackerOptions::
// pen_shaft_turn_ratio): a pen tracked in one frame is seen in the next
// through corners that fit a pose turned 20 deg about its cube (the shaft
// swung sideways across the image), while the image still shows the pen
// where it was. The corners alone take the turn; with the shaft's second
// opinion the tracker keeps the pen near the pose the image shows and
// reports the turn rejected. Where the image turns with the corners (the
// pen did turn), the turn is taken either way.
TEST(SynthTrackTest, ATurnTheShaftContradictsIsNotTaken) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  TrackerOptions options;
  options.smoothing.enabled = false;
  Tracker with_shaft(camera, rig, options);
  options.pen_shaft_turn_ratio = 0;
  Tracker without_shaft(camera, rig, options);
  auto detections = [&](const test_data::PenView& view) {
    std::vector<TagDetection> out;
    for (const TagPlacement& face : rig.pen->faces) {
      if (std::find(view.pen_tags.begin(), view.pen_tags.end(), face.id) ==
          view.pen_tags.end())
        continue;
      TagDetection d;
      d.id = face.id;
      d.decision_margin = 100;
      for (int k = 0; k < 4; ++k)
        d.corners[k] = camera.Project(Eigen::Vector3d(view.cam_from_pen *
                                                      face.CornerInObject(k))) +
                       Eigen::Vector2d(noise(rng), noise(rng));
      out.push_back(d);
    }
    return out;
  };
  // The rotation (degrees) between the pen reported in a second frame and
  // `truth`, after a first frame of `first`; -1 where either frame's pen is
  // not tracked confidently.
  auto second_error = [&](Tracker& tracker, const test_data::PenView& first,
                          const std::vector<TagDetection>& next,
                          const cv::Mat& next_gray, const Pose& truth,
                          bool* flip_rejected) {
    tracker.Reset();
    const FrameResult a =
        tracker.TrackDetections(detections(first), 0.0, 0, &first.gray);
    if (!a.pen.has_pose() || a.pen.ambiguous ||
        RotationDistance(*a.pen.cam_from_object, first.cam_from_pen) > 2 * kDeg)
      return -1.0;
    const FrameResult b =
        tracker.TrackDetections(next, 1.0 / 30, 0, &next_gray);
    if (!b.pen.has_pose()) return -1.0;
    *flip_rejected = b.pen.flip_rejected;
    return RotationDistance(*b.pen.cam_from_object, truth) / kDeg;
  };
  synth::SceneRenderer renderer(camera, rig);
  int views = 0, kept = 0, rejected = 0, taken_without = 0, real = 0,
      real_taken = 0;
  double worst_kept_deg = 0;
  for (const synth::FrameSpec& spec :
       test_data::SynthSpecs(camera, rig, "benchmark", 24, 4, 13)) {
    test_data::PenView view, turned_view;
    if (!test_data::RenderPenView(renderer, spec, spec.imaging, spec.noise_seed,
                                  &view))
      continue;
    // Turned about the line of sight's part across the shaft.
    const Eigen::Vector3d sight = view.cam_from_pen.rotation.conjugate() *
                                  view.cam_from_pen.translation.normalized();
    const Eigen::Vector3d axis = sight - sight.z() * Eigen::Vector3d::UnitZ();
    if (axis.norm() < 0.3) continue;  // looking down the shaft
    synth::FrameSpec turned_spec = spec;
    turned_spec.scene.tank_from_pen =
        *spec.scene.tank_from_pen *
        Pose::FromAxisAngle(axis.normalized() * (20 * kDeg),
                            Eigen::Vector3d::Zero());
    if (!test_data::RenderPenView(renderer, turned_spec, spec.imaging,
                                  spec.noise_seed, &turned_view))
      continue;
    // Corners of the turned pen, of the faces the image shows.
    test_data::PenView corners_turned = view;
    corners_turned.cam_from_pen = turned_view.cam_from_pen;
    const std::vector<TagDetection> next = detections(corners_turned);
    bool rejected_with = false, unused = false;
    const double with = second_error(with_shaft, view, next, view.gray,
                                     view.cam_from_pen, &rejected_with);
    const double without = second_error(without_shaft, view, next, view.gray,
                                        view.cam_from_pen, &unused);
    if (with >= 0 && without >= 0) {
      ++views;
      if (without > 15) ++taken_without;
      if (with < 10) {
        ++kept;
        worst_kept_deg = std::max(worst_kept_deg, with);
      }
      if (rejected_with) ++rejected;
    }
    const double turned =
        second_error(with_shaft, view, detections(turned_view),
                     turned_view.gray, turned_view.cam_from_pen, &unused);
    if (turned >= 0) {
      ++real;
      if (turned < 5) ++real_taken;
    }
  }
  std::printf(
      "%d views turned 20 deg in the corners only: without the shaft's check "
      "%d taken; with it %d kept (worst %.2f deg from the truth), %d reported "
      "rejected. %d turned in the image too: %d taken (within 5 deg)\n",
      views, taken_without, kept, worst_kept_deg, rejected, real, real_taken);
  ASSERT_GE(views, 8);
  EXPECT_GE(taken_without, views * 3 / 4) << "the corners alone take the turn";
  EXPECT_GE(kept, views * 3 / 4);
  EXPECT_EQ(rejected, kept);
  ASSERT_GE(real, 8);
  EXPECT_EQ(real_taken, real) << "a turn the image shows is taken";
}

// A pen at rest is refined with more dense iterations
// (TrackerOptions::pen_rest_iterations): on the static preset (segments of
// a still pen, only the noise changing) its raw rotation spreads less about
// each segment's mean; on the benchmark preset, where the pen moves, the
// rule fires on few frames and the others' poses are those of the moving
// pen's iterations exactly.
TEST(SynthTrackTest, APenAtRestIsIteratedFurther) {
  const Camera camera = DefaultCamera();
  const Rig rig = DefaultRig();
  TrackerOptions rest;
  rest.smoothing.enabled = false;
  TrackerOptions moving = rest;
  moving.pen_rest_iterations = moving.pen_dense.max_iterations;
  ASSERT_GT(rest.pen_rest_iterations, rest.pen_dense.max_iterations);
  const auto still = test_data::SynthSpecs(camera, rig, "static", 90, 30, 1);
  auto spread = [](const std::vector<Eigen::Vector3d>& e) {
    if (e.size() < 20) return NAN * 1.0;  // the pen not tracked
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& v : e) mean += v / e.size();
    double ss = 0;
    for (const auto& v : e) ss += (v - mean).squaredNorm();
    return std::sqrt(ss / e.size());
  };
  // One segment at a time: each has its own pose and bias.
  double sum_rest = 0, sum_moving = 0;
  for (int seg = 0; seg < 3; ++seg) {
    const std::vector<synth::FrameSpec> part(still.begin() + 30 * seg,
                                             still.begin() + 30 * (seg + 1));
    const double a = spread(PenRotationErrors(part, rest));
    const double b = spread(PenRotationErrors(part, moving));
    std::printf(
        "static segment %d: pen rotation spread %.4f deg at rest, "
        "%.4f deg with the moving pen's iterations\n",
        seg, a, b);
    EXPECT_LE(a, b) << "segment " << seg;
    sum_rest += a;
    sum_moving += b;
  }
  // Measured: 0.0193 / 0.0584 / 0.2032 deg against 0.0204 / 0.0731 /
  // 0.2113, a sum 0.92 of the moving pen's.
  EXPECT_LT(sum_rest, 0.95 * sum_moving);

  const auto strokes =
      test_data::SynthSpecs(camera, rig, "benchmark", 60, 30, 3);
  const auto a = PenRotationErrors(strokes, rest);
  const auto b = PenRotationErrors(strokes, moving);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 20u);
  // Measured: 1 frame of 30, where the pen's corners moved under 0.5 px.
  int differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
  std::printf("benchmark: %d of %zu pen frames iterated as at rest\n", differ,
              a.size());
  EXPECT_LE(differ, static_cast<int>(a.size() / 10));
}

}  // namespace
}  // namespace ripple::tracking
