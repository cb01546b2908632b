#include "geometry/height_field.h"

#include <gtest/gtest.h>

#include <vector>

namespace ripple::geometry {
namespace {

TEST(HeightFieldViewTest, IndexesRowsAlongYAndCentresOnTheTank) {
  const int nx = 4, ny = 2;
  std::vector<float> heights(nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) heights[j * nx + i] = 0.001f * (10 * j + i);
  HeightFieldView v;
  EXPECT_TRUE(v.empty());
  v.heights = heights.data();
  v.nx = nx;
  v.ny = ny;
  v.cell_m = 0.01;
  v.rest_level_m = 0.02;
  EXPECT_FALSE(v.empty());
  EXPECT_FLOAT_EQ(v.Height(3, 1), 0.013f);
  EXPECT_DOUBLE_EQ(v.SurfaceZ(3, 1), 0.02 + 0.013f);
  EXPECT_DOUBLE_EQ(v.CellCentreX(0), -0.015);
  EXPECT_DOUBLE_EQ(v.CellCentreX(3), 0.015);
  EXPECT_DOUBLE_EQ(v.CellCentreY(0), -0.005);
}

}  // namespace
}  // namespace ripple::geometry
