#include "render/camera.h"

namespace ripple::render {

glm::dmat4 ClipFromCam(const Intrinsics& k, double n, double f) {
  const double w = k.width, h = k.height;
  // glm is column-major: m[column][row].
  glm::dmat4 m(0.0);
  // x_clip = (2 fx / w) X + (2 (cx + 0.5) / w - 1) Z, so that
  // window x = (x_ndc + 1) w / 2 = fx X / Z + cx + 0.5.
  m[0][0] = 2.0 * k.fx / w;
  m[2][0] = 2.0 * (k.cx + 0.5) / w - 1.0;
  // Same for y: image rows grow downwards and so do our FBO rows.
  m[1][1] = 2.0 * k.fy / h;
  m[2][1] = 2.0 * (k.cy + 0.5) / h - 1.0;
  // z_ndc = -1 at Z = near, +1 at Z = far; w_clip = Z.
  m[2][2] = (f + n) / (f - n);
  m[3][2] = -2.0 * f * n / (f - n);
  m[2][3] = 1.0;
  return m;
}

glm::dvec2 WindowFromClip(const glm::dvec4& clip, int width, int height) {
  const double x_ndc = clip.x / clip.w, y_ndc = clip.y / clip.w;
  return {(x_ndc + 1.0) * 0.5 * width, (y_ndc + 1.0) * 0.5 * height};
}

glm::dvec2 DistortedPixel(const Intrinsics& k, double x, double y) {
  const Eigen::Vector2d uv = k.DistortNormalized(x, y);
  return {uv.x(), uv.y()};
}

}  // namespace ripple::render
