#include "render/camera.h"

namespace ripple::render {

bool Intrinsics::HasDistortion() const {
  for (double d : dist) {
    if (d != 0.0) return true;
  }
  return false;
}

bool Intrinsics::IsValid(std::string* error) const {
  if (width <= 0 || height <= 0) {
    if (error) *error = "intrinsics: image size must be positive";
    return false;
  }
  if (!(fx > 0) || !(fy > 0)) {
    if (error) *error = "intrinsics: focal lengths must be positive";
    return false;
  }
  return true;
}

bool Intrinsics::operator==(const Intrinsics& o) const {
  return width == o.width && height == o.height && fx == o.fx && fy == o.fy &&
         cx == o.cx && cy == o.cy && dist == o.dist;
}

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
  const auto& d = k.dist;
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double radial = (1 + d[0] * r2 + d[1] * r4 + d[4] * r6) /
                        (1 + d[5] * r2 + d[6] * r4 + d[7] * r6);
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  return {k.fx * xd + k.cx, k.fy * yd + k.cy};
}

}  // namespace ripple::render
