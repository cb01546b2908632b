#include "sim/pen_path.h"

#include <algorithm>

namespace ripple::sim {

void PenPath::Push(double time_s, bool present,
                   const std::array<double, 3>& tip) {
  Sample s;
  s.time_s = time_s;
  s.present = present;
  s.tip = tip;
  if (count_ < static_cast<int>(samples_.size())) {
    samples_[count_++] = s;
  } else {
    std::move(samples_.begin() + 1, samples_.end(), samples_.begin());
    samples_.back() = s;
  }
}

bool PenPath::At(double time_s, std::array<double, 3>* tip) const {
  if (count_ == 0) return false;
  const Sample& first = samples_[0];
  const Sample& last = samples_[count_ - 1];
  if (time_s <= first.time_s) {
    *tip = first.tip;
    return first.present;
  }
  if (time_s >= last.time_s) {
    *tip = last.tip;
    return last.present;
  }
  for (int s = 1; s < count_; ++s) {
    const Sample& b = samples_[s];
    if (time_s > b.time_s) continue;
    const Sample& a = samples_[s - 1];
    if (time_s == b.time_s) {
      *tip = b.tip;
      return b.present;
    }
    if (!a.present || !b.present) return false;
    const double span = b.time_s - a.time_s;
    const double w = span > 0 ? (time_s - a.time_s) / span : 1.0;
    for (int c = 0; c < 3; ++c)
      (*tip)[c] = a.tip[c] + w * (b.tip[c] - a.tip[c]);
    return true;
  }
  *tip = last.tip;
  return last.present;
}

}  // namespace ripple::sim
