// Pinhole camera with OpenCV's lens distortion model, in OpenCV's pixel
// convention: integer coordinates are pixel centres and (0,0) is the centre of
// the top-left pixel. Files are OpenCV calibration YAML (image_width,
// image_height, camera_matrix, distortion_coefficients), as OpenCV's own
// calibration sample writes them.
#ifndef RIPPLE_TRACKING_CAMERA_H_
#define RIPPLE_TRACKING_CAMERA_H_

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <optional>
#include <string>

namespace ripple::tracking {

struct Camera {
  int width = 0;                          // pixels
  int height = 0;                         // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  // OpenCV order: k1 k2 p1 p2 k3 k4 k5 k6 (rational model when k4..k6 != 0).
  std::array<double, 8> dist{};

  bool HasDistortion() const;
  // Checks sizes and focal lengths; `error` names the offending field.
  bool IsValid(std::string* error) const;

  // Ideal (undistorted) normalised coordinates -> distorted pixel. Templated
  // so that Ceres Jets can flow through.
  template <typename T>
  Eigen::Matrix<T, 2, 1> DistortNormalized(const T& x, const T& y) const {
    const T r2 = x * x + y * y;
    const T r4 = r2 * r2, r6 = r4 * r2;
    const T radial = (T(1) + dist[0] * r2 + dist[1] * r4 + dist[4] * r6) /
                     (T(1) + dist[5] * r2 + dist[6] * r4 + dist[7] * r6);
    const T xd =
        x * radial + T(2 * dist[2]) * x * y + dist[3] * (r2 + T(2) * x * x);
    const T yd =
        y * radial + dist[2] * (r2 + T(2) * y * y) + T(2 * dist[3]) * x * y;
    return {T(fx) * xd + T(cx), T(fy) * yd + T(cy)};
  }

  // Point in the camera frame (metres, z forward) -> distorted pixel. The
  // caller ensures z > 0.
  template <typename T>
  Eigen::Matrix<T, 2, 1> Project(const Eigen::Matrix<T, 3, 1>& p_in_cam) const {
    return DistortNormalized(p_in_cam.x() / p_in_cam.z(),
                             p_in_cam.y() / p_in_cam.z());
  }

  // Project() with its analytic Jacobian d pixel / d p_in_cam (2x3), for
  // inner loops where Jets cost too much.
  Eigen::Vector2d ProjectWithJacobian(const Eigen::Vector3d& p_in_cam,
                                      Eigen::Matrix<double, 2, 3>* j) const;

  // Distorted pixel -> ideal normalised coordinates (iterative inverse of the
  // distortion, accurate to ~1e-10 for typical webcam lenses).
  Eigen::Vector2d UndistortToNormalized(const Eigen::Vector2d& pixel) const;

  // Camera with the same intrinsics scaled to a new image size.
  Camera Scaled(int new_width, int new_height) const;
};

// A webcam of the given size with `hfov_deg` horizontal field of view, square
// pixels, the principal point at the image centre and no distortion.
Camera MakeIdealCamera(int width, int height, double hfov_deg);

// Reads an OpenCV calibration YAML. Returns nullopt and fills `error` with a
// message naming the file and the field on any problem.
std::optional<Camera> LoadCamera(const std::string& path, std::string* error);
// Writes an OpenCV calibration YAML; false (with `error`) if not writable.
bool SaveCamera(const Camera& camera, const std::string& path,
                std::string* error);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_CAMERA_H_
