// Cross-check of ripple::bench::ComputeFlip against NVIDIA's reference
// implementation of LDR-FLIP (github.com/NVlabs/flip, the single header
// src/cpp/FLIP.h), outside the project's build: neither their code nor any
// image is part of the repository. Prints, per pair, both mean FLIPs, their
// difference and the largest per-pixel difference, then the time per pair.
//
//   git clone https://github.com/NVlabs/flip /tmp/nvflip
//   g++ -O2 -std=c++17 -I/tmp/nvflip/src/cpp -I. -I/usr/include/opencv4 \
//     scripts/flip_crosscheck.cc bench/flip.cc -o /tmp/flip_crosscheck \
//     -lopencv_core -lopencv_imgproc -lopencv_imgcodecs
//   /tmp/flip_crosscheck [directory of real frames]
//
// The synthesized pairs are the test suite's photo (tests/bench/flip_test.cc)
// at 640x480 against a blurred, a 1 px shifted, a colour-shifted and a JPEG
// (quality 20) copy; the optional real pairs are frames 0 and 1 of a
// directory of color_image_NNNN.png frames, and frame 0 against its JPEG.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "FLIP.h"
#include "bench/flip.h"
#include "tests/bench/synth_photo.h"

namespace {

using ripple::bench::testing::SynthesizePhoto;

// NVIDIA's LDR-FLIP map: their sRGB decoding, interleaved linear RGB in.
cv::Mat NvidiaFlip(const cv::Mat& reference, const cv::Mat& test) {
  auto linear = [](const cv::Mat& bgr) {
    std::vector<float> rgb(bgr.total() * 3);
    for (int y = 0; y < bgr.rows; ++y) {
      for (int x = 0; x < bgr.cols; ++x) {
        const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
        for (int c = 0; c < 3; ++c) {
          rgb[3 * (y * bgr.cols + x) + c] =
              FLIP::color3::sRGBToLinearRGB(p[2 - c] / 255.0f);
        }
      }
    }
    return rgb;
  };
  const std::vector<float> r = linear(reference), t = linear(test);
  FLIP::Parameters parameters;  // 0.7 m from a 0.7 m wide 4K monitor
  float mean = 0;
  float* map = nullptr;
  FLIP::evaluate(r.data(), t.data(), reference.cols, reference.rows, false,
                 parameters, false, true, mean, &map);
  cv::Mat out(reference.rows, reference.cols, CV_32F);
  std::memcpy(out.data, map, out.total() * sizeof(float));
  delete[] map;
  return out;
}

cv::Mat Jpeg(const cv::Mat& image, int quality) {
  std::vector<uchar> bytes;
  cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality});
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  struct Pair {
    std::string name;
    cv::Mat reference, test;
  };
  std::vector<Pair> pairs;
  const cv::Mat photo = SynthesizePhoto(640, 480, 11);
  cv::Mat blurred, shifted = photo.clone(), colour;
  cv::GaussianBlur(photo, blurred, cv::Size(0, 0), 1.5);
  photo.colRange(0, photo.cols - 1).copyTo(shifted.colRange(1, photo.cols));
  cv::add(photo, cv::Scalar(-10, 0, 15), colour);
  pairs.push_back({"photo vs blur 1.5 px", photo, blurred});
  pairs.push_back({"photo vs 1 px shift", photo, shifted});
  pairs.push_back({"photo vs colour shift", photo, colour});
  pairs.push_back({"photo vs JPEG q20", photo, Jpeg(photo, 20)});
  if (argc > 1) {
    const std::string dir = std::string(argv[1]) + "/";
    const cv::Mat f0 = cv::imread(dir + "color_image_0000.png");
    const cv::Mat f1 = cv::imread(dir + "color_image_0001.png");
    if (!f0.empty() && !f1.empty()) {
      pairs.push_back({"real frame 0 vs 1", f0, f1});
      pairs.push_back({"real frame 0 vs JPEG q20", f0, Jpeg(f0, 20)});
    }
  }
  // The test suite's small pairs (FlipTest.MatchesNvidias...).
  const cv::Mat small = SynthesizePhoto(64, 48, 7);
  cv::Mat small_colour, small_shifted = small.clone();
  cv::add(small, cv::Scalar(-10, 0, 15), small_colour);
  small.colRange(0, 63).copyTo(small_shifted.colRange(1, 64));
  pairs.push_back({"64x48 colour shift", small, small_colour});
  pairs.push_back({"64x48 1 px shift", small, small_shifted});
  pairs.push_back({"64x48 other noise", small, SynthesizePhoto(64, 48, 8)});

  std::printf("%-26s %10s %10s %10s %10s %10s\n", "pair", "ripple", "nvidia",
              "|dmean|", "max|dpix|", "nv max");
  for (const Pair& pair : pairs) {
    cv::Mat ours;
    std::string error;
    if (!ripple::bench::ComputeFlip({}, pair.reference, pair.test, &ours,
                                    &error)) {
      std::fprintf(stderr, "%s: %s\n", pair.name.c_str(), error.c_str());
      return 1;
    }
    const cv::Mat theirs = NvidiaFlip(pair.reference, pair.test);
    const double mean_ours = ripple::bench::MeanFlip(ours);
    const double mean_theirs = cv::mean(theirs)[0];
    double max_theirs = 0;
    cv::minMaxLoc(theirs, nullptr, &max_theirs);
    std::printf("%-26s %10.7f %10.7f %10.2e %10.2e %10.7f\n", pair.name.c_str(),
                mean_ours, mean_theirs, std::abs(mean_ours - mean_theirs),
                cv::norm(ours, theirs, cv::NORM_INF), max_theirs);
  }

  cv::Mat map;
  std::string error;
  const int runs = 20;
  ripple::bench::ComputeFlip({}, photo, blurred, &map, &error);
  auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < runs; ++i) {
    ripple::bench::ComputeFlip({}, photo, blurred, &map, &error);
  }
  const double ours_ms = MsSince(start) / runs;
  start = std::chrono::steady_clock::now();
  for (int i = 0; i < 3; ++i) NvidiaFlip(photo, blurred);
  const double theirs_ms = MsSince(start) / 3;
  std::printf(
      "640x480 pair: ripple %.1f ms (OpenCV threads %d), nvidia %.1f ms\n",
      ours_ms, cv::getNumThreads(), theirs_ms);
  return 0;
}
