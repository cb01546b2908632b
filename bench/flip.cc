#include "bench/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "geometry/check.h"

namespace ripple::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The CSFs as sums of Gaussians in frequency f (cycles per degree),
// a1 exp(-b1 f^2) + a2 exp(-b2 f^2), with the paper's constants for the
// achromatic, red-green and blue-yellow channels (FLIP, colour pipeline).
struct CsfConstants {
  double a1, b1, a2, b2;
};
constexpr std::array<CsfConstants, 3> kCsf = {{
    {1.0, 0.0047, 0.0, 1e-5},
    {1.0, 0.0053, 0.0, 1e-5},
    {34.1, 0.04, 13.5, 0.025},
}};

// Width of the feature detectors, degrees (FLIP, feature pipeline: w).
constexpr double kFeatureWidthDeg = 0.082;
// Exponents of the colour and feature errors (FLIP: qc, qf).
constexpr double kColorExponent = 0.7;
constexpr float kFeatureExponent = 0.5f;
// The colour error's two-piece map (FLIP: pc, pt).
constexpr double kPc = 0.4;
constexpr double kPt = 0.95;

// Linear sRGB to CIE XYZ, derived from the chromaticities of the sRGB
// primaries and its D65 white (IEC 61966-2-1) rather than taken rounded: each
// primary's column is (x / y, 1, (1 - x - y) / y) scaled so that RGB (1, 1, 1)
// maps to the white with Y = 1.
const cv::Matx33d& XyzFromRgb() {
  static const cv::Matx33d m = [] {
    auto column = [](double x, double y) {
      return cv::Vec3d(x / y, 1, (1 - x - y) / y);
    };
    const cv::Vec3d r = column(0.64, 0.33), g = column(0.30, 0.60),
                    b = column(0.15, 0.06), white = column(0.3127, 0.3290);
    const cv::Matx33d primaries(r[0], g[0], b[0],  //
                                r[1], g[1], b[1],  //
                                r[2], g[2], b[2]);
    const cv::Vec3d scale = primaries.inv() * white;
    return primaries * cv::Matx33d::diag(scale);
  }();
  return m;
}

// Reference white: XYZ of linear RGB (1, 1, 1).
cv::Vec3d WhiteXyz() { return XyzFromRgb() * cv::Vec3d(1, 1, 1); }

// XYZ relative to the white from linear RGB, and its inverse, as floats.
struct ColorMatrices {
  float xyz_from_rgb[3][3];
  float rgb_from_xyz[3][3];
};
const ColorMatrices& Matrices() {
  static const ColorMatrices matrices = [] {
    const cv::Vec3d white = WhiteXyz();
    const cv::Matx33d to_white =
        cv::Matx33d::diag(cv::Vec3d(1 / white[0], 1 / white[1], 1 / white[2]));
    const cv::Matx33d forward = to_white * XyzFromRgb();
    const cv::Matx33d inverse = forward.inv();
    ColorMatrices m;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        m.xyz_from_rgb[i][j] = static_cast<float>(forward(i, j));
        m.rgb_from_xyz[i][j] = static_cast<float>(inverse(i, j));
      }
    }
    return m;
  }();
  return matrices;
}

// CIE L*a*b*'s f(t): the cube root with its linear toe.
template <typename T>
T LabF(T t) {
  constexpr T kDelta = T(6.0 / 29.0);
  return t > kDelta * kDelta * kDelta
             ? std::cbrt(t)
             : t / (T(3) * kDelta * kDelta) + T(4.0 / 29.0);
}

// Hunt-adjusted L*a*b* of XYZ relative to the white.
template <typename T>
void HuntLab(T x, T y, T z, T* l, T* a, T* b) {
  const T fx = LabF(x), fy = LabF(y), fz = LabF(z);
  *l = T(116) * fy - T(16);
  // Hunt effect: chroma falls with luminance (FLIP, colour pipeline).
  *a = T(0.01) * *l * T(500) * (fx - fy);
  *b = T(0.01) * *l * T(200) * (fy - fz);
}

