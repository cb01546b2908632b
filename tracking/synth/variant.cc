#include "tracking/synth/variant.h"

namespace ripple::synth {

std::vector<std::string> DataVariantNames() {
  return {"exact", "supersampled", "srgb", "lens", "webcam"};
}

bool GetDataVariant(const std::string& name, DataVariant* variant) {
  DataVariant v;
  v.name = name;
  if (name == "exact") {
    *variant = v;
    return true;
  }
  if (name != "supersampled" && name != "srgb" && name != "lens" &&
      name != "webcam")
    return false;
  v.formation.formation = Formation::kPointSampled;
  v.formation.samples_per_axis = 3;
  v.defocus_kernel = DefocusKernel::kDisc;
  v.srgb = name == "srgb" || name == "webcam";
  v.distorting_lens = name == "lens" || name == "webcam";
  v.formation.busy_table = v.distorting_lens;
  *variant = v;
  return true;
}

tracking::Camera VariantCamera(const DataVariant& variant,
                               const tracking::Camera& camera) {
  tracking::Camera c = camera;
  c.transfer =
      variant.srgb ? geometry::Transfer::kSrgb : geometry::Transfer::kLinear;
  if (variant.distorting_lens) {
    c.dist = {};
    c.dist[0] = -0.28;  // k1
    c.dist[1] = 0.09;   // k2
    c.dist[2] = 6e-4;   // p1
    c.dist[3] = -4e-4;  // p2
  }
  return c;
}

void ApplyVariant(const DataVariant& variant, ImagingOptions* imaging) {
  imaging->defocus_kernel = variant.defocus_kernel;
  imaging->srgb = variant.srgb;
}

}  // namespace ripple::synth
