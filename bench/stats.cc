#include "bench/stats.h"

#include <algorithm>
#include <cmath>

namespace ripple::bench {

double Percentile(std::vector<double> values, double p,
                  const PercentileOptions& options) {
  if (values.empty()) return options.empty_value;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  if (options.rank == PercentileOptions::Rank::kRounded) {
    const size_t i = static_cast<size_t>(p / 100.0 * (n - 1) + 0.5);
    return values[std::min(n - 1, i)];
  }
  const size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * n));
  return values[std::clamp<size_t>(rank, 1, n) - 1];
}

}  // namespace ripple::bench
