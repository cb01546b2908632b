// Scripted motion and imaging presets for synthetic sequences.
#include <cmath>
#include <optional>
#include <random>
#include <sstream>

#include "tracking/synth/synth.h"

namespace ripple::synth {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = M_PI / 180.0;

double Smooth(double t) { return t * t * (3 - 2 * t); }

struct Range {
  double lo, hi;
};

// The distributions of one preset (all uniform unless stated).
struct Preset {
  Range distance_m{0.3, 0.7};
  Range elevation_deg{40, 75};  // view direction above the board plane
  Range defocus_px{0, 0};
  Range motion_blur_px{0, 0};
  Range read_noise_dn{0, 0};
  double shot_noise_gain = 0;  // DN per electron
  Range jpeg_quality{0, 0};
  Range exposure{1, 1};
  double hand_fraction = 0;     // share of frames with a hand occluder
  bool hand_on_pen = false;     // a hand holds the pen's shaft
  bool hand_over_tank = false;  // a hand sweeps over the tank per segment
  bool scripted_demo = false;
  // Nothing moves within a segment (camera, pen, exposure and blur fixed):
  // only the noise differs from frame to frame.
  bool static_scene = false;
};

bool GetPreset(const std::string& name, Preset* p) {
  *p = Preset();
  if (name == "clean") return true;
  if (name == "benchmark") {
    p->defocus_px = {0.3, 1.2};
    p->motion_blur_px = {0, 3};
    p->read_noise_dn = {2, 4};
    p->shot_noise_gain = 0.1;
    p->jpeg_quality = {70, 95};
    p->exposure = {0.7, 1.1};
    p->hand_fraction = 0.25;
    return true;
  }
  if (name == "static") {
    // The benchmark's imaging without motion blur, held per segment.
    p->defocus_px = {0.3, 1.2};
    p->read_noise_dn = {2, 4};
    p->shot_noise_gain = 0.1;
    p->jpeg_quality = {70, 95};
    p->exposure = {0.7, 1.1};
    p->static_scene = true;
    return true;
  }
  if (name == "demo") {
    p->distance_m = {0.36, 0.36};
    p->elevation_deg = {55, 55};
    p->defocus_px = {0.5, 0.5};
    p->read_noise_dn = {2, 2};
    p->shot_noise_gain = 0.05;
    p->hand_on_pen = true;
    p->scripted_demo = true;
    return true;
  }
  if (name == "hands") {
    p->distance_m = {0.33, 0.5};
    p->elevation_deg = {45, 70};
    p->defocus_px = {0.4, 0.8};
    p->read_noise_dn = {1.5, 3};
    p->shot_noise_gain = 0.05;
    p->exposure = {0.85, 1.05};
    p->hand_on_pen = true;
    p->hand_over_tank = true;
    return true;
  }
  return false;
}

std::vector<Vector2d> HandOutline() {
  std::vector<Vector2d> o;
  for (int i = 0; i <= 12; ++i) {  // palm heel: an arc
    const double a = M_PI + M_PI * i / 12.0;
    o.emplace_back(0.042 * std::cos(a), -0.03 + 0.025 * std::sin(a));
  }
  const double xs[4] = {0.03, 0.01, -0.01, -0.03};
  const double len[4] = {0.055, 0.075, 0.07, 0.06};
  for (int f = 0; f < 4; ++f) {
    o.emplace_back(xs[f] + 0.009, 0.0);
    o.emplace_back(xs[f] + 0.008, len[f]);
    o.emplace_back(xs[f], len[f] + 0.008);
    o.emplace_back(xs[f] - 0.008, len[f]);
    o.emplace_back(xs[f] - 0.009, 0.0);
  }
  return o;
}

// A fist around the pen's shaft with the forearm leaving to the side, in its
// own plane: the shaft at x = -0.02, the forearm along +x (metres).
std::vector<Vector2d> FistOutline() {
  std::vector<Vector2d> o;
  for (int i = 0; i <= 16; ++i) {
    const double a = (60.0 + 240.0 * i / 16.0) * kDeg;
    o.emplace_back(0.026 * std::cos(a), 0.021 * std::sin(a));
  }
  o.emplace_back(0.14, -0.03);
  o.emplace_back(0.14, 0.028);
  return o;
}

// A hand holding the pen at `grip_in_tank` (on the shaft), facing the camera
// at `eye_in_tank`, the forearm leaving towards +x of the tank.
Occluder HandOnPen(const Pose& cam_from_tank, const Vector3d& eye_in_tank,
                   const Vector3d& grip_in_tank, const Vector3d& axis_in_tank) {
  const Vector3d view = (grip_in_tank - eye_in_tank).normalized();
  Vector3d side = axis_in_tank.cross(view).normalized();
  if (side.x() < 0) side = -side;
  const Vector3d up = view.cross(side).normalized();
  Eigen::Matrix3d r;
  r << side, up, side.cross(up);
  // The fist sits just in front of the shaft, its centre 20 mm to the side.
  const Vector3d centre = grip_in_tank + 0.02 * side - 0.012 * view;
  Occluder o;
  o.cam_from_occluder = cam_from_tank * Pose::FromMatrix(r, centre);
  o.outline_m = FistOutline();
  return o;
}

Pose PenPose(const tracking::Rig& rig, const Vector3d& tip_in_tank, double tilt,
             double tilt_azimuth, double spin) {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(tilt_azimuth, Vector3d::UnitZ()) *
       Eigen::AngleAxisd(tilt, Vector3d::UnitY()) *
       Eigen::AngleAxisd(spin, Vector3d::UnitZ()))
          .toRotationMatrix();
  const Vector3d tip_in_pen =
      rig.pen ? rig.pen->tip_in_pen : Vector3d(0, 0, -0.14);
  return Pose::FromMatrix(r, tip_in_tank - r * tip_in_pen);
}

}  // namespace

