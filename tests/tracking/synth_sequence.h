// A scripted synth sequence for tracking tests (one place for the
// SequenceOptions boilerplate).
#ifndef RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_
#define RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "tracking/synth/synth.h"

namespace ripple::test_data {

// Frames of `preset` in segments of `segment_frames`; a test failure (and
// no frames) if the sequence cannot be made.
inline std::vector<synth::FrameSpec> SynthSpecs(const tracking::Camera& camera,
                                                const tracking::Rig& rig,
                                                const std::string& preset,
                                                int frames, int segment_frames,
                                                uint64_t seed) {
  synth::SequenceOptions seq;
  seq.preset = preset;
  seq.frames = frames;
  seq.segment_frames = segment_frames;
  seq.seed = seed;
  std::vector<synth::FrameSpec> specs;
  std::string error;
  EXPECT_TRUE(synth::MakeSequence(camera, rig, seq, &specs, &error)) << error;
  return specs;
}

// A rendered frame with the pen's tags in view: its grey image and truth.
struct PenView {
  int index = 0;  // the spec's frame index
  cv::Mat gray;
  tracking::Pose cam_from_pen;
  std::vector<int> pen_tags;  // ids whose whole black square is visible
};

// Renders `spec`'s scene with `imaging` and noise `noise_seed`; false when
// the scene has no pen or none of its tags is in view.
inline bool RenderPenView(const synth::SceneRenderer& renderer,
                          const synth::FrameSpec& spec,
                          const synth::ImagingOptions& imaging,
                          uint64_t noise_seed, PenView* view) {
  if (!spec.scene.tank_from_pen) return false;
  synth::RenderedFrame frame = renderer.Render(spec.scene, imaging, noise_seed);
  if (frame.pen_tags.empty()) return false;
  view->index = spec.index;
  cv::cvtColor(frame.image, view->gray, cv::COLOR_BGR2GRAY);
  view->cam_from_pen = spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
  view->pen_tags = std::move(frame.pen_tags);
  return true;
}

// Renders `specs` (each with its own imaging, or `imaging` when given) and
// keeps those with the pen's tags in view, at most `max_views`.
inline std::vector<PenView> RenderPenViews(
    const tracking::Camera& camera, const tracking::Rig& rig,
    const std::vector<synth::FrameSpec>& specs,
    const synth::ImagingOptions* imaging = nullptr, size_t max_views = 1000) {
  synth::SceneRenderer renderer(camera, rig);
  std::vector<PenView> views;
  for (const synth::FrameSpec& spec : specs) {
    if (views.size() >= max_views) break;
    PenView v;
    if (RenderPenView(renderer, spec, imaging ? *imaging : spec.imaging,
                      spec.noise_seed, &v))
      views.push_back(std::move(v));
  }
  return views;
}

}  // namespace ripple::test_data

#endif  // RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_
