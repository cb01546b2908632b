// The FLIP tests' photo-like test image, shared with the cross-check
// against NVIDIA's implementation (scripts/flip_crosscheck.cc).
#ifndef RIPPLE_TESTS_BENCH_SYNTH_PHOTO_H_
#define RIPPLE_TESTS_BENCH_SYNTH_PHOTO_H_

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>

namespace ripple::bench::testing {

// A photo-like BGR8 image from formulas alone (no OpenCV drawing or random
// generator, so that its pixels do not depend on the OpenCV version): smooth
// colour gradients, a disc and a rectangle with hard edges, a thin dark
// diagonal, and hashed pixel noise in [-12, 12], the same for a given seed.
inline cv::Mat SynthesizePhoto(int width, int height, uint32_t seed) {
  cv::Mat image(height, width, CV_8UC3);
  const double cx = width / 3.0, cy = height / 2.0, radius = height / 5.0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double u = (x + 0.5) / width, v = (y + 0.5) / height;
      double bgr[3] = {40 + 160 * v, 90 + 80 * std::sin(6 * u + 2 * v),
                       200 - 150 * u * v};
      auto paint = [&bgr](double b, double g, double r) {
        bgr[0] = b, bgr[1] = g, bgr[2] = r;
      };
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= radius * radius) {
        paint(30, 60, 220);
      }
      if (2 * x >= width && 5 * x <= 4 * width && 5 * y >= height &&
          2 * y <= height) {
        paint(240, 240, 240);
      }
      if (std::abs(y - (height - 1) * (1 - u)) < 0.8) paint(10, 10, 10);
      for (int c = 0; c < 3; ++c) {
        uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^
                     seed * 83492791u ^ uint32_t(c) * 2654435761u;
        h ^= h >> 13;
        h *= 0x5bd1e995u;
        h ^= h >> 15;
        bgr[c] += int(h % 25) - 12;
      }
      image.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(bgr[0]),
                                            cv::saturate_cast<uchar>(bgr[1]),
                                            cv::saturate_cast<uchar>(bgr[2]));
    }
  }
  return image;
}

}  // namespace ripple::bench::testing

#endif  // RIPPLE_TESTS_BENCH_SYNTH_PHOTO_H_
