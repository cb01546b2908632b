// A scripted synth sequence for tracking tests (one place for the
// SequenceOptions boilerplate).
#ifndef RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_
#define RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_

#include <gtest/gtest.h>

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

}  // namespace ripple::test_data

#endif  // RIPPLE_TESTS_TRACKING_SYNTH_SEQUENCE_H_
