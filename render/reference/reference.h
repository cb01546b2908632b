// Ripple's offline reference renderer: a physically based, CPU-only,
// deterministic rendering of the scene the real-time renderer (render/)
// draws, to measure that renderer against (FLIP). It shares only the plain
// scene description (render/scene.h) and the camera model
// (geometry/camera_model.h) with it; no GL.
//
// Frames and units: the tank frame (origin at the tank centre, z up, the
// board and tank floor at z = 0), the camera frame is OpenCV's; metres,
// radians, pixels in OpenCV's convention (integer coordinates are pixel
// centres). Colours are linear BGR triples, one value per camera band.
//
// Radiometry (the display units the real-time renderer is matched to):
//   - A dry, unshadowed, horizontal board point of albedo rho has radiance
//     exactly rho.
//   - The light is a distant disc of angular radius alpha centred on the
//     unit direction l = normalize(light_in_tank) (l.z > sin alpha), plus a
//     uniform sky over the upper hemisphere. With ambient share a:
//       sky radiance           La = a,
//       disc irradiance        Ed = (1 - a) pi / l.z   (on a plane normal to
//       l), disc radiance          Ld = Ed / (pi sin^2 alpha),
//     exact for a uniform disc: a plane with normal n that sees all of the
//     disc receives Ld * integral of dot(n, w) over the disc = Ed dot(n, l),
//     so the dry board gets Ed l.z + pi La = pi and has radiance rho.
//   - Radiance across a dielectric interface obeys L / n^2 invariance:
//     L_t = T (n_t / n_i)^2 L_i. The floor under water, a Lambertian
//     reflector of the irradiance it receives in the water, is therefore
//     seen from the air dimmed by T / n_w^2 ~ 0.55, and the light it sends
//     back up is partly returned to it by Fresnel and total internal
//     reflection at the surface (beyond 48.6 degrees from the vertical in
//     water): Lekner & Dorf, "Why some things are darker when wet", Applied
//     Optics 27 (1988). Both are traced
//     (ReferenceOptions::max_diffuse_bounces).
//   - A pixel of the floor under water also holds the sky's mirror image on
//     the surface, R La (R = 0.0204 at normal incidence): compare an
//     analytic floor term with the pixel less R La.
//
// What is modelled: exact ray intersection with the water surface (see
// surface.h for its interpolant), the four glass walls (slabs of
// glass_thickness_m outside the inner size, wall_height tall, standing on
// the board), the board (Lambertian, floor_albedo over floor_rect_m,
// table_albedo elsewhere), the real pen (cube of cube_edge centred on the pen
// origin, shaft cylinder of shaft_radius along the pen's -z from the cube's
// -z face, shaft_length long, capped) and the virtual obstacles (box: base
// centre at the obstacle origin, extents size; cylinder: radius size.x,
// height size.z), all Lambertian. Every dielectric interface (air-water,
// air-glass, water-glass) reflects and refracts by the unpolarised Fresnel
// equations, with total internal reflection; Beer-Lambert absorption on
// every path segment inside the water (glass and air do not absorb).
//
// Light transport, split so that nothing is counted twice:
//   - Straight (unscattered) light from the disc on a diffuse point in air:
//     one shadow ray per shading sample towards a point sampled uniformly on
//     the disc; any solid, glass or water on the way blocks it (soft shadows).
//   - Light that met at least one dielectric interface: light tracing. Paths
//     are shot from the disc (a quadrature of `disc_directions` directions
//     over it, each with a lattice of launch points over the region from
//     which light can reach the tank) through the scene with exact
//     refraction, Fresnel splitting of reflected and transmitted flux,
//     Beer-Lambert absorption and occlusion, and their flux is deposited on
//     the first diffuse surface they meet (tank floor, board around and
//     under the tank, pen, obstacles) by a tent (bilinear) splat into
//     irradiance maps. Shading reads the maps bilinearly, so the caustics
//     carry a tent-of-a-tent filter: a cubic B-spline 4 texels wide
//     (standard deviation 0.58 texel). Under flat water a lattice moved
//     rigidly by the refraction is deposited exactly uniformly.
//   - Sky light: hemisphere rays (cosine-weighted) from every diffuse point,
//     traced through the water and the glass like any ray; the disc is not
//     counted on those rays (it is in the two terms above).
//   - Specular paths from the camera (reflections and refractions) end on
//     the sky (La), the disc (Ld: glints) or a diffuse point.
//
// Not modelled: polarisation (every interface sees unpolarised light, also
// after a first reflection), dispersion (one refractive index for all
// bands), scattering inside the water, absorption in the glass, the
// meniscus, the obstacles' cell mask in the height field, diffuse
// interreflections beyond max_diffuse_bounces, a camera inside the tank,
// lens vignetting, blur and sensor noise, SceneInputs::effects (the
// reference always renders everything), SceneInputs::video and
// SceneInputs::caustics_water.
#ifndef RIPPLE_RENDER_REFERENCE_REFERENCE_H_
#define RIPPLE_RENDER_REFERENCE_REFERENCE_H_

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "geometry/camera_model.h"
#include "render/scene.h"

