#include "app/app_synth_source.h"

namespace ripple::app {

SynthSource::SynthSource(const tracking::Camera& camera,
                         const tracking::Rig& rig,
                         std::vector<synth::FrameSpec> frames,
                         synth::FloorPattern floor)
    : FrameSource(Kind::kSynthetic, "synthetic"),
      renderer_(camera, rig, std::move(floor)),
      frames_(std::move(frames)) {
  size_ = cv::Size(camera.width, camera.height);
}

bool SynthSource::Read(cv::Mat* bgr, double* time_s) {
  if (next_ >= frames_.size()) return false;
  const synth::FrameSpec& f = frames_[next_++];
  *bgr = renderer_.Render(f.scene, f.imaging, f.noise_seed).image;
  *time_s = f.time_s;
  ++frames_read_;
  return true;
}

}  // namespace ripple::app