std::string DescribePreset(const std::string& name) {
  Preset p;
  if (!GetPreset(name, &p)) return "unknown preset '" + name + "'";
  std::ostringstream s;
  s << "preset " << name << " (uniform distributions):\n"
    << "  camera distance " << p.distance_m.lo << "-" << p.distance_m.hi
    << " m, elevation " << p.elevation_deg.lo << "-" << p.elevation_deg.hi
    << " deg, azimuth 0-360 deg, roll +-10 deg; within a segment it drifts by"
       " +-15 deg azimuth, +-5 deg elevation, +-8% distance\n"
    << "  pen: tilt 10-40 deg, spin 0-360 deg (+-90 deg per segment), tip "
       "dipping from 20 mm above the water to 8 mm above the floor\n"
    << "  defocus sigma " << p.defocus_px.lo << "-" << p.defocus_px.hi
    << " px; motion blur " << p.motion_blur_px.lo << "-" << p.motion_blur_px.hi
    << " px at a uniform angle\n"
    << "  read noise " << p.read_noise_dn.lo << "-" << p.read_noise_dn.hi
    << " DN; shot noise variance " << p.shot_noise_gain << " x signal (DN)\n"
    << "  JPEG quality "
    << (p.jpeg_quality.hi > 0 ? std::to_string(int(p.jpeg_quality.lo)) + "-" +
                                    std::to_string(int(p.jpeg_quality.hi))
                              : std::string("off"))
    << "; exposure " << p.exposure.lo << "-" << p.exposure.hi
    << " per segment\n"
    << "  hand occluder in " << int(100 * p.hand_fraction)
    << "% of frames (half of a random half of the segments)\n";
  if (p.hand_on_pen) s << "  a hand holds the pen's shaft below the cube\n";
  if (p.hand_over_tank)
    s << "  a hand sweeps across the tank, 40-90 mm above the board, over "
         "the middle half of each segment\n";
  if (p.static_scene)
    s << "  static: per segment one camera, pen, exposure, defocus and JPEG "
         "quality; only the noise changes between frames\n";
  if (p.scripted_demo)
    s << "  demo script: fixed camera, the pen dips in, stirs slowly, "
         "strokes fast under the obstacle and lifts out\n";
  return s.str();
}