namespace ripple::reference {

struct ReferenceScene {
  // cam_from_tank, tank, water heights (null = flat at the rest level), pen
  // pose + geometry + visibility, obstacles, light_in_tank. The water surface
  // must stay inside (0, wall_height).
  render::SceneInputs scene;
  // The real camera, with its lens distortion.
  geometry::CameraModel camera;
  // Linear BGR albedo (CV_32FC3, values in [0, 1]) of the board plane z = 0
  // over floor_rect_m; empty: table_albedo everywhere. Texel (col c, row r)
  // covers x in [x + c w / cols, x + (c + 1) w / cols) and y likewise with
  // rows: row 0 at the rectangle's MIN y, column 0 at its min x. Sampled
  // bilinearly between texel centres (clamped at the rectangle's edge).
  cv::Mat floor_albedo;
  cv::Rect2d floor_rect_m;  // tank-frame x, y, width, height (metres)
  cv::Vec3f table_albedo{0.3f, 0.3f, 0.3f};  // the board outside floor_rect_m
  // A printed tag face is about half black: its mean albedo.
  cv::Vec3f pen_albedo{0.45f, 0.45f, 0.45f};
  // The real-time renderer's obstacle colour (linear RGB 0.78, 0.74, 0.68).
  cv::Vec3f obstacle_albedo{0.68f, 0.74f, 0.78f};
  // Real things between the camera and the tank (hands): flat polygons in
  // the tank frame, in front of everything, of a fixed linear BGR radiance
  // (in display units, like the video), in the dry and the wet render
  // alike.
  struct Occluder {
    std::vector<glm::dvec3> polygon_in_tank;  // planar, convex or not
    cv::Vec3f radiance_bgr{0.45f, 0.55f, 0.75f};
  };
  std::vector<Occluder> occluders;
  // The room around the tank: four vertical walls standing on the board at
  // x = +-half_x, y = +-half_y (tank frame), `height` tall, open above (the
  // sky). They are emitters of a fixed radiance (display units, like the
  // video), in vertical stripes `stripe_m` wide alternating between the
  // wall's colour and `stripe_dark` of it, seen by every ray in the air
  // that reaches them before anything else: the camera beyond the board's
  // edge, the water's and the glass's reflections, the sky rays of the
  // diffuse points (so they light the board a little, in place of the sky
  // they hide). They do not block the disc's light. The camera must be
  // inside the room. Off: the board is unbounded under the uniform sky.
  struct Room {
    bool on = false;
    double half_x = 0.4, half_y = 0.4, height = 0.5;  // metres
    cv::Vec3f wall_bgr[4] = {{0.2f, 0.5f, 0.3f},      // -x wall
                             {0.2f, 0.3f, 0.5f},      // +x wall
                             {0.45f, 0.35f, 0.3f},    // -y wall
                             {0.55f, 0.4f, 0.2f}};    // +y wall
    double stripe_m = 0.05;
    float stripe_dark = 0.4f;
  };
  Room room;
  double light_angular_radius_rad = 2.0 * M_PI / 180.0;  // the disc's radius
  double ambient_share = 0.3;  // a in [0, 1]: the sky's share (see above)
  // Beer-Lambert absorption of pure water per metre and band (B, G, R):
  // Pope & Fry (1997) near each camera band's sensitivity peak (B ~445 nm,
  // G ~540 nm, R ~650 nm; bands 400-500, 500-600, 600-700 nm).
  cv::Vec3f absorption_per_m{0.0081f, 0.047f, 0.34f};
  double water_ior = 1.333;
  double glass_ior = 1.5;
  double glass_thickness_m = 0.003;  // > 0, outside the inner size
};

struct ReferenceOptions {
  // Camera samples per pixel, box filter over the pixel: a jittered n x n
  // grid when a square, otherwise a randomly rotated Hammersley set.
  int samples_per_pixel = 16;
  // Light paths per caustic-map texel area of the launch region (>= 64),
  // rounded up to disc_directions * m^2 (m launch points per texel edge).
  int light_paths_per_texel = 64;
  // Directions of the disc quadrature in light tracing (even, >= 2): rings
  // of equal solid angle, paired antipodally about the disc centre so the
  // quadrature has the disc's exact mean direction.
  int disc_directions = 16;
  // Caustic-map texels along the tank's inner x size (square-ish texels;
  // the board map around the tank has the same texel).
  int caustic_map_size = 256;
  // Dielectric interface events (reflections and refractions) along one
  // path; a path that needs more is dropped (counted as cut). Light guided
  // down a glass wall crosses its 3 mm slab several times: a ray from the
  // board under a 40 mm wall, 30 degrees off the vertical, needs about 8
  // events to leave it. At 8 the flat scene's open water read 2.8% darker
  // than at 32 and the board under the glass up to 12% darker; 32 and 64
  // agree to 0.1 grey levels (docs/render.md, "The reference's path
  // depth").
  int max_bounces = 32;
  // Diffuse interreflections: a diffuse point reached after this many
  // diffuse bounces gets the disc's light only (straight and light-traced;
  // no hemisphere rays, so no sky). 0: the surfaces the camera sees get the
  // disc's light only; under water with a = 1 the floor is then black and
  // a pixel of it shows R La alone.
  int max_diffuse_bounces = 3;
  // Hemisphere rays per camera sample at the first diffuse point (deeper
  // ones use one).
  int ambient_samples = 1;
  // Worker threads (0: std::thread::hardware_concurrency()). The output is
  // the same for any count: per-pixel seeds, fixed-point flux deposits.
  int threads = 0;
  std::uint64_t seed = 1;
  // true: the image through the full lens model, like a real camera frame
  // (the ray of pixel (u, v) is the one whose distorted projection is
  // (u, v)); false: an ideal pinhole with the same fx, fy, cx, cy (what the
  // real-time renderer outputs, since it undistorts the video).
  bool distort = false;
  // true: the "real camera image": the board and the real pen (with its
  // shadow) only; no tank, no water, no walls, no obstacles.
  bool dry = false;
  // Pixels to render (empty: the whole image); the rest of the output is 0.
  cv::Rect roi;

