#include "tracking/camera.h"

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>
#include <vector>

#include "tracking/yaml_tree.h"

namespace ripple::tracking {

namespace {

// An OpenCV matrix node (!!opencv-matrix: rows, cols, dt, data) of at most
// `max_values` values, row-major. False with `why` otherwise.
bool ReadMatrix(const YamlNode& n, size_t max_values, int* rows, int* cols,
                std::vector<double>* values, std::string* why) {
  if (!n.IsMapping()) {
    *why = "not an !!opencv-matrix mapping";
    return false;
  }
  const YamlNode& r = n["rows"];
  const YamlNode& c = n["cols"];
  const YamlNode& dt = n["dt"];
  const YamlNode& data = n["data"];
  auto small_int = [&](const YamlNode& v, int* out) {
    if (!v.IsNumber()) return false;
    const double x = v.Number();
    if (!(x >= 0 && x <= static_cast<double>(max_values)) || x != std::floor(x))
      return false;
    *out = static_cast<int>(x);
    return true;
  };
  if (!small_int(r, rows) || !small_int(c, cols) ||
      static_cast<size_t>(*rows) * static_cast<size_t>(*cols) > max_values) {
    *why = "rows and cols must be integers with rows*cols <= " +
           std::to_string(max_values);
    return false;
  }
  static const char* kTypes[] = {"u", "c", "w", "s", "i", "f", "d"};
  bool known = false;
  for (const char* t : kTypes) known = known || dt.Text() == t;
  if (!dt.IsScalar() || !known) {
    *why = "dt must be one of u c w s i f d";
    return false;
  }
  if (!data.IsSequence() ||
      data.size() != static_cast<size_t>(*rows) * static_cast<size_t>(*cols)) {
    *why = "data must be a list of rows*cols numbers";
    return false;
  }
  values->clear();
  for (const YamlNode& v : data.children()) {
    if (!v.IsNumber()) {
      *why = "data must hold numbers";
      return false;
    }
    values->push_back(v.Number());
  }
  return true;
}

}  // namespace

std::optional<Camera> LoadCamera(const std::string& path, std::string* error) {
  auto fail = [&](const std::string& what) -> std::optional<Camera> {
    if (error) *error = "camera file '" + path + "': " + what;
    return std::nullopt;
  };
  Camera c;
  try {
    std::string yaml_error;
    const std::optional<YamlNode> doc =
        LoadYamlFile(path, YamlLimits{}, &yaml_error);
    if (!doc) return fail(yaml_error);
    if (!doc->IsMapping()) return fail("not a YAML mapping of camera fields");
    const YamlNode& fs = *doc;
    auto read_int = [&](const char* key, int* out) {
      const YamlNode& n = fs[key];
      if (!n.IsNumber()) return false;
      const double v = n.Number();
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
    if (c.width < kMinImageSide || c.height < kMinImageSide)
      return fail("image_width/image_height " + std::to_string(c.width) + "x" +
                  std::to_string(c.height) + " is under " +
                  std::to_string(kMinImageSide) + " pixels per side");
    int rows = 0, cols = 0;
    std::vector<double> k, d;
    std::string why;
    if (fs["camera_matrix"].empty())
      return fail("field 'camera_matrix' missing");
    if (!ReadMatrix(fs["camera_matrix"], 9, &rows, &cols, &k, &why))
      return fail("field 'camera_matrix': " + why);
    if (rows != 3 || cols != 3)
      return fail("field 'camera_matrix' must be a 3x3 matrix");
    c.fx = k[0];
    c.fy = k[4];
    c.cx = k[2];
    c.cy = k[5];
    if (k[1] != 0 || k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1)
      return fail("field 'camera_matrix' must be [fx 0 cx; 0 fy cy; 0 0 1]");
    if (fs["distortion_coefficients"].empty())
      return fail("field 'distortion_coefficients' missing");
    if (!ReadMatrix(fs["distortion_coefficients"], 64, &rows, &cols, &d, &why))
      return fail("field 'distortion_coefficients': " + why);
    const int n = static_cast<int>(d.size());
    if (!(n == 0 || n == 4 || n == 5 || n == 8))
      return fail(
          "field 'distortion_coefficients' must have 4, 5 or 8 values"
          " (got " +
          std::to_string(n) + ")");
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(d[i]))
        return fail("field 'distortion_coefficients' must be finite");
      c.dist[i] = d[i];
    }
    // Optional: how the 8-bit values encode light (default sRGB, as
    // webcams deliver).
    const YamlNode& transfer = fs["transfer"];
    if (!transfer.empty()) {
      if (!transfer.IsString() ||
          !geometry::ParseTransfer(transfer.Text(), &c.transfer))
        return fail("field 'transfer' must be srgb or linear");
    }
  } catch (const std::exception& e) {
    // std::bad_alloc and the like: the file is named, the program goes on.
    return fail(std::string("cannot be read: ") + e.what());
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
