#include "calib/calib_io.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

namespace ripple::calib {

bool WriteAtomically(
    const std::string& path,
    const std::function<bool(const std::string&, std::string*)>& write,
    std::string* error) {
  namespace fs = std::filesystem;
  const fs::path dest(path);
  fs::path temp = dest.parent_path() /
                  ("." + dest.stem().string() + ".tmp" +
                   std::to_string(::getpid()) + dest.extension().string());
  std::string why;
  if (!write(temp.string(), &why)) {
    std::error_code ec;
    fs::remove(temp, ec);
    *error = why.empty() ? "cannot write '" + path + "'" : why;
    return false;
  }
  std::error_code ec;
  fs::rename(temp, dest, ec);
  if (ec) {
    fs::remove(temp, ec);
    *error = "cannot write '" + path + "': " + ec.message();
    return false;
  }
  return true;
}

bool SaveRigAtomically(const tracking::Rig& rig, const std::string& path,
                       std::string* error) {
  return WriteAtomically(
      path,
      [&](const std::string& temp, std::string* e) {
        if (tracking::SaveRig(rig, temp, e)) return true;
        *e = "cannot write rig '" + path + "'";
        return false;
      },
      error);
}

bool SaveCameraAtomically(const tracking::Camera& camera,
                          const std::string& path, std::string* error,
                          const std::string& comment) {
  return WriteAtomically(
      path,
      [&](const std::string& temp, std::string* e) {
        if (tracking::SaveCamera(camera, temp, e, comment)) return true;
        *e = "cannot write camera '" + path + "'";
        return false;
      },
      error);
}

}  // namespace ripple::calib
