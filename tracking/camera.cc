#include "tracking/camera.h"

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>

namespace ripple::tracking {

std::optional<Camera> LoadCamera(const std::string& path, std::string* error) {
  auto fail = [&](const std::string& what) -> std::optional<Camera> {
    if (error) *error = "camera file '" + path + "': " + what;
    return std::nullopt;
  };
  {
    std::ifstream probe(path);
    if (!probe) return fail("cannot open file");
  }
  Camera c;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) return fail("not a readable YAML/XML file");
    auto read_int = [&](const char* key, int* out) {
      const cv::FileNode n = fs[key];
      if (n.empty() || !(n.isInt() || n.isReal())) return false;
      const double v = static_cast<double>(n);
      // Finite and in int range before the conversion (.inf or 1e300 would
      // overflow it).
      if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e9)
        return false;
      *out = static_cast<int>(v);
      return true;
    };
    if (!read_int("image_width", &c.width))
      return fail("field 'image_width' missing or not an integer");
    if (!read_int("image_height", &c.height))
      return fail("field 'image_height' missing or not an integer");
    // Every frame of this size is allocated whole (and several times, by
    // the renderer and the synthetic camera): refuse sizes no webcam has
    // before anything tries.
    if (c.width > kMaxImageSide || c.height > kMaxImageSide)
      return fail("image size " + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + " exceeds " +
                  std::to_string(kMaxImageSide) + " pixels per side");
    cv::Mat k, d;
    fs["camera_matrix"] >> k;
    if (k.empty() || k.rows != 3 || k.cols != 3)
      return fail("field 'camera_matrix' missing or not a 3x3 matrix");
    k.convertTo(k, CV_64F);
    c.fx = k.at<double>(0, 0);
    c.fy = k.at<double>(1, 1);
    c.cx = k.at<double>(0, 2);
    c.cy = k.at<double>(1, 2);
    if (k.at<double>(0, 1) != 0 || k.at<double>(1, 0) != 0 ||
        k.at<double>(2, 0) != 0 || k.at<double>(2, 1) != 0 ||
        k.at<double>(2, 2) != 1)
      return fail("field 'camera_matrix' must be [fx 0 cx; 0 fy cy; 0 0 1]");
    if (fs["distortion_coefficients"].empty())
      return fail("field 'distortion_coefficients' missing");
    fs["distortion_coefficients"] >> d;
    d.convertTo(d, CV_64F);
    const int n = static_cast<int>(d.total());
    if (!(n == 0 || n == 4 || n == 5 || n == 8))
      return fail(
          "field 'distortion_coefficients' must have 4, 5 or 8 values"
          " (got " +
          std::to_string(n) + ")");
    for (int i = 0; i < n; ++i) c.dist[i] = d.at<double>(i);
    // Optional: how the 8-bit values encode light (default sRGB, as
    // webcams deliver).
    const cv::FileNode transfer = fs["transfer"];
    if (!transfer.empty()) {
      if (!transfer.isString() ||
          !geometry::ParseTransfer(transfer.string(), &c.transfer))
        return fail("field 'transfer' must be srgb or linear");
    }
  } catch (const cv::Exception& e) {
    return fail(std::string("malformed YAML: ") + e.err);
  }
  std::string why;
  if (!c.IsValid(&why)) return fail(why);
  return c;
}

bool SaveCamera(const Camera& camera, const std::string& path,
                std::string* error, const std::string& comment) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) {
      if (error) *error = "cannot write camera file '" + path + "'";
      return false;
    }
    if (!comment.empty()) fs.writeComment(comment);
    fs << "image_width" << camera.width;
    fs << "image_height" << camera.height;
    cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0,
                 camera.fy, camera.cy, 0, 0, 1);
    fs << "camera_matrix" << k;
    const bool rational =
        camera.dist[5] != 0 || camera.dist[6] != 0 || camera.dist[7] != 0;
    cv::Mat d(1, rational ? 8 : 5, CV_64F);
    for (int i = 0; i < d.cols; ++i) d.at<double>(i) = camera.dist[i];
    fs << "distortion_coefficients" << d;
    fs << "transfer" << geometry::TransferName(camera.transfer);
    fs.release();
  } catch (const cv::Exception& e) {
    if (error) *error = "cannot write camera file '" + path + "': " + e.err;
    return false;
  }
  return true;
}

}  // namespace ripple::tracking
