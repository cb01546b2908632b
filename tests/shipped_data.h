// The rigs and cameras shipped in data/, loaded for tests (one place for
// every module's tests).
#ifndef RIPPLE_TESTS_SHIPPED_DATA_H_
#define RIPPLE_TESTS_SHIPPED_DATA_H_

#include <gtest/gtest.h>

#include <string>

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

}  // namespace ripple::test_data

#endif  // RIPPLE_TESTS_SHIPPED_DATA_H_
