#include "tracking/synth/image_file.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace ripple::synth {

cv::Mat ReadImageFile(const std::string& path, int imread_flags,
                      std::string* reason) {
  std::ifstream in(path, std::ios::binary);
  std::vector<uchar> bytes((std::istreambuf_iterator<char>(in)), {});
  if (!in.good() && !in.eof()) bytes.clear();
  if (!in.is_open() || std::filesystem::is_directory(path)) {
    *reason = "cannot be opened";
    return {};
  }
  const bool png = bytes.size() > 8 && bytes[0] == 0x89 && bytes[1] == 'P' &&
                   bytes[2] == 'N' && bytes[3] == 'G';
  const bool jpeg = bytes.size() > 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 &&
                    bytes[2] == 0xFF;
  cv::Mat img;
  if (png || jpeg) {
    try {
      img = cv::imdecode(bytes, imread_flags);
    } catch (const cv::Exception&) {
      img.release();  // a damaged file: reported below
    }
  }
  if (img.empty()) *reason = "not a readable PNG or JPEG image";
  return img;
}

}  // namespace ripple::synth
