// Exact area-coverage primitives for the synthetic renderer. Pixel (u, v)
// covers the square [u-0.5, u+0.5] x [v-0.5, v+0.5] (OpenCV convention).
#ifndef RIPPLE_TRACKING_SYNTH_RASTER_H_
#define RIPPLE_TRACKING_SYNTH_RASTER_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

namespace ripple::synth {

// Area of a convex quadrilateral (vertices in order, either orientation)
// intersected with the axis-aligned rectangle [x0, x1] x [y0, y1].
double QuadRectArea(const Eigen::Vector2d quad[4], double x0, double y0,
                    double x1, double y1);

// Area, measured after mapping through the homography `h` (plane point
// (x, y) -> h * (x, y, 1), dehomogenised), of the convex quadrilateral `quad`
// clipped to [x0, x1] x [y0, y1]. Lets the renderer measure coverage in image
// space while clipping in the plane.
double QuadRectMappedArea(const Eigen::Vector2d quad[4], double x0, double y0,
                          double x1, double y1, const Eigen::Matrix3d& h);

// Signed area of a polygon (shoelace), positive when counter-clockwise in a
// y-up frame.
double PolygonArea(const std::vector<Eigen::Vector2d>& polygon);

// Sutherland-Hodgman clip of any polygon by an axis-aligned rectangle. The
// area of the result is exact even for a concave input.
std::vector<Eigen::Vector2d> ClipToRect(
    const std::vector<Eigen::Vector2d>& poly, double x0, double y0, double x1,
    double y1);

// Exact per-pixel coverage of a simple polygon in pixel coordinates (any
// orientation, concave allowed), by signed-area accumulation along rows (the
// scheme of font rasterisers). Writes coverage in [0, 1] for the pixels of
// `roi` (clipped to the image) into `coverage` (CV_32F, roi-sized). Returns
// false when the polygon misses the image.
bool RasterizePolygon(const std::vector<Eigen::Vector2d>& polygon_px, int width,
                      int height, cv::Mat* coverage, cv::Rect* roi);

}  // namespace ripple::synth

#endif  // RIPPLE_TRACKING_SYNTH_RASTER_H_
