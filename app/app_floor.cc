#include "app/app_floor.h"

#include <algorithm>
#include <cctype>

#include "app/command.h"

namespace ripple::app {

bool ParseFloor(const std::string& text, synth::FloorOptions* out,
                std::string* error) {
  synth::FloorOptions options;
  if (text == "plain") {
    options.kind = synth::FloorKind::kPlain;
  } else if (text == "tiles") {
    options.kind = synth::FloorKind::kTiles;
  } else {
    std::string lower = text;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    auto ends_with = [&lower](const std::string& ext) {
      return lower.size() > ext.size() &&
             lower.compare(lower.size() - ext.size(), ext.size(), ext) == 0;
    };
    if (!ends_with(".png") && !ends_with(".jpg") && !ends_with(".jpeg")) {
      *error = "'" + text +
               "': expected plain, tiles or an image file (.png, .jpg, .jpeg)";
      return false;
    }
    options.kind = synth::FloorKind::kImage;
    options.image_path = text;
  }
  *out = options;
  return true;
}

CLI::Option* AddFloorOption(CLI::App* sub, std::string* value) {
  *value = kDefaultFloor;
  return sub
      ->add_option("--floor", *value,
                   "Tank floor printed on the board: plain, tiles (10 mm "
                   "tiles, grout lines) or FILE.png/.jpg stretched over it")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            synth::FloorOptions options;
            std::string error;
            return ParseFloor(text, &options, &error) ? "" : error;
          },
          "plain|tiles|FILE"));
}

std::optional<synth::FloorPattern> MakeFloorOrReport(const std::string& value,
                                                     const tracking::Rig& rig) {
  synth::FloorOptions options;
  std::string error;
  std::optional<synth::FloorPattern> floor;
  if (ParseFloor(value, &options, &error))
    floor = synth::FloorPattern::Create(options, rig.tank, &error);
  if (!floor) Fail(kExitBadInput, "--floor: " + error);
  return floor;
}

}  // namespace ripple::app
