// Per-pass timing (internal to render/) as RendererOptions::Timing asks:
// GL timer queries, glFinish around the pass with wall-clock time, or none.
#ifndef RIPPLE_RENDER_PASS_TIMER_H_
#define RIPPLE_RENDER_PASS_TIMER_H_

#include <chrono>

#include "render/gl_objects.h"
#include "render/renderer.h"

namespace ripple::render::internal {

class PassTimer {
 public:
  enum Slot { kShadow = 0, kMain = 1, kEnvMap = 2, kSlots = 3 };
  void Create(RendererOptions::Timing timing);
  void Begin(Slot slot);
  // kCpuFinish: milliseconds since Begin; otherwise 0 (kGpuQueries: read the
  // result with Result() after the frame).
  double End(Slot slot);
  // kGpuQueries: the slot's GPU milliseconds, waiting for the result.
  double Result(Slot slot) const;

 private:
  RendererOptions::Timing timing_ = RendererOptions::Timing::kNone;
  Query queries_[kSlots];
  std::chrono::steady_clock::time_point t0_[kSlots];
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_TIMER_H_
