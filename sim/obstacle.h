// Obstacles standing in the water: plain descriptions (no tracking types) and
// the occupancy test the simulation runs on every grid point.
//
// An obstacle blocks the water at a grid point when the point on the rest
// surface above the cell centre, (x_i, y_j, rest_level) in the tank frame,
// lies inside it after mapping into the obstacle frame. An obstacle that does
// not reach the rest surface (sunk, or hovering above it) blocks nothing.
#ifndef RIPPLE_SIM_OBSTACLE_H_
#define RIPPLE_SIM_OBSTACLE_H_

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/transform.h"

namespace ripple::sim {

// An occupancy volume (the paper's voxel grid). Voxel (a, b, c) is the cube
// [a, a+1) x [b, b+1) x [c, c+1) times voxel_size_m in the volume frame; the
// volume frame is the obstacle frame shifted so that the volume is centred on
// the obstacle origin in x and y and starts at z = 0 (it stands on its origin
// like the cylinder does):
//   x in [-nx/2, nx/2) * voxel_size_m, y likewise, z in [0, nz) * voxel_size_m.
//
// File format (".rvox", text, documented in docs/sim.md):
//   ripple-voxels 1
//   <nx> <ny> <nz>
//   <nx*ny*nz characters '0' or '1'; whitespace ignored; x fastest, then y,
//    then z; '#' starts a comment to the end of the line>
// The voxel size is not in the file: it comes from the rig (voxel_size).
struct VoxelVolume {
  int nx = 0, ny = 0, nz = 0;
  double voxel_size_m = 0;
  std::vector<std::uint8_t> occupied;  // nx*ny*nz, index a + nx*(b + ny*c)

  bool IsValid(std::string* error) const;
  bool At(int a, int b, int c) const {
    return occupied[static_cast<size_t>(a) +
                    static_cast<size_t>(nx) *
                        (static_cast<size_t>(b) + static_cast<size_t>(ny) * c)];
  }
};

// Reads a volume file; `voxel_size_m` comes from the caller. Returns false and
// one line naming the file in `error` on any problem.
bool LoadVoxelVolume(const std::string& path, double voxel_size_m,
                     VoxelVolume* volume, std::string* error);
bool SaveVoxelVolume(const VoxelVolume& volume, const std::string& path,
                     std::string* error);

struct Obstacle {
  enum class Shape { kBox, kCylinder, kVoxels };
  Shape shape = Shape::kBox;
  // Box: full size along obstacle x, y, z, centred on the origin (metres).
  std::array<double, 3> box_size_m = {0, 0, 0};
  // Cylinder: axis along obstacle z, from z = 0 to z = height_m (metres).
  double radius_m = 0;
  double height_m = 0;
  // Voxels: shared, immutable volume.
  std::shared_ptr<const VoxelVolume> voxels;
  // Pose of the obstacle in the tank frame; Water::SetObstaclePose moves it.
  RigidTransform tank_from_obstacle;

  bool IsValid(std::string* error) const;
  // Inside test for a point in the obstacle frame (metres).
  bool ContainsInObstacle(const std::array<double, 3>& p) const;
  // Inside test for a point in the tank frame.
  bool ContainsInTank(const std::array<double, 3>& p_in_tank) const;
  // Axis-aligned bounds of the shape in its own frame: {min, max}.
  std::array<std::array<double, 3>, 2> LocalBounds() const;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_OBSTACLE_H_
