// The camera model of the tracker (geometry/camera_model.h) and its files:
// OpenCV calibration YAML (image_width, image_height, camera_matrix,
// distortion_coefficients), as OpenCV's own calibration sample writes them.
#ifndef RIPPLE_TRACKING_CAMERA_H_
#define RIPPLE_TRACKING_CAMERA_H_

#include <Eigen/Core>
#include <Eigen/LU>
#include <optional>
#include <string>

#include "geometry/camera_model.h"

namespace ripple::tracking {

using Camera = geometry::CameraModel;
using geometry::MakeIdealCamera;

// Largest image side a camera file may state, pixels.
inline constexpr int kMaxImageSide = 16384;
// Smallest image side a camera file may state, pixels: the tag detector's
// minimum (smaller images hold no tag).
inline constexpr int kMinImageSide = 8;

// Reads an OpenCV calibration YAML. Returns nullopt and fills `error` with a
// message naming the file and the field on any problem (sizes above
// kMaxImageSide included).
std::optional<Camera> LoadCamera(const std::string& path, std::string* error);
// Writes an OpenCV calibration YAML; false (with `error`) if not writable.
// A non-empty `comment` is written first, each of its lines as a YAML
// comment ("# ..."), which readers skip.
bool SaveCamera(const Camera& camera, const std::string& path,
                std::string* error, const std::string& comment = "");

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_CAMERA_H_
