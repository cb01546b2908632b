#include "bench/flip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "tests/bench/synth_photo.h"

namespace ripple::bench {
namespace {

using flip_internal::Channel;
using flip_internal::SeparableKernel;
using testing::SynthesizePhoto;

constexpr double kPi = 3.14159265358979323846;

cv::Mat Flat(int width, int height, const cv::Scalar& bgr, int type = CV_8UC3) {
  return cv::Mat(height, width, type, bgr);
}

cv::Mat Flip(const cv::Mat& reference, const cv::Mat& test,
             const FlipOptions& options = {}) {
  cv::Mat map;
  std::string error;
  EXPECT_TRUE(ComputeFlip(options, reference, test, &map, &error)) << error;
  return map;
}

double MaxAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_INF);
}

TEST(FlipOptionsTest, DefaultIsThePapersObserver) {
  // 0.7 m from a 0.7 m wide 4K monitor: 0.7 * (3840 / 0.7) * pi / 180.
  EXPECT_NEAR(FlipPixelsPerDegree(0.7, 0.7, 3840), 67.0206, 1e-4);
  EXPECT_NEAR(FlipPixelsPerDegree(0.7, 0.7, 3840), 3840 * kPi / 180, 1e-12);
  EXPECT_DOUBLE_EQ(FlipOptions().pixels_per_degree,
                   FlipPixelsPerDegree(0.7, 0.7, 3840));
  // Twice the distance, twice the pixels per degree.
  EXPECT_NEAR(FlipPixelsPerDegree(1.4, 0.7, 3840),
              2 * FlipPixelsPerDegree(0.7, 0.7, 3840), 1e-12);
  std::string error;
  EXPECT_TRUE(FlipOptions().IsValid(&error)) << error;
}

TEST(FlipOptionsTest, RejectsObserversOutsideTheRange) {
  for (double ppd : {0.0, -5.0, 0.5, 1001.0, double(NAN), double(INFINITY)}) {
    FlipOptions options;
    options.pixels_per_degree = ppd;
    std::string error;
    EXPECT_FALSE(options.IsValid(&error)) << ppd;
    EXPECT_NE(error.find("pixels_per_degree"), std::string::npos) << error;
  }
}

TEST(FlipKernelTest, CsfRadiusIsThreeSigmaOfTheWidestGaussian) {
  // Widest: b = 0.04 (blue-yellow), sigma = sqrt(0.04 / (2 pi^2)) = 0.045016
  // deg; 3 sigma at 67.02 px/deg is 9.05 px.
  EXPECT_EQ(flip_internal::CsfRadius(FlipOptions().pixels_per_degree), 10);
  EXPECT_EQ(flip_internal::CsfRadius(10), 2);    // 1.35 px
  EXPECT_EQ(flip_internal::CsfRadius(100), 14);  // 13.5 px
}

TEST(FlipKernelTest, CsfKernelsSumToOneAndMatchThePapersFormula) {
  struct Constants {
    Channel channel;
    double a1, b1, a2, b2;
  };
  // The paper's CSF constants, written out again for an independent check.
  const Constants channels[] = {
      {Channel::kAchromatic, 1, 0.0047, 0, 1e-5},
      {Channel::kRedGreen, 1, 0.0053, 0, 1e-5},
      {Channel::kBlueYellow, 34.1, 0.04, 13.5, 0.025},
  };
  for (double ppd : {10.0, FlipOptions().pixels_per_degree, 150.0}) {
    for (const Constants& c : channels) {
      const SeparableKernel kernel = flip_internal::CsfKernel(c.channel, ppd);
      const cv::Mat dense = flip_internal::Dense(kernel);
      const int r = kernel.radius;
      ASSERT_EQ(r, flip_internal::CsfRadius(ppd));
      EXPECT_NEAR(cv::sum(dense)[0], 1.0, 1e-5);
      // The 2-D spatial form a sqrt(pi/b) exp(-pi^2 d^2 / b), d in degrees,
      // normalised, against its separable evaluation.
      cv::Mat expected(2 * r + 1, 2 * r + 1, CV_64F);
      for (int y = -r; y <= r; ++y) {
        for (int x = -r; x <= r; ++x) {
          const double d2 = (x * x + y * y) / (ppd * ppd);
          expected.at<double>(y + r, x + r) =
              c.a1 * std::sqrt(kPi / c.b1) * std::exp(-kPi * kPi * d2 / c.b1) +
              c.a2 * std::sqrt(kPi / c.b2) * std::exp(-kPi * kPi * d2 / c.b2);
        }
      }
      expected /= cv::sum(expected)[0];
      expected.convertTo(expected, CV_32F);
      EXPECT_LT(MaxAbsDiff(dense, expected), 1e-6) << ppd;
    }
  }
  // Chroma is seen blurrier than luminance: the blue-yellow kernel is flatter.
  const double ppd = FlipOptions().pixels_per_degree;
  const cv::Mat a =
      flip_internal::Dense(flip_internal::CsfKernel(Channel::kAchromatic, ppd));
  const cv::Mat by =
      flip_internal::Dense(flip_internal::CsfKernel(Channel::kBlueYellow, ppd));
  const int c = a.rows / 2;
  EXPECT_GT(a.at<float>(c, c), 2 * by.at<float>(c, c));
}

