// The reference renderer pinned to physics: Snell displacement under flat
// water, uniform light-traced irradiance under flat water with its analytic
// value, flux conservation, the dry board's radiance, the pen's umbra, the
// radiance of a floor seen through water (L / n^2, Fresnel both ways,
// Beer-Lambert, total internal reflection), the sky on a floor under flat
// water and the floor-surface return series, the lens inversion,
// determinism across thread counts and option checks.
#include "render/reference/reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <vector>

#include "render/reference/optics.h"
#include "tests/render/reference_test_util.h"

namespace ripple::reference {
namespace {

using testing::CamFromTankLookAt;

// Unpolarised Fresnel reflectance from the angle form of the Fresnel
// equations (Hecht, Optics, 4th ed., eqs. 4.42-4.43):
// r_s = -sin(i - t) / sin(i + t), r_p = tan(i - t) / tan(i + t). Written
// independently of optics.h's cosine form on purpose.
double FresnelByAngles(double theta_i, double n1, double n2) {
  const double s = n1 / n2 * std::sin(theta_i);
  if (s >= 1) return 1.0;
  const double theta_t = std::asin(s);
  if (theta_i < 1e-9) {
    const double r = (n1 - n2) / (n1 + n2);
    return r * r;
  }
  const double rs = -std::sin(theta_i - theta_t) / std::sin(theta_i + theta_t);
  const double rp = std::tan(theta_i - theta_t) / std::tan(theta_i + theta_t);
  return 0.5 * (rs * rs + rp * rp);
}

// A uniform CV_32FC3 albedo texture of `rows` x `cols`.
cv::Mat Uniform(int rows, int cols, float b, float g, float r) {
  return cv::Mat(rows, cols, CV_32FC3, cv::Scalar(b, g, r));
}

ReferenceOptions FastOptions() {
  ReferenceOptions o;
  o.samples_per_pixel = 16;
  o.caustic_map_size = 64;
  o.threads = 2;
  return o;
}

Eigen::Vector2d ProjectTank(const geometry::CameraModel& cam,
                            const glm::dmat4& cam_from_tank,
                            const glm::dvec3& p, bool distort) {
  const glm::dvec3 c(cam_from_tank * glm::dvec4(p, 1.0));
  if (distort) return cam.Project(Eigen::Vector3d(c.x, c.y, c.z));
  return {cam.fx * c.x / c.z + cam.cx, cam.fy * c.y / c.z + cam.cy};
}

// The point on the flat surface z = level through which the camera at `eye`
// sees the floor point `floor_point` (z = 0): Snell's law, n sin(water) =
// sin(air), in the vertical plane through both, solved by bisection.
glm::dvec3 SnellSurfacePoint(const glm::dvec3& eye,
                             const glm::dvec3& floor_point, double level,
                             double n) {
  const glm::dvec2 to(floor_point.x - eye.x, floor_point.y - eye.y);
  const double dist = glm::length(to);
  const glm::dvec2 u = to / dist;
  const double hc = eye.z - level, hw = level;
  double lo = 0, hi = dist;
  for (int it = 0; it < 200; ++it) {
    const double s = 0.5 * (lo + hi);
    const double sin_air = s / std::hypot(s, hc);
    const double sin_water = (dist - s) / std::hypot(dist - s, hw);
    (sin_air < n * sin_water ? lo : hi) = s;
  }
  const double s = 0.5 * (lo + hi);
  return {eye.x + s * u.x, eye.y + s * u.y, level};
}

TEST(ReferenceOpticsTest, FresnelMatchesTheFresnelEquations) {
  // Normal incidence: ((n1 - n2) / (n1 + n2))^2 = 0.0204 for water.
  EXPECT_NEAR(FresnelReflectance(1.0, 1.0, 1.333), std::pow(0.333 / 2.333, 2),
              1e-12);
  for (double deg = 0; deg < 90; deg += 7.3) {
    const double th = deg * M_PI / 180;
    for (auto [n1, n2] : {std::pair{1.0, 1.333}, std::pair{1.333, 1.0},
                          std::pair{1.5, 1.333}, std::pair{1.0, 1.5}}) {
      double cos_t = 0;
      const double r = FresnelReflectance(std::cos(th), n1, n2, &cos_t);
      EXPECT_NEAR(r, FresnelByAngles(th, n1, n2), 1e-12) << deg << " " << n1;
      if (r < 1) {
        // Reciprocity: the same reflectance from the other side.
        EXPECT_NEAR(FresnelReflectance(cos_t, n2, n1), r, 1e-12);
      }
    }
  }
  // Brewster's angle: r_p = 0, so R = r_s^2 / 2.
  const double brewster = std::atan(1.333);
  const double rs = std::sin(brewster - (M_PI / 2 - brewster));
  EXPECT_NEAR(FresnelReflectance(std::cos(brewster), 1.0, 1.333), 0.5 * rs * rs,
              1e-12);
  // Total internal reflection beyond the critical angle asin(1 / 1.333).
  const double critical = std::asin(1 / 1.333);
  EXPECT_EQ(FresnelReflectance(std::cos(critical + 1e-6), 1.333, 1.0), 1.0);
  EXPECT_LT(FresnelReflectance(std::cos(critical - 1e-3), 1.333, 1.0), 1.0);
  // Refract obeys Snell's law.
  const glm::dvec3 d = glm::normalize(glm::dvec3(0.6, 0.1, -0.8));
  const glm::dvec3 n(0, 0, 1);
  double cos_t = 0;
  FresnelReflectance(-glm::dot(d, n), 1.0, 1.333, &cos_t);
  const glm::dvec3 t = Refract(d, n, 1.0, 1.333, -glm::dot(d, n), cos_t);
  EXPECT_NEAR(glm::length(glm::cross(d, n)),
              1.333 * glm::length(glm::cross(t, n)), 1e-12);
  EXPECT_NEAR(glm::length(t), 1.0, 1e-12);
}

// The lens model inverted: the distorted projection of each pixel's ray is
// the pixel.
TEST(ReferenceCameraTest, PixelRaysReprojectOntoTheirPixels) {
  geometry::CameraModel cam = geometry::MakeIdealCamera(640, 480, 70.0);
  cam.dist = {-0.28, 0.09, 0.0012, -0.0008, -0.01, 0, 0, 0};
  double worst = 0;
  for (double v = 0; v < 480; v += 37.3) {
    for (double u = 0; u < 640; u += 41.1) {
      const Eigen::Vector3d ray = PixelRay(cam, {u, v}, true);
      worst =
          std::max(worst, (cam.Project(ray) - Eigen::Vector2d(u, v)).norm());
      const Eigen::Vector3d pin = PixelRay(cam, {u, v}, false);
      EXPECT_NEAR(cam.fx * pin.x() / pin.z() + cam.cx, u, 1e-9);
    }
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("lens inversion: worst reprojection %.2g px\n", worst);
}

// A small bright dot on the floor under flat water appears where Snell's
// law puts it: the centroid of its image (the difference of renders with and
// without the dot, same seeds) against the analytic refraction point
// projected into the camera, with and without lens distortion.
TEST(ReferenceRenderTest, FlatWaterDisplacesTheFloorAsSnellPredicts) {
  for (const bool distort : {false, true}) {
    ReferenceScene rs;
    rs.camera.width = 640;
    rs.camera.height = 480;
    rs.camera.fx = rs.camera.fy = 900;
    rs.camera.cx = 322.8;
    rs.camera.cy = 237.4;
    if (distort) rs.camera.dist = {-0.25, 0.08, 0.0012, -0.0008, 0, 0, 0, 0};
    const glm::dvec3 dot(0.012, 0.008, 0.0);
    const glm::dvec3 eye(-0.06, -0.16, 0.2);
    rs.scene.cam_from_tank = CamFromTankLookAt(eye, dot);
    rs.scene.light_in_tank = {0.2, 0.3, 1.0};
    const double level = rs.scene.tank.water_level;
    const glm::dvec3 q = SnellSurfacePoint(eye, dot, level, rs.water_ior);
    const Eigen::Vector2d expected =
        ProjectTank(rs.camera, rs.scene.cam_from_tank, q, distort);
    // Without refraction the dot would be this far away.
    const Eigen::Vector2d straight =
        ProjectTank(rs.camera, rs.scene.cam_from_tank, dot, distort);
    ASSERT_GT((straight - expected).norm(), 20.0);

    const double half = 0.004, texel = 5e-5, sigma = 2e-4;
    rs.floor_rect_m =
        cv::Rect2d(dot.x - half, dot.y - half, 2 * half, 2 * half);
    const int n = static_cast<int>(std::lround(2 * half / texel));
    rs.table_albedo = {0.2f, 0.2f, 0.2f};
    rs.floor_albedo = Uniform(n, n, 0.2f, 0.2f, 0.2f);
    cv::Mat with_dot = rs.floor_albedo.clone();
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        const double x = -half + (c + 0.5) * texel,
                     y = -half + (r + 0.5) * texel;
        const float g = static_cast<float>(
            0.6 * std::exp(-(x * x + y * y) / (2 * sigma * sigma)));
        with_dot.at<cv::Vec3f>(r, c) += cv::Vec3f(g, g, g);
      }
    }
    ReferenceOptions o = FastOptions();
    o.samples_per_pixel = 64;
    o.distort = distort;
    o.roi = cv::Rect(static_cast<int>(expected.x()) - 20,
                     static_cast<int>(expected.y()) - 20, 40, 40);
    cv::Mat plain, dotted;
    std::string error;
    ASSERT_TRUE(RenderReference(o, rs, &plain, nullptr, &error)) << error;
    rs.floor_albedo = with_dot;
    ASSERT_TRUE(RenderReference(o, rs, &dotted, nullptr, &error)) << error;
    double sum = 0, su = 0, sv = 0, peak = 0;
    for (int v = o.roi.y; v < o.roi.y + o.roi.height; ++v) {
      for (int u = o.roi.x; u < o.roi.x + o.roi.width; ++u) {
        const double d =
            dotted.at<cv::Vec3f>(v, u)[1] - plain.at<cv::Vec3f>(v, u)[1];
        sum += d;
        su += d * u;
        sv += d * v;
        peak = std::max(peak, d);
      }
    }
    ASSERT_GT(peak, 0.01);
    const Eigen::Vector2d centroid(su / sum, sv / sum);
    std::printf("snell (distort %d): shift %.2f px, centroid error %.4f px\n",
                distort, (straight - expected).norm(),
                (centroid - expected).norm());
    EXPECT_LT((centroid - expected).norm(), 0.05)
        << "distort " << distort << ": centroid " << centroid.transpose()
        << " expected " << expected.transpose();
  }
}

// Flat water: the light-traced floor irradiance away from the walls is
// uniform and equals Ed l.z T(theta_L) exp(-sigma level / cos theta_t) per
// band (a strong absorption so that Beer-Lambert shows).
TEST(ReferenceLightTest, FlatWaterGivesUniformAnalyticIrradiance) {
  ReferenceScene rs;
  rs.camera = geometry::MakeIdealCamera(64, 48, 60);
  rs.scene.light_in_tank = {0.35, 0.25, 1.0};
  rs.absorption_per_m = {1.0f, 5.0f, 20.0f};
  ReferenceOptions o = FastOptions();
  o.caustic_map_size = 128;
  LightMaps maps;
  LightTraceSummary sum;
  std::string error;
  ASSERT_TRUE(ComputeLightMaps(o, rs, &maps, &sum, &error)) << error;
  EXPECT_GE(sum.paths_per_texel, 64);

  const glm::dvec3 l = glm::normalize(rs.scene.light_in_tank);
  const LightRadiometry rad = ComputeLightRadiometry(rs);
  EXPECT_NEAR(rad.disc_irradiance * l.z, 0.7 * M_PI, 1e-12);
  const double theta = std::acos(l.z);
  const double theta_t = std::asin(std::sin(theta) / rs.water_ior);
  const double t = 1.0 - FresnelByAngles(theta, 1.0, rs.water_ior);
  const double level = rs.scene.tank.water_level;

  const cv::Mat& m = maps.floor_irradiance;
  const double du = maps.floor_rect_m.width / m.cols;
  const double dv = maps.floor_rect_m.height / m.rows;
  const double margin = 0.03;  // light through the walls lands within it
  for (int band = 0; band < 3; ++band) {
    double s = 0, s2 = 0;
    int count = 0;
    for (int r = 0; r < m.rows; ++r) {
      const double y = maps.floor_rect_m.y + (r + 0.5) * dv;
      if (std::abs(y) > 0.5 * rs.scene.tank.size_y - margin) continue;
      for (int c = 0; c < m.cols; ++c) {
        const double x = maps.floor_rect_m.x + (c + 0.5) * du;
        if (std::abs(x) > 0.5 * rs.scene.tank.size_x - margin) continue;
        const double e = m.at<cv::Vec3f>(r, c)[band];
        s += e;
        s2 += e * e;
        ++count;
      }
    }
    ASSERT_GT(count, 1000);
    const double mean = s / count;
    const double rel_std =
        std::sqrt(std::max(0.0, s2 / count - mean * mean)) / mean;
    const double expected =
        rad.disc_irradiance * l.z * t *
        std::exp(-rs.absorption_per_m[band] * level / std::cos(theta_t));
    std::printf("flat irradiance band %d: mean / analytic %.5f, rel std %.2g\n",
                band, mean / expected, rel_std);
    EXPECT_LT(rel_std, 0.01) << "band " << band;
    EXPECT_NEAR(mean / expected, 1.0, 0.01) << "band " << band;
  }
}

// Light-traced flux is conserved: the floor map's integral is the flux the
// tracer deposited; what entered the water (surface x Fresnel T, and through
// the walls) equals what the floor and the submerged solids received plus
// what left the water and what it absorbed; under a vertical light on flat
// water, flux into the surface = Ed x inner area and the floor receives it
// times T(0).
TEST(ReferenceLightTest, LightTracedFluxIsConserved) {
  auto owned = testing::MakeRingScene(64, 48);
  ReferenceScene& rs = owned->scene;
  ReferenceOptions o = FastOptions();
  o.caustic_map_size = 128;
  for (const bool absorb : {false, true}) {
    rs.absorption_per_m =
        absorb ? cv::Vec3f(1.0f, 5.0f, 20.0f) : cv::Vec3f(0, 0, 0);
    LightMaps maps;
    LightTraceSummary s;
    std::string error;
    ASSERT_TRUE(ComputeLightMaps(o, rs, &maps, &s, &error)) << error;
    const double texel_area =
        maps.floor_rect_m.area() / maps.floor_irradiance.total();
    const cv::Scalar map_flux = cv::sum(maps.floor_irradiance) * texel_area;
    for (int b = 0; b < 3; ++b) {
      EXPECT_NEAR(map_flux[b] / s.deposited_floor[b], 1.0, 1e-4);
      const double into = s.surface_transmitted[b] + s.walls_into_water[b];
      const double out = map_flux[b] + s.deposited_solids_in_water[b] +
                         s.out_of_water[b] + s.absorbed_in_water[b] +
                         s.cut_in_water[b];
      std::printf(
          "flux band %d absorb %d: map / deposited %.6f, out / in %.5f,"
          " cut %.2g of launched\n",
          b, absorb, map_flux[b] / s.deposited_floor[b], out / into,
          s.cut[b] / s.launched[b]);
      EXPECT_NEAR(out / into, 1.0, 0.01)
          << "band " << b << " absorb " << absorb;
      EXPECT_LT(s.cut[b], 1e-3 * s.launched[b]);
      // Every launched path ends somewhere.
      const double sinks = s.occluded[b] + s.unscattered[b] +
                           s.deposited_floor[b] + s.deposited_board[b] +
                           s.deposited_solids[b] + s.outside_map[b] +
                           s.escaped[b] + s.absorbed_in_water[b] + s.cut[b];
      EXPECT_NEAR(sinks / s.launched[b], 1.0, 1e-9);
      if (!absorb) {
        EXPECT_EQ(s.absorbed_in_water[b], 0.0);
      }
    }
    if (absorb) {
      EXPECT_GT(s.absorbed_in_water[2], 0.1 * s.deposited_floor[2]);
    }
    // The ripple focuses light: caustics well above and below the mean.
    double lo = 0, hi = 0;
    cv::minMaxLoc(maps.floor_irradiance.reshape(1), &lo, &hi);
    EXPECT_GT(hi, 2.0 * cv::mean(maps.floor_irradiance)[1]);
  }

  // Flat water under a vertical light.
  ReferenceScene flat;
  flat.camera = rs.camera;
  flat.scene.light_in_tank = {0, 0, 1};
  flat.absorption_per_m = {0, 0, 0};
  LightMaps maps;
  LightTraceSummary s;
  std::string error;
  ASSERT_TRUE(ComputeLightMaps(o, flat, &maps, &s, &error)) << error;
  const LightRadiometry rad = ComputeLightRadiometry(flat);
  const double area = flat.scene.tank.size_x * flat.scene.tank.size_y;
  const double t0 = 1.0 - std::pow(0.333 / 2.333, 2);
  const double texel_area =
      maps.floor_rect_m.area() / maps.floor_irradiance.total();
  const double map_flux = cv::sum(maps.floor_irradiance)[1] * texel_area;
  std::printf(
      "flat vertical: incident / (Ed A) %.5f, floor / (incident T0) %.5f\n",
      s.surface_incident[1] / (rad.disc_irradiance * area),
      map_flux / (s.surface_incident[1] * t0));
  EXPECT_NEAR(s.surface_incident[1] / (rad.disc_irradiance * area), 1.0, 0.01);
  EXPECT_NEAR(map_flux / (s.surface_incident[1] * t0), 1.0, 0.01);
}

// One obstacle in flat, clear water under a small disc (0.5 degrees) tilted
// towards +x (tan theta = 0.5), for the shadow tests.
ReferenceScene TiltedLightScene(const render::Obstacle& obstacle) {
  ReferenceScene rs;
  rs.light_angular_radius_rad = 0.5 * M_PI / 180;
  rs.scene.light_in_tank = {0.5, 0.0, 1.0};
  rs.absorption_per_m = {0, 0, 0};
  rs.scene.obstacles.push_back(obstacle);
  return rs;
}

// How far towards -x of a point at height z (over the water) the light
// through it lands on the floor of TiltedLightScene: (z - level) tan(theta)
// in the air, level tan(theta_t) in the water.
double ShadowRun(const ReferenceScene& rs, double z) {
  const double level = rs.scene.tank.water_level;
  const double theta = std::atan(0.5);
  const double theta_t = std::asin(std::sin(theta) / rs.water_ior);
  return (z - level) * std::tan(theta) + level * std::tan(theta_t);
}

// Registration of the light-traced map and of its lookup: a box standing in
// flat water casts a shadow whose far edge lies where the ray grazing the
// box's top edge lands, (top - level) tan(theta) + level tan(theta_t) beyond
// it; the map's 50% crossing and that of the image of a camera looking
// straight down on the edge (where refraction does not move it) must be
// there.
TEST(ReferenceLightTest, ShadowEdgeUnderWaterIsWhereRefractionPutsIt) {
  render::Obstacle box;
  box.shape = render::Obstacle::Shape::kBox;
  box.size = {0.01f, 0.06f, 0.035f};
  ReferenceScene rs = TiltedLightScene(box);
  const double edge_x = -0.005 - ShadowRun(rs, box.size.z);
  // A camera 0.3 m straight above the edge, image x along tank x.
  const glm::dvec3 eye(edge_x, 0.0, 0.3);
  glm::dmat4 cam_from_tank(1.0);
  cam_from_tank[1][1] = -1;
  cam_from_tank[2][2] = -1;
  cam_from_tank[3] = glm::dvec4(-eye.x, eye.y, eye.z, 1.0);
  rs.scene.cam_from_tank = cam_from_tank;
  rs.camera.width = 96;
  rs.camera.height = 8;
  rs.camera.fx = rs.camera.fy = 3000;  // 10 px per mm on the floor
  rs.camera.cx = 47.5;
  rs.camera.cy = 3.5;
  ReferenceOptions o = FastOptions();
  o.caustic_map_size = 256;

  LightMaps maps;
  std::string error;
  ASSERT_TRUE(ComputeLightMaps(o, rs, &maps, nullptr, &error)) << error;
  const cv::Mat& m = maps.floor_irradiance;
  const double du = maps.floor_rect_m.width / m.cols;
  const int row = static_cast<int>((0.0 - maps.floor_rect_m.y) /
                                   (maps.floor_rect_m.height / m.rows));
  const double lit = m.at<cv::Vec3f>(row, 10)[1];
  double map_edge = 0;
  for (int c = 10; c + 1 < m.cols; ++c) {
    const double e0 = m.at<cv::Vec3f>(row, c)[1];
    const double e1 = m.at<cv::Vec3f>(row, c + 1)[1];
    if (e0 >= 0.5 * lit && e1 < 0.5 * lit) {
      const double x0 = maps.floor_rect_m.x + (c + 0.5) * du;
      map_edge = x0 + du * (e0 - 0.5 * lit) / (e0 - e1);
      break;
    }
  }
  std::printf("shadow edge in the map: %.4f texel from the analytic %.5f m\n",
              (map_edge - edge_x) / du, edge_x);
  EXPECT_NEAR(map_edge, edge_x, 0.25 * du);

  o.samples_per_pixel = 64;
  cv::Mat img;
  ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
  std::vector<double> profile(img.cols, 0.0);
  for (int v = 0; v < img.rows; ++v) {
    for (int u = 0; u < img.cols; ++u) {
      profile[u] += img.at<cv::Vec3f>(v, u)[1] / img.rows;
    }
  }
  // Lit where x < edge (left), the box's shadow to the right.
  double lit_level = 0, shadow_level = 0;
  for (int u = 0; u < 10; ++u) {
    lit_level += profile[u] / 10;
    shadow_level += profile[img.cols - 1 - u] / 10;
  }
  ASSERT_GT(lit_level, 2 * shadow_level);
  const double half = 0.5 * (lit_level + shadow_level);
  double image_edge = -1;
  for (int u = 0; u + 1 < img.cols; ++u) {
    if (profile[u] >= half && profile[u + 1] < half) {
      image_edge = u + (profile[u] - half) / (profile[u] - profile[u + 1]);
      break;
    }
  }
  std::printf("shadow edge in the image: %.3f px from the analytic\n",
              image_edge - rs.camera.cx);
  EXPECT_NEAR(image_edge, rs.camera.cx, 0.5);
}

// A solid that stands through the light tracer's launch plane (just over
// the walls' top) blocks the light like any other: a cylinder 60 mm tall in
// flat water leaves the floor where its middle's shadow falls dark. The
// solids' faces are found from outside only, so a path launched inside one
// would pass straight through it and light that floor (0.71 of the lit
// level here), leaving only a crescent of shadow from its part below the
// plane.
TEST(ReferenceLightTest, ASolidThroughTheLaunchPlaneCastsItsWholeShadow) {
  render::Obstacle cylinder;
  cylinder.shape = render::Obstacle::Shape::kCylinder;
  cylinder.size = {0.01f, 0.01f, 0.06f};
  ReferenceScene rs = TiltedLightScene(cylinder);
  ASSERT_GT(cylinder.size.z, rs.scene.tank.wall_height + 0.01);
  // The light maps need a valid camera; it plays no part in them.
  rs.camera.width = rs.camera.height = 8;
  rs.camera.fx = rs.camera.fy = 1000;
  rs.camera.cx = rs.camera.cy = 3.5;
  ReferenceOptions o = FastOptions();
  o.caustic_map_size = 256;
  LightMaps maps;
  std::string error;
  ASSERT_TRUE(ComputeLightMaps(o, rs, &maps, nullptr, &error)) << error;
  const cv::Mat& m = maps.floor_irradiance;
  auto irradiance_at = [&](double x) {
    const int col = static_cast<int>((x - maps.floor_rect_m.x) /
                                     (maps.floor_rect_m.width / m.cols));
    const int row = static_cast<int>((0.0 - maps.floor_rect_m.y) /
                                     (maps.floor_rect_m.height / m.rows));
    return double(m.at<cv::Vec3f>(row, col)[1]);
  };
  const double lit = irradiance_at(0.06);
  ASSERT_GT(lit, 0.0);
  // The shadows of the axis at 45 mm (above the launch plane at 41 mm) and
  // at 35 mm (below it), the cylinder's radius from the shadow's edges.
  for (const double z : {0.045, 0.035}) {
    const double e = irradiance_at(-ShadowRun(rs, z));
    std::printf("floor under the axis's shadow at z = %.3f m: %.4f of lit\n", z,
                e / lit);
    EXPECT_LT(e, 0.02 * lit) << z;
  }
}

// A dry, plain board in full light has radiance = albedo, with and without
// lens distortion, whatever the light's direction.
TEST(ReferenceRenderTest, DryBoardRadianceIsAlbedo) {
  ReferenceScene rs;
  rs.camera = geometry::MakeIdealCamera(64, 48, 60);
  rs.scene.cam_from_tank = CamFromTankLookAt({0.03, -0.25, 0.3}, {0, 0, 0});
  rs.floor_rect_m = cv::Rect2d(-1, -1, 2, 2);
  rs.floor_albedo = Uniform(8, 8, 0.2f, 0.5f, 0.8f);
  for (const glm::dvec3& light :
       {glm::dvec3(0.35, 0.25, 1.0), glm::dvec3(-1.0, 0.4, 0.5)}) {
    rs.scene.light_in_tank = light;
    for (const bool distort : {false, true}) {
      rs.camera.dist = distort
                           ? std::array<double, 8>{-0.2, 0.05, 0, 0, 0, 0, 0, 0}
                           : std::array<double, 8>{};
      ReferenceOptions o = FastOptions();
      o.dry = true;
      o.distort = distort;
      cv::Mat img;
      std::string error;
      ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
      double worst = 0;
      for (int v = 0; v < img.rows; ++v) {
        for (int u = 0; u < img.cols; ++u) {
          const cv::Vec3f p = img.at<cv::Vec3f>(v, u);
          worst =
              std::max({worst, std::abs(p[0] / 0.2 - 1),
                        std::abs(p[1] / 0.5 - 1), std::abs(p[2] / 0.8 - 1)});
        }
      }
      std::printf("dry board: worst |L / albedo - 1| %.2g\n", worst);
      EXPECT_LT(worst, 0.01);
    }
  }
}

// The pen held upright over the dry board: its umbra receives only the sky
// (radiance ~ albedo x ambient share, less what the pen hides of the sky),
// while the board beside it stays at its albedo.
TEST(ReferenceRenderTest, PenCastsItsShadowOnTheDryBoard) {
  ReferenceScene rs;
  rs.camera = geometry::MakeIdealCamera(64, 48, 40);
  rs.table_albedo = {0.5f, 0.5f, 0.5f};
  rs.scene.light_in_tank = {0.3, 0.2, 1.0};
  rs.scene.pen_visible = true;
  const glm::dvec3 cube(0.0, 0.0, 0.16);
  rs.scene.tank_from_pen[3] = glm::dvec4(cube, 1.0);
  const glm::dvec3 l = glm::normalize(rs.scene.light_in_tank);
  const glm::dvec3 umbra = cube - l * (cube.z / l.z);
  const glm::dvec3 lit = umbra + glm::dvec3(0.0, -0.06, 0.0);
  rs.scene.cam_from_tank =
      CamFromTankLookAt(umbra + glm::dvec3(0.05, -0.3, 0.35), umbra);
  ReferenceOptions o = FastOptions();
  o.dry = true;
  o.samples_per_pixel = 64;
  cv::Mat img;
  std::string error;
  ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
  auto mean_around = [&](const glm::dvec3& p) {
    const Eigen::Vector2d px =
        ProjectTank(rs.camera, rs.scene.cam_from_tank, p, false);
    const cv::Rect r(static_cast<int>(px.x()) - 1, static_cast<int>(px.y()) - 1,
                     3, 3);
    return cv::mean(img(r))[1];
  };
  std::printf("pen umbra %.4f (albedo x ambient share %.4f), lit %.4f\n",
              mean_around(umbra), 0.5 * rs.ambient_share, mean_around(lit));
  EXPECT_NEAR(mean_around(umbra), 0.5 * rs.ambient_share,
              0.05 * 0.5 * rs.ambient_share);
  EXPECT_NEAR(mean_around(lit), 0.5, 0.005);
}

// The floor under flat water seen from the air: the reflected sky R La plus
// the floor's radiance carried out by T / n^2 with Beer-Lambert on the way,
// the floor lit by the light-traced disc and by hemisphere light (the sky
// through the surface, n^2 T La inside the critical cone, and the floor's
// own light returned by Fresnel and total internal reflection), computed
// here by quadrature. One diffuse bounce (max_diffuse_bounces = 1).
TEST(ReferenceRenderTest, FloorThroughWaterFollowsTheRadianceLaw) {
  ReferenceScene rs;
  rs.scene.tank.size_x = rs.scene.tank.size_y = 2.0f;  // walls out of reach
  rs.scene.tank.wall_height = 0.05f;
  rs.scene.tank.water_level = 0.025f;
  rs.table_albedo = {0.6f, 0.6f, 0.6f};
  rs.absorption_per_m = {1.0f, 5.0f, 20.0f};
  rs.scene.light_in_tank = {-0.3, 0.4, 1.0};  // no glint in view
  rs.camera.width = rs.camera.height = 8;
  rs.camera.fx = rs.camera.fy = 2000;
  rs.camera.cx = rs.camera.cy = 3.5;
  const glm::dvec3 target(0.0, 0.0, 0.0);
  const glm::dvec3 eye(-0.12, -0.16, 0.3);
  rs.scene.cam_from_tank = CamFromTankLookAt(eye, target);
  ReferenceOptions o = FastOptions();
  o.samples_per_pixel = 256;
  o.max_diffuse_bounces = 1;
  cv::Mat img;
  std::string error;
  ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
  const cv::Scalar measured = cv::mean(img);

  const double n = rs.water_ior, z = rs.scene.tank.water_level;
  const LightRadiometry rad = ComputeLightRadiometry(rs);
  const double la = rad.sky_radiance;
  const glm::dvec3 l = glm::normalize(rs.scene.light_in_tank);
  const double theta_l = std::acos(l.z);
  const double theta_lw = std::asin(std::sin(theta_l) / n);
  // The camera's ray (the image centre, to 0.1 degree) onto the surface.
  const double theta_v = std::acos(glm::normalize(eye - target).z);
  const double theta_vw = std::asin(std::sin(theta_v) / n);
  const double rho = rs.table_albedo[0];
  for (int b = 0; b < 3; ++b) {
    const double sigma = rs.absorption_per_m[b];
    const double e_direct = rad.disc_irradiance * l.z *
                            (1 - FresnelByAngles(theta_l, 1.0, n)) *
                            std::exp(-sigma * z / std::cos(theta_lw));
    // E_hemisphere = 2 pi int L(theta) cos sin dtheta over the upper
    // hemisphere in water (midpoint rule; the integrand is bounded).
    const int steps = 200000;
    double e_hemi = 0;
    for (int k = 0; k < steps; ++k) {
      const double th = (k + 0.5) * (M_PI / 2) / steps;
      const double att = std::exp(-sigma * z / std::cos(th));
      const double r = FresnelByAngles(th, n, 1.0);
      const double radiance =
          att * ((1 - r) * n * n * la + r * att * rho * e_direct / M_PI);
      e_hemi += radiance * std::cos(th) * std::sin(th) * (M_PI / 2) / steps;
    }
    e_hemi *= 2 * M_PI;
    const double floor_radiance = rho * (e_direct + e_hemi) / M_PI;
    const double r_view = FresnelByAngles(theta_v, 1.0, n);
    const double expected =
        r_view * la + (1 - r_view) / (n * n) *
                          std::exp(-sigma * z / std::cos(theta_vw)) *
                          floor_radiance;
    std::printf("through water band %d: measured %.5f expected %.5f (%.4f)\n",
                b, measured[b], expected, measured[b] / expected);
    EXPECT_NEAR(measured[b] / expected, 1.0, 0.01) << "band " << b;
  }
}

// A uniform Lambertian floor of albedo rho under flat water of depth z
// (index n, absorption sigma per metre) in an unbounded tank, seen from the
// air straight down. The pixel is R(0) La, the sky's mirror image on the
// surface, plus the floor's radiance L_f carried out by
// T(0) / n^2 exp(-sigma z). The floor reflects the irradiance
//   E_direct, the disc's, through the surface (given),
//   E_sky = 2 pi int (1 - R_w(t)) n^2 La exp(-sigma z / cos t) cos t sin t dt
//     over the upward directions in water (angle t from the vertical,
//     R_w = 1 beyond the critical angle), and
//   pi r L_f, its own light returned by the surface (Fresnel and total
//     internal reflection, Beer-Lambert up and back down), with
//   r = 2 int R_w(t) exp(-2 sigma z / cos t) cos t sin t dt
//     (0.475 without absorption: DiffuseInternalReflectance in
//     render/optics.h).
// The reference gives hemisphere light to a floor point reached after k
// diffuse bounces only while k < K = max_diffuse_bounces (the last one gets
// the light-traced disc only), so with q = rho r the floor's radiance is the
// truncated series
//   L_f = rho / pi (E_direct sum_{k=0..K} q^k + E_sky sum_{k=0..K-1} q^k),
// 1 / (1 - q) for both as K grows (Lekner & Dorf, Appl. Opt. 27, 1988).
struct FlatFloorTerms {
  double reflected_sky = 0;  // R(0) La
  double floor = 0;          // T(0) / n^2 exp(-sigma z) L_f
  double e_sky = 0;          // E_sky
  double r = 0;              // the surface's return r
  double sky_series = 0;     // sum_{k=0..K-1} q^k
  double Pixel() const { return reflected_sky + floor; }
};
FlatFloorTerms FlatFloorUnderWater(double rho, double n, double sigma, double z,
                                   double la, double e_direct,
                                   int max_diffuse_bounces) {
  FlatFloorTerms f;
  // Midpoint rule; the integrands are bounded and continuous (R_w reaches 1
  // at the critical angle).
  const int steps = 200000;
  const double dt = (M_PI / 2) / steps;
  for (int k = 0; k < steps; ++k) {
    const double t = (k + 0.5) * dt;
    const double cs = std::cos(t) * std::sin(t) * dt;
    const double att = std::exp(-sigma * z / std::cos(t));
    const double r_w = FresnelByAngles(t, n, 1.0);
    f.e_sky += 2 * M_PI * (1 - r_w) * n * n * la * att * cs;
    f.r += 2 * r_w * att * att * cs;
  }
  const double q = rho * f.r;
  double sum_direct = 0, sum_sky = 0, qk = 1;
  for (int k = 0; k <= max_diffuse_bounces; ++k, qk *= q) {
    sum_direct += qk;
    if (k < max_diffuse_bounces) sum_sky += qk;
  }
  f.sky_series = sum_sky;
  const double floor_radiance =
      rho / M_PI * (e_direct * sum_direct + f.e_sky * sum_sky);
  const double r0 = FresnelByAngles(0, 1.0, n);
  f.reflected_sky = r0 * la;
  f.floor = (1 - r0) / (n * n) * std::exp(-sigma * z) * floor_radiance;
  return f;
}

// A 2 m tank (walls out of reach of the floor's returned light), flat water
// 25 mm deep, a uniform board of albedo rho, an 8 x 8 pixel camera 0.4 m
// above the centre looking straight down (0.1 degree field).
ReferenceScene FlatFloorScene(float rho) {
  ReferenceScene rs;
  rs.scene.tank.size_x = rs.scene.tank.size_y = 2.0f;
  rs.scene.tank.wall_height = 0.05f;
  rs.scene.tank.water_level = 0.025f;
  rs.table_albedo = {rho, rho, rho};
  rs.scene.light_in_tank = {0.35, 0.25, 1.0};  // no glint in view
  rs.camera.width = rs.camera.height = 8;
  rs.camera.fx = rs.camera.fy = 2000;
  rs.camera.cx = rs.camera.cy = 3.5;
  // Camera x along the tank's x, y along -y, z (forward) along -z.
  glm::dmat4 cam_from_tank(1.0);
  cam_from_tank[1][1] = -1;
  cam_from_tank[2][2] = -1;
  cam_from_tank[3][2] = 0.4;
  rs.scene.cam_from_tank = cam_from_tank;
  return rs;
}

// The disc's irradiance on the floor through flat water (per band).
double DirectOnFlatFloor(const ReferenceScene& rs, double sigma) {
  const LightRadiometry rad = ComputeLightRadiometry(rs);
  const glm::dvec3 l = glm::normalize(rs.scene.light_in_tank);
  const double theta_l = std::acos(l.z);
  const double theta_lw = std::asin(std::sin(theta_l) / rs.water_ior);
  return rad.disc_irradiance * l.z *
         (1 - FresnelByAngles(theta_l, 1.0, rs.water_ior)) *
         std::exp(-sigma * rs.scene.tank.water_level / std::cos(theta_lw));
}

// A dark floor (rho 0.1, return series ~1.05) under flat pure water, seen
// straight down, sky only (a = 1) and disc only (a = 0), against
// FlatFloorUnderWater. The sky reaching the floor is E_sky / pi = 0.934 La
// without absorption: flux through the surface, n^2 T La inside the Snell
// cone, whose cosine-weighted share of the hemisphere is 1 / n^2. The pixel
// also holds the sky's mirror image R(0) La = 0.0204 (all that is left with
// max_diffuse_bounces = 0, checked exactly), 27 % of it at a = 1: the floor
// term is compared after taking it out.
TEST(ReferenceRenderTest, SkyOnTheFloorUnderFlatWaterMatchesTheAnalyticValue) {
  const float rho = 0.1f;
  ReferenceScene rs = FlatFloorScene(rho);
  const double n = rs.water_ior, z = rs.scene.tank.water_level;
  for (const double a : {1.0, 0.0}) {
    rs.ambient_share = a;
    const LightRadiometry rad = ComputeLightRadiometry(rs);
    ReferenceOptions o = FastOptions();
    o.samples_per_pixel = 256;
    o.ambient_samples = 8;
    cv::Mat img;
    std::string error;
    ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
    const cv::Scalar measured = cv::mean(img);
    for (int b = 0; b < 3; ++b) {
      const double sigma = rs.absorption_per_m[b];
      const FlatFloorTerms expected = FlatFloorUnderWater(
          rho, n, sigma, z, rad.sky_radiance, DirectOnFlatFloor(rs, sigma),
          o.max_diffuse_bounces);
      const double floor = measured[b] - expected.reflected_sky;
      std::printf(
          "flat floor rho %.2f a %.0f band %d: pixel %.5f expected %.5f "
          "(R La %.5f), floor %.5f expected %.5f (%.4f); E_sky / pi La "
          "%.4f, r %.4f\n",
          rho, a, b, measured[b], expected.Pixel(), expected.reflected_sky,
          floor, expected.floor, floor / expected.floor,
          a > 0 ? expected.e_sky / (M_PI * rad.sky_radiance) : 0.0, expected.r);
      EXPECT_NEAR(floor / expected.floor, 1.0, 0.01) << "a " << a << " b " << b;
    }
    if (a == 1.0) {
      // No hemisphere rays: the floor gets no sky, the pixel is the sky's
      // reflection alone (both Fresnel branches traced at the surface).
      o.max_diffuse_bounces = 0;
      ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
      const double r0 = FresnelByAngles(0, 1.0, n);
      for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(cv::mean(img)[b] / (r0 * rad.sky_radiance), 1.0, 1e-5);
      }
    }
  }
}