  bool IsValid(std::string* error) const;
};

// Light-tracing flux figures, per band (B, G, R), in display units times
// m^2 (irradiance x area): one path of a uniformly lit horizontal patch of
// area A carries its share of Ed l.z A.
struct LightTraceSummary {
  std::int64_t paths = 0;   // launched light paths
  int paths_per_texel = 0;  // effective: disc_directions * m^2
  int disc_directions = 0;
  double texel_m = 0;  // caustic-map texel (x), metres
  double launch_spacing_m = 0;
  cv::Rect2d launch_rect_m;  // launch region on the plane z = launch_z_m
  double launch_z_m = 0;
  double seconds = 0;
  cv::Vec3d launched;             // all flux shot
  cv::Vec3d occluded;             // hit a solid before any dielectric
  cv::Vec3d unscattered;          // reached the board without meeting the tank
  cv::Vec3d surface_incident;     // arriving at the water surface from air
  cv::Vec3d surface_transmitted;  // of which transmitted into the water
  cv::Vec3d walls_into_water;     // entering the water from the glass
  cv::Vec3d out_of_water;         // leaving the water (surface or glass)
  cv::Vec3d absorbed_in_water;    // Beer-Lambert
  cv::Vec3d deposited_floor;      // on the tank floor (under water)
  cv::Vec3d deposited_board;      // on the board under and around the tank
  cv::Vec3d deposited_solids;     // on the pen and obstacles
  cv::Vec3d deposited_solids_in_water;  // part of which under water
  cv::Vec3d outside_map;   // scattered light landing beyond the board map
  cv::Vec3d escaped;       // scattered light leaving upwards
  cv::Vec3d cut;           // paths dropped at max_bounces or below 1e-6
  cv::Vec3d cut_in_water;  // part of which inside the water
};

// Irradiance of the light that met the tank (display units: a dry horizontal
// board in full light receives Ed l.z = (1 - a) pi), per band.
struct LightMaps {
  // The tank floor under the water, CV_32FC3, over floor_rect_m (= the inner
  // tank): texel (col c, row r) covers x in [x + c w / cols, x + (c + 1) w /
  // cols), y likewise with rows (row 0 at min y); its value is the tent-
  // filtered irradiance at the texel's centre.
  cv::Mat floor_irradiance;
  cv::Rect2d floor_rect_m;
  // The board under the glass and around the tank (scattered light only:
  // the straight light is added by shadow rays), same layout.
  cv::Mat board_irradiance;
  cv::Rect2d board_rect_m;
};

struct ReferenceSummary {
  LightTraceSummary light;  // empty in the dry render
  int width = 0, height = 0;
  cv::Rect roi;
  std::int64_t camera_samples = 0;
  int threads = 0;
  double light_seconds = 0, camera_seconds = 0, total_seconds = 0;
  std::string BriefReport() const;
};

// The light quantities of a scene (see the radiometry above).
struct LightRadiometry {
  double sky_radiance = 0;      // La
  double disc_irradiance = 0;   // Ed, on a plane normal to the light
  double disc_radiance = 0;     // Ld
  double disc_solid_angle = 0;  // 2 pi (1 - cos alpha), steradians
  double cos_zenith = 0;        // l.z
};
LightRadiometry ComputeLightRadiometry(const ReferenceScene& scene);

// Checks the scene (camera, sizes, albedos, light above the horizon by more
// than the disc's radius, water surface inside the tank); `error` names the
// offending field.
bool IsValidScene(const ReferenceScene& scene, std::string* error);

// Light tracing alone (the wet scene's caustics and the light through the
// walls): fills `maps` and `summary` (either may be null). options.dry and
// options.roi are ignored.
bool ComputeLightMaps(const ReferenceOptions& options,
                      const ReferenceScene& scene, LightMaps* maps,
                      LightTraceSummary* summary, std::string* error);

// Renders the scene into `linear_bgr` (CV_32FC3, camera size, linear
// radiance in the display units above). Returns false with a message for
// invalid options or scene. `summary` may be null.
bool RenderReference(const ReferenceOptions& options,
                     const ReferenceScene& scene, cv::Mat* linear_bgr,
                     ReferenceSummary* summary, std::string* error);

// The unit ray (camera frame) of `pixel` (OpenCV convention): with
// `distort`, the ray whose distorted projection is the pixel (the lens model
// inverted by Newton iterations to < 1e-9 px where they converge); without,
// the pinhole ray of the same fx, fy, cx, cy.
Eigen::Vector3d PixelRay(const geometry::CameraModel& camera,
                         const Eigen::Vector2d& pixel, bool distort);

// sRGB transfer function (IEC 61966-2-1) of a linear CV_32FC3 image, values
// clamped to [0, 1], into CV_8UC3; and its inverse for camera-like frames.
cv::Mat LinearToSrgb8(const cv::Mat& linear_bgr);
cv::Mat Srgb8ToLinear(const cv::Mat& bgr8);

}  // namespace ripple::reference

#endif  // RIPPLE_RENDER_REFERENCE_REFERENCE_H_
