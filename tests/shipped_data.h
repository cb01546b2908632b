// The rigs and cameras shipped in data/, loaded for tests (one place for
// every module's tests).
#ifndef RIPPLE_TESTS_SHIPPED_DATA_H_
#define RIPPLE_TESTS_SHIPPED_DATA_H_

#include <gtest/gtest.h>

#include <string>

#include "tracking/camera.h"
#include "tracking/rig.h"

namespace ripple::test_data {

// data/rig/default.yml; a test failure (and an empty rig) if it won't load.
inline tracking::Rig DefaultRig() {
  std::string error;
  auto rig = tracking::LoadRig(
      std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml", &error);
  EXPECT_TRUE(rig) << error;
  return rig.value_or(tracking::Rig{});
}

// data/camera/default_640x480.yml; a test failure (and an invalid camera)
// if it won't load.
inline tracking::Camera DefaultCamera() {
  std::string error;
  auto camera = tracking::LoadCamera(
      std::string(RIPPLE_SOURCE_DIR) + "/data/camera/default_640x480.yml",
      &error);
  EXPECT_TRUE(camera) << error;
  return camera.value_or(tracking::Camera{});
}

}  // namespace ripple::test_data

#endif  // RIPPLE_TESTS_SHIPPED_DATA_H_