TEST(FlipKernelTest, FeatureKernelsHaveZeroDcAndUnitSignedSums) {
  const double ppd = FlipOptions().pixels_per_degree;
  // sigma = 0.5 * 0.082 * 67.02 = 2.748 px; radius ceil(3 sigma) = 9.
  EXPECT_NEAR(flip_internal::FeatureSigma(ppd), 2.7478, 1e-4);
  const SeparableKernel edge = flip_internal::EdgeKernelX(ppd);
  const SeparableKernel point = flip_internal::PointKernelX(ppd);
  EXPECT_EQ(edge.radius, 9);
  EXPECT_EQ(point.radius, 9);
  for (const SeparableKernel& kernel :
       {edge, point, flip_internal::Transposed(edge),
        flip_internal::Transposed(point)}) {
    const cv::Mat dense = flip_internal::Dense(kernel);
    double positive = 0, negative = 0;
    for (int i = 0; i < dense.rows * dense.cols; ++i) {
      const float v = dense.at<float>(i);
      (v > 0 ? positive : negative) += v;
    }
    EXPECT_NEAR(positive, 1.0, 1e-5);
    EXPECT_NEAR(negative, -1.0, 1e-5);
    EXPECT_NEAR(cv::sum(dense)[0], 0.0, 1e-6);
  }
  const cv::Mat e = flip_internal::Dense(edge);
  const cv::Mat p = flip_internal::Dense(point);
  const int c = e.rows / 2;
  for (int x = 1; x <= edge.radius; ++x) {
    // The edge detector is odd along x, the point detector even.
    EXPECT_FLOAT_EQ(e.at<float>(c, c + x), -e.at<float>(c, c - x));
    EXPECT_FLOAT_EQ(p.at<float>(c, c + x), p.at<float>(c, c - x));
  }
  EXPECT_EQ(e.at<float>(c, c), 0.0f);
  EXPECT_LT(p.at<float>(c, c), 0.0f);  // negative inside |x| < sigma
  // The y detectors are the x detectors' transposes.
  const cv::Mat ey = flip_internal::Dense(flip_internal::Transposed(edge));
  EXPECT_EQ(MaxAbsDiff(ey, e.t()), 0.0);
}