// A bright floor (rho 0.88) under flat water, sky only: over a third of its
// light is returned light, so what is pinned is the series with
// Beer-Lambert on every return trip. Absorption (1, 5, 20) per metre over
// the 25 mm depth takes r from 0.475 to 0.415, 0.259 and 0.059 (the totally
// reflected rays are the slanted ones, with the longest paths), the
// converged series 1 / (1 - rho r) from 1.72 to 1.58, 1.30 and 1.05. At the
// default three diffuse bounces the reference sums the truncated series
// 1 + q + q^2; at 16 it has converged (q^16 < 1e-6).
TEST(ReferenceRenderTest, BrightFloorUnderFlatWaterSumsTheReturnSeries) {
  const float rho = 0.88f;
  ReferenceScene rs = FlatFloorScene(rho);
  rs.ambient_share = 1.0;
  rs.absorption_per_m = {1.0f, 5.0f, 20.0f};
  const double n = rs.water_ior, z = rs.scene.tank.water_level;
  const LightRadiometry rad = ComputeLightRadiometry(rs);
  for (const int bounces : {3, 16}) {
    ReferenceOptions o = FastOptions();
    o.samples_per_pixel = 256;
    o.ambient_samples = 8;
    o.max_diffuse_bounces = bounces;
    cv::Mat img;
    std::string error;
    ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
    const cv::Scalar measured = cv::mean(img);
    for (int b = 0; b < 3; ++b) {
      const double sigma = rs.absorption_per_m[b];
      const FlatFloorTerms expected =
          FlatFloorUnderWater(rho, n, sigma, z, rad.sky_radiance, 0.0, bounces);
      // The floor term with the series of clear water (no absorption on
      // the return trips), to show what the test tells apart.
      const FlatFloorTerms clear =
          FlatFloorUnderWater(rho, n, 0.0, z, rad.sky_radiance, 0.0, bounces);
      const double no_return_absorption =
          expected.floor * clear.sky_series / expected.sky_series;
      const double floor = measured[b] - expected.reflected_sky;
      std::printf(
          "bright floor K %d band %d: pixel %.5f expected %.5f, floor %.5f "
          "expected %.5f (%.4f; without absorption on the returns %.4f), r "
          "%.4f, series %.4f\n",
          bounces, b, measured[b], expected.Pixel(), floor, expected.floor,
          floor / expected.floor, floor / no_return_absorption, expected.r,
          expected.sky_series);
      EXPECT_NEAR(floor / expected.floor, 1.0, 0.01)
          << "bounces " << bounces << " band " << b;
    }
  }
}

