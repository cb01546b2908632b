// Shared helpers of the render tests and benchmarks: GL context or skip,
// synthesized scenes (a camera over a checkered table and the default
// tank), and golden-image comparison.
#ifndef RIPPLE_TESTS_RENDER_RENDER_TEST_UTIL_H_
#define RIPPLE_TESTS_RENDER_RENDER_TEST_UTIL_H_

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/context.h"
#include "render/scene.h"

namespace ripple::render::testing {

// Under CI=true a missing GL context is a failure, not a skip.
inline bool IsCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

// Declares `var` (std::unique_ptr<Context>) or skips/fails the test.
#define RIPPLE_CONTEXT_OR_SKIP(var, backend, w, h)                             \
  std::string var##_error;                                                     \
  auto var = ::ripple::render::Context::TryCreate(backend, w, h, &var##_error, \
                                                  false);                      \
  if (var == nullptr) {                                                        \
    if (::ripple::render::testing::IsCi()) {                                   \
      FAIL() << "no " << BackendName(backend)                                  \
             << " GL context under CI=true: " << var##_error;                  \
    }                                                                          \
    GTEST_SKIP() << "no " << BackendName(backend)                              \
                 << " GL context: " << var##_error;                            \
  }

// A webcam with `hfov_deg` horizontal field of view, principal point at the
// image centre (OpenCV pixel-centre convention).
inline Intrinsics MakeIntrinsics(int w, int h, double hfov_deg = 60.0) {
  Intrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.5 * w / std::tan(0.5 * hfov_deg * M_PI / 180.0);
  k.cx = 0.5 * (w - 1);
  k.cy = 0.5 * (h - 1);
  return k;
}

// cam_from_tank for a camera at `eye_in_tank` looking at `target_in_tank`,
// image rows pointing down the tank's z (OpenCV camera convention).
inline glm::dmat4 LookAt(const glm::dvec3& eye, const glm::dvec3& target) {
  const glm::dvec3 z = glm::normalize(target - eye);
  const glm::dvec3 x = glm::normalize(glm::cross(z, glm::dvec3(0, 0, 1)));
  const glm::dvec3 y = glm::cross(z, x);
  glm::dmat4 m(1.0);
  for (int c = 0; c < 3; ++c) {
    m[c][0] = x[c];
    m[c][1] = y[c];
    m[c][2] = z[c];
  }
  m[3][0] = -glm::dot(x, eye);
  m[3][1] = -glm::dot(y, eye);
  m[3][2] = -glm::dot(z, eye);
  return m;
}

// A scene with owned buffers (the views in `inputs` point into them).
struct TestScene {
  Intrinsics k;
  SceneInputs inputs;
  std::vector<std::uint8_t> video;  // BGR8
  std::vector<float> heights;
};

// Ray-casts the table plane z = 0 (tank frame): a checkered board with 1 cm
// squares over the board, a plain table colour beyond it. Pixels at or above
// the horizon get a wall colour.
inline void SynthesizeTable(const Intrinsics& k,
                            const glm::dmat4& cam_from_tank,
                            std::vector<std::uint8_t>* bgr,
                            bool black = false) {
  bgr->assign(static_cast<size_t>(k.width) * k.height * 3, 0);
  if (black) return;
  const glm::dmat4 tank_from_cam = glm::inverse(cam_from_tank);
  const glm::dvec3 eye(tank_from_cam[3]);
  const glm::dmat3 r(tank_from_cam);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const glm::dvec3 d =
          r * glm::dvec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      std::uint8_t* px = &(*bgr)[(static_cast<size_t>(v) * k.width + u) * 3];
      if (d.z >= -1e-6) {
        px[0] = 150, px[1] = 160, px[2] = 170;
        continue;
      }
      const glm::dvec3 p = eye + d * (-eye.z / d.z);
      if (std::abs(p.x) < 0.14 && std::abs(p.y) < 0.095) {
        const bool odd = (static_cast<int>(std::floor(p.x / 0.01)) +
                          static_cast<int>(std::floor(p.y / 0.01))) &
                         1;
        const int g = odd ? 70 : 225;
        px[0] = g, px[1] = g, px[2] = g;
        if (std::abs(p.x) < 0.004 && std::abs(p.y) < 0.03) {
          px[0] = 40, px[1] = 40, px[2] = 200;  // a red mark: shows refraction
        }
      } else {
        px[0] = 80, px[1] = 120, px[2] = 160;  // wood
      }
    }
  }
}

