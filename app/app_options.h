// Command-line options shared by the pipeline commands (live, replay): GL
// backend, water and effects settings, with their units in the help text.
#ifndef RIPPLE_APP_APP_OPTIONS_H_
#define RIPPLE_APP_APP_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <cmath>
#include <opencv2/core.hpp>
#include <string>

#include "app/app_pipeline.h"
#include "app/app_smoothing.h"
#include "app/app_water.h"
#include "tracking/rig.h"

namespace ripple::app {

struct PipelineArgs {
  std::string gl;  // empty: the command's default
  PipelineOptions options;
  WaterArgs water;
  bool no_caustics = false, no_shadows = false, no_reflection = false,
       no_refraction = false;
  // --tank-shadow auto | on | off (a bare --tank-shadow: on)
  std::string tank_shadow = "auto";
  // Optics (render/optics.h); NaN: the look's default.
  std::string water_look = "clear";
  double ambient = std::nan("");         // sky's share of the light, [0, 1]
  double light_size_deg = std::nan("");  // angular radius of the light
  std::string floor;           // --floor: the printed tank floor (app_floor.h)
  std::string light = "auto";  // --light auto | AZ,EL (degrees)
  bool no_occluders = false;
  bool no_overlap = false;  // PipelineOptions::overlap_tracking off
  bool full_frame = false;  // RendererOptions::full_frame_output
  // --water-columns auto | full | N (RendererOptions::water_shading_columns)
  std::string water_columns = "auto";
  // --sun LAT,LON,DATETIME: the light from the sun's position (app_sun.h);
  // --north: the bearing of the board's +y, degrees clockwise from north.
  std::string sun;
  double north_deg = 0;
  double turbidity = 3;             // --turbidity: the sky model's, with --sun
  std::string reflection = "fold";  // --reflection fold | cubemap
  std::string shadows = "pcf";      // --shadows pcf | gauss | hard
  double shadow_sigma_texels = std::nan("");  // --shadow-sigma; NaN: default
  std::string refraction_filter = "cubic";    // --refraction-filter
  SmoothingArgs smoothing;  // --smoothing and the filters' cut-offs
};

// --tank-shadow: auto (the camera's width decides, render::
// TankShadowByDefault), on (also given bare) or off; false if `text` is
// none of these.
bool ParseTankShadow(const std::string& text, bool* by_resolution, bool* on);

// --water-columns: auto (render::kWaterColumnsAuto), full or 0 (every
// pixel), or 64..16384 (RendererOptions::water_shading_columns); false if
// `text` is none of these.
bool ParseWaterColumns(const std::string& text, int* columns);
CLI::Validator WaterColumnsValidator();

// Adds --gl, the water's options (app_water.h), --no-caustics, ... to `sub`.
void AddPipelineOptions(CLI::App* sub, PipelineArgs* args);

// Resolves the backend and toggles into args->options; false with `error`.
bool FinishPipelineOptions(PipelineArgs* args, const std::string& default_gl,
                           std::string* error);

// --light AZ,EL (degrees: azimuth from the tank's +x towards +y, elevation
// above the board) as a unit vector towards the light; false with `error`
// naming the option for anything else.
bool ParseLightDirection(const std::string& text, Eigen::Vector3d* light,
                         std::string* error);

// The printed board's floor (--floor) for the clean plate's prior, into
// args->options.board_floor; false after printing the one line (the caller
// exits with kExitBadInput).
bool SetBoardFloor(PipelineArgs* args, const tracking::Rig& rig);

// Checks a frame size against the calibration. Same size: ok. Same aspect
// ratio: the intrinsics are scaled, with a warning on stderr. Otherwise
// false with a message naming both sizes.
bool MatchCameraToFrames(cv::Size frames, const std::string& camera_path,
                         tracking::Camera* camera, std::string* error);

// A one-line progress bar on stderr: "[=====>    ] 45/99 frames 31.2 fps".
void PrintProgress(int done, int total, double fps);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_OPTIONS_H_
