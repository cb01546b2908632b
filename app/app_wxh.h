// The one parser of "WxH" arguments: image sizes (--size, --sizes) and
// chessboard patterns (--chessboard COLSxROWS), with a CLI11 validator so that
// a malformed value is a usage error (exit 2) naming the option.
#ifndef RIPPLE_APP_APP_WXH_H_
#define RIPPLE_APP_APP_WXH_H_

#include <CLI/CLI.hpp>
#include <string>

namespace ripple::app {

struct WxH {
  int width = 0;   // pixels, or pattern columns
  int height = 0;  // pixels, or pattern rows
};

struct WxHLimits {
  int min = 1;      // smallest width and height
  int max = 16384;  // largest width and height
  // How the expected form is named in the message.
  std::string form = "WIDTHxHEIGHT, e.g. 1280x720";

  // Image sizes in pixels: 1 to 16384 each way.
  static WxHLimits Size() { return {}; }
  // Chessboard inner corners: 2 to 100 each way.
  static WxHLimits Pattern() {
    return {2, 100, "COLSxROWS inner corners, e.g. 9x6"};
  }
};

// Parses "<int>x<int>" (nothing before or after) within `limits`.
bool ParseWxH(const std::string& text, WxH* out,
              const WxHLimits& limits = WxHLimits::Size());

// Rejects values ParseWxH refuses: "'64by48': expected WIDTHxHEIGHT, ...".
CLI::Validator WxHValidator(const WxHLimits& limits);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_WXH_H_
