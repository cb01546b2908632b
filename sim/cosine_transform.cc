#include "sim/cosine_transform.h"

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "geometry/check.h"

namespace ripple::sim {
namespace {

float* AllocFloats(std::size_t n) { return fftwf_alloc_real(n); }

std::mutex& PlannerMutex() {
  static std::mutex m;
  return m;
}

struct PlanPair {
  fftwf_plan synth = nullptr;
  fftwf_plan analyze = nullptr;
};

// One pair of plans per size for the life of the process, shared by every
// transform of that size.
PlanPair PlansFor(int nx, int ny) {
  std::lock_guard<std::mutex> lock(PlannerMutex());
  static std::map<std::pair<int, int>, PlanPair>* cache =
      new std::map<std::pair<int, int>, PlanPair>();
  auto it = cache->find({nx, ny});
  if (it != cache->end()) return it->second;
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  float* a = AllocFloats(n);
  float* b = AllocFloats(n);
  PlanPair p;
  // Row-major ny x nx: the last dimension (x) is contiguous. FFTW_ESTIMATE:
  // the plan, and so every rounding, is the same on every run (measured
  // plans are chosen by timing, and replays differed by a grey level).
  p.synth = fftwf_plan_r2r_2d(ny, nx, a, b, FFTW_REDFT01, FFTW_REDFT01,
                              FFTW_ESTIMATE);
  p.analyze = fftwf_plan_r2r_2d(ny, nx, a, b, FFTW_REDFT10, FFTW_REDFT10,
                                FFTW_ESTIMATE);
  fftwf_free(a);
  fftwf_free(b);
  RIPPLE_CHECK(p.synth && p.analyze,
               "FFTW could not plan a " + std::to_string(nx) + "x" +
                   std::to_string(ny) + " cosine transform");
  (*cache)[{nx, ny}] = p;
  return p;
}

// Row-column plans for SynthesizeRows: x transforms of `rows` rows
// (scratch -> samples) and in-place y transforms of every column.
struct RowPlans {
  fftwf_plan rows = nullptr;
  fftwf_plan columns = nullptr;
};

RowPlans RowPlansFor(int nx, int ny, int rows) {
  std::lock_guard<std::mutex> lock(PlannerMutex());
  static std::map<std::array<int, 3>, RowPlans>* cache =
      new std::map<std::array<int, 3>, RowPlans>();
  auto it = cache->find({nx, ny, rows});
  if (it != cache->end()) return it->second;
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  float* a = AllocFloats(n);
  float* b = AllocFloats(n);
  const fftwf_r2r_kind kind[1] = {FFTW_REDFT01};
  RowPlans p;
  p.rows = fftwf_plan_many_r2r(1, &nx, rows, a, nullptr, 1, nx, b, nullptr, 1,
                               nx, kind, FFTW_ESTIMATE);
  p.columns = fftwf_plan_many_r2r(1, &ny, nx, b, nullptr, nx, 1, b, nullptr, nx,
                                  1, kind, FFTW_ESTIMATE);
  fftwf_free(a);
  fftwf_free(b);
  RIPPLE_CHECK(p.rows && p.columns, "FFTW could not plan row transforms");
  (*cache)[{nx, ny, rows}] = p;
  return p;
}

}  // namespace

AlignedFloats::AlignedFloats(std::size_t n)
    : data_(AllocFloats(n > 0 ? n : 1)), size_(n) {
  Fill(0.0f);
}
AlignedFloats::AlignedFloats(AlignedFloats&& o) noexcept
    : data_(std::exchange(o.data_, nullptr)),
      size_(std::exchange(o.size_, 0)) {}
AlignedFloats& AlignedFloats::operator=(AlignedFloats&& o) noexcept {
  if (this != &o) {
    if (data_) fftwf_free(data_);
    data_ = std::exchange(o.data_, nullptr);
    size_ = std::exchange(o.size_, 0);
  }
  return *this;
}
AlignedFloats::~AlignedFloats() {
  if (data_) fftwf_free(data_);
}
void AlignedFloats::Fill(float v) {
  for (std::size_t i = 0; i < size_; ++i) data_[i] = v;
}

CosineTransform2D::CosineTransform2D(int nx, int ny) : nx_(nx), ny_(ny) {
  RIPPLE_CHECK(nx >= 1 && ny >= 1, "cosine transform of an empty grid");
  const PlanPair p = PlansFor(nx, ny);
  synth_plan_ = p.synth;
  analyze_plan_ = p.analyze;
}

CosineTransform2D::~CosineTransform2D() = default;

AlignedFloats CosineTransform2D::NewBuffer() const {
  return AlignedFloats(static_cast<std::size_t>(nx_) * ny_);
}

void CosineTransform2D::HalveForRedft01(const float* coefficients, int rows,
                                        float* scratch) const {
  // REDFT01: y_i = x_0 + 2 sum_{a>0} x_a cos(pi a (i+1/2)/n), so the a > 0
  // (and b > 0) coefficients are halved first.
  const std::size_t nx = nx_;
  for (int b = 0; b < rows; ++b) {
    const float* in = coefficients + b * nx;
    float* out = scratch + b * nx;
    const float row = b == 0 ? 1.0f : 0.5f;
    out[0] = row * in[0];
    const float rest = 0.5f * row;
    for (std::size_t a = 1; a < nx; ++a) out[a] = rest * in[a];
  }
}

void CosineTransform2D::Synthesize(const float* coefficients, float* samples,
                                   float* scratch) const {
  HalveForRedft01(coefficients, ny_, scratch);
  fftwf_execute_r2r(static_cast<fftwf_plan>(synth_plan_), scratch, samples);
}

void CosineTransform2D::SynthesizeRows(const float* coefficients, int rows,
                                       float* samples, float* scratch) const {
  rows = std::clamp(rows, 1, ny_);
  if (rows == ny_) return Synthesize(coefficients, samples, scratch);
  HalveForRedft01(coefficients, rows, scratch);
  const std::size_t nx = nx_;
  const RowPlans p = RowPlansFor(nx_, ny_, rows);
  fftwf_execute_r2r(p.rows, scratch, samples);
  std::fill(samples + rows * nx, samples + ny_ * nx, 0.0f);
  fftwf_execute_r2r(p.columns, samples, samples);
}

void CosineTransform2D::Analyze(const float* samples,
                                float* coefficients) const {
  // REDFT10: X_a = 2 sum_i x_i cos(pi a (i+1/2)/n); our basis has
  // sum_i C_a(i)^2 = n (a = 0) or n/2, so X_a/(2n) * (a ? 2 : 1) is the
  // coefficient; in 2-D the factors multiply.
  // Out-of-place r2r plans preserve their input (FFTW's default for every
  // kind but c2r), so the const_cast is safe.
  fftwf_execute_r2r(static_cast<fftwf_plan>(analyze_plan_),
                    const_cast<float*>(samples), coefficients);
  const std::size_t nx = nx_;
  const float base = 1.0f / (4.0f * nx_ * ny_);
  for (int b = 0; b < ny_; ++b) {
    float* c = coefficients + b * nx;
    const float row = base * (b == 0 ? 1.0f : 2.0f);
    c[0] *= row;
    const float rest = 2.0f * row;
    for (std::size_t a = 1; a < nx; ++a) c[a] *= rest;
  }
}

void CosineTransform2D::AnalyzeSparse1D(int n, int first, const float* values,
                                        int count, float* coefficients,
                                        int num) {
  if (num < 0 || num > n) num = n;
  // cos((a+1) t) = 2 cos(t) cos(a t) - cos((a-1) t): one cosine per sample.
  thread_local std::vector<double> acc;
  acc.assign(num, 0.0);
  const double w = M_PI / n;
  for (int k = 0; k < count; ++k) {
    const double v = values[k];
    if (v == 0) continue;
    const double t = w * (first + k + 0.5);
    const double two_c = 2 * std::cos(t);
    double prev = std::cos(t), cur = 1.0;  // cos(-t), cos(0)
    for (int a = 0; a < num; ++a) {
      acc[a] += v * cur;
      const double next = two_c * cur - prev;
      prev = cur;
      cur = next;
    }
  }
  for (int a = 0; a < num; ++a)
    coefficients[a] = static_cast<float>(acc[a] * (a == 0 ? 1.0 : 2.0) / n);
}

}  // namespace ripple::sim