template <typename T>
T HyABOf(T l0, T a0, T b0, T l1, T a1, T b1) {
  const T da = a0 - a1, db = b0 - b1;
  return std::abs(l0 - l1) + std::sqrt(da * da + db * db);
}

// cmax: the colour error between green and blue, the largest of any two
// colours in [0, 1]^3 (FLIP, colour pipeline).
double ColorErrorMax() {
  static const double cmax = [] {
    const cv::Vec3d white = WhiteXyz();
    cv::Vec3d lab[2];
    for (int i = 0; i < 2; ++i) {
      const cv::Vec3d xyz =
          XyzFromRgb() * (i == 0 ? cv::Vec3d(0, 1, 0) : cv::Vec3d(0, 0, 1));
      HuntLab(xyz[0] / white[0], xyz[1] / white[1], xyz[2] / white[2],
              &lab[i][0], &lab[i][1], &lab[i][2]);
    }
    return std::pow(HyABOf(lab[0][0], lab[0][1], lab[0][2], lab[1][0],
                           lab[1][1], lab[1][2]),
                    kColorExponent);
  }();
  return cmax;
}

// The HyAB distance to the colour error in [0, 1] (FLIP, colour pipeline):
// e = hyab^qc; e pt / (pc cmax) below pc cmax, else linear from pt to 1 at
// cmax. Clamped to 1 against rounding at cmax.
template <typename T>
T Compress(T hyab) {
  static const T cmax = static_cast<T>(ColorErrorMax());
  static const T knee = static_cast<T>(kPc) * cmax;
  const T e = std::pow(hyab, static_cast<T>(kColorExponent));
  const T mapped = e < knee ? static_cast<T>(kPt) / knee * e
                            : static_cast<T>(kPt) + (e - knee) / (cmax - knee) *
                                                        static_cast<T>(1 - kPt);
  return std::min(mapped, T(1));
}

cv::Mat GaussianTaps(int radius, double sigma_px) {
  cv::Mat taps(1, 2 * radius + 1, CV_64F);
  for (int k = -radius; k <= radius; ++k) {
    taps.at<double>(k + radius) = std::exp(-k * k / (2 * sigma_px * sigma_px));
  }
  return taps / cv::sum(taps)[0];
}

// Scales the positive taps to sum 1 and the negative ones to -1 (FLIP,
// feature pipeline), which also gives the detectors a zero DC response.
cv::Mat NormaliseSigned(cv::Mat taps) {
  double positive = 0, negative = 0;
  for (int k = 0; k < taps.cols; ++k) {
    const double v = taps.at<double>(k);
    (v > 0 ? positive : negative) += v;
  }
  for (int k = 0; k < taps.cols; ++k) {
    double& v = taps.at<double>(k);
    v /= v > 0 ? positive : -negative;
  }
  return taps;
}

cv::Mat ToFloat(const cv::Mat& taps) {
  cv::Mat out;
  taps.convertTo(out, CV_32F);
  return out;
}

// `derivative` (1 or 2) of the Gaussian along x, up to a factor that the
// signed normalisation removes, times the Gaussian along y. The 2-D kernel's
// sign depends on x alone, so normalising the x taps' signs and the y taps'
// sum normalises the 2-D kernel's positive and negative parts.
flip_internal::SeparableKernel FeatureKernelX(double pixels_per_degree,
                                              int derivative) {
  const double sigma = flip_internal::FeatureSigma(pixels_per_degree);
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  const cv::Mat gaussian = GaussianTaps(radius, sigma);
  cv::Mat x(1, 2 * radius + 1, CV_64F);
  for (int k = -radius; k <= radius; ++k) {
    const double g = gaussian.at<double>(k + radius);
    x.at<double>(k + radius) =
        derivative == 1 ? -k * g : (k * k / (sigma * sigma) - 1) * g;
  }
  flip_internal::SeparableKernel kernel;
  kernel.radius = radius;
  kernel.terms.push_back({1.0, ToFloat(NormaliseSigned(x)), ToFloat(gaussian)});
  return kernel;
}

}  // namespace

