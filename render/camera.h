// The calibrated pinhole camera as GL matrices. Inputs use OpenCV's
// conventions (camera x right, y down, z forward; integer pixel coordinates
// are pixel centres); GL's conventions stay inside render/.
//
// Ripple's FBO stores the image top row first (GL row 0 = image row 0), so a
// video frame uploads and reads back without flipping. With that layout the
// GL window coordinate of OpenCV pixel (u, v) is (u + 0.5, v + 0.5).
#ifndef RIPPLE_RENDER_CAMERA_H_
#define RIPPLE_RENDER_CAMERA_H_

#include <glm/glm.hpp>

#include "geometry/camera_model.h"

namespace ripple::render {

// Calibrated intrinsics of the output image (OpenCV calibration values):
// the project's camera model, geometry/camera_model.h.
using Intrinsics = geometry::CameraModel;

// Near and far clip distances of the renderer (metres along the optical
// axis): a tabletop scene lies well inside.
inline constexpr double kNearM = 0.01;
inline constexpr double kFarM = 20.0;

// clip_from_cam: a point in the OpenCV camera frame -> GL clip coordinates
// for a viewport of intrinsics.width x height storing the image top row
// first. Window x = u + 0.5, window y = v + 0.5 for the ideal (undistorted)
// projection (u, v) = (fx X/Z + cx, fy Y/Z + cy). Depth maps [near, far] to
// NDC [-1, 1].
glm::dmat4 ClipFromCam(const Intrinsics& k, double near_m = kNearM,
                       double far_m = kFarM);

// GL window coordinates (pixels, viewport at the origin) of a clip-space
// point, exactly as the rasteriser's viewport transform computes them.
glm::dvec2 WindowFromClip(const glm::dvec4& clip, int width, int height);

// OpenCV pixel of a GL window position in Ripple's top-row-first FBO.
inline glm::dvec2 PixelFromWindow(const glm::dvec2& window) {
  return window - glm::dvec2(0.5);
}

// OpenCV's distortion model: ideal normalised coordinates (x, y) = (X/Z,
// Y/Z) -> distorted pixel. Same formula as cv::projectPoints
// (CameraModel::DistortNormalized).
glm::dvec2 DistortedPixel(const Intrinsics& k, double x, double y);

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_CAMERA_H_