bool MakeSequence(const tracking::Camera& camera, const tracking::Rig& rig,
                  const SequenceOptions& options,
                  std::vector<FrameSpec>* frames, std::string* error) {
  Preset preset;
  if (!GetPreset(options.preset, &preset)) {
    if (error)
      *error = "unknown preset '" + options.preset +
               "' (benchmark, clean, demo, hands, static)";
    return false;
  }
  if (options.frames < 1 || options.segment_frames < 1 || !(options.fps > 0)) {
    if (error) *error = "frames, segment length and fps must be positive";
    return false;
  }
  frames->clear();
  std::mt19937_64 rng(options.seed);
  // The hands' own draws, so that adding them leaves the other presets'
  // sequences as they were.
  std::mt19937_64 hand_rng(options.seed ^ 0x68616e6473ull);
  auto hand01 = [&]() {
    return std::uniform_real_distribution<double>(0, 1)(hand_rng);
  };
  // The light's own draws, likewise.
  std::mt19937_64 light_rng(options.seed ^ 0x6c69676874ull);
  auto light01 = [&]() {
    return std::uniform_real_distribution<double>(0, 1)(light_rng);
  };
  auto uni = [&](Range r) {
    return std::uniform_real_distribution<double>(r.lo, r.hi)(rng);
  };
  auto u01 = [&]() {
    return std::uniform_real_distribution<double>(0, 1)(rng);
  };
  const double level = rig.tank.water_level_m;
  const double hx = 0.5 * rig.tank.size_x_m - 0.015,
               hy = 0.5 * rig.tank.size_y_m - 0.015;
  const int seg_len =
      preset.scripted_demo ? options.frames : options.segment_frames;

  for (int start = 0; start < options.frames; start += seg_len) {
    const int n = std::min(seg_len, options.frames - start);
    // Segment parameters.
    const double dist0 = uni(preset.distance_m),
                 dist1 = dist0 * (1 + 0.08 * (2 * u01() - 1));
    const double elev0 = uni(preset.elevation_deg) * kDeg;
    const double elev1 =
        preset.scripted_demo ? elev0 : elev0 + 5 * kDeg * (2 * u01() - 1);
    const double az0 = preset.scripted_demo ? -90 * kDeg : 2 * M_PI * u01();
    const double az1 =
        preset.scripted_demo ? az0 : az0 + 15 * kDeg * (2 * u01() - 1);
    const double roll =
        preset.scripted_demo ? 0.0 : 10 * kDeg * (2 * u01() - 1);
    const Vector2d a(hx * (2 * u01() - 1), hy * (2 * u01() - 1));
    const Vector2d b(hx * (2 * u01() - 1), hy * (2 * u01() - 1));
    // Aim between the board and the pen cube so both stay in view.
    const Vector2d mid = 0.25 * (a + b);
    const Vector3d target0(mid.x() + 0.02 * (2 * u01() - 1),
                           mid.y() + 0.02 * (2 * u01() - 1), 0.09);
    const Vector3d target1 =
        target0 + Vector3d(0.01 * (2 * u01() - 1), 0.01 * (2 * u01() - 1), 0);
    const int dips = 1 + int(u01() * 2);
    const double tilt = (10 + 30 * u01()) * kDeg;
    const double tilt_az = 2 * M_PI * u01();
    const double spin0 = 2 * M_PI * u01(),
                 spin1 = spin0 + 90 * kDeg * (2 * u01() - 1);
    const double exposure = uni(preset.exposure);
    const bool hand = u01() < 2 * preset.hand_fraction;
    const int hand_start = start + int(u01() * n / 2),
              hand_end = hand_start + n / 2;
    const Vector2d hand_target(0.12 * (2 * u01() - 1), 0.08 * (2 * u01() - 1));
    const double hand_frac = 0.45 + 0.3 * u01(), hand_rot = 2 * M_PI * u01();
    // A hand sweeping over the tank: from one side to the other at 40-90 mm
    // above the board, over the middle half of the segment.
    const double sweep_height = 0.04 + 0.05 * hand01();
    const double sweep_y = 0.6 * hy * (2 * hand01() - 1);
    const double sweep_rot = (hand01() - 0.5) * 60 * kDeg;
    const double sweep_dir = hand01() < 0.5 ? -1.0 : 1.0;
    // A fixed room light for the segment.
    std::optional<Vector3d> light;
    double ambient_share = 0;
    if (options.directional_light) {
      const double light_az = 2 * M_PI * light01();
      const double light_elev = (30 + 45 * light01()) * kDeg;
      light = Vector3d(std::cos(light_elev) * std::cos(light_az),
                       std::cos(light_elev) * std::sin(light_az),
                       std::sin(light_elev));
      ambient_share = 0.25 + 0.25 * light01();
    }

    // A static segment's imaging, drawn once (only for it, so that the other
    // presets' sequences stay as they were).
    const bool still = preset.static_scene;
    const double static_defocus = still ? uni(preset.defocus_px) : 0.0;
    const double static_read = still ? uni(preset.read_noise_dn) : 0.0;
    const int static_jpeg =
        still ? int(std::round(uni(preset.jpeg_quality))) : 0;
    for (int i = 0; i < n; ++i) {
      const double t = preset.static_scene ? 0.0
                       : n > 1             ? double(i) / (n - 1)
                                           : 0.0;
      const double s = Smooth(t);
      FrameSpec f;
      f.index = start + i;
      f.time_s = f.index / options.fps;
      // Camera: orbit around the target.
      const double dist = dist0 + (dist1 - dist0) * s;
      const double elev = elev0 + (elev1 - elev0) * s,
                   az = az0 + (az1 - az0) * s;
      const Vector3d target = target0 + (target1 - target0) * s;
      const Vector3d eye =
          target + dist * Vector3d(std::cos(elev) * std::cos(az),
                                   std::cos(elev) * std::sin(az),
                                   std::sin(elev));
      Pose tank_from_cam = tracking::LookAt(eye, target, Vector3d::UnitZ());
      tank_from_cam.rotation =
          tank_from_cam.rotation *
          Eigen::Quaterniond(Eigen::AngleAxisd(roll, Vector3d::UnitZ()));
      f.scene.cam_from_tank = tank_from_cam.Inverse();
      if (light) {
        f.scene.light_in_tank = light;
        f.scene.ambient_share = ambient_share;
      }
      // Pen.
      if (rig.pen) {
        Vector3d tip;
        double pen_tilt = tilt, pen_az = tilt_az,
               spin = spin0 + (spin1 - spin0) * s;
        if (preset.scripted_demo) {
          // The events users try, timed for the default 8 s (240 frames at
          // 30 fps; other lengths scale): dip in at the left (~0.07 m/s
          // down), a slow stir (two turns of 15 mm at ~0.08 m/s, below the
          // 0.23 m/s minimum phase speed of capillary-gravity waves), a
          // fast stroke to the right under the obstacle (110 mm in 0.4 s,
          // peaking near 0.4 m/s), waves left to ring, then a lift out.
          const double sec = 8.0 * t;
          auto ramp = [](double x, double a, double b) {
            return Smooth(std::clamp((x - a) / (b - a), 0.0, 1.0));
          };
          const Vector2d stir_centre(-0.045, -0.012);
          const double stir = 2 * M_PI * 2 * ramp(sec, 1.0, 4.2);
          const Vector2d on_circle =
              stir_centre + 0.015 * Vector2d(-std::cos(stir), -std::sin(stir));
          const Vector2d start = stir_centre + Vector2d(-0.015, 0.0);
          const Vector2d stroke_from(-0.05, -0.03), stroke_to(0.06, -0.03);
          Vector2d xy = sec < 1.0 ? start : on_circle;
          const double to_stroke = ramp(sec, 4.2, 4.6);
          xy = xy + (stroke_from - xy) * to_stroke;
          xy = xy + (stroke_to - stroke_from) * ramp(sec, 4.8, 5.2);
          const double down = ramp(sec, 0.0, 1.0) * (1 - ramp(sec, 6.6, 7.4));
          tip = Vector3d(xy.x(), xy.y(), level + 0.03 - 0.042 * down);
          pen_tilt = 20 * kDeg;
          pen_az = M_PI;
          spin = 30 * kDeg + 60 * kDeg * t;
        } else {
          const Vector2d xy = a + (b - a) * s;
          const double dip = std::pow(std::sin(M_PI * dips * t), 2);
          const double z_top = level + 0.02, z_bottom = 0.008;
          tip = Vector3d(xy.x(), xy.y(), z_top - (z_top - z_bottom) * dip);
        }
        f.scene.tank_from_pen = PenPose(rig, tip, pen_tilt, pen_az, spin);
        if (preset.hand_on_pen) {
          const Pose& tank_from_pen = *f.scene.tank_from_pen;
          const Vector3d top(0, 0, -0.5 * rig.pen->cube_edge_m);
          const Vector3d axis =
              tank_from_pen.R() * (top - rig.pen->tip_in_pen).normalized();
          const Vector3d grip = tank_from_pen * top - 0.035 * axis;
          f.scene.occluders.push_back(
              HandOnPen(f.scene.cam_from_tank, eye, grip, axis));
        }
      }
      if (preset.hand_over_tank && t > 0.25 && t < 0.75) {
        const double u = (t - 0.25) / 0.5;
        const Vector3d centre(sweep_dir * (1.6 * hx) * (u - 0.5), sweep_y,
                              sweep_height);
        // Palm down-ish, facing the camera enough to be seen.
        const Vector3d view = (centre - eye).normalized();
        Pose tank_from_hand =
            tracking::LookAt(centre, centre + view, Vector3d::UnitZ());
        tank_from_hand.rotation =
            tank_from_hand.rotation *
            Eigen::Quaterniond(Eigen::AngleAxisd(sweep_rot, Vector3d::UnitZ()));
        Occluder o;
        o.cam_from_occluder = f.scene.cam_from_tank * tank_from_hand;
        o.outline_m = HandOutline();
        o.bgr = cv::Vec3f(0.38f, 0.47f, 0.68f);
        f.scene.occluders.push_back(o);
      }
      // Hand occluder, between the camera and a point near the board edge.
      if (hand && f.index >= hand_start && f.index < hand_end) {
        const Vector3d board_pt(hand_target.x(), hand_target.y(), 0);
        const Vector3d p =
            eye + hand_frac * (board_pt - eye) +
            Vector3d(0.01 * std::sin(3 * t), 0.01 * std::cos(2 * t), 0);
        Pose tank_from_hand =
            tracking::LookAt(p, p + (board_pt - eye), Vector3d::UnitZ());
        tank_from_hand.rotation =
            tank_from_hand.rotation *
            Eigen::Quaterniond(Eigen::AngleAxisd(hand_rot, Vector3d::UnitZ()));
        Occluder o;
        o.cam_from_occluder = f.scene.cam_from_tank * tank_from_hand;
        o.outline_m = HandOutline();
        f.scene.occluders.push_back(o);
      }
      // Imaging.
      f.imaging.exposure = exposure * (1 + 0.03 * std::sin(2 * M_PI * t));
      f.imaging.defocus_sigma_px = uni(preset.defocus_px);
      f.imaging.motion_blur_px = uni(preset.motion_blur_px);
      f.imaging.motion_angle_rad = M_PI * u01();
      f.imaging.read_noise_dn = uni(preset.read_noise_dn);
      f.imaging.shot_noise_gain = preset.shot_noise_gain;
      f.imaging.jpeg_quality = int(std::round(uni(preset.jpeg_quality)));
      if (preset.static_scene) {
        f.imaging.exposure = exposure;
        f.imaging.defocus_sigma_px = static_defocus;
        f.imaging.motion_blur_px = 0;
        f.imaging.read_noise_dn = static_read;
        f.imaging.jpeg_quality = static_jpeg;
      }
      f.noise_seed = rng();
      frames->push_back(std::move(f));
    }
  }
  (void)camera;
  return true;
}

}  // namespace ripple::synth
