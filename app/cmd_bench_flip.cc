// `ripple bench flip`: LDR-FLIP of any test image against a reference image,
// inside an optional mask, as `ripple bench render` scores its renders. With
// `bench render --export DIR`, another renderer's image of an exported scene
// is scored exactly as the real-time renderer's is:
//
//   ripple bench flip --reference DIR/flat/reference.png
//       --test mine.png --mask DIR/flat/water_mask.png --map flip_map.png
//
// Prints the mean, median and 95th percentile of the FLIP map over the mask,
// and the uniform gain on the test's linear light that would lower the mean
// most (what a bias of brightness costs, bench/flip_budget.h).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "app/app_bench.h"
#include "app/app_third_party_log.h"
#include "bench/flip.h"
#include "bench/flip_budget.h"
#include "bench/stats.h"
#include "tracking/synth/image_file.h"

namespace ripple::app {
namespace {

struct FlipArgs {
  std::string reference;
  std::string test;
  std::string mask;
  std::string map;
  double pixels_per_degree = bench::FlipOptions().pixels_per_degree;
};

// A PNG or JPEG file as 8-bit BGR (`grey`: one channel); empty with `error`
// when it cannot be read. A damaged file makes libpng print its own lines:
// ours is the one.
cv::Mat ReadImage(const std::string& what, const std::string& path, bool grey,
                  std::string* error) {
  StderrCapture quiet;
  std::string why;
  cv::Mat img = synth::ReadImageFile(
      path, grey ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR, &why);
  if (img.empty()) *error = what + " '" + path + "': " + why;
  return img;
}

std::string SizeText(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

int RunBenchFlip(const FlipArgs& args) {
  std::string error;
  const cv::Mat reference =
      ReadImage("reference", args.reference, false, &error);
  if (reference.empty()) return Fail(kExitBadInput, error);
  const cv::Mat test = ReadImage("test", args.test, false, &error);
  if (test.empty()) return Fail(kExitBadInput, error);
  if (test.size() != reference.size())
    return Fail(kExitBadInput, "test '" + args.test + "' is " + SizeText(test) +
                                   ", the reference " + SizeText(reference));
  cv::Mat mask(reference.size(), CV_8UC1, cv::Scalar(255));
  if (!args.mask.empty()) {
    mask = ReadImage("mask", args.mask, true, &error);
    if (mask.empty()) return Fail(kExitBadInput, error);
    if (mask.size() != reference.size())
      return Fail(kExitBadInput, "mask '" + args.mask + "' is " +
                                     SizeText(mask) + ", the reference " +
                                     SizeText(reference));
  }
  const int pixels = cv::countNonZero(mask);
  if (pixels == 0)
    return Fail(kExitBadInput, "mask '" + args.mask + "' selects no pixel");
  // Check the output before the work, so a bad path costs nothing.
  if (!args.map.empty()) {
    const std::filesystem::path parent =
        std::filesystem::path(args.map).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent))
      return Fail(kExitBadInput,
                  "--map '" + args.map + "': its folder does not exist");
    if (std::filesystem::is_directory(args.map))
      return Fail(kExitBadInput, "--map '" + args.map + "': is a folder");
  }
  bench::FlipOptions options;
  options.pixels_per_degree = args.pixels_per_degree;
  cv::Mat flip_map;
  if (!bench::ComputeFlip(options, reference, test, &flip_map, &error))
    return Fail(kExitBadInput, error);
  std::vector<double> values;
  values.reserve(pixels);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<uchar>(y, x)) values.push_back(flip_map.at<float>(y, x));
  bench::UniformGainFit gain;
  if (!bench::FitUniformGain(options, reference, test, mask, 0.1, 0.002, &gain,
                             &error))
    return Fail(kExitRuntime, error);
  std::printf(
      "LDR-FLIP over %d pixels (%.2f px per degree): mean %.4f, median %.4f, "
      "p95 %.4f\n"
      "best uniform gain on the test's linear light %.3f: mean %.4f\n",
      pixels, options.pixels_per_degree, bench::MeanFlip(flip_map, mask),
      bench::Percentile(values, 50), bench::Percentile(values, 95), gain.gain,
      gain.flip);
  if (!args.map.empty()) {
    bool ok = false;
    try {
      ok = cv::imwrite(args.map, bench::FlipHeatmap(flip_map));
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) return Fail(kExitRuntime, "cannot write '" + args.map + "'");
    std::printf("wrote %s\n", args.map.c_str());
  }
  return kExitOk;
}

CommandAction SetupBenchFlip(CLI::App* sub) {
  auto args = std::make_shared<FlipArgs>();
  sub->add_option("--reference", args->reference,
                  "Reference image, PNG or JPEG, sRGB")
      ->required();
  sub->add_option("--test", args->test,
                  "Test image, PNG or JPEG, sRGB, of the reference's size")
      ->required();
  sub->add_option("--mask", args->mask,
                  "Pixels to score: non-zero in this greyscale image (default "
                  "every pixel)");
  sub->add_option("--map", args->map,
                  "Write the FLIP map here as a PNG (magma colours)");
  sub->add_option("--ppd", args->pixels_per_degree,
                  "Observer, pixels per degree of visual angle")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  return [args] { return RunBenchFlip(*args); };
}

}  // namespace

RIPPLE_REGISTER_BENCH(flip,
                      "LDR-FLIP of a test image against a reference, inside "
                      "a mask (score another renderer on an exported scene)",
                      SetupBenchFlip);

}  // namespace ripple::app
