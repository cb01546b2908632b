// LDR-FLIP: the perceptual difference between a reference and a test image as
// seen by an observer flipping between them (Andersson, Nilsson,
// Akenine-Moller, Oskarsson, Astrom, Fairchild, "FLIP: A Difference Evaluator
// for Alternating Images", HPG 2020). Per pixel, a colour error (both images
// filtered by the contrast sensitivity functions of the observer, compared in
// a Hunt-adjusted L*a*b* by the HyAB distance) is raised by a feature error
// (differences in edges and points of the achromatic channel):
//   dE = dEc ^ (1 - dEf), in [0, 1].
// The observer is one number, pixels per degree of visual angle.
#ifndef RIPPLE_BENCH_FLIP_H_
#define RIPPLE_BENCH_FLIP_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ripple::bench {

// Pixels per degree of visual angle of a screen `screen_width_m` wide showing
// `screen_width_px` pixels across, seen from `distance_m` (FLIP, viewing
// conditions: p = d (r / w) pi / 180, the small-angle form).
constexpr double FlipPixelsPerDegree(double distance_m, double screen_width_m,
                                     double screen_width_px) {
  return distance_m * (screen_width_px / screen_width_m) *
         3.14159265358979323846 / 180.0;
}

struct FlipOptions {
  // Observer, pixels per degree of visual angle. Default: the paper's viewing
  // conditions, 0.7 m from a 0.7 m wide monitor of 3840 px across,
  // 0.7 * (3840 / 0.7) * pi / 180 = 67.02 px/deg. Valid in [1, 1000]: below 1
  // the feature kernels are narrower than a pixel, above 1000 the colour
  // kernels pass 270 taps.
  double pixels_per_degree = FlipPixelsPerDegree(0.7, 0.7, 3840);

  bool IsValid(std::string* error) const;
};

// The FLIP error map of `test` against `reference`.
// Images: both CV_8UC3 BGR, sRGB-encoded (LDR-FLIP's input), or both CV_32FC3
// linear BGR with every value in [0, 1]; equal size, at least 1x1. Borders
// are clamped to the edge. `error_map` (may be null: inputs are only checked)
// becomes CV_32FC1 of the image size, values in [0, 1]: 0 wherever the
// images agree over the filters' reach (everywhere for identical images).
// Returns false with `error` on invalid options or inputs.
bool ComputeFlip(const FlipOptions& options, const cv::Mat& reference,
                 const cv::Mat& test, cv::Mat* error_map, std::string* error);

// Mean of `error_map` (CV_32FC1) over the pixels where `mask` (CV_8UC1, same
// size) is non-zero; an empty mask means every pixel. 0 when no pixel counts.
// A mask of another type or size is a programmer error (RIPPLE_CHECK).
double MeanFlip(const cv::Mat& error_map, const cv::Mat& mask = cv::Mat());

// A CV_8UC3 sRGB image as CV_32FC3 linear light, decoded as ComputeFlip
// decodes its 8-bit inputs (IEC 61966-2-1).
cv::Mat SrgbToLinear(const cv::Mat& bgr8);

// `error_map` (CV_32FC1, [0, 1]) as a BGR8 image through the magma colour
// map, as the paper's figures: black at 0, pale yellow at 1.
cv::Mat FlipHeatmap(const cv::Mat& error_map);

// The pipeline's parts, exposed for their tests.
namespace flip_internal {

// Channels of the YyCxCz opponent space (FLIP, colour pipeline).
enum class Channel { kAchromatic, kRedGreen, kBlueYellow };

// A 2-D kernel as a sum of separable terms, sum_i weight_i * y_i * x_i^T;
// x and y are CV_32FC1 rows of 2 * radius + 1 taps. Applied by correlation
// (cv::sepFilter2D) with borders clamped to the edge.
struct SeparableKernel {
  struct Term {
    double weight = 1;
    cv::Mat x;
    cv::Mat y;
  };
  std::vector<Term> terms;
  int radius = 0;
};

// Radius in pixels of the colour filters of every channel: three standard
// deviations of the widest Gaussian of the CSFs (FLIP, colour pipeline).
int CsfRadius(double pixels_per_degree);

// The spatial-domain CSF filter of `channel`, sum_i a_i sqrt(pi / b_i)
// exp(-pi^2 r^2 / b_i) with r in degrees (FLIP, colour
// pipeline), normalised
// to sum 1.
SeparableKernel CsfKernel(Channel channel, double pixels_per_degree);

// Standard deviation in pixels of the feature detectors' Gaussian,
// 0.5 * w * ppd with w = 0.082 degrees (FLIP, feature pipeline); radius ceil(3
// sigma).
double FeatureSigma(double pixels_per_degree);

// The edge (first derivative of the Gaussian) and point (second derivative)
// detectors along x (FLIP, feature pipeline); their transposes detect along y.
// The positive taps sum to 1 and the negative ones to -1.
SeparableKernel EdgeKernelX(double pixels_per_degree);
SeparableKernel PointKernelX(double pixels_per_degree);
SeparableKernel Transposed(const SeparableKernel& kernel);

// `kernel` as a dense (2r+1) x (2r+1) CV_32FC1 matrix.
cv::Mat Dense(const SeparableKernel& kernel);

// `plane` (CV_32FC1) correlated with `kernel`, borders clamped to the edge.
cv::Mat Apply(const SeparableKernel& kernel, const cv::Mat& plane);

// Linear RGB in [0, 1] to Hunt-adjusted CIE L*a*b* (D65, white = RGB 1 1 1):
// (L*, L* a* / 100, L* b* / 100) (FLIP, colour pipeline).
cv::Vec3d HuntLabFromLinearRgb(const cv::Vec3d& rgb);

// The HyAB distance |dL| + sqrt(da^2 + db^2) (FLIP, colour pipeline).
double HyAB(const cv::Vec3d& lab0, const cv::Vec3d& lab1);

// HyAB distance in Hunt-adjusted L*a*b* to the colour error in [0, 1]: the
// distance to the power 0.7, then the two-piece linear map of the paper
// (pc = 0.4, pt = 0.95, cmax the error between green and blue).
double CompressColorError(double hyab);

// The feature error dEf of two normalised achromatic planes (CV_32FC1, values
// in [0, 1]): (max(|de|, |dp|) / sqrt(2)) ^ 0.5, de and dp the differences of
// the edge and point magnitudes (FLIP, feature pipeline).
cv::Mat FeatureDifference(const cv::Mat& reference_y, const cv::Mat& test_y,
                          double pixels_per_degree);

}  // namespace flip_internal
}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_FLIP_H_