namespace flip_internal {

int CsfRadius(double pixels_per_degree) {
  double b_max = 0;
  for (const CsfConstants& c : kCsf) {
    if (c.a1 != 0) b_max = std::max(b_max, c.b1);
    if (c.a2 != 0) b_max = std::max(b_max, c.b2);
  }
  // exp(-pi^2 r^2 / b) is a Gaussian of standard deviation sqrt(b / (2 pi^2))
  // degrees.
  return static_cast<int>(
      std::ceil(3 * std::sqrt(b_max / (2 * kPi * kPi)) * pixels_per_degree));
}

SeparableKernel CsfKernel(Channel channel, double pixels_per_degree) {
  const CsfConstants& c = kCsf[static_cast<int>(channel)];
  const int radius = CsfRadius(pixels_per_degree);
  SeparableKernel kernel;
  kernel.radius = radius;
  double weight_sum = 0;
  for (const auto& [a, b] : {std::pair{c.a1, c.b1}, std::pair{c.a2, c.b2}}) {
    if (a == 0) continue;
    // a sqrt(pi / b) exp(-pi^2 (x^2 + y^2) / b) = a sqrt(pi / b) g(x) g(y):
    // with unit-sum taps g / s, the term's weight is a sqrt(pi / b) s^2.
    cv::Mat taps(1, 2 * radius + 1, CV_64F);
    for (int k = -radius; k <= radius; ++k) {
      const double x_deg = k / pixels_per_degree;
      taps.at<double>(k + radius) = std::exp(-kPi * kPi * x_deg * x_deg / b);
    }
    const double s = cv::sum(taps)[0];
    const double weight = a * std::sqrt(kPi / b) * s * s;
    const cv::Mat unit = ToFloat(taps / s);
    kernel.terms.push_back({weight, unit, unit});
    weight_sum += weight;
  }
  for (SeparableKernel::Term& term : kernel.terms) term.weight /= weight_sum;
  return kernel;
}

double FeatureSigma(double pixels_per_degree) {
  return 0.5 * kFeatureWidthDeg * pixels_per_degree;
}

SeparableKernel EdgeKernelX(double pixels_per_degree) {
  return FeatureKernelX(pixels_per_degree, 1);
}

SeparableKernel PointKernelX(double pixels_per_degree) {
  return FeatureKernelX(pixels_per_degree, 2);
}

SeparableKernel Transposed(const SeparableKernel& kernel) {
  SeparableKernel out = kernel;
  for (SeparableKernel::Term& term : out.terms) std::swap(term.x, term.y);
  return out;
}

cv::Mat Dense(const SeparableKernel& kernel) {
  const int n = 2 * kernel.radius + 1;
  cv::Mat dense = cv::Mat::zeros(n, n, CV_32F);
  for (const SeparableKernel::Term& term : kernel.terms) {
    const cv::Mat outer = term.y.t() * term.x;
    cv::scaleAdd(outer, term.weight, dense, dense);
  }
  return dense;
}

cv::Mat Apply(const SeparableKernel& kernel, const cv::Mat& plane) {
  cv::Mat sum, filtered;
  for (const SeparableKernel::Term& term : kernel.terms) {
    cv::sepFilter2D(plane, filtered, CV_32F, term.x, term.y, cv::Point(-1, -1),
                    0, cv::BORDER_REPLICATE);
    if (sum.empty()) {
      sum =
          term.weight == 1 ? filtered.clone() : cv::Mat(filtered * term.weight);
    } else {
      cv::scaleAdd(filtered, term.weight, sum, sum);
    }
  }
  return sum;
}

cv::Vec3d HuntLabFromLinearRgb(const cv::Vec3d& rgb) {
  const cv::Vec3d xyz = XyzFromRgb() * rgb;
  const cv::Vec3d white = WhiteXyz();
  cv::Vec3d lab;
  HuntLab(xyz[0] / white[0], xyz[1] / white[1], xyz[2] / white[2], &lab[0],
          &lab[1], &lab[2]);
  return lab;
}

double HyAB(const cv::Vec3d& lab0, const cv::Vec3d& lab1) {
  return HyABOf(lab0[0], lab0[1], lab0[2], lab1[0], lab1[1], lab1[2]);
}

double CompressColorError(double hyab) { return Compress(hyab); }

cv::Mat FeatureDifference(const cv::Mat& reference_y, const cv::Mat& test_y,
                          double pixels_per_degree) {
  const SeparableKernel edge_x = EdgeKernelX(pixels_per_degree);
  const SeparableKernel point_x = PointKernelX(pixels_per_degree);
  const SeparableKernel edge_y = Transposed(edge_x);
  const SeparableKernel point_y = Transposed(point_x);
  auto magnitude = [](const SeparableKernel& kx, const SeparableKernel& ky,
                      const cv::Mat& plane) {
    cv::Mat m;
    cv::magnitude(Apply(kx, plane), Apply(ky, plane), m);
    return m;
  };
  const cv::Mat edge_r = magnitude(edge_x, edge_y, reference_y);
  const cv::Mat edge_t = magnitude(edge_x, edge_y, test_y);
  const cv::Mat point_r = magnitude(point_x, point_y, reference_y);
  const cv::Mat point_t = magnitude(point_x, point_y, test_y);
  cv::Mat out(reference_y.size(), CV_32F);
  const float inv_sqrt2 = static_cast<float>(1 / std::sqrt(2.0));
  for (int row = 0; row < out.rows; ++row) {
    const float* er = edge_r.ptr<float>(row);
    const float* et = edge_t.ptr<float>(row);
    const float* pr = point_r.ptr<float>(row);
    const float* pt = point_t.ptr<float>(row);
    float* o = out.ptr<float>(row);
    for (int col = 0; col < out.cols; ++col) {
      const float d =
          std::max(std::abs(er[col] - et[col]), std::abs(pr[col] - pt[col]));
      o[col] = std::pow(d * inv_sqrt2, kFeatureExponent);
    }
  }
  return out;
}

}  // namespace flip_internal

