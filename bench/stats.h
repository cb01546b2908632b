// Measurement helpers shared by every timing and error statistic: one
// percentile and one stopwatch on the steady clock.
#ifndef RIPPLE_BENCH_STATS_H_
#define RIPPLE_BENCH_STATS_H_

#include <chrono>
#include <limits>
#include <vector>

namespace ripple::bench {

struct PercentileOptions {
  // How the rank of percentile p (in [0, 100]) of n sorted values is chosen.
  enum class Rank {
    // The ceil(p/100 * n)-th value (1-based, at least the first): every
    // reported value is a sample, and p95 of 20 values is the 19th.
    kNearest,
    // The value at index round(p/100 * (n - 1)) (0-based).
    kRounded,
  };
  Rank rank = Rank::kNearest;
  // Returned for an empty sample.
  double empty_value = 0.0;
};

// Percentile `p` (percent, in [0, 100]) of `values`.
double Percentile(std::vector<double> values, double p,
                  const PercentileOptions& options = {});

// Elapsed wall-clock time on the steady clock since construction or the last
// Restart().
class Stopwatch {
 public:
  using Clock = std::chrono::steady_clock;
  Stopwatch() : start_(Clock::now()) {}
  void Restart() { start_ = Clock::now(); }
  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_)
        .count();
  }
  double ElapsedS() const {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }

 private:
  Clock::time_point start_;
};

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_STATS_H_