enum class View { kFront, kTilted, kTop };

// The default tank seen from a webcam; `ripple` adds one cos * Gaussian ring
// of 1.5 mm amplitude at (x0, y0).
inline TestScene MakeScene(int w, int h, View view, bool ripple,
                           bool black_video = false, double x0 = 0.02,
                           double y0 = 0.0) {
  TestScene s;
  s.k = MakeIntrinsics(w, h);
  glm::dvec3 eye(0.0, -0.24, 0.22);
  if (view == View::kTilted) eye = glm::dvec3(0.17, -0.17, 0.12);
  if (view == View::kTop) eye = glm::dvec3(0.001, -0.02, 0.32);
  s.inputs.cam_from_tank = LookAt(eye, glm::dvec3(0, 0, 0.0));
  SynthesizeTable(s.k, s.inputs.cam_from_tank, &s.video, black_video);
  s.inputs.video = {s.video.data(), w, h, w * 3};
  const int nx = 128, ny = 83;
  const float d = s.inputs.tank.size_x / nx;
  s.heights.assign(nx * ny, 0.0f);
  if (ripple) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double x = (i + 0.5 - 0.5 * nx) * d - x0;
        const double y = (j + 0.5 - 0.5 * ny) * d - y0;
        const double r = std::sqrt(x * x + y * y);
        s.heights[j * nx + i] =
            static_cast<float>(0.0015 * std::cos(2 * M_PI * r / 0.012) *
                               std::exp(-r * r / (0.02 * 0.02)));
      }
    }
  }
  s.inputs.water = {s.heights.data(), nx, ny, d, ripple ? 2u : 1u};
  return s;
}

// Paints the real pen (PenGeometry; cube and shaft) into a BGR8 frame by
// splatting dense surface points: a stand-in for the pen in a camera image.
// The pen is assumed in front of everything else.
inline void PaintPen(const Intrinsics& k, const glm::dmat4& cam_from_tank,
                     const glm::dmat4& tank_from_pen, const PenGeometry& g,
                     std::vector<std::uint8_t>* bgr) {
  const glm::dmat4 cam_from_pen = cam_from_tank * tank_from_pen;
  auto paint = [&](const glm::dvec3& p_in_pen, int shade) {
    const glm::dvec4 c = cam_from_pen * glm::dvec4(p_in_pen, 1.0);
    if (c.z <= 1e-3) return;
    const int u = static_cast<int>(std::lround(k.fx * c.x / c.z + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * c.y / c.z + k.cy));
    if (u < 0 || v < 0 || u >= k.width || v >= k.height) return;
    std::uint8_t* px = &(*bgr)[(static_cast<size_t>(v) * k.width + u) * 3];
    px[0] = static_cast<std::uint8_t>(std::min(255, 120 + shade));
    px[1] = static_cast<std::uint8_t>(std::min(255, 40 + shade / 2));
    px[2] = 30;
  };
  const double step = 0.0003;
  const double r = g.shaft_radius, e = g.cube_edge;
  for (double z = -0.5 * e - g.shaft_length; z <= -0.5 * e; z += step) {
    for (double a = 0; a < 2 * M_PI; a += step / r) {
      paint({r * std::cos(a), r * std::sin(a), z},
            static_cast<int>(60 * (1 + std::cos(a))));
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (double s : {-0.5, 0.5}) {
      for (double a = -0.5 * e; a <= 0.5 * e; a += step) {
        for (double b = -0.5 * e; b <= 0.5 * e; b += step) {
          glm::dvec3 p;
          p[axis] = s * e;
          p[(axis + 1) % 3] = a;
          p[(axis + 2) % 3] = b;
          paint(p, 40 * axis);
        }
      }
    }
  }
}

}  // namespace ripple::render::testing

#endif  // RIPPLE_TESTS_RENDER_RENDER_TEST_UTIL_H_