TEST(FlipColorTest, HuntLabOfKnownColours) {
  // White: L* = 100, no chroma.
  const cv::Vec3d white = flip_internal::HuntLabFromLinearRgb({1, 1, 1});
  EXPECT_NEAR(white[0], 100, 1e-9);
  EXPECT_NEAR(white[1], 0, 1e-9);
  EXPECT_NEAR(white[2], 0, 1e-9);
  // sRGB 128 grey: linear ((128/255 + 0.055) / 1.055)^2.4 = 0.215861, so
  // L* = 116 * 0.215861^(1/3) - 16 = 53.585.
  const double grey_linear = std::pow((128 / 255.0 + 0.055) / 1.055, 2.4);
  EXPECT_NEAR(grey_linear, 0.215861, 1e-6);
  const cv::Vec3d grey = flip_internal::HuntLabFromLinearRgb(
      {grey_linear, grey_linear, grey_linear});
  EXPECT_NEAR(grey[0], 53.585, 1e-3);
  EXPECT_NEAR(grey[1], 0, 1e-9);
  EXPECT_NEAR(grey[2], 0, 1e-9);
  // Red: Y = 0.212639 (the sRGB primaries and D65 white), CIE L*a*b*
  // (53.2371, 80.0901, 67.2033); the Hunt adjustment scales a* and b* by
  // L* / 100 to (42.638, 35.777).
  const cv::Vec3d red = flip_internal::HuntLabFromLinearRgb({1, 0, 0});
  EXPECT_NEAR(red[0], 53.2371, 1e-3);
  EXPECT_NEAR(red[1], 42.638, 1e-3);
  EXPECT_NEAR(red[2], 35.777, 1e-3);
  // Black is the origin.
  const cv::Vec3d black = flip_internal::HuntLabFromLinearRgb({0, 0, 0});
  EXPECT_NEAR(cv::norm(black), 0, 1e-9);
}

TEST(FlipColorTest, HyABAndItsCompression) {
  EXPECT_DOUBLE_EQ(flip_internal::HyAB({50, 3, 4}, {40, 0, 0}), 10 + 5);
  EXPECT_DOUBLE_EQ(flip_internal::HyAB({40, 0, 0}, {50, 3, 4}), 10 + 5);
  EXPECT_EQ(flip_internal::CompressColorError(0), 0);
  // Green against blue is cmax: error 1.
  const double green_blue =
      flip_internal::HyAB(flip_internal::HuntLabFromLinearRgb({0, 1, 0}),
                          flip_internal::HuntLabFromLinearRgb({0, 0, 1}));
  EXPECT_NEAR(green_blue, 203.305, 1e-3);
  EXPECT_NEAR(flip_internal::CompressColorError(green_blue), 1.0, 1e-9);
  // Black against white: 100^0.7 = 25.119 past the knee pc cmax = 16.511
  // (cmax = 203.305^0.7 = 41.277): 0.95 + (25.119 - 16.511) / (41.277 -
  // 16.511) * 0.05 = 0.96738.
  EXPECT_NEAR(flip_internal::CompressColorError(100), 0.96738, 1e-5);
  // Continuous and increasing across the knee (HyAB 16.511^(1/0.7) = 54.91).
  double previous = 0;
  for (double hyab = 0.5; hyab <= 210; hyab += 0.5) {
    const double e = flip_internal::CompressColorError(hyab);
    EXPECT_GE(e, previous) << hyab;
    EXPECT_LT(e - previous, 0.1) << hyab;
    EXPECT_LE(e, 1.0);
    previous = e;
  }
  const double knee = std::pow(0.4 * std::pow(green_blue, 0.7), 1 / 0.7);
  EXPECT_NEAR(flip_internal::CompressColorError(knee), 0.95, 1e-9);
}

TEST(FlipTest, IdenticalImagesGiveExactlyZero) {
  const cv::Mat photo = SynthesizePhoto(120, 90, 1);
  const cv::Mat map = Flip(photo, photo);
  ASSERT_EQ(map.type(), CV_32FC1);
  ASSERT_EQ(map.size(), photo.size());
  EXPECT_EQ(cv::countNonZero(map), 0);
  cv::Mat linear;
  photo.convertTo(linear, CV_32FC3, 1 / 255.0);
  EXPECT_EQ(cv::countNonZero(Flip(linear, linear)), 0);
  EXPECT_EQ(MeanFlip(map), 0);
}

TEST(FlipTest, MapIsWithinTheUnitIntervalAndSymmetric) {
  const cv::Mat reference = SynthesizePhoto(160, 120, 2);
  cv::Mat noise(reference.size(), CV_8UC3);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  for (const cv::Mat& test :
       {SynthesizePhoto(160, 120, 4), noise, Flat(160, 120, {0, 255, 0}),
        Flat(160, 120, {255, 0, 0})}) {
    const cv::Mat map = Flip(reference, test);
    double lo, hi;
    cv::minMaxLoc(map, &lo, &hi);
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 1.0);
    EXPECT_GT(hi, 0.0);
    // Both pipelines compare the images by absolute differences.
    EXPECT_EQ(MaxAbsDiff(map, Flip(test, reference)), 0.0);
  }
}

