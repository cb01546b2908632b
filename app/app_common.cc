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

bool WriteNpy(const std::string& path, const float* data, int ny, int nx) {
  char dict[128];
  std::snprintf(dict, sizeof(dict),
                "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }",
                ny, nx);
  std::string header(dict);
  // Magic (6) + version (2) + length (2) + header, padded to 64 with '\n'.
  const std::size_t total = ((10 + header.size() + 1 + 63) / 64) * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header.push_back('\n');
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const unsigned char magic[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  const std::uint16_t len = static_cast<std::uint16_t>(header.size());
  const unsigned char len_le[2] = {static_cast<unsigned char>(len & 0xff),
                                   static_cast<unsigned char>(len >> 8)};
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  bool ok = std::fwrite(magic, 1, 8, f) == 8 &&
            std::fwrite(len_le, 1, 2, f) == 2 &&
            std::fwrite(header.data(), 1, header.size(), f) == header.size() &&
            std::fwrite(data, sizeof(float), n, f) == n;
  ok = std::fclose(f) == 0 && ok;
  return ok;
}

}  // namespace ripple::app
