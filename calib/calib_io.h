// Output files that are either complete or absent: every calibration result
// is written to a temporary file beside its destination and renamed over it
// only when the write succeeded, so a failed run leaves no partial file.
#ifndef RIPPLE_CALIB_CALIB_IO_H_
#define RIPPLE_CALIB_CALIB_IO_H_

#include <functional>
#include <string>

#include "tracking/camera.h"
#include "tracking/rig.h"

namespace ripple::calib {

// Calls write(temp_path, error) with a temporary path in the destination's
// folder that keeps the destination's extension (writers that pick their
// format by extension still work), then renames it to `path`. On any
// failure the temporary file is removed and `error` says why.
bool WriteAtomically(const std::string& path,
                     const std::function<bool(const std::string& temp_path,
                                              std::string* error)>& write,
                     std::string* error);

bool SaveRigAtomically(const tracking::Rig& rig, const std::string& path,
                       std::string* error);
// `comment`: as tracking::SaveCamera's.
bool SaveCameraAtomically(const tracking::Camera& camera,
                          const std::string& path, std::string* error,
                          const std::string& comment = "");

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_CALIB_IO_H_
