// The rig: everything physical the tracker, the simulation and the renderer
// need to know about the printed tank board, the pen cube and the obstacles.
// Files are versioned YAML (schema in README.md, "Rig file"); all lengths are
// metres and every pose is parent_from_child.
#ifndef RIPPLE_TRACKING_RIG_H_
#define RIPPLE_TRACKING_RIG_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "tracking/pose.h"

namespace ripple::tracking {

inline constexpr int kRigVersion = 1;
// Bounds on a rig's lengths, metres: a tabletop tank (what the simulation
// grid and the renderer's integer rasterisers are sized for). Sides, wall
// height, tag edges and obstacle sizes in [kMinTankSideM, kMaxTankSideM]
// (tags and obstacles: (0, kMaxTankSideM]); every position within
// kMaxRigReachM of its parent's origin.
inline constexpr double kMinTankSideM = 0.01;
inline constexpr double kMaxTankSideM = 10.0;
inline constexpr double kMaxRigReachM = 100.0;

// One square tag fixed to an object.
struct TagPlacement {
  int id = -1;
  double edge_m = 0;     // outer edge of the black square, metres
  Pose object_from_tag;  // tag frame: centre, x right, y down, z into tag

  // Corner k (0..3: top-left, top-right, bottom-right, bottom-left of the tag
  // image as the family draws it) in the object frame.
  Eigen::Vector3d CornerInObject(int k) const;
};

// Viewing angle cosine of a tag: 1 when it faces the camera squarely, <= 0
// when seen edge-on or from behind.
double FacingCosine(const Pose& cam_from_object, const Pose& object_from_tag);

struct TankSpec {
  double size_x_m = 0;       // inner size along tank x (the long side)
  double size_y_m = 0;       // inner size along tank y
  double wall_height_m = 0;  // floor (z = 0) to the top of the walls
  double water_level_m = 0;  // rest level of the water above the floor
};

struct PenSpec {
  double cube_edge_m = 0;           // edge of the cube the faces are glued on
  std::vector<TagPlacement> faces;  // object = pen frame (cube centre)
  Eigen::Vector3d tip_in_pen = Eigen::Vector3d::Zero();
  double shaft_radius_m = 0;  // the shaft runs from the cube to the tip
  double shaft_length_m = 0;
};

struct ObstacleSpec {
  enum class Shape { kBox, kCylinder, kVoxels };
  Shape shape = Shape::kBox;
  std::string name;
  // Parent frame: the tank (attached_tag < 0) or a tag of the tank board.
  int attached_tag = -1;
  Pose parent_from_obstacle;
  // Box: full size along obstacle x, y, z; centred on the origin.
  Eigen::Vector3d box_size_m = Eigen::Vector3d::Zero();
  // Cylinder: axis along obstacle z, from z = 0 to z = height.
  double radius_m = 0;
  double height_m = 0;
  // Voxels: an occupancy volume file (path relative to the rig file is
  // resolved at load time) and its voxel edge.
  std::string voxel_file;
  double voxel_size_m = 0;
};

struct Rig {
  int version = kRigVersion;
  std::string family = "tag36h11";
  std::vector<TagPlacement> tank_tags;  // object = tank frame
  TankSpec tank;
  std::optional<PenSpec> pen;  // absent for a board-only rig
  std::vector<ObstacleSpec> obstacles;

  const TagPlacement* FindTankTag(int id) const;
  const TagPlacement* FindPenFace(int id) const;
  // Checks sizes, duplicate ids (across tank and pen) and the family.
  bool IsValid(std::string* error) const;
};

// Tag families the tracker supports (libapriltag's).
bool IsKnownTagFamily(const std::string& family);

// Loads and validates a rig file. Returns nullopt and fills `error` with one
// line naming the file and the field on any problem.
std::optional<Rig> LoadRig(const std::string& path, std::string* error);
bool SaveRig(const Rig& rig, const std::string& path, std::string* error);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_RIG_H_
