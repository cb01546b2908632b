#include "bench/stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

namespace ripple::bench {
namespace {

TEST(PercentileTest, NearestRankIsASampleAndAtLeastTheFirst) {
  const std::vector<double> v = {5, 1, 4, 2, 3};
  EXPECT_EQ(Percentile(v, 50), 3);
  EXPECT_EQ(Percentile(v, 95), 5);
  EXPECT_EQ(Percentile(v, 0), 1);
  EXPECT_EQ(Percentile(v, 100), 5);
  // 20 values: p95 is the 19th (ceil(0.95 * 20)).
  std::vector<double> twenty;
  for (int i = 1; i <= 20; ++i) twenty.push_back(i);
  EXPECT_EQ(Percentile(twenty, 95), 19);
  EXPECT_EQ(Percentile(twenty, 50), 10);
}

TEST(PercentileTest, RoundedRankRoundsTheZeroBasedIndex) {
  PercentileOptions options;
  options.rank = PercentileOptions::Rank::kRounded;
  std::vector<double> four = {10, 20, 30, 40};
  // index round(0.5 * 3) = 2.
  EXPECT_EQ(Percentile(four, 50, options), 30);
  EXPECT_EQ(Percentile(four, 0, options), 10);
  EXPECT_EQ(Percentile(four, 100, options), 40);
}

TEST(PercentileTest, EmptySampleGivesTheChosenValue) {
  EXPECT_EQ(Percentile({}, 50), 0);
  PercentileOptions options;
  options.empty_value = NAN;
  EXPECT_TRUE(std::isnan(Percentile({}, 50, options)));
}

TEST(StopwatchTest, MeasuresAndRestarts) {
  Stopwatch watch;
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double ms = watch.ElapsedMs();
  EXPECT_GE(ms, 19.0);
  EXPECT_NEAR(watch.ElapsedS(), ms / 1000, 0.05);
  watch.Restart();
  EXPECT_LT(watch.ElapsedMs(), ms);
}

}  // namespace
}  // namespace ripple::bench
