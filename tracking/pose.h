// Rigid transforms as a small value type, templated on the scalar so that
// Ceres Jets flow through (after Sophus' SE3). Naming: a Pose variable called
// `a_from_b` maps a point expressed in frame b into frame a:
//   p_in_a = a_from_b * p_in_b.
#ifndef RIPPLE_TRACKING_POSE_H_
#define RIPPLE_TRACKING_POSE_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ripple::tracking {

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

using Pose = Rigid3<double>;

// Angle of the relative rotation between two poses, radians in [0, pi].
inline double RotationDistance(const Pose& a, const Pose& b) {
  return a.rotation.angularDistance(b.rotation);
}
// Distance between the translations, metres.
inline double TranslationDistance(const Pose& a, const Pose& b) {
  return (a.translation - b.translation).norm();
}

// Pose with the camera at `eye` looking at `target`; `up` is a rough up
// direction in the world. Returns world_from_cam in the OpenCV camera
// convention (x right, y down, z forward).
Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
            const Eigen::Vector3d& up);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_POSE_H_
