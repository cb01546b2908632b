// The one parser of --floor (markers, synth, demo, bench tracking): the tank
// floor printed on the board and drawn in synthetic frames, "plain",
// "tiles" (the default) or a PNG/JPEG file stretched over the tank floor
// (tracking/synth/floor_pattern.h).
#ifndef RIPPLE_APP_APP_FLOOR_H_
#define RIPPLE_APP_APP_FLOOR_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"

namespace ripple::app {

inline constexpr const char* kDefaultFloor = "tiles";

// "plain", "tiles" or a file name ending in .png, .jpg or .jpeg (any case):
// the pattern's options (the file is not opened here). False with `error`
// for anything else.
bool ParseFloor(const std::string& text, synth::FloorOptions* out,
                std::string* error);

// Adds `--floor` to `sub`, stored in `value` (kDefaultFloor unless given); a
// malformed value is a usage error (exit 2) naming the option.
CLI::Option* AddFloorOption(CLI::App* sub, std::string* value);

// The floor of `value` for the rig's tank; on failure (an image file that
// cannot be read, a tank without a size) prints the one line naming --floor
// and the file, and returns nullopt (the caller exits with kExitBadInput).
std::optional<synth::FloorPattern> MakeFloorOrReport(const std::string& value,
                                                     const tracking::Rig& rig);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_FLOOR_H_
