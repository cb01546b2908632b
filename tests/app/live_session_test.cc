#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <set>

#include "app/app_live_session.h"

namespace ripple::app {
namespace {

using ::testing::ElementsAre;

int WidthPx(const std::string& line) {
  int baseline = 0;
  return cv::getTextSize(line, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline)
      .width;
}

TEST(LiveSessionTest, HelpLinesComeFromTheKeyTable) {
  LiveSession session(LiveSessionOptions(), nullptr, nullptr);
  const std::vector<std::string> help = session.HelpLines();
  ASSERT_EQ(help.size(), session.keys().size());
  EXPECT_EQ(help.front(), "h  this help");
  EXPECT_EQ(help[1], "v/V  viscosity down/up");
  EXPECT_EQ(help[help.size() - 2], "space  pause");
  EXPECT_EQ(help.back(), "q/Esc  quit");
  // Every key is bound once.
  std::set<int> keys;
  for (const KeyBinding& b : session.keys())
    for (int key : b.keys) EXPECT_TRUE(keys.insert(key).second) << key;
  for (int key :
       std::vector<int>{'h', 'v', 'V', 'r', 'R', 'f', 'F', 'c', 's', 'e',
                        't', 'o', 'O', 'w', 'p', 'm', 'k', ' ', 'q', 27})
    EXPECT_TRUE(keys.count(key)) << key;
  EXPECT_FALSE(session.HandleKey('Z'));
  EXPECT_TRUE(session.HandleKey('h'));
}

TEST(LiveSessionTest, HudLinesFitTheWindow) {
  const std::string stage =
      "ms  cap 12.3 det 4.5 pose 1.2 sim 0.4 caus 15.6 shad 5.9 drw 10.1 tot "
      "38.2";
  for (int width : {320, 640, 1280}) {
    const std::vector<std::string> fitted =
        FitHudLines({"short", stage}, width);
    EXPECT_EQ(fitted.front(), "short");
    for (const std::string& line : fitted)
      EXPECT_LE(WidthPx(line) + 16, width) << width << ": " << line;
    const cv::Mat hud = DrawHud({"short", stage}, width);
    EXPECT_LE(hud.cols, width);
    EXPECT_EQ(hud.rows, static_cast<int>(fitted.size()) * 18 + 10);
    EXPECT_EQ(hud.type(), CV_8UC4);
  }
  // Wide enough: nothing is broken.
  EXPECT_THAT(FitHudLines({stage}, 2000), ElementsAre(stage));
  // 320 px: the stage line is broken at spaces, every word kept.
  const std::vector<std::string> narrow = FitHudLines({stage}, 320);
  EXPECT_GT(narrow.size(), 1u);
  std::string joined;
  for (const std::string& line : narrow) joined += line + " ";
  for (const char* word : {"cap", "12.3", "tot", "38.2"})
    EXPECT_NE(joined.find(word), std::string::npos) << word;
}

}  // namespace
}  // namespace ripple::app