TEST(FlipTest, FlatExtremesGiveTheirHandComputedErrors) {
  // Flat images have no features, so dE = dEc: black against white is
  // 0.96738 (see HyABAndItsCompression), green against blue the maximum, 1.
  const cv::Mat bw =
      Flip(Flat(40, 30, {0, 0, 0}), Flat(40, 30, {255, 255, 255}));
  double lo, hi;
  cv::minMaxLoc(bw, &lo, &hi);
  EXPECT_NEAR(lo, 0.96738, 1e-4);
  EXPECT_NEAR(hi, 0.96738, 1e-4);
  const cv::Mat gb = Flip(Flat(40, 30, {0, 255, 0}), Flat(40, 30, {255, 0, 0}));
  cv::minMaxLoc(gb, &lo, &hi);
  EXPECT_NEAR(lo, 1.0, 1e-5);
  EXPECT_NEAR(hi, 1.0, 1e-5);
}

TEST(FlipTest, ErrorGrowsWithTheColourDifference) {
  // A flat grey against flat greys of growing red: a ramp in dE.
  const cv::Mat reference = Flat(32, 24, {100, 110, 120});
  double previous = 0;
  for (int step = 2; step <= 120; step += 2) {
    const double mean =
        MeanFlip(Flip(reference, Flat(32, 24, {100, 110, 120.0 + step})));
    EXPECT_GT(mean, previous) << step;
    previous = mean;
  }
  EXPECT_LT(MeanFlip(Flip(reference, Flat(32, 24, {100, 110, 122}))), 0.1);
  // And on a photo: more colour shift, more error.
  const cv::Mat photo = SynthesizePhoto(96, 72, 5);
  previous = 0;
  for (int shift : {2, 6, 15, 40}) {
    cv::Mat shifted;
    cv::add(photo, cv::Scalar(0, 0, shift), shifted);
    const double mean = MeanFlip(Flip(photo, shifted));
    EXPECT_GT(mean, previous) << shift;
    previous = mean;
  }
}

TEST(FlipTest, OnePixelEdgeShiftGivesFeatureErrorAlongTheEdgeOnly) {
  const int width = 80, height = 40, edge = 40;
  cv::Mat reference = Flat(width, height, {60, 60, 60});
  cv::Mat test = reference.clone();
  reference.colRange(edge, width).setTo(cv::Scalar(200, 200, 200));
  test.colRange(edge + 1, width).setTo(cv::Scalar(200, 200, 200));
  const double ppd = FlipOptions().pixels_per_degree;

  // The achromatic channel normalised to [0, 1] of a grey is its linear value.
  const float dark = std::pow((60 / 255.0f + 0.055f) / 1.055f, 2.4f);
  const float bright = std::pow((200 / 255.0f + 0.055f) / 1.055f, 2.4f);
  cv::Mat y_r(height, width, CV_32F, cv::Scalar(dark));
  cv::Mat y_t = y_r.clone();
  y_r.colRange(edge, width).setTo(bright);
  y_t.colRange(edge + 1, width).setTo(bright);
  const cv::Mat feature = flip_internal::FeatureDifference(y_r, y_t, ppd);
  const int reach = flip_internal::EdgeKernelX(ppd).radius;
  double near_max = 0;
  cv::minMaxLoc(feature.colRange(edge - 3, edge + 4), nullptr, &near_max);
  EXPECT_GT(near_max, 0.3);
  // Beyond the detectors' reach the neighbourhoods are identical.
  EXPECT_EQ(cv::countNonZero(feature.colRange(0, edge - reach)), 0);
  EXPECT_EQ(cv::countNonZero(feature.colRange(edge + reach + 2, width)), 0);

  const cv::Mat map = Flip(reference, test);
  const int colour_reach = flip_internal::CsfRadius(ppd);
  cv::minMaxLoc(map.colRange(edge - 3, edge + 4), nullptr, &near_max);
  EXPECT_GT(near_max, 0.5);
  const int far = std::max(reach, colour_reach) + 2;
  EXPECT_EQ(cv::countNonZero(map.colRange(0, edge - far)), 0);
  EXPECT_EQ(cv::countNonZero(map.colRange(edge + far, width)), 0);
}

