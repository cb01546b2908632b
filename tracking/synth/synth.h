// Ground-truth frames: a CPU renderer of the tank board (paper, tags and the
// printed floor pattern of floor_pattern.h), the pen (cube with tagged faces
// and its shaft) and a hand-like occluder through the full
// camera model (lens distortion included), with area-correct edges, plus the
// imaging effects of a real webcam and scripted motion. Used by `ripple
// synth`, the tracking tests and benchmarks, and the demo.
#ifndef RIPPLE_TRACKING_SYNTH_SYNTH_H_
#define RIPPLE_TRACKING_SYNTH_SYNTH_H_

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"

namespace ripple::synth {

using tracking::Pose;

// A flat occluder standing in for a hand: a polygon (metres, in its own
// plane z = 0) at a pose in the camera frame, drawn in front of everything.
struct Occluder {
  Pose cam_from_occluder;
  std::vector<Eigen::Vector2d> outline_m;  // counter-clockwise polygon
  cv::Vec3f bgr{0.45f, 0.55f, 0.75f};      // linear 0..1
};

// What is in front of the camera in one frame.
struct SceneState {
  Pose cam_from_tank;
  std::optional<Pose> tank_from_pen;  // nullopt: no pen in the scene
  std::vector<Occluder> occluders;
  // Unit illumination everywhere (no spotlight, no face shading, no cast
  // shadow): lets tests compare pixels with exact coverage.
  bool flat_lighting = false;
  // A distant light (a lamp across the room, the sun through a window) that
  // makes the pen cast a shadow on the board; nullopt: no cast shadow, the
  // fixed shading alone. Unit, tank frame, from the board towards the light
  // (z > 0). Model, for the board's layers (paper, floor pattern, tags):
  //   radiance = albedo * spot * (ambient_share + (1 - ambient_share) * V),
  // with spot the fixed soft falloff the board has without the light and V
  // the visible share of the light's disc (1 lit, 0 in the umbra), from
  // rays to the pen's cube and shaft (the cylinder drawn: the shaft's
  // radius, flat ends at the tip and at the cube). The board is flat and the
  // light
  // distant, so the light's cosine is the same at every board point: it is
  // part of the lit level, not a shading term. The cube's faces are shaded
  // by their cosine to this light instead of the fixed direction; nothing
  // else casts shadows (hands do not).
  std::optional<Eigen::Vector3d> light_in_tank;
  // Share of the lit board's light that does not come from `light_in_tank`
  // (room ambient, sky): the umbra's brightness over the lit board's, 0..1.
  double ambient_share = 0.35;
  // Angular radius of the light's disc, radians (0.5 degrees: a lamp of
  // 2.6 cm at 1.5 m, about the sun's): the penumbra's width.
  double light_radius_rad = 0.0087;
};

// The defocus point-spread function's shape.
enum class DefocusKernel {
  kGaussian,  // sigma = defocus_sigma_px
  // A uniform disc (a thin lens' geometric blur) of radius
  // 2 * defocus_sigma_px, which has the same per-axis standard deviation;
  // its edge is anti-aliased by the disc's area in each kernel pixel.
  kDisc,
};

// Imaging applied after the geometric render, in this order:
// exposure gain, defocus, linear motion blur, shot + read noise,
// the sRGB transfer (when `srgb`), 8-bit quantisation, JPEG round trip.
struct ImagingOptions {
  double exposure = 1.0;          // multiplies the scene radiance
  double defocus_sigma_px = 0.0;  // PSF standard deviation per axis, pixels
  DefocusKernel defocus_kernel = DefocusKernel::kGaussian;
  double motion_blur_px = 0.0;    // length of the linear blur, pixels
  double motion_angle_rad = 0.0;  // direction of the blur
  double read_noise_dn = 0.0;     // Gaussian sigma, 8-bit digital numbers
  double shot_noise_gain = 0.0;   // DN per electron; 0 disables shot noise
  int jpeg_quality = 0;           // 1..100 round trip; 0 disables
  // Encode the (noisy, linear) signal with the sRGB transfer before
  // quantising, as a webcam's image processor does; false: 8-bit values
  // linear in radiance (the camera file then says `transfer: linear`).
  bool srgb = false;
};

struct RenderedFrame {
  cv::Mat image;               // CV_8UC3, BGR, the camera's size
  std::vector<int> tank_tags;  // ids whose whole black square is visible
  std::vector<int> pen_tags;
};

// How the geometric render forms a pixel's value from the scene.
enum class Formation {
  // Each pixel's pre-image on every layer clipped exactly against the tag
  // cells and the floor (exact area coverage; see the README).
  kExactArea,
  // A second, independent image formation: one ray per point of a regular
  // N x N grid inside each pixel (its centres at ((i + 0.5) / N - 0.5) px
  // from the pixel centre), undistorted by OpenCV's cv::undistortPoints, the
  // colour looked up at the ray's hit point (no area integration), polygons
  // filled by point sampling (cv::fillPoly), then the N x N samples
  // averaged (a box filter). Edges are staircases of 1/N^2 steps, not the
  // exact ramp.
  kPointSampled,
};

// Parses and names "exact" / "supersampled".
bool ParseFormation(const std::string& name, Formation* formation);
const char* FormationName(Formation formation);

struct FormationOptions {
  Formation formation = Formation::kExactArea;
  int samples_per_axis = 3;  // kPointSampled: N, 1..8
  // A cluttered table around the printed sheet (random dark and bright
  // patches of 4-40 mm and a wood-like grain) instead of the plain one.
  // kPointSampled only (the exact formation integrates piecewise-constant
  // rectangles and draws the plain table).
  bool busy_table = false;

