// Rigid transforms as a small value type, templated on the scalar so that
// Ceres Jets flow through (after Sophus' SE3): a unit quaternion and a
// translation. Naming: a variable called `a_from_b` maps a point expressed in
// frame b into frame a:
//   p_in_a = a_from_b * p_in_b.
// Rigid3Matrix (geometry/rigid3_matrix.h) is the same transform as plain
// numbers for layers without Eigen; ToMatrixForm / FromMatrixForm convert.
#ifndef RIPPLE_GEOMETRY_RIGID3_H_
#define RIPPLE_GEOMETRY_RIGID3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/rigid3_matrix.h"

namespace ripple::geometry {

template <typename T>
struct Rigid3 {
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Quat = Eigen::Quaternion<T>;

  Quat rotation = Quat::Identity();  // unit quaternion
  Vec3 translation = Vec3::Zero();   // metres

  Rigid3() = default;
  Rigid3(const Quat& q, const Vec3& t) : rotation(q), translation(t) {}

  static Rigid3 Identity() { return Rigid3(); }
  // From a rotation matrix (orthonormal, det +1) and a translation.
  static Rigid3 FromMatrix(const Eigen::Matrix<T, 3, 3>& r, const Vec3& t) {
    return Rigid3(Quat(r).normalized(), t);
  }
  // From an axis-angle vector (radians) and a translation.
  static Rigid3 FromAxisAngle(const Vec3& aa, const Vec3& t) {
    const T angle = aa.norm();
    if (angle < T(1e-12)) return Rigid3(Quat::Identity(), t);
    return Rigid3(Quat(Eigen::AngleAxis<T>(angle, aa / angle)), t);
  }

  Vec3 operator*(const Vec3& p) const { return rotation * p + translation; }
  Rigid3 operator*(const Rigid3& other) const {
    return Rigid3((rotation * other.rotation).normalized(),
                  rotation * other.translation + translation);
  }
  Rigid3 Inverse() const {
    const Quat inv = rotation.conjugate();
    return Rigid3(inv, -(inv * translation));
  }
  Eigen::Matrix<T, 3, 3> R() const { return rotation.toRotationMatrix(); }
  Eigen::Matrix<T, 4, 4> Matrix() const {
    Eigen::Matrix<T, 4, 4> m = Eigen::Matrix<T, 4, 4>::Identity();
    m.template topLeftCorner<3, 3>() = R();
    m.template topRightCorner<3, 1>() = translation;
    return m;
  }
  // Quaternion with w >= 0 (the canonical sign the pose CSV writes).
  Quat CanonicalRotation() const {
    return rotation.w() < T(0) ? Quat(-rotation.w(), -rotation.x(),
                                      -rotation.y(), -rotation.z())
                               : rotation;
  }
  template <typename U>
  Rigid3<U> Cast() const {
    return Rigid3<U>(rotation.template cast<U>(),
                     translation.template cast<U>());
  }
};

using Rigid3d = Rigid3<double>;

// Angle of the relative rotation between two poses, radians in [0, pi].
inline double RotationDistance(const Rigid3d& a, const Rigid3d& b) {
  return a.rotation.angularDistance(b.rotation);
}
// Distance between the translations, metres.
inline double TranslationDistance(const Rigid3d& a, const Rigid3d& b) {
  return (a.translation - b.translation).norm();
}

// The same transform as a row-major matrix and a translation.
template <typename T>
Rigid3Matrix<T> ToMatrixForm(const Rigid3<T>& a_from_b) {
  Rigid3Matrix<T> out;
  const Eigen::Matrix<T, 3, 3> r = a_from_b.R();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out.rotation[i * 3 + j] = r(i, j);
    out.translation[i] = a_from_b.translation[i];
  }
  return out;
}
// From a row-major rotation (orthonormal, det +1) and a translation.
template <typename T>
Rigid3<T> FromMatrixForm(const Rigid3Matrix<T>& a_from_b) {
  Eigen::Matrix<T, 3, 3> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = a_from_b.rotation[i * 3 + j];
  const Eigen::Matrix<T, 3, 1> t(a_from_b.translation[0],
                                 a_from_b.translation[1],
                                 a_from_b.translation[2]);
  return Rigid3<T>::FromMatrix(r, t);
}

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_RIGID3_H_
