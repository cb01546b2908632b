#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "app/app_wxh.h"

namespace ripple::app {
namespace {

using ::testing::HasSubstr;

TEST(WxHTest, ParsesSizesWithinTheLimits) {
  WxH size;
  ASSERT_TRUE(ParseWxH("1280x720", &size));
  EXPECT_EQ(size.width, 1280);
  EXPECT_EQ(size.height, 720);
  for (const char* bad :
       {"", "1280", "1280x", "x720", "1280by720", "1280x720x3", "1280x720 ",
        "0x720", "-3x4", "16385x10"}) {
    WxH untouched{7, 8};
    EXPECT_FALSE(ParseWxH(bad, &untouched)) << bad;
    EXPECT_EQ(untouched.width, 7) << bad;
  }
}

TEST(WxHTest, PatternsNeedTwoToAHundredCorners) {
  WxH pattern;
  EXPECT_TRUE(ParseWxH("9x6", &pattern, WxHLimits::Pattern()));
  EXPECT_EQ(pattern.width, 9);
  EXPECT_EQ(pattern.height, 6);
  EXPECT_FALSE(ParseWxH("1x6", &pattern, WxHLimits::Pattern()));
  EXPECT_FALSE(ParseWxH("9x101", &pattern, WxHLimits::Pattern()));
}

TEST(WxHTest, ValidatorIsAUsageErrorNamingTheValue) {
  CLI::App app;
  std::string size;
  app.add_option("--size", size)->check(WxHValidator(WxHLimits::Size()));
  EXPECT_NO_THROW(app.parse(std::vector<std::string>{"640x480", "--size"}));
  EXPECT_EQ(size, "640x480");
  try {
    app.parse(std::vector<std::string>{"64by48", "--size"});
    FAIL() << "64by48 accepted";
  } catch (const CLI::ValidationError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--size"));
    EXPECT_THAT(e.what(), HasSubstr("'64by48'"));
    EXPECT_THAT(e.what(), HasSubstr("WIDTHxHEIGHT"));
  }
}

}  // namespace
}  // namespace ripple::app
