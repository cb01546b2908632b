#include "sim/transform.h"

#include <cmath>

namespace ripple::sim {

RigidTransform RigidTransform::FromQuaternion(double w, double x, double y,
                                              double z,
                                              const std::array<double, 3>& t) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  RigidTransform out;
  out.translation = t;
  if (!(n > 0) || !std::isfinite(n)) return out;
  w /= n;
  x /= n;
  y /= n;
  z /= n;
  out.rotation = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),
                  2 * (x * z + w * y),     2 * (x * y + w * z),
                  1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                  2 * (x * z - w * y),     2 * (y * z + w * x),
                  1 - 2 * (x * x + y * y)};
  return out;
}

RigidTransform RigidTransform::FromTranslation(double x, double y, double z) {
  RigidTransform out;
  out.translation = {x, y, z};
  return out;
}

std::array<double, 3> RigidTransform::Apply(
    const std::array<double, 3>& p) const {
  const auto& r = rotation;
  return {r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + translation[0],
          r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + translation[1],
          r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + translation[2]};
}

RigidTransform RigidTransform::Inverse() const {
  RigidTransform out;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) out.rotation[a * 3 + b] = rotation[b * 3 + a];
  for (int a = 0; a < 3; ++a) {
    out.translation[a] = -(out.rotation[a * 3 + 0] * translation[0] +
                           out.rotation[a * 3 + 1] * translation[1] +
                           out.rotation[a * 3 + 2] * translation[2]);
  }
  return out;
}

RigidTransform RigidTransform::operator*(const RigidTransform& o) const {
  RigidTransform out;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double s = 0;
      for (int c = 0; c < 3; ++c)
        s += rotation[a * 3 + c] * o.rotation[c * 3 + b];
      out.rotation[a * 3 + b] = s;
    }
  }
  out.translation = Apply(o.translation);
  return out;
}

bool RigidTransform::IsFinite() const {
  for (double v : rotation)
    if (!std::isfinite(v)) return false;
  for (double v : translation)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace ripple::sim
