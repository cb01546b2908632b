// Data variants: the same scripted scenes formed and imaged in other ways,
// so that the tracker is measured on frames it was not tuned on.
//
//   exact         the exact-area renderer, Gaussian defocus, values linear in
//                 radiance (what the tracker's defaults were tuned on);
//   supersampled  ray-cast point sampling, 3 x 3 rays per pixel averaged
//                 (Formation::kPointSampled), a disc defocus kernel;
//   srgb          supersampled, from a gamma-encoded camera (the sRGB
//                 transfer before quantisation; the camera file says
//                 `transfer: srgb`);
//   lens          supersampled, through a strongly distorting lens (k1
//                 -0.28, k2 0.09, p1 6e-4, p2 -4e-4, OpenCV's model), over
//                 a busy table;
//   webcam        all of them: supersampled, sRGB, the lens, the busy table.
#ifndef RIPPLE_TRACKING_SYNTH_VARIANT_H_
#define RIPPLE_TRACKING_SYNTH_VARIANT_H_

#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/synth/synth.h"

namespace ripple::synth {

struct DataVariant {
  std::string name = "exact";
  FormationOptions formation;
  DefocusKernel defocus_kernel = DefocusKernel::kGaussian;
  bool srgb = false;             // sRGB-encoded frames
  bool distorting_lens = false;  // the webcam lens replaces the camera's
};

// The names GetDataVariant knows, in the order benchmarks list them.
std::vector<std::string> DataVariantNames();
// False for an unknown name.
bool GetDataVariant(const std::string& name, DataVariant* variant);

// The camera the variant's frames are taken (and tracked) with: `camera`
// with the variant's lens and transfer.
tracking::Camera VariantCamera(const DataVariant& variant,
                               const tracking::Camera& camera);
// The variant's imaging on top of a sequence frame's.
void ApplyVariant(const DataVariant& variant, ImagingOptions* imaging);

}  // namespace ripple::synth

#endif  // RIPPLE_TRACKING_SYNTH_VARIANT_H_