namespace {

using flip_internal::Channel;

// The sRGB transfer function, decoded (IEC 61966-2-1).
const std::array<float, 256>& SrgbToLinearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = static_cast<float>(
          c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

bool CheckImage(const cv::Mat& image, const char* name, std::string* error) {
  if (image.empty()) {
    *error = std::string(name) + " image is empty";
    return false;
  }
  if (image.type() != CV_8UC3 && image.type() != CV_32FC3) {
    *error = std::string(name) +
             " image must be CV_8UC3 (sRGB BGR) or CV_32FC3 (linear BGR), "
             "got type " +
             std::to_string(image.type());
    return false;
  }
  if (image.type() == CV_32FC3) {
    for (int row = 0; row < image.rows; ++row) {
      const float* p = image.ptr<float>(row);
      for (int i = 0; i < 3 * image.cols; ++i) {
        if (!(p[i] >= 0.0f && p[i] <= 1.0f)) {
          *error = std::string(name) +
                   " image has a value outside [0, 1] at pixel (" +
                   std::to_string(i / 3) + ", " + std::to_string(row) + ")";
          return false;
        }
      }
    }
  }
  return true;
}

// The YyCxCz planes of `image` (FLIP, colour pipeline: from XYZ relative to
// the white, Yy = 116 Y - 16, Cx = 500 (X - Y), Cz = 200 (Y - Z)).
std::array<cv::Mat, 3> YccFromImage(const cv::Mat& image) {
  std::array<cv::Mat, 3> ycc;
  for (cv::Mat& plane : ycc) plane.create(image.size(), CV_32F);
  const std::array<float, 256>& decode = SrgbToLinearTable();
  const auto& m = Matrices().xyz_from_rgb;
  const bool srgb = image.type() == CV_8UC3;
  for (int row = 0; row < image.rows; ++row) {
    const unsigned char* p8 = srgb ? image.ptr<unsigned char>(row) : nullptr;
    const float* p32 = srgb ? nullptr : image.ptr<float>(row);
    float* yy = ycc[0].ptr<float>(row);
    float* cx = ycc[1].ptr<float>(row);
    float* cz = ycc[2].ptr<float>(row);
    for (int col = 0; col < image.cols; ++col) {
      // OpenCV's channel order is B, G, R.
      const float b = srgb ? decode[p8[3 * col]] : p32[3 * col];
      const float g = srgb ? decode[p8[3 * col + 1]] : p32[3 * col + 1];
      const float r = srgb ? decode[p8[3 * col + 2]] : p32[3 * col + 2];
      const float x = m[0][0] * r + m[0][1] * g + m[0][2] * b;
      const float y = m[1][0] * r + m[1][1] * g + m[1][2] * b;
      const float z = m[2][0] * r + m[2][1] * g + m[2][2] * b;
      yy[col] = 116.0f * y - 16.0f;
      cx[col] = 500.0f * (x - y);
      cz[col] = 200.0f * (y - z);
    }
  }
  return ycc;
}

// Filtered YyCxCz back to linear RGB, clamped to [0, 1], then to
// Hunt-adjusted L*a*b* (FLIP, colour pipeline).
void HuntLabFromYcc(float yy, float cx, float cz, float* l, float* a,
                    float* b) {
  const auto& to_rgb = Matrices().rgb_from_xyz;
  const auto& to_xyz = Matrices().xyz_from_rgb;
  const float y = (yy + 16.0f) / 116.0f;
  const float xyz[3] = {cx / 500.0f + y, y, y - cz / 200.0f};
  float rgb[3];
  for (int i = 0; i < 3; ++i) {
    const float v =
        to_rgb[i][0] * xyz[0] + to_rgb[i][1] * xyz[1] + to_rgb[i][2] * xyz[2];
    rgb[i] = std::clamp(v, 0.0f, 1.0f);
  }
  float back[3];
  for (int i = 0; i < 3; ++i) {
    back[i] =
        to_xyz[i][0] * rgb[0] + to_xyz[i][1] * rgb[1] + to_xyz[i][2] * rgb[2];
  }
  HuntLab(back[0], back[1], back[2], l, a, b);
}

}  // namespace

bool FlipOptions::IsValid(std::string* error) const {
  if (!(pixels_per_degree >= 1 && pixels_per_degree <= 1000)) {
    *error = "pixels_per_degree must be in [1, 1000], got " +
             std::to_string(pixels_per_degree);
    return false;
  }
  return true;
}

bool ComputeFlip(const FlipOptions& options, const cv::Mat& reference,
                 const cv::Mat& test, cv::Mat* error_map, std::string* error) {
  if (!options.IsValid(error)) return false;
  if (!CheckImage(reference, "reference", error) ||
      !CheckImage(test, "test", error)) {
    return false;
  }
  if (reference.size() != test.size() || reference.type() != test.type()) {
    *error = "reference (" + std::to_string(reference.cols) + "x" +
             std::to_string(reference.rows) + ", type " +
             std::to_string(reference.type()) + ") and test (" +
             std::to_string(test.cols) + "x" + std::to_string(test.rows) +
             ", type " + std::to_string(test.type()) +
             ") differ in size or type";
    return false;
  }
  if (error_map == nullptr) return true;

  const double ppd = options.pixels_per_degree;
  const std::array<cv::Mat, 3> ycc_r = YccFromImage(reference);
  const std::array<cv::Mat, 3> ycc_t = YccFromImage(test);

  // Feature pipeline on the unfiltered achromatic channel normalised to
  // [0, 1], (Yy + 16) / 116.
  cv::Mat y_r, y_t;
  ycc_r[0].convertTo(y_r, CV_32F, 1.0 / 116, 16.0 / 116);
  ycc_t[0].convertTo(y_t, CV_32F, 1.0 / 116, 16.0 / 116);
  const cv::Mat feature = flip_internal::FeatureDifference(y_r, y_t, ppd);

  // Colour pipeline: each opponent channel filtered by its CSF.
  std::array<cv::Mat, 3> f_r, f_t;
  for (int c = 0; c < 3; ++c) {
    const flip_internal::SeparableKernel kernel =
        flip_internal::CsfKernel(static_cast<Channel>(c), ppd);
    f_r[c] = flip_internal::Apply(kernel, ycc_r[c]);
    f_t[c] = flip_internal::Apply(kernel, ycc_t[c]);
  }

  error_map->create(reference.size(), CV_32F);
  cv::Mat& map = *error_map;
  // Rows are independent; the per-pixel colour conversions dominate the cost.
  cv::parallel_for_(cv::Range(0, reference.rows), [&](const cv::Range& rows) {
    for (int row = rows.start; row < rows.end; ++row) {
      const float* r0 = f_r[0].ptr<float>(row);
      const float* r1 = f_r[1].ptr<float>(row);
      const float* r2 = f_r[2].ptr<float>(row);
      const float* t0 = f_t[0].ptr<float>(row);
      const float* t1 = f_t[1].ptr<float>(row);
      const float* t2 = f_t[2].ptr<float>(row);
      const float* fe = feature.ptr<float>(row);
      float* out = map.ptr<float>(row);
      for (int col = 0; col < map.cols; ++col) {
        float lr, ar, br, lt, at, bt;
        HuntLabFromYcc(r0[col], r1[col], r2[col], &lr, &ar, &br);
        HuntLabFromYcc(t0[col], t1[col], t2[col], &lt, &at, &bt);
        const float color = Compress(HyABOf(lr, ar, br, lt, at, bt));
        // dE = dEc^(1 - dEf) (FLIP, final error).
        out[col] = std::pow(color, 1.0f - fe[col]);
      }
    }
  });
  return true;
}

cv::Mat SrgbToLinear(const cv::Mat& bgr8) {
  const std::array<float, 256>& decode = SrgbToLinearTable();
  cv::Mat out;
  cv::LUT(bgr8, cv::Mat(1, 256, CV_32F, const_cast<float*>(decode.data())),
          out);
  return out;
}

double MeanFlip(const cv::Mat& error_map, const cv::Mat& mask) {
  if (error_map.empty()) return 0;
  RIPPLE_CHECK(error_map.type() == CV_32FC1, "error map must be CV_32FC1");
  if (mask.empty()) return cv::mean(error_map)[0];
  RIPPLE_CHECK(mask.type() == CV_8UC1 && mask.size() == error_map.size(),
               "mask must be CV_8UC1 of the error map's size");
  return cv::mean(error_map, mask)[0];
}

cv::Mat FlipHeatmap(const cv::Mat& error_map) {
  RIPPLE_CHECK(error_map.empty() || error_map.type() == CV_32FC1,
               "error map must be CV_32FC1");
  if (error_map.empty()) return cv::Mat();
  cv::Mat index, heatmap;
  error_map.convertTo(index, CV_8U, 255.0);  // saturates outside [0, 1]
  cv::applyColorMap(index, heatmap, cv::COLORMAP_MAGMA);
  return heatmap;
}

}  // namespace ripple::bench
