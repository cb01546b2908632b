// A rigid transform as plain numbers (row-major rotation matrix and
// translation), so that layers without a maths library (sim/) can hold and
// apply poses. The estimation form with a quaternion, Rigid3 in
// geometry/rigid3.h, converts to and from it.
//
// Naming follows the project: `tank_from_obstacle` maps a point expressed in
// the obstacle frame into the tank frame: p_in_tank = R * p_in_obstacle + t.
// Templated on the scalar (after Sophus) so that Ceres Jets can flow through.
#ifndef RIPPLE_GEOMETRY_RIGID3_MATRIX_H_
#define RIPPLE_GEOMETRY_RIGID3_MATRIX_H_

#include <array>
#include <cmath>

namespace ripple::geometry {

template <typename T>
struct Rigid3Matrix {
  using Vec3 = std::array<T, 3>;

  // Row-major 3x3 rotation (orthonormal, det +1) and translation in metres.
  std::array<T, 9> rotation = {T(1), T(0), T(0), T(0), T(1),
                               T(0), T(0), T(0), T(1)};
  Vec3 translation = {T(0), T(0), T(0)};

  static Rigid3Matrix Identity() { return Rigid3Matrix(); }
  // From a unit quaternion (w, x, y, z; normalised here) and a translation.
  // A zero or non-finite quaternion gives the identity rotation.
  static Rigid3Matrix FromQuaternion(T w, T x, T y, T z, const Vec3& t) {
    using std::isfinite;
    using std::sqrt;
    const T n = sqrt(w * w + x * x + y * y + z * z);
    Rigid3Matrix out;
    out.translation = t;
    if (!(n > T(0)) || !isfinite(n)) return out;
    w /= n;
    x /= n;
    y /= n;
    z /= n;
    out.rotation = {T(1) - T(2) * (y * y + z * z), T(2) * (x * y - w * z),
                    T(2) * (x * z + w * y),        T(2) * (x * y + w * z),
                    T(1) - T(2) * (x * x + z * z), T(2) * (y * z - w * x),
                    T(2) * (x * z - w * y),        T(2) * (y * z + w * x),
                    T(1) - T(2) * (x * x + y * y)};
    return out;
  }
  static Rigid3Matrix FromTranslation(T x, T y, T z) {
    Rigid3Matrix out;
    out.translation = {x, y, z};
    return out;
  }

  // target_from_source applied to p_in_source gives p_in_target.
  Vec3 Apply(const Vec3& p) const {
    const auto& r = rotation;
    return {r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + translation[0],
            r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + translation[1],
            r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + translation[2]};
  }
  // source_from_target (transposed rotation).
  Rigid3Matrix Inverse() const {
    Rigid3Matrix out;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) out.rotation[a * 3 + b] = rotation[b * 3 + a];
    for (int a = 0; a < 3; ++a) {
      out.translation[a] = -(out.rotation[a * 3 + 0] * translation[0] +
                             out.rotation[a * 3 + 1] * translation[1] +
                             out.rotation[a * 3 + 2] * translation[2]);
    }
    return out;
  }
  // a_from_b * b_from_c = a_from_c.
  Rigid3Matrix operator*(const Rigid3Matrix& o) const {
    Rigid3Matrix out;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        T s = T(0);
        for (int c = 0; c < 3; ++c)
          s += rotation[a * 3 + c] * o.rotation[c * 3 + b];
        out.rotation[a * 3 + b] = s;
      }
    }
    out.translation = Apply(o.translation);
    return out;
  }
  // True when every number is finite.
  bool IsFinite() const {
    using std::isfinite;
    for (const T& v : rotation)
      if (!isfinite(v)) return false;
    for (const T& v : translation)
      if (!isfinite(v)) return false;
    return true;
  }

  bool operator==(const Rigid3Matrix& o) const {
    return rotation == o.rotation && translation == o.translation;
  }
  bool operator!=(const Rigid3Matrix& o) const { return !(*this == o); }
};

using Rigid3dMatrix = Rigid3Matrix<double>;

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_RIGID3_MATRIX_H_
