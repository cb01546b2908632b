// The rig's obstacles converted for the water (sim) and the renderer, so
// that `ripple sim` and the AR pipeline read a rig the same way.
#ifndef RIPPLE_APP_APP_OBSTACLES_H_
#define RIPPLE_APP_APP_OBSTACLES_H_

#include <optional>
#include <string>
#include <vector>

#include "render/scene.h"
#include "sim/obstacle.h"
#include "tracking/rig.h"

namespace ripple::app {

sim::RigidTransform ToSim(const tracking::Pose& pose);
glm::dmat4 ToGlm(const tracking::Pose& pose);

// tank_from_obstacle for an obstacle in the tank frame or on a board tag;
// nullopt if its tag is not on the board.
std::optional<tracking::Pose> TankFromObstacle(
    const tracking::Rig& rig, const tracking::ObstacleSpec& spec);

// The rig's obstacles as sim obstacles (voxel files loaded), in rig order.
// False with `error` naming the obstacle.
bool SimObstaclesFromRig(const tracking::Rig& rig,
                         std::vector<sim::Obstacle>* out, std::string* error);

// The rig's obstacles as drawn obstacles, parallel to rig.obstacles: boxes
// and cylinders; nullopt for voxel volumes (they shape the water but are
// not drawn) and for a tag that is not on the board.
std::vector<std::optional<render::Obstacle>> RenderObstaclesFromRig(
    const tracking::Rig& rig);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_OBSTACLES_H_