// The same image for 1, 2 and 3 threads (per-pixel seeds, fixed-point
// light deposits).
TEST(ReferenceRenderTest, DeterministicAcrossThreadCounts) {
  auto owned = testing::MakeRingScene(640, 480);
  ReferenceScene& rs = owned->scene;
  ReferenceOptions o = FastOptions();
  o.samples_per_pixel = 4;
  o.roi = cv::Rect(280, 180, 64, 48);
  cv::Mat first;
  for (int threads : {1, 2, 3}) {
    o.threads = threads;
    cv::Mat img;
    std::string error;
    ASSERT_TRUE(RenderReference(o, rs, &img, nullptr, &error)) << error;
    if (first.empty()) {
      first = img;
      EXPECT_GT(cv::mean(img(o.roi))[1], 0.05);
    } else {
      EXPECT_EQ(cv::norm(img, first, cv::NORM_INF), 0.0) << threads;
    }
  }
}

TEST(ReferenceOptionsTest, BadOptionsAndScenesAreRefusedWithAMessage) {
  const ReferenceOptions good;
  std::string error;
  EXPECT_TRUE(good.IsValid(&error)) << error;
  auto refused = [](ReferenceOptions o) {
    std::string e;
    return !o.IsValid(&e) && !e.empty();
  };
  ReferenceOptions o = good;
  o.samples_per_pixel = 0;
  EXPECT_TRUE(refused(o));
  o = good;
  o.light_paths_per_texel = 63;
  EXPECT_TRUE(refused(o));
  o = good;
  o.disc_directions = 15;
  EXPECT_TRUE(refused(o));
  o = good;
  o.caustic_map_size = 4;
  EXPECT_TRUE(refused(o));
  o = good;
  o.max_bounces = 1;
  EXPECT_TRUE(refused(o));
  o = good;
  o.max_diffuse_bounces = -1;
  EXPECT_TRUE(refused(o));
  o = good;
  o.threads = -2;
  EXPECT_TRUE(refused(o));
  o = good;
  o.roi = cv::Rect(-1, 0, 4, 4);
  EXPECT_TRUE(refused(o));

  auto owned = testing::MakeRingScene(64, 48);
  const ReferenceScene base = owned->scene;
  EXPECT_TRUE(IsValidScene(base, &error)) << error;
  auto scene_refused = [&](const ReferenceScene& s) {
    std::string e;
    cv::Mat img;
    const bool ok = RenderReference(good, s, &img, nullptr, &e);
    return !ok && !e.empty();
  };
  ReferenceScene s = base;
  s.camera.fx = 0;
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.scene.light_in_tank = {1.0, 0.0, 0.01};  // disc partly below the horizon
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.scene.tank.water_level = 0.05f;  // above the walls
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.glass_thickness_m = 0;
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.floor_albedo = cv::Mat(4, 4, CV_8UC3);
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.ambient_share = 1.5;
  EXPECT_TRUE(scene_refused(s));
  s = base;
  s.scene.tank_from_pen[0][0] = 2.0;  // not a rotation
  EXPECT_TRUE(scene_refused(s));
  ReferenceOptions roi_outside = good;
  roi_outside.roi = cv::Rect(60, 40, 10, 10);
  cv::Mat img;
  EXPECT_FALSE(RenderReference(roi_outside, base, &img, nullptr, &error));
  EXPECT_FALSE(error.empty());
}

}  // namespace
}  // namespace ripple::reference