TEST(FlipTest, MatchesNvidiasReferenceImplementationOnSmallPairs) {
  // Expected values from NVIDIA's reference implementation (NVlabs/flip,
  // FLIP.h v1.6, LDR-FLIP at its default 67.02 px/deg, CPU) on these exact
  // pairs; its flip tool on the same pairs saved as PNG prints the same
  // means. Ours differ by at most 4e-6 in the mean and 4e-5 per pixel, from
  // the RGB-to-XYZ matrix (NVIDIA's rounded rationals, ours derived from the
  // sRGB chromaticities); the tolerances leave a few times that.
  const cv::Mat photo = SynthesizePhoto(64, 48, 7);
  cv::Mat colour;
  cv::add(photo, cv::Scalar(-10, 0, 15), colour);
  cv::Mat shifted = photo.clone();  // one pixel right, first column repeated
  photo.colRange(0, 63).copyTo(shifted.colRange(1, 64));
  const cv::Mat other_noise = SynthesizePhoto(64, 48, 8);
  struct Expected {
    const char* name;
    cv::Mat test;
    double mean, max;
  };
  const Expected pairs[] = {
      {"colour shift", colour, 0.2312894, 0.3294477},
      {"1 px shift", shifted, 0.1527882, 0.6777254},
      {"other noise", other_noise, 0.0891291, 0.2800862},
  };
  for (const Expected& pair : pairs) {
    const cv::Mat map = Flip(photo, pair.test);
    double max = 0;
    cv::minMaxLoc(map, nullptr, &max);
    EXPECT_NEAR(MeanFlip(map), pair.mean, 1e-5) << pair.name;
    EXPECT_NEAR(max, pair.max, 1e-4) << pair.name;
  }
}

TEST(FlipTest, LinearFloatInputMatchesItsSrgbEncoding) {
  const cv::Mat a = SynthesizePhoto(64, 48, 6);
  const cv::Mat b = SynthesizePhoto(64, 48, 7);
  auto decode = [](const cv::Mat& srgb) {
    cv::Mat lut(1, 256, CV_32FC3);
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      const float v =
          float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
      lut.at<cv::Vec3f>(i) = {v, v, v};
    }
    cv::Mat out(srgb.size(), CV_32FC3);
    for (int y = 0; y < srgb.rows; ++y) {
      for (int x = 0; x < srgb.cols; ++x) {
        const cv::Vec3b p = srgb.at<cv::Vec3b>(y, x);
        out.at<cv::Vec3f>(y, x) = {lut.at<cv::Vec3f>(p[0])[0],
                                   lut.at<cv::Vec3f>(p[1])[0],
                                   lut.at<cv::Vec3f>(p[2])[0]};
      }
    }
    return out;
  };
  EXPECT_LT(MaxAbsDiff(Flip(a, b), Flip(decode(a), decode(b))), 1e-6);
}

TEST(FlipTest, TinyImagesAreFine) {
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(3, 2), cv::Size(1, 9)}) {
    const cv::Mat a = Flat(size.width, size.height, {10, 20, 30});
    const cv::Mat b = Flat(size.width, size.height, {30, 20, 10});
    EXPECT_EQ(cv::countNonZero(Flip(a, a)), 0);
    const cv::Mat map = Flip(a, b);
    ASSERT_EQ(map.size(), size);
    double lo, hi;
    cv::minMaxLoc(map, &lo, &hi);
    EXPECT_GT(lo, 0.0);
    EXPECT_LE(hi, 1.0);
  }
}

