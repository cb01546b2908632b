// A PNG or JPEG file read whole and decoded, with one reason when it cannot
// be: the bytes are read here, so that OpenCV's imread logs no warning of
// its own for a missing or foreign file. Used by the floor pattern's image
// (`--floor FILE.png`) and by `ripple bench flip`.
#ifndef RIPPLE_TRACKING_SYNTH_IMAGE_FILE_H_
#define RIPPLE_TRACKING_SYNTH_IMAGE_FILE_H_

#include <opencv2/core.hpp>
#include <string>

namespace ripple::synth {

// The image at `path` decoded with cv::imdecode's `imread_flags`
// (cv::IMREAD_COLOR: 8-bit BGR, cv::IMREAD_GRAYSCALE: 8-bit grey). Empty,
// with `reason` "cannot be opened" (missing, unreadable, a folder) or "not
// a readable PNG or JPEG image" (another format, damaged, truncated).
cv::Mat ReadImageFile(const std::string& path, int imread_flags,
                      std::string* reason);

}  // namespace ripple::synth

#endif  // RIPPLE_TRACKING_SYNTH_IMAGE_FILE_H_
