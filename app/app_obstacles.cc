#include "app/app_obstacles.h"

namespace ripple::app {

sim::RigidTransform ToSim(const tracking::Pose& pose) {
  sim::RigidTransform t;
  const Eigen::Matrix3d r = pose.R();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) t.rotation[a * 3 + b] = r(a, b);
    t.translation[a] = pose.translation[a];
  }
  return t;
}

bool SimObstaclesFromRig(const tracking::Rig& rig,
                         std::vector<sim::Obstacle>* out, std::string* error) {
  for (const tracking::ObstacleSpec& spec : rig.obstacles) {
    const std::string name = spec.name.empty() ? "(unnamed)" : spec.name;
    sim::Obstacle o;
    const std::optional<tracking::Pose> tank_from_obstacle =
        TankFromObstacle(rig, spec);
    if (!tank_from_obstacle) {
      *error = "obstacle '" + name + "': tag " +
               std::to_string(spec.attached_tag) + " is not a tank tag";
      return false;
    }
    o.tank_from_obstacle = ToSim(*tank_from_obstacle);
    switch (spec.shape) {
      case tracking::ObstacleSpec::Shape::kBox:
        o.shape = sim::Obstacle::Shape::kBox;
        o.box_size_m = {spec.box_size_m.x(), spec.box_size_m.y(),
                        spec.box_size_m.z()};
        break;
      case tracking::ObstacleSpec::Shape::kCylinder:
        o.shape = sim::Obstacle::Shape::kCylinder;
        o.radius_m = spec.radius_m;
        o.height_m = spec.height_m;
        break;
      case tracking::ObstacleSpec::Shape::kVoxels: {
        o.shape = sim::Obstacle::Shape::kVoxels;
        auto volume = std::make_shared<sim::VoxelVolume>();
        if (!sim::LoadVoxelVolume(spec.voxel_file, spec.voxel_size_m,
                                  volume.get(), error))
          return false;
        o.voxels = volume;
        break;
      }
    }
    std::string why;
    if (!o.IsValid(&why)) {
      *error = "obstacle '" + name + "': " + why;
      return false;
    }
    out->push_back(std::move(o));
  }
  return true;
}

glm::dmat4 ToGlm(const tracking::Pose& pose) {
  const Eigen::Matrix4d m = pose.Matrix();
  glm::dmat4 g(1.0);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) g[c][r] = m(r, c);
  return g;
}

std::optional<tracking::Pose> TankFromObstacle(
    const tracking::Rig& rig, const tracking::ObstacleSpec& spec) {
  if (spec.attached_tag < 0) return spec.parent_from_obstacle;
  const tracking::TagPlacement* tag = rig.FindTankTag(spec.attached_tag);
  if (!tag) return std::nullopt;
  return tag->object_from_tag * spec.parent_from_obstacle;
}

std::vector<std::optional<render::Obstacle>> RenderObstaclesFromRig(
    const tracking::Rig& rig) {
  std::vector<std::optional<render::Obstacle>> out;
  for (const tracking::ObstacleSpec& spec : rig.obstacles) {
    const std::optional<tracking::Pose> tank_from_obstacle =
        TankFromObstacle(rig, spec);
    if (!tank_from_obstacle) {
      out.push_back(std::nullopt);
      continue;
    }
    render::Obstacle r;
    if (spec.shape == tracking::ObstacleSpec::Shape::kBox) {
      r.shape = render::Obstacle::Shape::kBox;
      r.size = glm::vec3(spec.box_size_m.x(), spec.box_size_m.y(),
                         spec.box_size_m.z());
      // The renderer's box stands on its origin; the rig's is centred.
      r.tank_from_obstacle = ToGlm(
          *tank_from_obstacle *
          tracking::Pose(Eigen::Quaterniond::Identity(),
                         Eigen::Vector3d(0, 0, -0.5 * spec.box_size_m.z())));
    } else if (spec.shape == tracking::ObstacleSpec::Shape::kCylinder) {
      r.shape = render::Obstacle::Shape::kCylinder;
      r.size = glm::vec3(spec.radius_m, spec.radius_m, spec.height_m);
      r.tank_from_obstacle = ToGlm(*tank_from_obstacle);
    } else {
      out.push_back(std::nullopt);
      continue;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace ripple::app
