// Synthetic frames as a FrameSource: synth's scene renderer drawing a list of
// frame specs (the demo's scripted pen path), timed by the specs' times.
#ifndef RIPPLE_APP_APP_SYNTH_SOURCE_H_
#define RIPPLE_APP_APP_SYNTH_SOURCE_H_

#include <vector>

#include "app/app_source.h"
#include "tracking/synth/synth.h"

namespace ripple::app {

class SynthSource : public FrameSource {
 public:
  SynthSource(const tracking::Camera& camera, const tracking::Rig& rig,
              std::vector<synth::FrameSpec> frames,
              synth::FloorPattern floor = synth::FloorPattern());

  // Renders the next spec (exact scene, imaging effects, the spec's noise
  // seed); its time is the spec's time_s.
  bool Read(cv::Mat* bgr, double* time_s) override;
  int frame_count() const override { return static_cast<int>(frames_.size()); }

 private:
  synth::SceneRenderer renderer_;
  std::vector<synth::FrameSpec> frames_;
  size_t next_ = 0;
};

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_SYNTH_SOURCE_H_
