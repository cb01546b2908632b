#include "bench/pose_errors.h"

#include <Eigen/Geometry>
#include <cstdio>
#include <functional>
#include <sstream>

#include "bench/stats.h"

namespace ripple::bench {
namespace {

using tracking::Pose;
constexpr double kDeg = M_PI / 180.0;

ErrorSpread Spread(const std::vector<double>& v) {
  return {ErrorPercentile(v, 50), ErrorPercentile(v, 95)};
}

bool SamePose(const PoseErrorOptions& o, const Pose& a, const Pose& b) {
  return tracking::RotationDistance(a, b) <= o.static_rotation_deg * kDeg &&
         tracking::TranslationDistance(a, b) <= o.static_translation_m;
}

// Maximal runs of at least `min_frames` consecutive frames (frame numbers
// without gaps) where still(first, j) holds for every j of the run.
std::vector<FrameRange> StaticRuns(
    const std::vector<TruthFrame>& truth, int min_frames,
    const std::function<bool(const TruthFrame&, const TruthFrame&)>& still) {
  std::vector<FrameRange> runs;
  const int n = static_cast<int>(truth.size());
  int begin = 0;
  while (begin < n) {
    int end = begin + 1;
    if (still(truth[begin], truth[begin]))
      while (end < n && truth[end].frame == truth[end - 1].frame + 1 &&
             still(truth[begin], truth[end]))
        ++end;
    if (end - begin >= min_frames) runs.push_back({begin, end});
    begin = end;
  }
  return runs;
}

// Pooled spread over `runs` of the values that sample(i, &value) yields:
// deviation(values of a run) gives each value's squared deviation from the
// run's mean.
template <typename T>
Jitter PooledSpread(const std::vector<FrameRange>& runs,
                    const std::function<bool(int, T*)>& sample,
                    const std::function<double(const std::vector<T>&)>& ss) {
  Jitter j;
  j.segments = static_cast<int>(runs.size());
  double sum_sq = 0;
  int dof = 0;
  for (const FrameRange& r : runs) {
    std::vector<T> values;
    T v;
    for (int i = r.begin; i < r.end; ++i)
      if (sample(i, &v)) values.push_back(v);
    j.samples += static_cast<int>(values.size());
    if (values.size() < 2) continue;
    sum_sq += ss(values);
    dof += static_cast<int>(values.size()) - 1;
  }
  if (dof > 0) j.std = std::sqrt(sum_sq / dof);
  return j;
}

// Sum of squared angles (radians) of `rotations` from their chordal mean.
double RotationSumSq(const std::vector<Eigen::Quaterniond>& rotations) {
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (const Eigen::Quaterniond& q : rotations)
    sum +=
        (q.coeffs().dot(rotations[0].coeffs()) < 0 ? -1.0 : 1.0) * q.coeffs();
  Eigen::Quaterniond mean;
  mean.coeffs() = sum.normalized();
  double ss = 0;
  for (const Eigen::Quaterniond& q : rotations) {
    const double a = q.angularDistance(mean);
    ss += a * a;
  }
  return ss;
}

double PointSumSq(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p / points.size();
  double ss = 0;
  for (const Eigen::Vector3d& p : points) ss += (p - mean).squaredNorm();
  return ss;
}

std::string Num(const char* format, double v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string Share(double share) {
  return std::isnan(share) ? "-" : Num("%.1f%%", 100 * share);
}

}  // namespace

bool PoseErrorOptions::IsValid(std::string* error) const {
  if (!(flip_deg > 0) || !(static_rotation_deg >= 0) ||
      !(static_translation_m >= 0) || static_min_frames < 2) {
    if (error)
      *error =
          "flip_deg must be > 0, the static tolerances >= 0 and "
          "static_min_frames >= 2";
    return false;
  }
  return true;
}

FrameErrors ComputeFrameErrors(const PoseErrorOptions& options,
                               const TruthFrame& truth,
                               const EstimateFrame& estimate) {
  FrameErrors e;
  const double flip = options.flip_deg * kDeg;
  if (estimate.cam_from_tank) {
    const double r = tracking::RotationDistance(*estimate.cam_from_tank,
                                                truth.cam_from_tank);
    e.tank_rot_deg = r / kDeg;
    e.tank_mm = 1000 * tracking::TranslationDistance(*estimate.cam_from_tank,
                                                     truth.cam_from_tank);
    e.flip |= r > flip;
  }
  if (estimate.cam_from_pen && truth.cam_from_pen) {
    const double r =
        tracking::RotationDistance(*estimate.cam_from_pen, *truth.cam_from_pen);
    e.pen_rot_deg = r / kDeg;
    e.pen_mm = 1000 * tracking::TranslationDistance(*estimate.cam_from_pen,
                                                    *truth.cam_from_pen);
    e.flip |= r > flip;
  }
  if (estimate.tip_in_tank && truth.tip_in_tank)
    e.tip_mm = 1000 * (*estimate.tip_in_tank - *truth.tip_in_tank).norm();
  return e;
}

double PoseErrorSummary::tank_tracked_share() const {
  return tank_visible > 0 ? double(tank_tracked) / tank_visible : NAN;
}

double PoseErrorSummary::pen_tracked_share() const {
  return pen_visible > 0 ? double(pen_tracked) / pen_visible : NAN;
}

PoseErrorAccumulator::PoseErrorAccumulator(const PoseErrorOptions& options)
    : options_(options) {}

FrameErrors PoseErrorAccumulator::Add(const TruthFrame& truth,
                                      const EstimateFrame& estimate) {
  const FrameErrors e = ComputeFrameErrors(options_, truth, estimate);
  truth_.push_back(truth);
  estimates_.push_back(estimate);
  errors_.push_back(e);
  auto push = [](double v, std::vector<double>* samples) {
    if (!std::isnan(v)) samples->push_back(v);
  };
  push(e.tank_rot_deg, &tank_rot_deg_);
  push(e.tank_mm, &tank_mm_);
  push(e.pen_rot_deg, &pen_rot_deg_);
  push(e.pen_mm, &pen_mm_);
  push(e.tip_mm, &tip_mm_);
  return e;
}

PoseErrorSummary PoseErrorAccumulator::Summarize() const {
  PoseErrorSummary s;
  s.frames = frames();
  s.tank_rot_deg = Spread(tank_rot_deg_);
  s.tank_mm = Spread(tank_mm_);
  s.pen_rot_deg = Spread(pen_rot_deg_);
  s.pen_mm = Spread(pen_mm_);
  s.tip_mm = Spread(tip_mm_);
  for (size_t i = 0; i < truth_.size(); ++i) {
    const TruthFrame& t = truth_[i];
    const EstimateFrame& e = estimates_[i];
    s.flips += errors_[i].flip;
    s.tank_visible += t.tank_visible;
    s.pen_visible += t.pen_visible;
    s.tank_tracked += t.tank_visible && e.tank_tracked;
    s.pen_tracked += t.pen_visible && e.pen_tracked;
  }

  const PoseErrorOptions& o = options_;
  const auto tank_still = [&o](const TruthFrame& a, const TruthFrame& b) {
    return SamePose(o, a.cam_from_tank, b.cam_from_tank);
  };
  const auto pen_still = [&o](const TruthFrame& a, const TruthFrame& b) {
    return a.cam_from_pen && b.cam_from_pen &&
           SamePose(o, *a.cam_from_pen, *b.cam_from_pen);
  };
  s.tank_static = StaticRuns(truth_, o.static_min_frames, tank_still);
  s.pen_static = StaticRuns(truth_, o.static_min_frames, pen_still);
  s.tip_static =
      StaticRuns(truth_, o.static_min_frames,
                 [&](const TruthFrame& a, const TruthFrame& b) {
                   return a.tip_in_tank && tank_still(a, b) && pen_still(a, b);
                 });

  const std::function<double(const std::vector<Eigen::Quaterniond>&)> rot_ss =
      RotationSumSq;
  const std::function<double(const std::vector<Eigen::Vector3d>&)> tip_ss =
      PointSumSq;
  s.tank_jitter_deg = PooledSpread<Eigen::Quaterniond>(
      s.tank_static,
      [this](int i, Eigen::Quaterniond* q) {
        if (!estimates_[i].cam_from_tank) return false;
        *q = estimates_[i].cam_from_tank->rotation;
        return true;
      },
      rot_ss);
  s.pen_jitter_deg = PooledSpread<Eigen::Quaterniond>(
      s.pen_static,
      [this](int i, Eigen::Quaterniond* q) {
        if (!estimates_[i].cam_from_pen) return false;
        *q = estimates_[i].cam_from_pen->rotation;
        return true;
      },
      rot_ss);
  s.tip_jitter_mm = PooledSpread<Eigen::Vector3d>(
      s.tip_static,
      [this](int i, Eigen::Vector3d* p) {
        if (!estimates_[i].tip_in_tank) return false;
        *p = *estimates_[i].tip_in_tank;
        return true;
      },
      tip_ss);
  s.tank_jitter_deg.std /= kDeg;
  s.pen_jitter_deg.std /= kDeg;
  s.tip_jitter_mm.std *= 1000;
  return s;
}

double ErrorPercentile(const std::vector<double>& v, double p) {
  PercentileOptions options;
  options.rank = PercentileOptions::Rank::kRounded;
  options.empty_value = NAN;
  return Percentile(v, p, options);
}

std::string ErrorTableHeaderCells() {
  return "| tank rot ° med / p95 | tank mm med / p95 | pen rot ° med / p95 | "
         "tip mm med / p95 | flips | tracked tank / pen | static jitter tank "
         "° / pen ° / tip mm ";
}

std::string ErrorTableSeparatorCells() {
  return "|---|---|---|---|---|---|---";
}

std::string ErrorTableCells(const PoseErrorSummary& s) {
  std::ostringstream out;
  out << "| " << Num("%.3f", s.tank_rot_deg.median) << " / "
      << Num("%.3f", s.tank_rot_deg.p95) << " | "
      << Num("%.2f", s.tank_mm.median) << " / " << Num("%.2f", s.tank_mm.p95)
      << " | " << Num("%.2f", s.pen_rot_deg.median) << " / "
      << Num("%.2f", s.pen_rot_deg.p95) << " | " << Num("%.2f", s.tip_mm.median)
      << " / " << Num("%.2f", s.tip_mm.p95) << " | " << s.flips << " | "
      << Share(s.tank_tracked_share()) << " / " << Share(s.pen_tracked_share())
      << " | " << Num("%.4f", s.tank_jitter_deg.std) << " / "
      << Num("%.4f", s.pen_jitter_deg.std) << " / "
      << Num("%.3f", s.tip_jitter_mm.std) << " ";
  return out.str();
}

std::string ErrorCsvHeader() {
  return "tank_rot_deg_median,tank_rot_deg_p95,tank_mm_median,tank_mm_p95,"
         "pen_rot_deg_median,pen_rot_deg_p95,pen_mm_median,pen_mm_p95,"
         "tip_mm_median,tip_mm_p95,flips,tank_tracked_share,pen_tracked_share,"
         "tank_static_frames,pen_static_frames,tip_static_frames,"
         "tank_jitter_deg,pen_jitter_deg,tip_jitter_mm";
}

std::string ErrorCsvFields(const PoseErrorSummary& s) {
  auto frames = [](const std::vector<FrameRange>& runs) {
    int n = 0;
    for (const FrameRange& r : runs) n += r.end - r.begin;
    return n;
  };
  std::ostringstream out;
  out << s.tank_rot_deg.median << ',' << s.tank_rot_deg.p95 << ','
      << s.tank_mm.median << ',' << s.tank_mm.p95 << ',' << s.pen_rot_deg.median
      << ',' << s.pen_rot_deg.p95 << ',' << s.pen_mm.median << ','
      << s.pen_mm.p95 << ',' << s.tip_mm.median << ',' << s.tip_mm.p95 << ','
      << s.flips << ',' << s.tank_tracked_share() << ','
      << s.pen_tracked_share() << ',' << frames(s.tank_static) << ','
      << frames(s.pen_static) << ',' << frames(s.tip_static) << ','
      << s.tank_jitter_deg.std << ',' << s.pen_jitter_deg.std << ','
      << s.tip_jitter_mm.std;
  return out.str();
}

}  // namespace ripple::bench
