// The canonical scenes of `ripple bench render`: the rig's tank under a
// stated light, seen by a stated camera, with a stated water surface, floor,
// pen and obstacles, as the physically based reference takes them
// (render/reference/reference.h). The real-time renderer gets the same
// SceneInputs and, as its video, the reference's dry render through the
// lens.
#ifndef RIPPLE_APP_APP_RENDER_SCENES_H_
#define RIPPLE_APP_APP_RENDER_SCENES_H_

#include <memory>
#include <string>
#include <vector>

#include "render/reference/reference.h"
#include "tracking/camera.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"

namespace ripple::app {

struct RenderBenchScene {
  std::string name;         // file-name safe
  std::string description;  // one line
  reference::ReferenceScene scene;
  // The printed floor inside the tank (plain or tiles): with the rig's
  // board, the design the pipeline gives its clean plate.
  synth::FloorPattern floor;
  // Storage behind scene.scene.water (nx * ny floats, metres).
  std::shared_ptr<std::vector<float>> heights;
};

// The scenes' names, in the order MakeRenderScenes builds them.
const std::vector<std::string>& RenderSceneNames();

struct RenderScenesOptions {
  int width = 640, height = 480;  // pixels
  // Board albedo texels per metre (0.25 mm texels by default).
  double board_px_per_m = 4000;
};

// Builds every canonical scene for `camera` (its intrinsics, scaled to the
// options' size; distortion is dropped except in the lens scene) and `rig`
// (tank, pen, obstacles, board tags): flat, ring (0.4 mm, 8 mm), three
// frames of the demo's water (the demo script driving the default water
// model), tiled floor, shadowed pen, grazing view, distorting lens, the
// demo's water in a room whose walls the water reflects. False
// with `error` on a rig without a tank or pen, or a failing water model.
bool MakeRenderScenes(const RenderScenesOptions& options,
                      const tracking::Camera& camera, const tracking::Rig& rig,
                      std::vector<RenderBenchScene>* scenes,
                      std::string* error);

// Pixels (CV_8U, 255) whose ideal-pinhole ray meets the water's rest plane
// inside the tank (`water`: where FLIP is averaged), and those of them whose
// ray does not pass through a glass wall on its way (`open_water`: the water
// seen over the walls, without the glass's own refraction and reflections).
void WaterMasks(const reference::ReferenceScene& scene, cv::Mat* water,
                cv::Mat* open_water);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_RENDER_SCENES_H_
