// The 2-D cosine transform pair that diagonalises the wave operator on a
// rectangular tank with reflecting (Neumann) walls, on cell-centred samples
// (sim/height_field.h): the surface is
//   h(i, j) = sum_{a < nx, b < ny} X[b*nx + a] * C_a(i, nx) * C_b(j, ny),
//   C_a(i, n) = cos(pi * a * (i + 1/2) / n)   (c_0 = 1),
// and each coefficient X_ab is one standing wave of wave number
//   k_ab = pi * sqrt((a / (nx*d))^2 + (b / (ny*d))^2).
// Synthesis is FFTW's REDFT01 (a DCT-III) along both axes after halving the
// a > 0 and b > 0 coefficients; analysis is REDFT10 (DCT-II) scaled by
// 1/(nx*ny). FFTW (libfftw3-dev) is used because fast cosine transforms of
// arbitrary sizes are what it was written for; plans are made once per size
// and shared (FFTW's planner is not thread-safe, execution is).
// The plans are deterministic, so a replay gives the same heights bit for
// bit.
#ifndef RIPPLE_SIM_COSINE_TRANSFORM_H_
#define RIPPLE_SIM_COSINE_TRANSFORM_H_

#include <cstddef>
#include <memory>
#include <vector>

namespace ripple::sim {

// Float buffers aligned as FFTW's plans expect.
class AlignedFloats {
 public:
  AlignedFloats() = default;
  explicit AlignedFloats(std::size_t n);
  AlignedFloats(AlignedFloats&& o) noexcept;
  AlignedFloats& operator=(AlignedFloats&& o) noexcept;
  AlignedFloats(const AlignedFloats&) = delete;
  AlignedFloats& operator=(const AlignedFloats&) = delete;
  ~AlignedFloats();

  float* data() { return data_; }
  const float* data() const { return data_; }
  std::size_t size() const { return size_; }
  float& operator[](std::size_t i) { return data_[i]; }
  float operator[](std::size_t i) const { return data_[i]; }
  void Fill(float v);

 private:
  float* data_ = nullptr;
  std::size_t size_ = 0;
};

class CosineTransform2D {
 public:
  // nx, ny >= 1. Plans (FFTW_ESTIMATE, deterministic) the first time a size
  // is seen.
  CosineTransform2D(int nx, int ny);
  ~CosineTransform2D();
  CosineTransform2D(const CosineTransform2D&) = delete;
  CosineTransform2D& operator=(const CosineTransform2D&) = delete;

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  // Buffers of nx*ny floats for the calls below.
  AlignedFloats NewBuffer() const;

  // Coefficients -> samples. `coefficients` is left untouched; `scratch` is a
  // buffer of nx*ny floats. in, out and scratch must not alias.
  void Synthesize(const float* coefficients, float* samples,
                  float* scratch) const;
  // The same for coefficients that are zero in every row b >= rows: x
  // transforms for those rows only, then the y transforms (~25% less work
  // for a third of the rows). `samples` and `scratch` are overwritten.
  void SynthesizeRows(const float* coefficients, int rows, float* samples,
                      float* scratch) const;
  // Samples -> coefficients (the exact inverse of Synthesize).
  void Analyze(const float* samples, float* coefficients) const;

  // The 1-D analysis of a sparse row: coefficients c[a], a < n, of the
  // samples v[k] at cells first..first+count-1 (others zero), such that
  // sum_a c[a] * C_a(i, n) reproduces them; only c[0, num) are computed
  // (num <= n; -1: all n). O(num * count).
  static void AnalyzeSparse1D(int n, int first, const float* values, int count,
                              float* coefficients, int num = -1);

 private:
  // Rows [0, rows) of the coefficients into scratch, scaled to FFTW's
  // REDFT01 convention.
  void HalveForRedft01(const float* coefficients, int rows,
                       float* scratch) const;

  int nx_, ny_;
  void* synth_plan_ = nullptr;  // fftwf_plan
  void* analyze_plan_ = nullptr;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_COSINE_TRANSFORM_H_
