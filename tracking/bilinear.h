// Bilinear sampling of 8-bit grey images in OpenCV's pixel convention
// (integer coordinates are pixel centres). Internal to tracking/.
#ifndef RIPPLE_TRACKING_BILINEAR_H_
#define RIPPLE_TRACKING_BILINEAR_H_

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>

namespace ripple::tracking {

// Value at (x, y); false (and *v untouched) unless all four neighbours are
// inside the image.
inline bool SampleBilinear(const cv::Mat& g, double x, double y, double* v) {
  const int x0 = static_cast<int>(std::floor(x));
  const int y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= g.cols || y0 + 1 >= g.rows) return false;
  const double fx = x - x0, fy = y - y0;
  const uint8_t* r0 = g.ptr<uint8_t>(y0) + x0;
  const uint8_t* r1 = g.ptr<uint8_t>(y0 + 1) + x0;
  *v = (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) +
       fy * ((1 - fx) * r1[0] + fx * r1[1]);
  return true;
}

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_BILINEAR_H_
