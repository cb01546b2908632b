#include "bench/flip_budget.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace ripple::bench {
namespace {

bool CheckInputs(const cv::Mat& reference, const cv::Mat& test,
                 const cv::Mat& mask, std::string* error) {
  if (reference.type() != CV_8UC3 || test.type() != CV_8UC3 ||
      reference.size() != test.size() || reference.empty()) {
    *error = "FLIP budget: the images must be non-empty CV_8UC3 of one size";
    return false;
  }
  if (mask.type() != CV_8UC1 || mask.size() != reference.size() ||
      cv::countNonZero(mask) == 0) {
    *error =
        "FLIP budget: the mask must be CV_8UC1 of the images' size with a "
        "pixel set";
    return false;
  }
  return true;
}

}  // namespace

bool FitUniformGain(const FlipOptions& options, const cv::Mat& reference,
                    const cv::Mat& test, const cv::Mat& mask, double max_change,
                    double tolerance, UniformGainFit* fit, std::string* error) {
  if (!CheckInputs(reference, test, mask, error)) return false;
  if (!(max_change > 0 && max_change < 1 && tolerance > 0 &&
        tolerance < max_change)) {
    *error =
        "FLIP budget: max_change must lie in (0, 1) and tolerance in "
        "(0, max_change)";
    return false;
  }
  const cv::Mat ref_linear = SrgbToLinear(reference);
  const cv::Mat test_linear = SrgbToLinear(test);
  cv::Mat scaled, map;
  auto flip_at = [&](double gain, double* out) {
    test_linear.copyTo(scaled);
    cv::Mat region = test_linear * gain;
    region.copyTo(scaled, mask);
    cv::min(scaled, 1.0, scaled);
    if (!ComputeFlip(options, ref_linear, scaled, &map, error)) return false;
    *out = MeanFlip(map, mask);
    return true;
  };
  if (!flip_at(1.0, &fit->flip_at_one)) return false;
  // Golden-section search: FLIP against a gain is unimodal near the optimum
  // (a brightness error grows either way).
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = 1.0 - max_change, b = 1.0 + max_change;
  double c = b - inv_phi * (b - a), d = a + inv_phi * (b - a);
  double fc = 0, fd = 0;
  if (!flip_at(c, &fc) || !flip_at(d, &fd)) return false;
  while (b - a > tolerance) {
    if (fc <= fd) {
      b = d, d = c, fd = fc;
      c = b - inv_phi * (b - a);
      if (!flip_at(c, &fc)) return false;
    } else {
      a = c, c = d, fc = fd;
      d = a + inv_phi * (b - a);
      if (!flip_at(d, &fd)) return false;
    }
  }
  fit->gain = fc <= fd ? c : d;
  fit->flip = std::min(fc, fd);
  // Never worse than no gain at all.
  if (fit->flip_at_one <= fit->flip) {
    fit->gain = 1.0;
    fit->flip = fit->flip_at_one;
  }
  return true;
}

bool ResolutionLossFlip(const FlipOptions& options, const cv::Mat& reference,
                        const cv::Mat& mask, double magnification, double* flip,
                        std::string* error) {
  if (!CheckInputs(reference, reference, mask, error)) return false;
  if (!(magnification >= 1.0 && magnification <= 8.0)) {
    *error = "FLIP budget: magnification must lie in [1, 8]";
    return false;
  }
  const cv::Mat linear = SrgbToLinear(reference);
  cv::Mat coarse, back;
  if (magnification == 1.0) {
    back = linear;
  } else {
    cv::resize(linear, coarse, cv::Size(), 1.0 / magnification,
               1.0 / magnification, cv::INTER_AREA);
    cv::resize(coarse, back, linear.size(), 0, 0, cv::INTER_CUBIC);
    cv::max(back, 0.0, back);
    cv::min(back, 1.0, back);
  }
  cv::Mat test = linear.clone(), map;
  back.copyTo(test, mask);
  if (!ComputeFlip(options, linear, test, &map, error)) return false;
  *flip = MeanFlip(map, mask);
  return true;
}

}  // namespace ripple::bench
