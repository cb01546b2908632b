// Helpers shared by the subcommands: loading the camera and rig files with
// the one-line error contract, and locating the embedded default data.
#ifndef RIPPLE_APP_APP_COMMON_H_
#define RIPPLE_APP_APP_COMMON_H_

#include <optional>
#include <string>

#include "tracking/camera.h"
#include "tracking/rig.h"

namespace ripple::app {

// Folder holding the default camera and rig (data/ of the source tree, or
// $RIPPLE_DATA_DIR when set).
std::string DataDir();
std::string DefaultCameraPath();  // data/camera/default_640x480.yml
std::string DefaultRigPath();     // data/rig/default.yml

// Load a file; on failure print the one-line reason and return nullopt (the
// caller exits with kExitBadInput).
std::optional<tracking::Camera> LoadCameraOrReport(const std::string& path);
std::optional<tracking::Rig> LoadRigOrReport(const std::string& path);

// Creates `dir` (and parents); false with a message on failure.
bool MakeDirectories(const std::string& dir, std::string* error);

// NumPy's .npy format, version 1.0: float32 little-endian, C order,
// shape (ny, nx). False if the file cannot be written whole.
bool WriteNpy(const std::string& path, const float* data, int ny, int nx);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_COMMON_H_
