// Pinhole camera with OpenCV's lens distortion model, in OpenCV's pixel
// convention: integer coordinates are pixel centres and (0,0) is the centre of
// the top-left pixel. The camera frame is OpenCV's (x right, y down, z
// forward). The same formula as cv::projectPoints:
//   (x, y) = (X/Z, Y/Z), r2 = x^2 + y^2,
//   radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3),
//   xd = x radial + 2 p1 x y + p2 (r2 + 2 x^2),
//   yd = y radial + p1 (r2 + 2 y^2) + 2 p2 x y,
//   (u, v) = (fx xd + cx, fy yd + cy).
// Reading and writing calibration files lives in tracking/camera.h.
#ifndef RIPPLE_GEOMETRY_CAMERA_MODEL_H_
#define RIPPLE_GEOMETRY_CAMERA_MODEL_H_

#include <Eigen/Core>
#include <array>
#include <string>

namespace ripple::geometry {

// How a camera's 8-bit values encode light.
enum class Transfer {
  kSrgb,    // IEC 61966-2-1, what webcams deliver
  kLinear,  // proportional to radiance (`ripple synth` writes these)
};
// "srgb" / "linear"; false for anything else.
bool ParseTransfer(const std::string& name, Transfer* transfer);
const char* TransferName(Transfer transfer);

struct CameraModel {
  int width = 0;                          // pixels
  int height = 0;                         // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  // OpenCV order: k1 k2 p1 p2 k3 k4 k5 k6 (rational model when k4..k6 != 0).
  std::array<double, 8> dist{};
  // Photometric, not geometric: the renderer decodes the video with it.
  Transfer transfer = Transfer::kSrgb;

  bool HasDistortion() const;
  // Checks sizes, focal lengths and finiteness; `error` (may be null) names
  // the offending field.
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

  // Camera with the same intrinsics scaled to a new image size (pixels).
  CameraModel Scaled(int new_width, int new_height) const;

  bool operator==(const CameraModel& o) const {
    return width == o.width && height == o.height && fx == o.fx && fy == o.fy &&
           cx == o.cx && cy == o.cy && dist == o.dist && transfer == o.transfer;
  }
  bool operator!=(const CameraModel& o) const { return !(*this == o); }
};

// A camera of the given size (pixels) with `hfov_deg` horizontal field of
// view (degrees), square pixels, the principal point at the image centre and
// no distortion.
CameraModel MakeIdealCamera(int width, int height, double hfov_deg);

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_CAMERA_MODEL_H_
