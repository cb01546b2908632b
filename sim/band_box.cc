#include "sim/band_box.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace ripple::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// y[0, n) += c * x[0, n)
__attribute__((target_clones("avx2", "default"))) void Axpy(
    int n, float c, const float* __restrict x, float* __restrict y) {
  for (int i = 0; i < n; ++i) y[i] += c * x[i];
}

__attribute__((target_clones("avx2", "default"))) float Dot(
    int n, const float* __restrict x, const float* __restrict y) {
  // Eight partial sums, so the loop vectorises without -ffast-math and the
  // result does not depend on the instruction set.
  float s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int k = 0; k < 8; ++k) s[k] += x[i + k] * y[i + k];
  for (int k = 0; i < n; ++i, ++k) s[k] += x[i] * y[i];
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

}  // namespace

void BandBoxTransform::Reset(int nx, int ny, int band_nx, int band_ny, int i0,
                             int i1, int j0, int j1) {
  nx_ = nx;
  ny_ = ny;
  na_ = band_nx;
  nb_ = band_ny;
  i0_ = i0;
  j0_ = j0;
  width_ = std::max(0, i1 - i0);
  height_ = std::max(0, j1 - j0);
  cx_.assign(static_cast<std::size_t>(na_) * width_, 0.0f);
  cy_.assign(static_cast<std::size_t>(nb_) * height_, 0.0f);
  for (int a = 0; a < na_; ++a)
    for (int i = 0; i < width_; ++i)
      cx_[static_cast<std::size_t>(a) * width_ + i] =
          static_cast<float>(std::cos(kPi * a * (i0 + i + 0.5) / nx));
  for (int b = 0; b < nb_; ++b)
    for (int j = 0; j < height_; ++j)
      cy_[static_cast<std::size_t>(b) * height_ + j] =
          static_cast<float>(std::cos(kPi * b * (j0 + j + 0.5) / ny));
  rows_.assign(static_cast<std::size_t>(nb_) * width_, 0.0f);
}

void BandBoxTransform::Synthesize(const float* coefficients, float* values) {
  // rows[b][i] = sum_a F[b][a] cx[a][i]; values[j][i] = sum_b cy[b][j]
  // rows[b][i].
  std::fill(rows_.begin(), rows_.end(), 0.0f);
  for (int b = 0; b < nb_; ++b) {
    const float* f = coefficients + static_cast<std::size_t>(b) * nx_;
    float* row = rows_.data() + static_cast<std::size_t>(b) * width_;
    for (int a = 0; a < na_; ++a)
      if (f[a] != 0.0f)
        Axpy(width_, f[a], cx_.data() + static_cast<std::size_t>(a) * width_,
             row);
  }
  std::fill(values, values + static_cast<std::size_t>(width_) * height_, 0.0f);
  for (int j = 0; j < height_; ++j) {
    float* out = values + static_cast<std::size_t>(j) * width_;
    for (int b = 0; b < nb_; ++b)
      Axpy(width_, cy_[static_cast<std::size_t>(b) * height_ + j],
           rows_.data() + static_cast<std::size_t>(b) * width_, out);
  }
}

void BandBoxTransform::AddAnalysis(const float* values, float* coefficients) {
  // rows[b][i] = sum_j cy[b][j] values[j][i];
  // F[b][a] += s_ab sum_i rows[b][i] cx[a][i], s_ab = (a ? 2 : 1)(b ? 2 : 1)
  // / (nx ny), the normalisation of CosineTransform2D::Analyze.
  std::fill(rows_.begin(), rows_.end(), 0.0f);
  for (int b = 0; b < nb_; ++b) {
    float* row = rows_.data() + static_cast<std::size_t>(b) * width_;
    for (int j = 0; j < height_; ++j)
      Axpy(width_, cy_[static_cast<std::size_t>(b) * height_ + j],
           values + static_cast<std::size_t>(j) * width_, row);
  }
  const float base = 1.0f / (static_cast<float>(nx_) * ny_);
  for (int b = 0; b < nb_; ++b) {
    const float sb = base * (b == 0 ? 1.0f : 2.0f);
    const float* row = rows_.data() + static_cast<std::size_t>(b) * width_;
    float* f = coefficients + static_cast<std::size_t>(b) * nx_;
    for (int a = 0; a < na_; ++a)
      f[a] +=
          sb * (a == 0 ? 1.0f : 2.0f) *
          Dot(width_, row, cx_.data() + static_cast<std::size_t>(a) * width_);
  }
}

}  // namespace ripple::sim