  bool IsValid(std::string* error) const;
};

// Renders scenes for one camera and rig. Thread-compatible.
class SceneRenderer {
 public:
  // `floor` is drawn inside the tank outline (the default, plain paper, draws
  // nothing there). CHECKs formation.IsValid().
  SceneRenderer(const tracking::Camera& camera, const tracking::Rig& rig,
                FloorPattern floor = FloorPattern(),
                FormationOptions formation = FormationOptions());
  // Geometric render (no imaging effects) by the renderer's formation,
  // linear BGR in [0, 1], CV_32FC3.
  cv::Mat RenderLinear(const SceneState& scene) const;
  const FormationOptions& formation() const { return formation_; }
  // Full frame: exact render, imaging effects with noise drawn from `seed`.
  RenderedFrame Render(const SceneState& scene, const ImagingOptions& imaging,
                       uint64_t seed) const;
  // Tag ids of the board and of the pen whose full black square is inside
  // the image, facing the camera and unoccluded.
  void VisibleTags(const SceneState& scene, std::vector<int>* tank_tags,
                   std::vector<int>* pen_tags) const;
  // Ground truth of what stands in front of the board, per pixel of the
  // image as Render() draws it (lens distortion included): the share covered
  // by the occluders (`hands`) and by the pen where no occluder hides it
  // (`pen`), CV_32F in [0, 1], the camera's size.
  void OccluderCoverage(const SceneState& scene, cv::Mat* hands,
                        cv::Mat* pen) const;

 private:
  struct Impl;
  cv::Mat RenderExactArea(const SceneState& scene) const;
  cv::Mat RenderPointSampled(const SceneState& scene) const;
  tracking::Camera camera_;
  tracking::Rig rig_;
  FloorPattern floor_;
  FormationOptions formation_;
  std::shared_ptr<const Impl> impl_;
};

// Scripted motion and imaging: smooth segments of `segment_frames` frames
// joined by cuts, the camera at `distance_m` from the board, the pen dipping
// in and out of the water.
struct SequenceOptions {
  std::string preset = "benchmark";  // "benchmark", "clean" or "demo"
  int frames = 100;
  int segment_frames = 50;
  double fps = 30.0;
  uint64_t seed = 1;
  // Adds SceneState::light_in_tank: per segment a fixed light at azimuth
  // 0-360 degrees and elevation 30-75 degrees, ambient share 0.25-0.5
  // (uniform; drawn from their own generator, so the rest of the sequence
  // is the same with or without it).
  bool directional_light = false;
};

struct FrameSpec {
  int index = 0;
  double time_s = 0;
  SceneState scene;
  ImagingOptions imaging;
  uint64_t noise_seed = 0;
};

// Fills `frames`; false with `error` for an unknown preset or bad counts.
bool MakeSequence(const tracking::Camera& camera, const tracking::Rig& rig,
                  const SequenceOptions& options,
                  std::vector<FrameSpec>* frames, std::string* error);

// Human-readable statement of a preset's distributions (printed by
// `ripple synth --help-presets` and quoted in the README).
std::string DescribePreset(const std::string& preset);

}  // namespace ripple::synth

#endif  // RIPPLE_TRACKING_SYNTH_SYNTH_H_
