// Google Benchmark kernel for LDR-FLIP: one reference/test pair (a noisy
// gradient against a blurred copy) per iteration, swept over image sizes at
// the default observer. Run (Release):
//   build/tests/bench/bench_flip_benchmark --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true  (one command line)
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "bench/flip.h"

namespace ripple::bench {
namespace {

void BM_ComputeFlip(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = width * 3 / 4;
  cv::Mat reference(height, width, CV_8UC3);
  cv::RNG rng(1);
  rng.fill(reference, cv::RNG::NORMAL, 128, 20);
  for (int y = 0; y < height; ++y) {
    reference.row(y) += cv::Scalar(y * 100 / height, 0, 50 - y * 50 / height);
  }
  cv::Mat test;
  cv::GaussianBlur(reference, test, cv::Size(0, 0), 1.5);
  const FlipOptions options;
  cv::Mat map;
  std::string error;
  for (auto _ : state) {
    ComputeFlip(options, reference, test, &map, &error);
    benchmark::DoNotOptimize(map.data);
  }
  state.SetItemsProcessed(state.iterations() * width * height);
  state.SetLabel(std::to_string(width) + "x" + std::to_string(height));
}
BENCHMARK(BM_ComputeFlip)
    ->Arg(160)
    ->Arg(320)
    ->Arg(640)
    ->Arg(1280)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ripple::bench
