#include "tracking/pose.h"

namespace ripple::tracking {

Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
            const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(up);
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = y;
  r.col(2) = z;
  return Pose::FromMatrix(r, eye);
}

}  // namespace ripple::tracking
