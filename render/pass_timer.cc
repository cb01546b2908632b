#include "render/pass_timer.h"

namespace ripple::render::internal {

using Timing = RendererOptions::Timing;

void PassTimer::Create(Timing timing) {
  timing_ = timing;
  for (Query& q : queries_) q.Create();
}

void PassTimer::Begin(Slot slot) {
  t0_[slot] = std::chrono::steady_clock::now();
  if (timing_ == Timing::kGpuQueries) {
    glBeginQuery(GL_TIME_ELAPSED, queries_[slot].id());
  } else if (timing_ == Timing::kCpuFinish) {
    glFinish();
  }
}

double PassTimer::End(Slot slot) {
  if (timing_ == Timing::kGpuQueries) {
    glEndQuery(GL_TIME_ELAPSED);
    return 0;
  }
  if (timing_ == Timing::kCpuFinish) {
    glFinish();
    return std::chrono::duration<double, std::milli>(
               std::chrono::steady_clock::now() - t0_[slot])
        .count();
  }
  return 0;
}

double PassTimer::Result(Slot slot) const {
  GLuint64 ns = 0;
  glGetQueryObjectui64v(queries_[slot].id(), GL_QUERY_RESULT, &ns);
  return ns * 1e-6;
}

}  // namespace ripple::render::internal
