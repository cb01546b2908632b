// What a mean LDR-FLIP between a render and its reference is made of, inside
// a region: how much of it one uniform change of brightness would take away
// (a bias of the light, not of the image's structure), and how much any
// renderer that reads the scene from an image of coarser resolution cannot
// avoid (the floor under water is seen magnified by about the water's
// index, so a renderer that refracts the camera's own frame holds it at
// 1/n of the output's resolution).
#ifndef RIPPLE_BENCH_FLIP_BUDGET_H_
#define RIPPLE_BENCH_FLIP_BUDGET_H_

#include <opencv2/core.hpp>
#include <string>

#include "bench/flip.h"

namespace ripple::bench {

struct UniformGainFit {
  double gain = 1;         // on the test image's linear light, in the region
  double flip = 0;         // mean FLIP over the region at `gain`
  double flip_at_one = 0;  // the same without a gain
};

// The gain g in [1 - max_change, 1 + max_change] that, multiplying the
// linear light of `test` inside `mask` (sRGB decoded; values above 1 clip),
// gives the lowest mean FLIP against `reference` over `mask`, found by
// golden-section search to `tolerance`. Images as ComputeFlip's, CV_8UC3
// sRGB; `mask` CV_8UC1 of the same size with at least one pixel set.
// max_change in (0, 1), tolerance in (0, max_change). False with `error`
// otherwise.
bool FitUniformGain(const FlipOptions& options, const cv::Mat& reference,
                    const cv::Mat& test, const cv::Mat& mask, double max_change,
                    double tolerance, UniformGainFit* fit, std::string* error);

// Mean FLIP over `mask` of `reference` against itself read at
// 1/magnification of its resolution: reduced by area averaging and brought
// back by bicubic interpolation, in linear light, inside `mask` only (the
// pixels outside keep the reference). 0 at magnification 1. magnification
// in [1, 8]; images and mask as FitUniformGain's.
bool ResolutionLossFlip(const FlipOptions& options, const cv::Mat& reference,
                        const cv::Mat& mask, double magnification, double* flip,
                        std::string* error);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_FLIP_BUDGET_H_
