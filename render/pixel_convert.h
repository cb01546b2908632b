// CPU pixel conversions of the video upload (internal to render/).
#ifndef RIPPLE_RENDER_PIXEL_CONVERT_H_
#define RIPPLE_RENDER_PIXEL_CONVERT_H_

#include <cstdint>

namespace ripple::render::internal {

// One row of `n` BGR8 pixels -> RGBA8 (alpha 255), the layout llvmpipe gives
// a GL_RGBA8 texture, so the upload is a plain copy (Mesa's own BGR8 upload
// is a slow per-pixel conversion on the calling thread). SSSE3 where the CPU
// has it.
void BgrToRgbaRow(const std::uint8_t* bgr, int n, std::uint32_t* out);

// Quarter-size RGBA8 image (w / 4 x h / 4; w, h multiples of 4) as
// glBlitFramebuffer with GL_LINEAR makes it: each output pixel's centre
// falls between source pixels 4i+1 and 4i+2 in x and y, i.e. the mean of
// that 2x2 block (rounded; the GPU's 8-bit lerps may differ by 1).
void QuarterRgba(const std::uint32_t* src, int w, int h, std::uint32_t* out);

// The same quarter-size RGBA8 image straight from a BGR8 frame (rows
// `stride` bytes apart): equal, byte for byte, to QuarterRgba of the frame's
// BgrToRgbaRow conversion, without converting the whole frame.
void QuarterRgbaFromBgr(const std::uint8_t* bgr, int stride, int w, int h,
                        std::uint32_t* out);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PIXEL_CONVERT_H_
