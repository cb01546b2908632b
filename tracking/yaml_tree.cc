#include "tracking/yaml_tree.h"

#include <sys/stat.h>
#include <yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <set>

namespace ripple::tracking {
namespace {

const YamlNode& MissingNode() {
  static const YamlNode missing;
  return missing;
}

// YAML 1.1's float and int forms, restricted to decimal: digits, sign,
// point and exponent (strtod alone would also take hex, "inf" and "nan").
bool ParseNumber(const std::string& s, double* value) {
  if (s.empty() || s.size() > 64) return false;
  const char* kInf[] = {".inf", ".Inf", ".INF"};
  const char* kNan[] = {".nan", ".NaN", ".NAN"};
  for (int sign = 0; sign < 3; ++sign) {
    const std::string prefix = sign == 0 ? "" : sign == 1 ? "+" : "-";
    for (const char* w : kInf)
      if (s == prefix + w) {
        *value = sign == 2 ? -std::numeric_limits<double>::infinity()
                           : std::numeric_limits<double>::infinity();
        return true;
      }
  }
  for (const char* w : kNan)
    if (s == w) {
      *value = std::numeric_limits<double>::quiet_NaN();
      return true;
    }
  bool digit = false;
  for (char c : s) {
    if (c >= '0' && c <= '9')
      digit = true;
    else if (c != '+' && c != '-' && c != '.' && c != 'e' && c != 'E')
      return false;
  }
  if (!digit) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return false;
  *value = v;  // overflow gives +-HUGE_VAL: a number, not finite
  return true;
}

// OpenCV's writer puts flow mappings as "{ id:0, edge:3.e-02 }": no space
// after the key's colon, which YAML reads as one plain scalar "id:0".
// OpenCV's own reader splits a flow mapping's key at the first colon, so we
// do the same: in a flow mapping's key, outside quotes and comments, the
// first ':' followed by something else gets a space ("frame: tag:99" keeps
// its value). One linear pass, no recursion.
std::string SpaceFlowColons(const std::string& text) {
  std::string out;
  out.reserve(text.size() + text.size() / 16);
  std::vector<bool> in_map;  // open flow collections: mapping (or sequence)
  bool key = false;          // in the innermost flow mapping's key
  char quote = 0;
  bool comment = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    out.push_back(c);
    if (c == '\n') comment = false;
    if (comment) continue;
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    switch (c) {
      case '"':
      case '\'':
        // A quote opens a quoted scalar only where a scalar starts.
        if (i == 0 || std::strchr(" \t\n[{,:", text[i - 1]) != nullptr)
          quote = c;
        break;
      case '#':
        comment = i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t' ||
                  text[i - 1] == '\n';
        break;
      case '[':
      case '{':
        in_map.push_back(c == '{');
        key = c == '{';
        break;
      case ']':
      case '}':
        if (!in_map.empty()) in_map.pop_back();
        key = false;
        break;
      case ',':
        key = !in_map.empty() && in_map.back();
        break;
      case ':':
        if (key && i + 1 < text.size() &&
            std::strchr(" \t\r\n,", text[i + 1]) == nullptr)
          out.push_back(' ');
        key = false;
        break;
      default:
        break;
    }
  }
  return out;
}

}  // namespace

// Builds the tree from libyaml's events with an explicit stack.
class YamlBuilder {
 public:
  explicit YamlBuilder(const YamlLimits& limits) : limits_(limits) {}

