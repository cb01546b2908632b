// Plain per-frame inputs of the renderer. Poses are 4x4 rigid transforms
// `a_from_b` (column-major glm, double). The camera frame is OpenCV's (x
// right, y down, z forward); the tank frame has its origin at the tank
// centre, z up, the floor at z = 0 (DESIGN.md). Lengths in metres.
#ifndef RIPPLE_RENDER_SCENE_H_
#define RIPPLE_RENDER_SCENE_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace ripple::render {

// A BGR8 camera image, top row first (cv::Mat CV_8UC3 layout). Not owned.
struct VideoFrame {
  const std::uint8_t* bgr = nullptr;
  int width = 0, height = 0;  // pixels
  int stride_bytes = 0;       // 0 means width * 3
};

// A view of the simulated water surface. Not owned; read during Render().
// heights[j * nx + i] is the displacement (metres, up positive) of the
// surface from the rest level at the centre of cell (i, j): i along tank x,
// j along tank y, cell centre at ((i + 0.5 - nx / 2) d, (j + 0.5 - ny / 2) d)
// for cell size d, so the field is centred on the tank origin.
struct HeightFieldView {
  const float* heights = nullptr;
  int nx = 0, ny = 0;
  float cell_size = 0;  // metres
  // Bumped by the simulation whenever `heights` changed; equal counters mean
  // an unchanged surface, so the renderer skips the upload and caustics.
  std::uint64_t change_counter = 0;
};

// Pixels of the output image (ideal pinhole, top row first) where the video
// shows something real in front of the board: 255 an occluder in front of
// the virtual tank (a hand, a sleeve: the water, the walls and the obstacles
// leave the video there), 128 the real pen's silhouette (its phantom decides
// what hides it); the water's refraction takes neither for the floor. Only
// the window (x, y, w, h) is read; the mask is taken as zero outside it. Not
// owned; read during Render(). Null: nothing real in front.
struct OccluderMaskView {
  const std::uint8_t* mask = nullptr;
  int width = 0, height = 0;  // the output's size
  int stride_bytes = 0;       // 0 means width
  glm::ivec4 window{0};       // x, y, w, h (pixels)
};

// The board with nothing on it (tracking's clean plate), in the tank frame:
// BGRA8 (alpha 255 where known), the video's encoding, relative to `gain`;
// the centre of texel (column i, row j) is the tank point corner_m +
// texel_m * (i + 0.5, j + 0.5). Where the video shows a real object over a
// board point the refraction looks for (the pen, a hand), the water takes
// the board from here. Not owned; uploaded when change_counter moves.
struct BoardPlateView {
  const std::uint8_t* bgra = nullptr;
  int width = 0, height = 0;
  int stride_bytes = 0;  // 0 means width * 4
  glm::dvec2 corner_m{0.0};
  double texel_m = 0;
  float gain = 1.0f;  // this frame's brightness over the plate's (encoded)
  std::uint64_t change_counter = 0;
};

// The virtual glass tank standing on the board.
struct TankGeometry {
  float size_x = 0.17f, size_y = 0.11f;  // inner size, metres
  float wall_height = 0.04f;             // metres above the floor (z = 0)
  float water_level = 0.025f;            // rest surface z, metres
};

// The real pen (DESIGN.md, rig file): a cube centred on the pen origin and a
// shaft cylinder along -z from the cube's -z face.
struct PenGeometry {
  float cube_edge = 0.03f;      // metres
  float shaft_radius = 0.005f;  // metres
  float shaft_length = 0.125f;  // metres
};

// A virtual obstacle standing in the tank, drawn and casting shadows.
struct Obstacle {
  enum class Shape { kBox, kCylinder };
  Shape shape = Shape::kCylinder;
  // Box: full extents in x, y, z. Cylinder: radius in x, height in z.
  glm::vec3 size{0.012f, 0.012f, 0.05f};
  // Obstacle frame: base centre at its origin, axis along +z.
  glm::dmat4 tank_from_obstacle{1.0};
};

// Toggles for the passes; all but tank_shadow and flat_water on by default.
struct Effects {
  bool reflection = true;
  bool refraction = true;
  bool walls = true;
  bool shadows = true;       // shadow map
  bool caustics = true;      // Nishita-Nakamae caustics map
  bool pen_occludes = true;  // pen phantom in depth
  // The tank's shadow and the sky it hides on the video's board around it
  // (pass_board_light.h). Off here; the commands turn it on for frames up
  // to 640 columns (TankShadowByDefault, renderer.h): above, the board
  // around the tank drawn and the clean plate's search twice the size cost
  // more than the webcam budget leaves.
  bool tank_shadow = false;
  // The real pen and occluders in the water's refraction: the submerged
  // shaft seen bent, floor points the video does not show read from the
  // clean plate (off: the floor is read from the video wherever it is).
  bool real_objects = true;
  // Debugging and registration checks: the water in one flat colour.
  bool flat_water = false;
};

struct SceneInputs {
  VideoFrame video;  // the camera image; null keeps the last one
  glm::dmat4 cam_from_tank{1.0};
  TankGeometry tank;
  HeightFieldView water;  // null heights: flat water at the rest level
  // The same surface on a coarser grid for the caustics map, whose cost
  // grows with the cell count (null heights: `water` itself). Its change
  // counter must move with water's.
  HeightFieldView caustics_water;
  bool pen_visible = false;
  glm::dmat4 tank_from_pen{1.0};
  PenGeometry pen;
  // How far the real pen may lie outside its tracked geometry in the
  // video (tracking error, blur), metres: the phantom that hides the water
  // and the test for pen pixels in the refraction are grown by this.
  float pen_margin_m = 0.001f;
  OccluderMaskView occluders;
  BoardPlateView plate;
  std::vector<Obstacle> obstacles;
  // Direction towards the (directional) light, tank frame; normalised inside.
  glm::dvec3 light_in_tank{0.35, 0.25, 1.0};
  Effects effects;
};

}  // namespace ripple::render

#endif  // RIPPLE_RENDER_SCENE_H_
