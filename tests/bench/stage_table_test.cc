#include "bench/stage_table.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace ripple::bench {
namespace {

using ::testing::HasSubstr;

StageTimes Times(double total) {
  StageTimes t;
  t.cap = 1;
  t.det = 2;
  t.total = total;
  return t;
}

TEST(StageTableTest, FormatHasEveryStageAndBothStatistics) {
  StageTable table;
  for (double t : {10.0, 20.0, 30.0}) table.Add(Times(t));
  const std::string text = table.Format("replay");
  EXPECT_THAT(text, HasSubstr("replay (3 frames, ms)"));
  for (const char* column : {"cap", "det", "pose", "occ", "drw", "sim",
                             "caustics", "shadow", "total"})
    EXPECT_THAT(text, HasSubstr(column));
  EXPECT_THAT(text, HasSubstr("median"));
  EXPECT_THAT(text, HasSubstr("p95"));
  EXPECT_THAT(text, HasSubstr("20.00"));
  EXPECT_THAT(text, HasSubstr("30.00"));
}

TEST(StageTableTest, RecentMedianLooksAtTheLastRowsOnly) {
  StageTable table;
  for (double t : {100.0, 100.0, 100.0, 1.0, 2.0, 3.0}) table.Add(Times(t));
  EXPECT_EQ(table.RecentMedian(3).total, 2.0);
  EXPECT_EQ(table.RecentMedian(3).cap, 1.0);
  EXPECT_EQ(table.RecentMedian(100).total, 3.0);  // nearest rank of 6
  EXPECT_EQ(StageTable().RecentMedian(3).total, 0.0);
}

TEST(StageTableTest, AppendCsvWritesHeaderOnceAndTwoRowsPerLabel) {
  const std::string path =
      ::testing::TempDir() + "/stage_table_test_timing.csv";
  StageTable table;
  table.Add(Times(5));
  std::string error;
  ASSERT_TRUE(table.AppendCsv(path, "active", true, &error)) << error;
  ASSERT_TRUE(table.AppendCsv(path, "idle", false, &error)) << error;
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(
      text.str(),
      "label,stat,cap,det,pose,occ,drw,sim,caustics,shadow,total,lat,frames\n"
      "active,median,1.000,2.000,0.000,0.000,0.000,0.000,0.000,0.000,5.000,0."
      "000,1\n"
      "active,p95,1.000,2.000,0.000,0.000,0.000,0.000,0.000,0.000,5.000,0.000,"
      "1\n"
      "idle,median,1.000,2.000,0.000,0.000,0.000,0.000,0.000,0.000,5.000,0.000,"
      "1\n"
      "idle,p95,1.000,2.000,0.000,0.000,0.000,0.000,0.000,0.000,5.000,0.000,"
      "1\n");
  std::remove(path.c_str());
  EXPECT_FALSE(table.AppendCsv("/nonexistent/dir/t.csv", "x", true, &error));
  EXPECT_THAT(error, HasSubstr("/nonexistent/dir/t.csv"));
}

}  // namespace
}  // namespace ripple::bench
