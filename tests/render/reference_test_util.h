// Synthesised scenes for the reference renderer's tests and benchmark: a
// webcam looking at the default tank, a ring wave, a checkered floor.
#ifndef RIPPLE_TESTS_RENDER_REFERENCE_TEST_UTIL_H_
#define RIPPLE_TESTS_RENDER_REFERENCE_TEST_UTIL_H_

#include <cmath>
#include <glm/glm.hpp>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "render/reference/reference.h"

namespace ripple::reference::testing {

// cam_from_tank of a camera at `eye` looking at `target` (tank frame), the
// image's x axis horizontal (OpenCV camera: x right, y down, z forward).
inline glm::dmat4 CamFromTankLookAt(const glm::dvec3& eye,
                                    const glm::dvec3& target) {
  const glm::dvec3 z = glm::normalize(target - eye);
  const glm::dvec3 x = glm::normalize(glm::cross(z, glm::dvec3(0, 0, 1)));
  const glm::dvec3 y = glm::cross(z, x);
  glm::dmat4 cam_from_tank(1.0);
  for (int c = 0; c < 3; ++c) {
    cam_from_tank[c][0] = x[c];
    cam_from_tank[c][1] = y[c];
    cam_from_tank[c][2] = z[c];
  }
  cam_from_tank[3] =
      glm::dvec4(-glm::dot(x, eye), -glm::dot(y, eye), -glm::dot(z, eye), 1.0);
  return cam_from_tank;
}

// A scene that owns the buffers its views point into.
struct OwnedScene {
  ReferenceScene scene;
  std::vector<float> heights;
};

// Fills `heights` (nx x ny cells of `cell` metres, centred on the tank) with
// amplitude cos(2 pi r / wavelength) exp(-r^2 / sigma^2) around `centre`.
inline void FillRing(int nx, int ny, double cell, double amplitude,
                     double wavelength, double sigma, glm::dvec2 centre,
                     std::vector<float>* heights) {
  heights->assign(static_cast<size_t>(nx) * ny, 0.0f);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 - 0.5 * nx) * cell - centre.x;
      const double y = (j + 0.5 - 0.5 * ny) * cell - centre.y;
      const double r = std::hypot(x, y);
      (*heights)[static_cast<size_t>(j) * nx + i] =
          static_cast<float>(amplitude * std::cos(2 * M_PI * r / wavelength) *
                             std::exp(-r * r / (sigma * sigma)));
    }
  }
}

// A checkered floor texture (CV_32FC3 linear BGR) over `rect`: squares of
// `square` metres alternating `a` and `b`, `texel` metres per texel, and a
// thin dark line along each square's edge.
inline cv::Mat MakeChecker(const cv::Rect2d& rect, double texel, double square,
                           const cv::Vec3f& a, const cv::Vec3f& b) {
  const int cols = static_cast<int>(std::lround(rect.width / texel));
  const int rows = static_cast<int>(std::lround(rect.height / texel));
  cv::Mat m(rows, cols, CV_32FC3);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double x = rect.x + (c + 0.5) * rect.width / cols;
      const double y = rect.y + (r + 0.5) * rect.height / rows;
      const double fx = x / square - std::floor(x / square);
      const double fy = y / square - std::floor(y / square);
      const bool odd = (static_cast<long>(std::floor(x / square)) +
                        static_cast<long>(std::floor(y / square))) &
                       1;
      cv::Vec3f v = odd ? b : a;
      const double edge = 0.04;  // line width, share of a square
      if (fx < edge || fy < edge) v *= 0.35f;
      m.at<cv::Vec3f>(r, c) = v;
    }
  }
  return m;
}

// The pen leaning over the tank with its tip (0.14 m from the cube centre
// along -z of the pen frame) at `tip_in_tank`.
inline glm::dmat4 PenWithTipAt(const glm::dvec3& tip_in_tank) {
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.35, -0.45, 1.0));
  const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), axis));
  const glm::dvec3 y = glm::cross(axis, x);
  glm::dmat4 tank_from_pen(1.0);
  tank_from_pen[0] = glm::dvec4(x, 0);
  tank_from_pen[1] = glm::dvec4(y, 0);
  tank_from_pen[2] = glm::dvec4(axis, 0);
  tank_from_pen[3] = glm::dvec4(tip_in_tank + 0.14 * axis, 1);
  return tank_from_pen;
}

// The demo-like view: the default tank (17 x 11 cm, walls 4 cm, water 2.5
// cm) from 0.33 m away, 60 degrees horizontal field of view; a ring wave of
// 0.4 mm and 8 mm wavelength over 256 x 166 cells; a checkered board; the
// pen dipped at the ring's centre and one cylinder obstacle. The light is
// the project's default direction, or with `backlit` behind the tank as seen
// from the camera, so that the sun's glint and the ring's glints are in view.
inline std::unique_ptr<OwnedScene> MakeRingScene(int width, int height,
                                                 bool backlit = false) {
  auto s = std::make_unique<OwnedScene>();
  ReferenceScene& rs = s->scene;
  rs.camera = geometry::MakeIdealCamera(width, height, 60.0);
  rs.scene.cam_from_tank =
      CamFromTankLookAt({0.0, -0.23, 0.24}, {0.0, 0.0, 0.01});
  const int nx = 256, ny = 166;
  const double cell = rs.scene.tank.size_x / nx;
  FillRing(nx, ny, cell, 0.0004, 0.008, 0.03, {0.01, 0.005}, &s->heights);
  rs.scene.water = {s->heights.data(), nx, ny, static_cast<float>(cell), 1};
  rs.floor_rect_m = cv::Rect2d(-0.14, -0.1, 0.28, 0.2);
  rs.floor_albedo = MakeChecker(rs.floor_rect_m, 0.00025, 0.01,
                                {0.8f, 0.8f, 0.8f}, {0.25f, 0.3f, 0.35f});
  rs.scene.pen_visible = true;
  rs.scene.tank_from_pen = PenWithTipAt({0.01, 0.005, 0.012});
  render::Obstacle pillar;
  pillar.shape = render::Obstacle::Shape::kCylinder;
  pillar.size = {0.008f, 0.008f, 0.035f};
  pillar.tank_from_obstacle[3] = glm::dvec4(-0.05, 0.02, 0.0, 1.0);
  rs.scene.obstacles.push_back(pillar);
  if (backlit) rs.scene.light_in_tank = {0.25, 0.9, 1.0};
  return s;
}

}  // namespace ripple::reference::testing

#endif  // RIPPLE_TESTS_RENDER_REFERENCE_TEST_UTIL_H_
