// A rigid transform as plain numbers, so that sim/ needs no maths library.
// Naming follows the project: `tank_from_obstacle` maps a point expressed in
// the obstacle frame into the tank frame: p_in_tank = R * p_in_obstacle + t.
#ifndef RIPPLE_SIM_TRANSFORM_H_
#define RIPPLE_SIM_TRANSFORM_H_

#include <array>

namespace ripple::sim {

struct RigidTransform {
  // Row-major 3x3 rotation (orthonormal, det +1) and translation in metres.
  std::array<double, 9> rotation = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> translation = {0, 0, 0};

  static RigidTransform Identity() { return RigidTransform(); }
  // From a unit quaternion (w, x, y, z; normalised here) and a translation.
  static RigidTransform FromQuaternion(double w, double x, double y, double z,
                                       const std::array<double, 3>& t);
  static RigidTransform FromTranslation(double x, double y, double z);

  std::array<double, 3> Apply(const std::array<double, 3>& p) const;
  RigidTransform Inverse() const;
  RigidTransform operator*(const RigidTransform& other) const;
  // True when every number is finite.
  bool IsFinite() const;

  bool operator==(const RigidTransform& o) const {
    return rotation == o.rotation && translation == o.translation;
  }
  bool operator!=(const RigidTransform& o) const { return !(*this == o); }
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_TRANSFORM_H_
