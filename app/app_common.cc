#include "app/app_common.h"

#include <cstdlib>
#include <filesystem>

#include "app/command.h"

namespace ripple::app {

std::string DataDir() {
  if (const char* env = std::getenv("RIPPLE_DATA_DIR")) return env;
  return RIPPLE_DATA_DIR;
}

std::string DefaultCameraPath() {
  return DataDir() + "/camera/default_640x480.yml";
}
std::string DefaultRigPath() { return DataDir() + "/rig/default.yml"; }

std::optional<tracking::Camera> LoadCameraOrReport(const std::string& path) {
  std::string error;
  auto camera = tracking::LoadCamera(path, &error);
  if (!camera) Fail(kExitBadInput, error);
  return camera;
}

std::optional<tracking::Rig> LoadRigOrReport(const std::string& path) {
  std::string error;
  auto rig = tracking::LoadRig(path, &error);
  if (!rig) Fail(kExitBadInput, error);
  return rig;
}

bool MakeDirectories(const std::string& dir, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    if (error) *error = "cannot create output folder '" + dir + "'";
    return false;
  }
  return true;
}

}  // namespace ripple::app
