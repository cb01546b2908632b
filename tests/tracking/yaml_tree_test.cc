// The bounded YAML reader (tracking/yaml_tree.h): what it accepts is read
// exactly, and every bound and refused construct is an error naming the line.
#include "tracking/yaml_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace ripple::tracking {
namespace {

std::optional<YamlNode> Parse(const std::string& text, std::string* error,
                              YamlLimits limits = {}) {
  return ParseYaml(text, limits, error);
}

TEST(YamlTree, ReadsOpenCvCalibrationFile) {
  std::string error;
  const auto root = Parse(
      "%YAML:1.0\n---\nimage_width: 640\nname: \"7\"\n"
      "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 1., 0, 2.5e2, -.inf, .nan, 7 ]\n",
      &error);
  ASSERT_TRUE(root) << error;
  EXPECT_TRUE(root->IsMapping());
  EXPECT_EQ((*root)["image_width"].Number(), 640);
  // Quoted scalars stay strings, whatever they spell.
  EXPECT_FALSE((*root)["name"].IsNumber());
  EXPECT_EQ((*root)["name"].Text(), "7");
  const YamlNode& k = (*root)["camera_matrix"];
  EXPECT_EQ(k.Tag(), "tag:yaml.org,2002:opencv-matrix");
  const YamlNode& data = k["data"];
  ASSERT_EQ(data.size(), 6u);
  EXPECT_EQ(data[2].Number(), 250);
  EXPECT_TRUE(std::isinf(data[3].Number()) && data[3].Number() < 0);
  EXPECT_TRUE(std::isnan(data[4].Number()));
  EXPECT_TRUE((*root)["absent"].empty());
}

TEST(YamlTree, ReadsOpenCvFlowMappings) {
  // OpenCV writes "key:value" in flow mappings; its reader splits at the
  // key's first colon, and so do we (values keep theirs).
  std::string error;
  const auto root = Parse(
      "tags:\n  - { id:0, edge:2.5e-02, frame: tag:99, p:[\n   1, 2 ],"
      " name: 'a:b' }\n",
      &error);
  ASSERT_TRUE(root) << error;
  const YamlNode& tag = (*root)["tags"][0];
  EXPECT_EQ(tag["id"].Number(), 0);
  EXPECT_EQ(tag["edge"].Number(), 0.025);
  EXPECT_EQ(tag["frame"].Text(), "tag:99");
  EXPECT_EQ(tag["p"].size(), 2u);
  EXPECT_EQ(tag["name"].Text(), "a:b");
}

TEST(YamlTree, NonDecimalNumbersAreText) {
  std::string error;
  const auto root = Parse("a: 0x10\nb: inf\nc: 1e\nd: 12abc\n", &error);
  ASSERT_TRUE(root) << error;
  for (const char* key : {"a", "b", "c", "d"})
    EXPECT_FALSE((*root)[key].IsNumber()) << key;
}

TEST(YamlTree, DepthIsBoundedWithoutRecursion) {
  std::string error;
  const int deep = 200000;
  EXPECT_FALSE(
      Parse("x: " + std::string(deep, '[') + std::string(deep, ']'), &error));
  EXPECT_NE(error.find("nesting deeper than 16"), std::string::npos) << error;
  YamlLimits limits;
  limits.max_depth = 3;
  EXPECT_TRUE(Parse("a: [[1]]", &error, limits)) << error;
  EXPECT_FALSE(Parse("a: [[[1]]]", &error, limits));
}

TEST(YamlTree, RefusesAliasesEmptyAndDuplicateKeys) {
  std::string error;
  EXPECT_FALSE(Parse("a: &x [1]\nb: *x\n", &error));
  EXPECT_NE(error.find("line 2: aliases"), std::string::npos) << error;
  EXPECT_FALSE(Parse("a:\n  ?\n  : 1\n", &error));
  EXPECT_NE(error.find("empty mapping key"), std::string::npos) << error;
  EXPECT_FALSE(Parse("a: 1\nb: 2\na: 3\n", &error));
  EXPECT_NE(error.find("line 3: duplicate key 'a'"), std::string::npos)
      << error;
  EXPECT_FALSE(Parse("? [1]\n: 2\n", &error));
}

TEST(YamlTree, SizesAndCountsAreBounded) {
  std::string error;
  YamlLimits limits;
  limits.max_file_bytes = 64;
  EXPECT_FALSE(Parse("a: " + std::string(100, '1'), &error, limits));
  EXPECT_NE(error.find("more than the 64 bytes"), std::string::npos);
  limits = YamlLimits{};
  limits.max_nodes = 10;
  EXPECT_FALSE(Parse("a: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]", &error, limits));
  limits = YamlLimits{};
  limits.max_scalar_bytes = 8;
  EXPECT_FALSE(Parse("a: 123456789", &error, limits));
}

TEST(YamlTree, MalformedTextIsOneErrorWithItsLine) {
  std::string error;
  EXPECT_FALSE(Parse("", &error));
  EXPECT_FALSE(Parse("a: 1\n\tb: 2\n", &error));
  EXPECT_EQ(error.rfind("line 2: ", 0), 0u) << error;
  EXPECT_FALSE(Parse(std::string("a: \xff\xfe\n"), &error));
  EXPECT_FALSE(Parse(std::string("a: 1\0b", 6), &error));
  EXPECT_FALSE(Parse("a: [1, 2\n", &error));
  EXPECT_FALSE(Parse("--- 1\n--- 2\n", &error));
}

}  // namespace
}  // namespace ripple::tracking
