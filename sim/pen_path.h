// The pen tip's recent path, sampled at frame ends and read at sub-step
// times: the tip moves linearly between two seen samples, so a fast stroke
// leaves a continuous wake whatever the frame rate; across a sample where the
// pen was not seen it is absent.
#ifndef RIPPLE_SIM_PEN_PATH_H_
#define RIPPLE_SIM_PEN_PATH_H_

#include <array>

namespace ripple::sim {

class PenPath {
 public:
  // Appends the state at time_s (seconds, non-decreasing); the oldest of the
  // kept samples is dropped when full.
  void Push(double time_s, bool present, const std::array<double, 3>& tip);
  // The tip at time_s (tank frame, metres) and whether the pen is present
  // then. Before the first sample: the first; after the last: the last.
  bool At(double time_s, std::array<double, 3>* tip) const;
  void Clear() { count_ = 0; }

 private:
  struct Sample {
    double time_s = 0;
    bool present = false;
    std::array<double, 3> tip = {0, 0, 0};
  };
  std::array<Sample, 8> samples_{};  // oldest first
  int count_ = 0;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_PEN_PATH_H_
