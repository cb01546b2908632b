// A bounded YAML reader for the rig and camera files, which come from users
// and must never crash, hang or exhaust memory whatever their bytes.
//
// libyaml's event parser (a state machine with explicit stacks, no
// recursion) turns the text into a small tree here, iteratively, with every
// dimension bounded: file size, nesting depth, node count, scalar length.
// Aliases, complex keys, empty keys and duplicate keys are refused. OpenCV's
// "%YAML:1.0" first line (not YAML 1.1 syntax) is accepted. Scalars stay
// text: a plain scalar that parses whole as a number is a number, quoted
// ones are strings.
//
//   std::string error;
//   auto root = LoadYamlFile(path, YamlLimits{}, &error);
//   if (!root) return fail(error);             // "line 3: ..." etc.
//   const YamlNode& tank = (*root)["tank"];   // missing: empty()
#ifndef RIPPLE_TRACKING_YAML_TREE_H_
#define RIPPLE_TRACKING_YAML_TREE_H_

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ripple::tracking {

struct YamlLimits {
  size_t max_file_bytes = 1 << 20;  // bytes; a rig with 500 tags is ~50 KB
  int max_depth = 16;               // nested mappings/sequences
  size_t max_nodes = 20000;         // scalars, mappings and sequences
  size_t max_scalar_bytes = 4096;   // one scalar's text
};

class YamlNode {
 public:
  enum class Kind { kMissing, kScalar, kSequence, kMapping };

  Kind kind() const { return kind_; }
  bool empty() const { return kind_ == Kind::kMissing; }
  bool IsScalar() const { return kind_ == Kind::kScalar; }
  bool IsSequence() const { return kind_ == Kind::kSequence; }
  bool IsMapping() const { return kind_ == Kind::kMapping; }
  // A plain scalar that parses whole as a number (YAML's .inf/.nan forms
  // included); Number() is its value.
  bool IsNumber() const;
  double Number() const;
  // A scalar that is not a number, or any quoted scalar.
  bool IsString() const { return IsScalar() && !IsNumber(); }
  const std::string& Text() const { return text_; }
  // The tag as libyaml resolves it ("tag:yaml.org,2002:opencv-matrix" for
  // OpenCV's "!!opencv-matrix"), empty when untagged.
  const std::string& Tag() const { return tag_; }
  int line() const { return line_; }  // 1-based line of the node's start

  // Sequence items, or mapping values in file order.
  size_t size() const { return children_.size(); }
  const YamlNode& operator[](size_t i) const { return children_[i]; }
  // Mapping lookup; a missing key (or a non-mapping) gives an empty node.
  const YamlNode& operator[](const std::string& key) const;
  const std::vector<YamlNode>& children() const { return children_; }
  const std::vector<std::string>& keys() const { return keys_; }

 private:
  friend class YamlBuilder;
  Kind kind_ = Kind::kMissing;
  std::string text_, tag_;
  bool quoted_ = false;
  int line_ = 0;
  std::vector<std::string> keys_;  // mappings: one per child
  std::vector<YamlNode> children_;
};

// Parses `text` (one document). nullopt with "line N: what" in `error`.
std::optional<YamlNode> ParseYaml(std::string text, const YamlLimits& limits,
                                  std::string* error);
// Reads and parses a file, checking its size before reading it. nullopt
// with the problem in `error` (without the path: callers name the file).
std::optional<YamlNode> LoadYamlFile(const std::string& path,
                                     const YamlLimits& limits,
                                     std::string* error);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_YAML_TREE_H_
