#include "sim/height_field.h"

namespace ripple::sim {

void ComputeGradients(const HeightFieldView& view, std::vector<float>* dzdx,
                      std::vector<float>* dzdy) {
  const int nx = view.nx, ny = view.ny;
  const size_t n = static_cast<size_t>(nx) * ny;
  dzdx->assign(n, 0.f);
  dzdy->assign(n, 0.f);
  if (view.empty() || nx < 1 || ny < 1) return;
  const float* h = view.heights;
  const std::uint8_t* w = view.water;
  auto wet = [&](size_t idx) { return w == nullptr || w[idx] != 0; };
  const float inv_d = static_cast<float>(1.0 / view.cell_m);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const size_t c = static_cast<size_t>(j) * nx + i;
      if (!wet(c)) continue;
      // Neighbours that are outside the tank or blocked do not count; a
      // one-sided difference (or zero) is used instead.
      const bool l = i > 0 && wet(c - 1), r = i + 1 < nx && wet(c + 1);
      const bool b = j > 0 && wet(c - nx), t = j + 1 < ny && wet(c + nx);
      const float hl = l ? h[c - 1] : h[c], hr = r ? h[c + 1] : h[c];
      const float hb = b ? h[c - nx] : h[c], ht = t ? h[c + nx] : h[c];
      const int sx = (l ? 1 : 0) + (r ? 1 : 0), sy = (b ? 1 : 0) + (t ? 1 : 0);
      (*dzdx)[c] = sx ? (hr - hl) * inv_d / sx : 0.f;
      (*dzdy)[c] = sy ? (ht - hb) * inv_d / sy : 0.f;
    }
  }
}

}  // namespace ripple::sim
