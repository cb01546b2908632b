#include "app/app_wxh.h"

#include <sstream>

namespace ripple::app {

bool ParseWxH(const std::string& text, WxH* out, const WxHLimits& limits) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || in.peek() != EOF) return false;
  if (w < limits.min || h < limits.min || w > limits.max || h > limits.max)
    return false;
  out->width = w;
  out->height = h;
  return true;
}

CLI::Validator WxHValidator(const WxHLimits& limits) {
  return CLI::Validator(
      [limits](std::string& value) -> std::string {
        WxH parsed;
        if (ParseWxH(value, &parsed, limits)) return "";
        return "'" + value + "': expected " + limits.form + " (each " +
               std::to_string(limits.min) + " to " +
               std::to_string(limits.max) + ")";
      },
      "");
}

}  // namespace ripple::app