TEST(FlipTest, RejectsBadInputWithAMessage) {
  const cv::Mat good = Flat(16, 12, {1, 2, 3});
  cv::Mat floats = Flat(16, 12, {0.5, 0.5, 0.5}, CV_32FC3);
  cv::Mat too_bright = floats.clone();
  too_bright.at<cv::Vec3f>(3, 4)[1] = 1.5f;
  cv::Mat not_a_number = floats.clone();
  not_a_number.at<cv::Vec3f>(0, 0)[0] = NAN;
  struct Case {
    cv::Mat reference, test;
    const char* expected;
  };
  const Case cases[] = {
      {good, Flat(17, 12, {1, 2, 3}), "differ in size"},
      {good, floats, "differ in size or type"},
      {good, cv::Mat(12, 16, CV_8UC1, cv::Scalar(3)), "must be CV_8UC3"},
      {cv::Mat(12, 16, CV_16UC3, cv::Scalar(3, 3, 3)), good, "must be CV_8UC3"},
      {cv::Mat(12, 16, CV_8UC4, cv::Scalar(3, 3, 3)), good, "must be CV_8UC3"},
      {cv::Mat(), good, "empty"},
      {floats, too_bright, "outside [0, 1] at pixel (4, 3)"},
      {not_a_number, floats, "outside [0, 1]"},
  };
  for (const Case& c : cases) {
    cv::Mat map(2, 2, CV_32F, cv::Scalar(7));
    std::string error;
    EXPECT_FALSE(ComputeFlip({}, c.reference, c.test, &map, &error));
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_EQ(map.at<float>(0, 0), 7.0f);  // untouched
  }
  FlipOptions bad;
  bad.pixels_per_degree = 0;
  std::string error;
  cv::Mat map;
  EXPECT_FALSE(ComputeFlip(bad, good, good, &map, &error));
  EXPECT_NE(error.find("pixels_per_degree"), std::string::npos);
  // Without a map only the inputs are checked.
  EXPECT_TRUE(ComputeFlip({}, good, good, nullptr, &error));
  EXPECT_FALSE(ComputeFlip({}, good, floats, nullptr, &error));
}

TEST(FlipTest, MeanOverAMask) {
  cv::Mat map(4, 4, CV_32F, cv::Scalar(0.2));
  map.rowRange(0, 2).setTo(0.6);
  EXPECT_NEAR(MeanFlip(map), 0.4, 1e-7);
  EXPECT_NEAR(MeanFlip(map, cv::Mat()), 0.4, 1e-7);
  cv::Mat mask = cv::Mat::zeros(4, 4, CV_8U);
  mask.rowRange(0, 1).setTo(255);
  EXPECT_NEAR(MeanFlip(map, mask), 0.6, 1e-7);
  mask.row(3).setTo(1);
  EXPECT_NEAR(MeanFlip(map, mask), 0.4, 1e-7);
  EXPECT_EQ(MeanFlip(map, cv::Mat::zeros(4, 4, CV_8U)), 0);
  EXPECT_EQ(MeanFlip(cv::Mat()), 0);
  // OpenCV's worker threads are running by now: re-execute for the child.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(MeanFlip(map, cv::Mat::zeros(3, 4, CV_8U)), "mask");
  EXPECT_DEATH(MeanFlip(map, cv::Mat::zeros(4, 4, CV_32F)), "mask");
}

TEST(FlipTest, HeatmapIsMagma) {
  cv::Mat map(2, 3, CV_32F);
  map.at<float>(0, 0) = 0;
  map.at<float>(0, 1) = 0.5f;
  map.at<float>(0, 2) = 1;
  map.row(1).setTo(1.7f);  // saturates to the top of the scale
  const cv::Mat heat = FlipHeatmap(map);
  ASSERT_EQ(heat.type(), CV_8UC3);
  ASSERT_EQ(heat.size(), map.size());
  const cv::Vec3b low = heat.at<cv::Vec3b>(0, 0);
  const cv::Vec3b mid = heat.at<cv::Vec3b>(0, 1);
  const cv::Vec3b high = heat.at<cv::Vec3b>(0, 2);
  // Magma: near black at 0, a red-purple in the middle (red above blue and
  // green), pale yellow at 1 (red and green above blue).
  EXPECT_LT(low[0] + low[1] + low[2], 30);
  EXPECT_GT(mid[2], mid[1]);
  EXPECT_GT(mid[2], mid[0]);
  EXPECT_GT(high[2], 240);
  EXPECT_GT(high[1], 240);
  EXPECT_GT(high[1], high[0]);
  EXPECT_EQ(heat.at<cv::Vec3b>(1, 1), high);
  EXPECT_TRUE(FlipHeatmap(cv::Mat()).empty());
}

}  // namespace
}  // namespace ripple::bench