  std::optional<YamlNode> Run(const std::string& text, std::string* error) {
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) {
      *error = "out of memory starting the YAML parser";
      return std::nullopt;
    }
    std::unique_ptr<yaml_parser_t, void (*)(yaml_parser_t*)> guard(
        &parser, yaml_parser_delete);
    yaml_parser_set_input_string(
        &parser, reinterpret_cast<const unsigned char*>(text.data()),
        text.size());
    int documents = 0;
    bool done = false;
    while (!done) {
      yaml_event_t event;
      if (!yaml_parser_parse(&parser, &event)) {
        *error = "line " + std::to_string(parser.problem_mark.line + 1) + ": " +
                 (parser.problem ? parser.problem : "invalid YAML");
        if (parser.context) *error += std::string(" (") + parser.context + ")";
        return std::nullopt;
      }
      std::unique_ptr<yaml_event_t, void (*)(yaml_event_t*)> event_guard(
          &event, yaml_event_delete);
      const int line = static_cast<int>(event.start_mark.line) + 1;
      auto fail = [&](const std::string& what) {
        *error = "line " + std::to_string(line) + ": " + what;
        return false;
      };
      bool ok = true;
      switch (event.type) {
        case YAML_STREAM_END_EVENT:
          done = true;
          break;
        case YAML_DOCUMENT_START_EVENT:
          if (++documents > 1) ok = fail("more than one YAML document");
          break;
        case YAML_ALIAS_EVENT:
          ok = fail("aliases (*name) are not supported");
          break;
        case YAML_SCALAR_EVENT: {
          YamlNode node;
          node.kind_ = YamlNode::Kind::kScalar;
          if (event.data.scalar.length > limits_.max_scalar_bytes) {
            ok = fail("a value longer than " +
                      std::to_string(limits_.max_scalar_bytes) + " bytes");
            break;
          }
          node.text_.assign(reinterpret_cast<char*>(event.data.scalar.value),
                            event.data.scalar.length);
          node.quoted_ = event.data.scalar.style != YAML_PLAIN_SCALAR_STYLE;
          if (event.data.scalar.tag)
            node.tag_ = reinterpret_cast<char*>(event.data.scalar.tag);
          node.line_ = line;
          ok = Add(std::move(node), line, error);
          break;
        }
        case YAML_SEQUENCE_START_EVENT:
        case YAML_MAPPING_START_EVENT: {
          YamlNode node;
          const bool map = event.type == YAML_MAPPING_START_EVENT;
          node.kind_ =
              map ? YamlNode::Kind::kMapping : YamlNode::Kind::kSequence;
          const yaml_char_t* tag = map ? event.data.mapping_start.tag
                                       : event.data.sequence_start.tag;
          if (tag) node.tag_ = reinterpret_cast<const char*>(tag);
          node.line_ = line;
          if (static_cast<int>(stack_.size()) >= limits_.max_depth) {
            ok = fail("nesting deeper than " +
                      std::to_string(limits_.max_depth) + " levels");
            break;
          }
          ok = Add(std::move(node), line, error);
          if (ok) stack_.push_back({Last(), true});
          break;
        }
        case YAML_SEQUENCE_END_EVENT:
        case YAML_MAPPING_END_EVENT:
          if (!stack_.empty()) stack_.pop_back();
          break;
        default:
          break;
      }
      if (!ok) return std::nullopt;
    }
    if (!has_root_) {
      *error = "empty file (no YAML document)";
      return std::nullopt;
    }
    return std::move(root_);
  }

 private:
  struct Open {
    YamlNode* node;
    bool expect_key;  // mappings: the next scalar is a key
  };

  YamlNode* Last() {
    if (stack_.empty()) return &root_;
    return &stack_.back().node->children_.back();
  }

  // Adds a node where the event stream puts it: the root, a sequence item,
  // a mapping key (scalars only) or a mapping value.
  bool Add(YamlNode node, int line, std::string* error) {
    auto fail = [&](const std::string& what) {
      *error = "line " + std::to_string(line) + ": " + what;
      return false;
    };
    if (++nodes_ > limits_.max_nodes)
      return fail("more than " + std::to_string(limits_.max_nodes) + " values");
    if (stack_.empty()) {
      if (has_root_) return fail("more than one top-level value");
      root_ = std::move(node);
      has_root_ = true;
      return true;
    }
    Open& top = stack_.back();
    if (top.node->kind_ == YamlNode::Kind::kSequence) {
      top.node->children_.push_back(std::move(node));
      return true;
    }
    if (top.expect_key) {
      if (node.kind_ != YamlNode::Kind::kScalar)
        return fail("a mapping key must be a plain value");
      if (node.text_.empty()) return fail("empty mapping key");
      for (const std::string& k : top.node->keys_)
        if (k == node.text_) return fail("duplicate key '" + k + "'");
      pending_key_ = node.text_;
      top.expect_key = false;
      --nodes_;  // keys are bounded with their values
      return true;
    }
    top.node->keys_.push_back(std::move(pending_key_));
    top.node->children_.push_back(std::move(node));
    top.expect_key = true;
    return true;
  }

  const YamlLimits& limits_;
  YamlNode root_;
  bool has_root_ = false;
  std::vector<Open> stack_;
  std::string pending_key_;
  size_t nodes_ = 0;
};

bool YamlNode::IsNumber() const {
  double v;
  return kind_ == Kind::kScalar && !quoted_ && tag_.empty() &&
         ParseNumber(text_, &v);
}

double YamlNode::Number() const {
  double v = std::numeric_limits<double>::quiet_NaN();
  if (kind_ == Kind::kScalar) ParseNumber(text_, &v);
  return v;
}

const YamlNode& YamlNode::operator[](const std::string& key) const {
  if (kind_ != Kind::kMapping) return MissingNode();
  for (size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return children_[i];
  return MissingNode();
}

std::optional<YamlNode> ParseYaml(std::string text, const YamlLimits& limits,
                                  std::string* error) {
  if (text.size() > limits.max_file_bytes) {
    *error = std::to_string(text.size()) + " bytes, more than the " +
             std::to_string(limits.max_file_bytes) + " bytes allowed";
    return std::nullopt;
  }
  // OpenCV writes "%YAML:1.0" (not a YAML 1.1 directive); blank it, keeping
  // the line numbers.
  if (text.compare(0, 6, "%YAML:") == 0)
    for (size_t i = 0; i < text.size() && text[i] != '\n'; ++i) text[i] = ' ';
  YamlBuilder builder(limits);
  return builder.Run(SpaceFlowColons(text), error);
}

std::optional<YamlNode> LoadYamlFile(const std::string& path,
                                     const YamlLimits& limits,
                                     std::string* error) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    *error = "cannot open file";
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    *error = "not a regular file";
    return std::nullopt;
  }
  if (static_cast<unsigned long long>(st.st_size) > limits.max_file_bytes) {
    *error = std::to_string(st.st_size) + " bytes, more than the " +
             std::to_string(limits.max_file_bytes) + " bytes allowed";
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = "cannot open file";
    return std::nullopt;
  }
  std::string text(static_cast<size_t>(st.st_size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  return ParseYaml(std::move(text), limits, error);
}

}  // namespace ripple::tracking
